/* report.h — haircompare's report: what it measured per tier, and the
   pieces of REPORT_DIR/index.html written from it (plain HTML and inline
   SVG, no script; images are files beside index.html, linked by relative
   paths, so the directory opens from disk anywhere). Every string that
   came from a file or the command line (tier names, requirements, dropped
   features, reasons, paths, the GL renderer) goes through report_escape.

   Usage:
       report r;
       report_init(&r);
       ... fill r.tiers[0 .. r.tier_count-1] (report_read_bundle does the manifest's part) ...
       report_write_page(stdout, &r);
       report_free(&r);

   Layout: the tiers' cards wrap (CSS flex-wrap), so the page fits a
   1400 px window (the Makefile's REPORT_WIDTH) without scrolling sideways; images keep their
   pixel size where they fit and scale down where they do not.
   tests/report_screenshot_check.c finds every image, full size, in a
   headless Chromium screenshot of that width (make report-check). */
#ifndef HT_EXAMPLES_REPORT_H
#define HT_EXAMPLES_REPORT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "crop.h"
#include "metric_order.h"
#include "flip.h"
#include "manifest.h"
#include <hairtier/lod.h>
#include "metrics.h"

#define REPORT_MAX_TIERS 8
#define REPORT_MAX_DROPPED 32
#define REPORT_MAX_NOTES 32
/* The heatmaps' scale: per-pixel CIEDE2000 from 0 (black) to this (white
   and above). About 1 is the least difference one sees side by side, 10 a
   plain one; a strand drawn a pixel away from full's differs from the
   background by 20-40, so the scale stops at 20 to keep the gradations
   of shading visible rather than every edge. */
#define REPORT_HEAT_MAX 20.0

/* Page geometry, CSS pixels. */
#define REPORT_MARGIN 24          /* around the page */
#define REPORT_GAP 16             /* between tier cards */
/* The zoomed crops: the reference's brightest REPORT_CROP_SIZE² window
   (crop.h), every tier's image and heatmap cut there and enlarged
   REPORT_CROP_SCALE times, nearest neighbour: 128 px, so five tiers'
   crops sit in one line of the page. */
#define REPORT_CROP_SIZE 32
#define REPORT_CROP_SCALE 4

typedef struct report_tier {
    char name[16];                 /* as the manifest spells it */
    char needs[256];               /* "GL 2.0, GLSL 1.10, GL_ARB_texture_env_combine, 4 units" */
    char *dropped[REPORT_MAX_DROPPED]; /* the manifest's "dropped" (malloc'd) */
    int dropped_count;
    ht_tier tier;                  /* HT_TIER_COUNT: a tier this runtime does not know */
    bool known;                    /* a tier this runtime knows (else not rendered) */
    bool ran;
    char reason[512];              /* why it did not run; the renderer's reason when it did */
    double frame_ms;
    bool compared;                 /* the reference ran, so the metrics below are set */
    double cost_ratio;             /* frame_ms / the reference's */
    ht_metrics whole, hair;        /* against the reference, over the frame and over hair pixels */
    ht_flip_result flip;           /* LDR-FLIP against the reference, whole frame */
    ht_manifest_measured measured; /* the manifest's (hairgen --measure); .present false when absent */
    char image[64];                /* file beside index.html, "" when the tier did not run */
    char heatmap[64];              /* "" for the reference itself and for tiers not compared */
    char crop[64], heatmap_crop[64]; /* the zoomed crops of those two, "" when absent */
} report_tier;

/* The LOD x tier grid (report_lod.c), for a bundle that stores levels
   (lods.bin of this scene: hairgen --scene, --cards) or was measured with
   hairgen --measure-lods: every geometry level (rows: the bundle's stored
   ones, cards included, else the ladder built from the scene) drawn by
   every tier that ran at REPORT_LOD_SIZE of the scene's size, each
   against (level 0, the reference tier) at that size, beside the
   manifest's numbers for the cell when it has them. Each row's cells
   wrap (flex-wrap) so the grid fits the 1400 px window at any scene size;
   a 512-pixel scene's six tiers of 128 px sit in one line. */
#define REPORT_LOD_SIZE 0.25
#define REPORT_LOD_MAX_LEVELS HT_LOD_FILE_MAX_LEVELS
typedef struct report_lod_cell {
    bool ran;
    char image[64];                /* file beside index.html */
    double frame_ms, cost_ratio;   /* cost: over (level 0, the reference tier)'s in this run */
    ht_metrics whole;              /* against (level 0, the reference tier) at the grid's size */
    bool measured;                 /* the manifest has this cell: */
    double measured_psnr_db, measured_cost_ratio;
} report_lod_cell;

/* Where the grid's levels came from. */
typedef enum report_lod_source {
    REPORT_LOD_STORED,             /* the bundle's lods.bin, made from this scene's mesh */
    REPORT_LOD_BUILT,              /* built from the scene (lod.h's ladder): the bundle stores none */
    REPORT_LOD_BUILT_OTHER_SCENE,  /* built from the scene: the bundle's lods.bin is another scene's */
} report_lod_source;

typedef struct report_lod_grid {
    int levels;                    /* 0: no grid */
    report_lod_source source;
    double size;                   /* of the scene's: the measured size nearest REPORT_LOD_SIZE */
    int width, height;             /* of every grid image */
    uint32_t strands[REPORT_LOD_MAX_LEVELS]; /* the level's components: strands, or cards */
    bool cards[REPORT_LOD_MAX_LEVELS];       /* a cards level (lods.bin's kind) */
    uint32_t strands_per_card[REPORT_LOD_MAX_LEVELS]; /* its param, for a cards level */
    int measured_cells;            /* the manifest's cells shown beside the grid's */
    int other_cells;               /* its cells at this size that match no row (other geometry) */
    report_lod_cell cells[REPORT_LOD_MAX_LEVELS][REPORT_MAX_TIERS]; /* [level][the report's tier] */
    /* soft[k][l]: strand level l past 0 also drawn soft by soften[k] (lod.h:
       that many times wider at its inverse opacity, back to front), a row
       of its own, for each factor the bundle measured soft cells at
       (error:DB may pick one), in the order its cells first name them */
    float soften[HT_LOD_MAX_SOFTENS];
    int soften_count;
    bool soft[HT_LOD_MAX_SOFTENS][REPORT_LOD_MAX_LEVELS];
    report_lod_cell soft_cells[HT_LOD_MAX_SOFTENS][REPORT_LOD_MAX_LEVELS][REPORT_MAX_TIERS];
} report_lod_grid;

/* A grid row's cell: row_kind 0 the plain level, k + 1 it soft by soften[k]
   (as strchr, the grid's constness is the caller's). */
report_lod_cell *report_lod_row_cell(const report_lod_grid *g, int level, int row_kind, int tier);
/* Whether the grid has that row (level 0 never soft, cards never). */
bool report_lod_has_row(const report_lod_grid *g, int level, int row_kind);

typedef struct report {
    char material[64];
    char *notes[REPORT_MAX_NOTES]; /* the manifest's root "notes" (malloc'd) */
    int note_count;
    const char *bundle, *scene;    /* as given on the command line */
    char driver[128];              /* GL_RENDERER the tiers ran on */
    int width, height;             /* of every image */
    int frames;                    /* timed frames per tier */
    report_tier tiers[REPORT_MAX_TIERS]; /* bundle order, best first */
    int tier_count;
    int reference;                 /* the tier every other is measured against; -1 when none ran */
    crop_region crop;              /* where the crops were cut (w 0: none) */
    ht_manifest_lods measured_lods; /* the manifest's "lods" (cell_count 0: none) */
    report_lod_grid lods;
} report;

void report_init(report *r);
void report_free(report *r);

/* Fills material, notes and each tier's name, needs and dropped from
   BUNDLE/manifest.json (runtime/io/manifest.h reads and checks it; the
   free-text lists are read here). One line in err naming the file and
   field on failure. */
ht_result report_read_bundle(report *r, const char *bundle, char *err, size_t err_size);

/* s with & < > " ' as character references: safe in text and in quoted
   attribute values. NULL writes nothing. */
void report_escape(FILE *f, const char *s);

/* The reference among the tiers that ran: marschner (a Marschner
   material's lower tiers draw constants fitted to it, and hairgen
   --measure measures against it), else full; -1 when neither ran. */
int report_pick_reference(const report *r);
/* tiers[reference].name, or "the reference" when none ran: what every
   label that says "against ..." names. */
const char *report_reference_name(const report *r);

/* ---- the plot of error against cost (report_plot.c) ---- */

/* An axis from 0 to a round number at or above max_value: steps of 1, 2
   or 5 times a power of ten, 4 to 10 of them. */
typedef struct plot_axis {
    double hi, step;
    int ticks;                     /* tick marks including 0 and hi */
} plot_axis;
plot_axis plot_axis_fit(double max_value);
/* value on [0, hi] to [px0, px1] (px1 < px0 for an upward y axis). */
double plot_map(const plot_axis *a, double value, double px0, double px1);

/* Label baselines for points (px, py) whose labels start at x and are w
   wide: each beside its point unless that covers a label placed before it
   (points higher up first) or another point, else moved down below it. */
void plot_place_labels(const double *px, const double *py, const double *x, const double *w, int n,
                       double *label_y);

#define PLOT_W 720
#define PLOT_H 400

/* The SVG (PLOT_W x PLOT_H) of ΔE00 mean against cost ratio, one labelled
   point per compared tier; a note instead when none was compared. */
void report_write_plot(FILE *f, const report *r);
/* The colour scale of the heatmaps as an SVG bar with numbers. */
void report_write_legend(FILE *f, const report *r);
/* The measurements: tier, frame ms; this run's cost, PSNR, SSIM, ΔE00
   mean and p95 and FLIP mean and p95 over the frame and ΔE00 over hair
   pixels; beside them the bundle's measured numbers when any tier has
   them, else a sentence saying the bundle has none; then whether PSNR and
   FLIP rank the tiers alike (metric_order.h). */
void report_write_table(FILE *f, const report *r);
/* PSNR against FLIP over the compared tiers, the reference aside
   (metric_order.h); a and b are indices into r->tiers. */
metric_order report_metric_order(const report *r);
/* What each tier needs and the features it drops. */
void report_write_needs(FILE *f, const report *r);

/* ---- the LOD x tier grid (report_lod.c) ---- */

/* The grid's size for these measured cells: the measured size nearest
   REPORT_LOD_SIZE; 0 when there are none. */
double report_lod_size(const ht_manifest_lods *m);
/* Fills each grid cell's measured numbers from r->measured_lods: the
   cells at the grid's size whose level, kind (cards or strands), tier and
   strand (card) count are the row's; the rest at that size are counted in
   other_cells (measured on other geometry: another scene's levels). */
void report_lod_attach_measured(report *r);
/* The section: which levels and reference, then a row of cells a level
   (its tiers across, wrapping). Nothing when r->lods.levels is 0. */
void report_write_lod_grid(FILE *f, const report *r);
/* The whole page. 0, or -1 when the stream reports an error. */
int report_write_page(FILE *f, const report *r);

#endif

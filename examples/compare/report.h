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

   Layout: fixed pixel sizes (REPORT_* below), so a page with N tiers is
   report_page_width(N) wide and its images sit where report_image_rect
   says, whatever the fonts; tests/report_screenshot_check.c finds them in
   a headless Chromium screenshot. */
#ifndef HT_EXAMPLES_REPORT_H
#define HT_EXAMPLES_REPORT_H

#include <stdbool.h>
#include <stdio.h>

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
#define REPORT_GAP 16             /* between tier columns */
#define REPORT_HEADER_H 120       /* title and scene line, clipped to this */
#define REPORT_CAPTION_H 32       /* a tier's name above its image, its heatmap's line above that */

typedef struct report_tier {
    char name[16];                 /* as the manifest spells it */
    char needs[256];               /* "GL 2.0, GLSL 1.10, GL_ARB_texture_env_combine, 4 units" */
    char *dropped[REPORT_MAX_DROPPED]; /* the manifest's "dropped" (malloc'd) */
    int dropped_count;
    bool known;                    /* a tier this runtime knows (else not rendered) */
    bool ran;
    char reason[512];              /* why it did not run; the renderer's reason when it did */
    double frame_ms;
    bool compared;                 /* full ran, so the metrics below are set */
    double cost_ratio;             /* frame_ms / full's */
    ht_metrics whole, hair;        /* against full, over the frame and over hair pixels */
    char image[64];                /* file beside index.html, "" when the tier did not run */
    char heatmap[64];              /* "" for full itself and for tiers not compared */
} report_tier;

typedef struct report {
    char material[64];
    char *notes[REPORT_MAX_NOTES]; /* the manifest's root "notes" (malloc'd) */
    int note_count;
    const char *bundle, *scene;    /* as given on the command line */
    char driver[128];              /* GL_RENDERER the tiers ran on */
    int width, height;             /* of every image */
    int frames;                    /* timed frames per tier */
    report_tier tiers[REPORT_MAX_TIERS]; /* bundle order, best first; [0] is the reference when named full */
    int tier_count;
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

/* Where a tier's image (row 0) or heatmap (row 1) sits on the page. */
typedef struct report_rect {
    int x, y, w, h;
} report_rect;
report_rect report_image_rect(const report *r, int column, int row);
int report_page_width(const report *r);

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
void report_write_legend(FILE *f);
/* The table: tier, needs, frame ms, cost, PSNR, SSIM, ΔE00 mean and p95
   over the frame, ΔE00 over hair pixels, features dropped. */
void report_write_table(FILE *f, const report *r);
/* The whole page. 0, or -1 when the stream reports an error. */
int report_write_page(FILE *f, const report *r);

#endif

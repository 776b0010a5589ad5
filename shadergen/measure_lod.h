/* measure_lod.h — hairgen --measure-lods: every tier of the bundle drawn
   at every geometry LOD of the scene (include/hairtier/lod.h's ladder, up
   to ht_lod_max_level) at HT_MEASURE_LOD_SIZES projected sizes (the image
   scaled: 1, 1/2, 1/4), and every strand level past 0 soft (lod.h's
   ht_lod_cell.soften: ht_mesh_widen_back_to_front by each soften factor,
   HT_LOD_DEFAULT_SOFTENS unless hairgen --lod-soften says, as the runtime derives
   it, at its inverse opacity), each (LOD, tier) cell against (LOD 0, the bundle's
   first tier) at the same size (PSNR, SSIM, ΔE00 mean, cost as a ratio of
   that pair's median frame, timed first and again last at each size, the
   faster of the two; each cell's timed frames after a warm-up,
   offscreen_warmup_ms) and against the tier's level before (the
   pop), written into the manifest's "lods" object (manifest.h), which
   ht_renderer_lod_cells hands to ht_lod_pick_error / ht_lod_pick_frame.
   A tier this context cannot run is left out (listed in skipped); the
   first tier must run. Errors are one line starting "measure: lods: ". */
#ifndef HT_MEASURE_LOD_H
#define HT_MEASURE_LOD_H

#include <stdbool.h>
#include <stdio.h>

#include <hairtier/hairtier.h>
#include <hairtier/scene.h>
#include "manifest.h"
#include "metrics.h"

#define HT_MEASURE_LOD_SIZES 3
#define HT_MEASURE_LOD_TIMED_FRAMES 3  /* after the warm-up; the median */

typedef struct ht_measure_lod_cell {
    int level;
    char tier[16];           /* the tier drawn */
    uint32_t strands;        /* the level's components: strands, or cards */
    bool cards;              /* a stored cards level (lods.bin) */
    float soften;            /* 0: plain; else the level soft by this factor (lod.h) */
    double size;
    ht_metrics whole;        /* against (LOD 0, the first tier) at this size */
    double frame_ms, cost_ratio;
    double pop_psnr_db;      /* against the tier's level - 1 at this size; INFINITY at level 0 */
} ht_measure_lod_cell;

typedef struct ht_measure_lods {
    char tier[16];           /* the reference tier: the bundle's first */
    char skipped[128];       /* tiers this context could not run, space-separated */
    int samples;             /* 0: one a pixel; else the frames' multisampling */
    ht_lod_reference reference; /* SUPERSAMPLE: against the 16x truth, cells drawn with the width rule */
    double warmup_ms;        /* drawn before each cell's timed frames (offscreen_warmup_ms; 0: one frame) */
    ht_measure_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    int count;
} ht_measure_lods;

/* How the cells are drawn (zeroed: the defaults). samples: 0, one a
   pixel; 2..32, every frame multisampled (the manifest records it).
   reference: HT_LOD_REFERENCE_SAMPLES, every cell against (LOD 0, first
   tier) drawn as the cells are; _SUPERSAMPLE, against that pair drawn at
   4 x 4 the pixels and box-filtered (the 16x truth), every cell drawn with
   the width rule (lod.h) as ht_lod_chain draws with width_rule set (the
   manifest records it). soften: the soft cells' factors, each in
   (1, HT_LOD_MAX_SOFTEN], none twice, the first 0 ending them (each soft
   cell records its own); all 0: HT_LOD_DEFAULT_SOFTENS (lod.h). */
typedef struct ht_measure_lods_desc {
    int samples;
    ht_lod_reference reference;
    float soften[HT_LOD_MAX_SOFTENS];
} ht_measure_lods_desc;
/* Whether desc's soften factors are as above (hairgen --lod-soften checks
   its list with it before anything is written). */
bool ht_measure_lods_softens_valid(const ht_measure_lods_desc *desc);

/* The 16x truth (lod.h's supersampled reference): mesh drawn in tier at
   HT_MEASURE_SUPERSAMPLE x HT_MEASURE_SUPERSAMPLE the pixels of a
   width x height image, one sample each, in a context of its own (context,
   egl_device as platform/offscreen.h's), box-filtered down into rgba
   (width x height x 4, rows bottom first as GL reads them). */
#define HT_MEASURE_SUPERSAMPLE 4
typedef struct ht_measure_truth_desc {
    const char *bundle_dir;
    ht_tier tier;
    int width, height;
    int context, egl_device; /* offscreen_kind (0: auto), -1: the default display */
    float background[3];
    const ht_frame_desc *frame;
    const ht_mesh *mesh;
} ht_measure_truth_desc;
ht_result ht_measure_truth(const ht_measure_truth_desc *desc, unsigned char *rgba, char *err, size_t err_size);
/* Draws and measures (needs an offscreen context: OSMesa, else EGL). A
   bad desc is HT_ERR_INVALID_ARGUMENT naming the hairgen option. */
ht_result ht_measure_lods_run(const char *dir, const ht_scene *scene, const char *scene_file,
                              const ht_measure_lods_desc *desc, ht_measure_lods *out, char *err, size_t err_size);
/* Replaces the "lods" object of dir/manifest.json (whole or not at all),
   after checking the runtime reads the result. */
ht_result ht_measure_lods_write(const char *dir, const ht_measure_lods *m, char *err, size_t err_size);
void ht_measure_lods_print(FILE *out, const ht_measure_lods *m);

#endif

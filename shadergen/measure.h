/* measure.h — `hairgen --measure`: the speed-for-accuracy trade of a
   finished bundle, measured offline and written into its manifest.

   Every tier of the bundle renders the bundle's reference scene offscreen,
   OSMesa where it loads, else EGL (platform/offscreen.h; HAIRTIER_CONTEXT
   forces one) (a context of its own per tier, forced and strict, through hairtier.h),
   frames round-robin across the tiers so that a change in the machine's
   load falls on every tier alike. Each tier's last frame is compared with
   the reference's ("full" below: the full tier, or for a Marschner
   material its marschner tier) over the whole frame (shadergen/metrics.h,
   and LDR-FLIP at 67 pixels per degree, shadergen/flip.h) and its median
   frame time divided by the reference's. The result goes into each tier's
   `measured` object (docs/bundle.md), which the runtime's error:DB,
   error:flip:E and fastest policies read.

   Usage (what hairgen does; the step runs before the bundle is published):
       ht_measure_job job = { .scene_path = scene_path, .out_dir = out_dir };
       r = ht_generate_bundle_then(material, scene_path, out_dir, stdout,
                                   ht_measure_step, &job, err, sizeof err);
       if (r == HT_OK) ht_measure_print(stdout, &job.result);

   Errors are one line starting "measure: " naming the tier or field. */
#ifndef HT_MEASURE_H
#define HT_MEASURE_H

#include <stdio.h>

#include <hairtier/hairtier.h>
#include "manifest.h"
#include "flip.h"
#include "metrics.h"
#include <hairtier/scene.h>
#include "measure_lod.h"

#define HT_MEASURE_WARMUP_FRAMES 2   /* per tier, untimed: shader variants, uploads, caches (at least) */
#define HT_MEASURE_TIMED_FRAMES 5    /* per tier; the median is the tier's frame time */
#define HT_MEASURE_BUILT_IN_SCENE "built-in"

typedef struct ht_measure_tier {
    char name[16];           /* the manifest's tier name */
    double frame_ms;         /* median of the timed frames, each ended by glFinish */
    double cost_ratio;       /* frame_ms / full's frame_ms */
    ht_metrics whole;        /* against full's image, whole frame; psnr INFINITY: identical */
    ht_flip_result flip;     /* LDR-FLIP against full's image at HT_FLIP_DEFAULT_PPD, whole frame */
    /* the tier's device-only variant (hairtier.h ht_variant), when its
       backend has one for this bundle: the same numbers, written as
       "measured_device" */
    struct {
        bool present;
        double frame_ms, cost_ratio;
        ht_metrics whole;
    } device;
} ht_measure_tier;

typedef struct ht_measure_result {
    ht_measure_tier tiers[HT_MANIFEST_MAX_TIERS];  /* the manifest's order */
    int tier_count;
    char scene[64];          /* the scene file's base name, or HT_MEASURE_BUILT_IN_SCENE */
    char driver[128];        /* GL_RENDERER as the driver reports it */
    char reference[16];      /* the tier measured against: marschner for a Marschner bundle, else full */
    int width, height;
    int warmup_rounds;       /* untimed rounds of every tier: at least HT_MEASURE_WARMUP_FRAMES */
    double warmup_ms;        /* ht_timing_warmup_ms of the driver: 0 on a software rasterizer */
} ht_measure_result;

/* The scene label: scene_path's base name (cut to fit, at a UTF-8
   character boundary), HT_MEASURE_BUILT_IN_SCENE for NULL. */
void ht_measure_scene_label(const char *scene_path, char out[64]);

/* The monotonic clock in ms, and the median of v[0..n-1] (n >= 1; v is
   sorted in place): what every measured frame time is made of. */
double ht_measure_clock_ms(void);
double ht_measure_median(double *v, int n);

/* Renders `scene` with every tier of the bundle in dir and measures each
   against full. Fails when the bundle has no full tier, when any tier
   cannot run on this driver (forced, strict: the line says why) or when a
   number is not finite or out of the manifest's range. scene_file (NULL
   for the built-in scene) is where a strands scene's file is resolved. */
ht_result ht_measure_bundle(const char *dir, const ht_scene *scene, const char *scene_file,
                            const char *scene_label, ht_measure_result *out, char *err, size_t err_size);

/* Adds each tier's `measured` object to dir/manifest.json (a temporary
   file renamed over it), then reads the manifest back with the runtime's
   reader and checks every tier carries it. Numbers are rounded for
   reading: psnr_db to 0.01 dB (null when identical), ssim to 1e-4, ΔE to
   1e-3, FLIP to 1e-5, cost_ratio to 4 significant digits. On failure the manifest is as
   it was. */
ht_result ht_measure_write_manifest(const char *dir, const ht_measure_result *m, char *err, size_t err_size);

/* The table hairgen prints after the bundle's summary. */
void ht_measure_print(FILE *out, const ht_measure_result *m);

/* An ht_bundle_step_fn (hairgen.h): ht_measure_bundle, then
   ht_measure_write_manifest, on the unpublished bundle. user is an
   ht_measure_job; out_dir, when set, stands for the temporary directory's
   path in error lines. */
typedef struct ht_measure_job {
    const char *scene_path;  /* NULL: the built-in (default) scene */
    const char *out_dir;
    bool lods;               /* also the geometry LODs (measure_lod.h: --measure-lods) */
    ht_measure_lods_desc lod;  /* how the LOD cells are drawn (--lod-samples, --lod-reference, --lod-soften) */
    ht_measure_result result;
    ht_measure_lods lods_result;
} ht_measure_job;

ht_result ht_measure_step(void *job, const char *dir, const ht_scene *scene, char *err, size_t err_size);

#endif

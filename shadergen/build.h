/* build.h — every tier of one material in memory, as jobs over a few
   threads (build.c): what generate.c turns into a bundle's files. */
#ifndef HT_BUILD_H
#define HT_BUILD_H

#include "emit.h"
#include "marschner_fit.h"

/* The emitters, best first: the order the runtime walks. */
#define HT_BUILD_TIERS 6

typedef struct ht_built_png {
    unsigned char *bytes;   /* the PNG file (png_encode.c); NULL for no image */
    size_t size;
} ht_built_png;

typedef struct ht_built {
    ht_plan plan;             /* the material's plan, texture measurements in */
    bool physical;            /* a Marschner material: fit holds its lower tiers' constants */
    ht_marschner_fit fit;
    ht_image albedo, detail;  /* pixels NULL when the plan has no such texture */
    ht_built_png albedo_png, detail_png;
    /* The tiers the bundle holds, best first; a tier the plan rules out
       (HT_ERR_UNSUPPORTED from its emitter) is left out. */
    ht_tier_output tiers[HT_BUILD_TIERS];
    ht_built_png tier_png[HT_BUILD_TIERS][HT_OUT_MAX_IMAGES];
    int tier_count;
} ht_built;

/* Builds *out on the calling thread and up to threads - 1 more (threads
   < 1: one per online core); the result is the same whatever the count.
   m is checked already. On failure out is freed and err holds the first
   error in the order the steps would run one after another: the fit, the
   textures (slot order), the tiers (best first). */
ht_result ht_build(const ht_material *m, const ht_scene *scene, int threads, ht_built *out, char *err,
                   size_t err_size);
void ht_built_free(ht_built *b);

#endif

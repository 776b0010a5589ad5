/* hairgen.h — the offline generator's internal interfaces: material and scene
   files in, a plan of what to model, emitted tiers, a bundle directory out.
   No GL context anywhere in shadergen/. */
#ifndef HT_HAIRGEN_H
#define HT_HAIRGEN_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hairtier.h"
#include "model.h"
#include "scene.h"
#include "image.h"

/* ---- material (materials/NAME.json, format "hairtier-material/1") ---- */

typedef enum ht_texture_slot {
    HT_TEX_BASE = 0,   /* rgb */
    HT_TEX_ALPHA,      /* coverage */
    HT_TEX_SHIFT,      /* tangent shift jitter, 0.5 = none */
    HT_TEX_SPARKLE,    /* secondary highlight mask */
    HT_TEX_COUNT
} ht_texture_slot;

const char *ht_texture_slot_name(ht_texture_slot s); /* "base", ... */

typedef enum ht_texture_origin {
    HT_TEXTURE_ABSENT = 0,     /* not modelled anywhere */
    HT_TEXTURE_PROCEDURAL,
    HT_TEXTURE_FILE,
} ht_texture_origin;

typedef struct ht_texture_source {
    ht_texture_origin origin;
    char procedural[32];   /* "stretched-noise", "strand-alpha", "noise", "sparkle" */
    int size;              /* procedural: power of two 16..2048 */
    uint32_t seed;
    char path[1024];       /* file: resolved against the material file's folder */
} ht_texture_source;

typedef struct ht_material {
    char name[64];
    ht_shading shading;
    ht_texture_source textures[HT_TEX_COUNT];
    double opaque_cutoff;  /* alpha at or above this is opaque; (0,1], default 0.98 */
    char file[1024];       /* the file it was read from, naming it in errors;
                              "" for a material built in memory */
} ht_material;

/* Errors are one line "FILE: FIELD: what is wrong" written to err. */
ht_result ht_material_load(const char *path, ht_material *out, char *err, size_t err_size);
ht_result ht_material_parse(const char *json_text, const char *file_name,
                            ht_material *out, char *err, size_t err_size);

/* ---- textures ---- */

/* Makes one texture of the material: procedural ones generated, file ones
   read (PNG) and reduced to the channels the slot needs (base: 3, others: 1). */
ht_result ht_texture_make(const ht_texture_source *src, ht_texture_slot slot,
                          ht_image *out, char *err, size_t err_size);

/* ---- plan: what the scene needs modelled ---- */

#define HT_MAX_NOTES 16
#define HT_MAX_UNITS 4

typedef struct ht_plan_texture {
    char name[16];          /* "albedo", "detail", "lut" */
    char sampler[24];       /* uniform name in GLSL tiers */
    char contents[64];      /* "base.rgb alpha.a" */
    int unit;
} ht_plan_texture;

typedef struct ht_plan {
    ht_shading shading;
    int light_count;
    ht_light_type light_types[HT_MAX_LIGHTS];
    bool base, alpha, shift, sparkle, secondary, ao;  /* modelled features */
    double opaque_cutoff;
    /* Mean of the sparkle texture (1 until generate.c measures it): the
       tiers that cannot sample the mask scale the secondary highlight by it
       instead of leaving it unmasked. */
    double sparkle_mean;
    ht_plan_texture textures[HT_MAX_UNITS];  /* GLSL tiers' texture units */
    int texture_count;
    char notes[HT_MAX_NOTES][160];           /* what was dropped and why */
    int note_count;
} ht_plan;

void ht_plan_make(const ht_material *m, const ht_scene *scene, ht_plan *out);
/* The shading a tier without the sparkle mask evaluates: the secondary
   colour scaled by plan->sparkle_mean (unchanged when sparkle is absent). */
ht_shading ht_plan_unmasked_shading(const ht_plan *plan);

/* ---- generator (shadergen/generate.c) ---- */

/* Generates every tier for (material, scene) and writes DIR atomically (a
   temporary sibling renamed into place; an existing DIR is replaced only
   after the new one is complete). scene_path may be NULL (ht_scene_default).
   summary, when not NULL, receives the human-readable table. */
ht_result ht_generate_bundle(const char *material_path, const char *scene_path,
                             const char *out_dir, FILE *summary, char *err, size_t err_size);

#endif

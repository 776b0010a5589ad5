/* fixed4_stages.h — fixed4's fragment stages (fixed4_program.h's table: the
   LUT units, the albedo unit, the final unit) as one piece shared by the two
   backends that run them: the `fixed4` tier (fixed4.c: LUT coordinates from
   texture matrices or the CPU, diffuse from GL lighting) and the `vertex`
   tier (runtime/render/tier_glsl.c: coordinates and diffuse from its GLSL 1.10
   vertex shader). Owns the LUT textures (baked for the frame's light
   colours and scale), the albedo texture and the texture-environment setup;
   the caller owns texture coordinates, texture matrices and the primary
   colour.

   Usage (both backends):
       ht_fixed4_stages st;
       ht_fixed4_stages_init(&st, gl, &program, "fixed4");
       ht_fixed4_stages_load_albedo(&st, ctx, err, sizeof err);           // create
       ht_fixed4_stages_bake(&st, colors, scale, err, sizeof err);        // create: white lights
       ht_fixed4_stages_update(&st, colors, scale, log, log_user);        // begin_frame
       ht_fixed4_stages_bind(&st, prime);                                 // bind_pass
       ht_fixed4_stages_unbind(&st);                                      // end_frame
       ht_fixed4_stages_release(&st);                                     // destroy */
#ifndef HT_FIXED4_STAGES_H
#define HT_FIXED4_STAGES_H

#include <stdbool.h>

#include "fixed4_program.h"
#include "tier.h"

typedef struct ht_fixed4_stages {
    const ht_gl *gl;
    const ht_fixed4_program *program; /* outlives the stages */
    const char *name;                 /* the tier, for LUT names and log lines */
    int luts, units;
    GLuint lut_textures[HT_FIXED4_MAX_LUTS];
    GLuint albedo;
    bool albedo_is_white;
    /* what the LUTs were baked for */
    bool baked;
    float baked_colors[HT_FIXED4_MAX_LIGHTS][3];
    int scale;
    /* the frame's width rule (tier.h): the final stage's alpha x (1 - this),
       through its constant colour */
    float opacity_cut;
} ht_fixed4_stages;

void ht_fixed4_stages_init(ht_fixed4_stages *st, const ht_gl *gl, const ht_fixed4_program *program,
                           const char *name);
/* The tier's "albedo" texture (checked against the manifest and for NPOT),
   or a white texel when the bundle has none. */
ht_result ht_fixed4_stages_load_albedo(ht_fixed4_stages *st, const ht_tier_context *ctx, char *err,
                                       size_t err_size);
/* Bakes and uploads every LUT for these light colours (program lights rows)
   and scale. */
ht_result ht_fixed4_stages_bake(ht_fixed4_stages *st, const float light_colors[][3], int scale, char *err,
                                size_t err_size);
/* Rebakes only when a colour or the scale changed; a failure is logged and
   leaves the stages unbaked (ht_fixed4_stages_ready false). */
void ht_fixed4_stages_update(ht_fixed4_stages *st, const float light_colors[][3], int scale, ht_log_fn log,
                             void *log_user);
static inline bool ht_fixed4_stages_ready(const ht_fixed4_stages *st) { return st->baked; }
/* Every unit's texture and combiner stage; the prime-Z pass enables only
   the final unit (the albedo's alpha). Leaves unit 0 active. */
void ht_fixed4_stages_bind(const ht_fixed4_stages *st, bool prime);
/* GL ES: the LUTs and the albedo on their units for the ES fragment stage
   (emit_vertex.c writes the combiners out as ESSL), no texture environment;
   unbind_textures leaves every unit's 2D binding 0. */
void ht_fixed4_stages_bind_textures(const ht_fixed4_stages *st);
void ht_fixed4_stages_unbind_textures(const ht_fixed4_stages *st);
/* Every unit back to GL_MODULATE, scale 1, no texture, target off; unit 0
   active. */
void ht_fixed4_stages_unbind(const ht_fixed4_stages *st);
void ht_fixed4_stages_release(ht_fixed4_stages *st);

#endif

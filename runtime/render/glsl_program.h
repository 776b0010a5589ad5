/* glsl_program.h — what the GLSL tiers share (the full tier here in
   runtime/render/tier_glsl.c, the vertex tier in fallback/vertex.c): a program
   built from the bundle's shader files with one-line errors and the info
   log echoed, its per-frame uniforms, and a bundle texture uploaded for a
   sampler. Internal to libhairtier.

   Usage:
       ht_glsl_program p;
       if ((r = ht_glsl_program_build(ctx, "full.vert", "full.frag", &p, err, sizeof err)) != HT_OK)
           return r;   // err: "compile failed: full.frag: 0:12(3): error: ..."
       every frame: ht_glsl_program_set_frame(gl, &p, frame, bundle->light_count, 1.0f); */
#ifndef HT_GLSL_PROGRAM_H
#define HT_GLSL_PROGRAM_H

#include "tier.h"

typedef struct ht_glsl_program {
    GLuint id;
    GLint u_eye, u_light_vector, u_light_color, u_lut_scale; /* -1: not used by the program */
    GLint u_mvp;                                             /* ES texts: projection x view */
    GLint u_opacity_cut;                                     /* the width rule (-1: a text without it) */
    GLint u_width_rule;                                      /* the width rule per vertex (-1: a text without it) */
} ht_glsl_program;

/* On a GL ES context: the tier's ES target selection chose
   (ht_select_es_target), logged once with its ESSL version and precision;
   NULL with the reason in err. */
const ht_manifest_es *ht_glsl_es_target(const ht_tier_context *ctx, char *err, size_t err_size);

/* Compiles vert (and frag, unless NULL: a vertex-only program) from the
   bundle, binds the generic attributes (shader_interface.h), links, and
   points the tier's samplers at their units. HT_ERR_COMPILE with "compile
   failed: FILE: first log line" or "link failed: ..." in err; every log
   line is also logged. Nothing is left on failure. */
ht_result ht_glsl_program_build(const ht_tier_context *ctx, const char *vert, const char *frag,
                                ht_glsl_program *out, char *err, size_t err_size);

/* What the fixed-function transform applies, for the ES texts' u_mvp:
   projection x view, column-major (the model matrix is identity). */
void ht_glsl_mvp(const ht_tier_frame *f, float out[16]);

/* Uses the program and sets the eye, the planned lights (light_count of
   them; lights missing from the frame are black) and the LUT scale. */
void ht_glsl_program_set_frame(const ht_gl *gl, const ht_glsl_program *p, const ht_tier_frame *f, int light_count,
                               float lut_scale);

/* A bundle texture checked against the manifest (size from the PNG header
   before decoding, 2D only) and uploaded for a sampler: linear, repeat. */
ht_result ht_glsl_texture_upload(const ht_gl *gl, const ht_manifest *b, const ht_manifest_texture *t, GLuint *out,
                                 char *err, size_t err_size);

#endif

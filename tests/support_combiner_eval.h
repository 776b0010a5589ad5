/* support_combiner_eval.h — a CPU emulator of a combiner program
   (GL_COMBINE semantics), so tests can hold the fixed tier against
   runtime/shading/model.c without a GL context. Test-only: nothing that ships
   needs it, so it lives here rather than in libhairtier.a. */
#ifndef HT_SUPPORT_COMBINER_EVAL_H
#define HT_SUPPORT_COMBINER_EVAL_H

#include "combiner.h"

/* ---- CPU emulation of the program (GL_COMBINE semantics) ---- */

/* A texture the program may bind, by the name its stages use. */
typedef struct ht_combiner_texture {
    const char *name;        /* "fixed-lut", "albedo" */
    const ht_image *image;   /* 8-bit; a 3D texture has its slices stacked vertically */
    int depth;               /* 1 for 2D */
} ht_combiner_texture;

/* What one fragment sees: interpolated vertex data, and the frame's
   texture matrix. */
typedef struct ht_combiner_fragment {
    float lut_coord[3];      /* texcoord of "cpu-dots" stages */
    float uv[2];             /* texcoord of "uv" stages */
    float primary[4];        /* primary colour, clamped to [0,1] as GL does */
    float tangent[3];        /* texcoord (s,t,r) of "texture-matrix" stages, q = 1 */
    float texture_matrix[16]; /* their GL_TEXTURE matrix, column-major (glLoadMatrixf) */
} ht_combiner_fragment;

/* Evaluates the program for one fragment as GL would: a "texture-matrix"
   stage's coordinate is texture_matrix x (tangent, 1) divided by its q
   (GL transforms per vertex and interpolates, the same for an affine
   matrix), then 8-bit texels (value / 255), GL_LINEAR / GL_NEAREST
   filtering with GL_CLAMP_TO_EDGE / GL_REPEAT (trilinear for 3D, no
   mipmaps), each stage's function, then its scale, then a clamp to [0,1].
   Fails when a stage's texture is missing or its size disagrees with the
   program, or a texture matrix gives q <= 0 or a non-finite coordinate. */
ht_result ht_combiner_eval(const ht_combiner_program *p, const ht_combiner_texture *textures,
                           int texture_count, const ht_combiner_fragment *frag, float rgba[4],
                           char *err, size_t err_size);

#endif

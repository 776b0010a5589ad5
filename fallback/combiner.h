/* combiner.h — the fixed tier's GL 1.3 texture-combiner program as data:
   the struct the runtime applies, its JSON form ("fixed.json", format
   "hairtier-combiner/1"). The CPU emulator of GL_COMBINE semantics that
   tests hold the whole tier against runtime/shading/model.c with is test-only:
   tests/support_combiner_eval.h.

   The tier (Heidrich-Seidel): every term of the model that depends only on
   dot products lives in one lookup texture, the LUT, indexed by
       Scheuermann: a = N.L, b = t1.H, c = t2.H      (3D texture)
       Kajiya-Kay:  a = T.L, b = T.H                 (2D texture)
   holding rgb = ht_model_dot_terms_d(a, b, c) / lut_scale in 8 bits. The
   LUT stage's "coords" says who computes its coordinates per vertex:
     "cpu-dots"        the CPU, every frame (fixed_coords.h): Scheuermann
                       always (t1.H and t2.H need two shifted tangents that
                       one texture-matrix row cannot produce), Kajiya-Kay
                       with a point key light.
     "texture-matrix"  GL (Heidrich-Seidel): Kajiya-Kay with a directional
                       key light only. The vertex tangent T is the texture
                       coordinate (s,t,r,q) = (T,1) and the texture matrix
                       (ht_fixed_coords_texture_matrix), loaded per frame,
                       holds the rows
                           s = k0 (L.T) + 1/2,  t = k1 (H.T) + 1/2,  r = 1/2,  q = 1
                       with k = (n-1)/(2n): the "endpoints" mapping below is
                       affine in d, so it folds into the row. H = normalize(L
                       + V) with V the direction from the camera's target to
                       its eye, constant per frame: an infinite viewer, since
                       a matrix cannot form V = eye - position per vertex
                       (the emitter lists it as dropped). A row without a
                       direction (no L, or L = -V) is the constant the CPU
                       rule would give; a vertex without a tangent gets
                       primary colour 0, the model's answer there (sin = 0,
                       S = 0), because the matrix cannot tell T = 0.
   Typical program (shadergen/emit_fixed.c writes it):
       unit 0: LUT,    rgb = MODULATE(TEXTURE, PRIMARY_COLOR)
                       primary = light0.color * ao / light_scale
       unit 1: albedo, rgb = MODULATE(TEXTURE, PREVIOUS) x RGB_SCALE lut_scale,
                       alpha = REPLACE(TEXTURE)
   The LUT scale is restored on the last stage, not on the LUT's own: every
   stage clamps to [0,1], and clamping lighting above 1 before it is
   multiplied by a dark base would cut highlights the model keeps.

   Light colours above 1 ("light_scale", in "lut"): the primary colour is
   clamped to [0,1] by GL, so it carries light.color * ao / light_scale and
   the LUT holds dot_terms * light_scale / lut_scale: their product is
   dot_terms * light.color * ao / lut_scale again. light_scale (in [1,4])
   is the scene's brightest channel of the lights drawn, so no channel of
   theirs clamps; GL_RGB_SCALE reaching at most 4 is the one limit left
   (lighting above 4 clamps, as in every combiner tier).

   More lights ("add_lights"): each listed light is drawn by one more
   sub-pass of every pass that writes colour, after the key light's
   (sub-pass 0), over the same index range with the same stages: its own
   LUT coordinates (or texture matrix) and primary colour by the same rule,
   added to the framebuffer: blend (ONE, ONE) in the opaque pass and
   (SRC_ALPHA, ONE) in the transparent ones, depth EQUAL (the opaque and
   front passes: only the fragments sub-pass 0 left in the depth buffer) or
   the pass's own LESS (the back pass writes no depth, so sub-pass 0 and
   this one pass the same fragments), no depth or alpha writes. Exact for
   opaque fragments and for a single transparent layer (a (c0 + c1) + (1 - a)
   dst is a c0 + (1 - a) dst, then + a c1); where transparent layers overlap
   a deeper layer's added light is not attenuated by the layers blended over
   it in the same pass (back pass: too bright by a_deep a_over c1) or not
   added (front pass: the deeper layer fails EQUAL; too dark by
   (1 - a_over) a_deep c1); measured in docs/accuracy.md.

   LUT texel mapping ("centres": "endpoints"): along an axis of n texels,
   texel x holds the function at d = 2x/(n-1) - 1, so the first and last
   texel centres sit exactly on d = -1 and d = +1 and GL_CLAMP_TO_EDGE is
   never needed inside [-1,1] (the half-texel mapping d = 2(x+0.5)/n - 1
   would hold sin(T,L) at T = L as sqrt(2/n) instead of 0). With n a power
   of two (GL 1.x) no texel centre sits on d = 0: a highlight's peak is read
   as S(1/(n-1)) ~ exp(-e / (2 (n-1)^2)), 0.992 for e = 1000 at n = 256.
   A 3D LUT is stored as depth slices stacked vertically in one image:
   texel (x, y, z) is pixel (x, z * size[1] + y).

   Usage:
       ht_combiner_program p;
       char err[256];
       if (ht_combiner_parse(text, "fixed.json", &p, err, sizeof err) != HT_OK) { log(err); ... }
       for each stage s: glActiveTexture(GL_TEXTURE0 + s.unit); bind s.texture;
           glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
           glTexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, s.combine_rgb); ...
       every frame, "cpu-dots": ht_fixed_coords_compute(&p, ...) for unit 0's
       texcoords and the primary colours; "texture-matrix": unit 0's texcoords
       are the tangents, ht_fixed_coords_texture_matrix(&p, ...) goes into
       unit 0's GL_TEXTURE matrix and ht_fixed_coords_colors(&p, ...) gives
       the primary colours (only when the light colour changes).
   GL 1.2 only promises GL_MAX_3D_TEXTURE_SIZE >= 16: check it against
   lut_size before choosing this tier (the emitter's LUT axes reach 256).

   Enum fields hold GL enum values (<GL/gl.h>); the JSON names them
   ("GL_MODULATE"). Only what ARB_texture_env_combine offers is accepted:
   sources TEXTURE, CONSTANT, PRIMARY_COLOR, PREVIOUS (no crossbar), no DOT3. */
#ifndef HT_COMBINER_H
#define HT_COMBINER_H

#include <stdbool.h>
#include <stddef.h>

#include <GL/gl.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include <hairtier/model.h>

#define HT_COMBINER_FORMAT "hairtier-combiner/1"
#define HT_COMBINER_MAX_STAGES 4
#define HT_COMBINER_NAME_SIZE 24
/* Largest LUT axis the parser accepts (the emitter stays at or below 256). */
#define HT_COMBINER_MAX_LUT_SIZE 1024

/* Where a stage's texture coordinates come from. */
typedef enum ht_combiner_coords {
    HT_COORDS_UV = 0,       /* "uv": the vertex uv */
    HT_COORDS_CPU_DOTS,     /* "cpu-dots": LUT coordinates of the model's dot products */
    HT_COORDS_TEXTURE_MATRIX, /* "texture-matrix": the tangent through the texture matrix
                                 (Kajiya-Kay's LUT stage only, see above) */
} ht_combiner_coords;

typedef struct ht_combiner_stage {
    int unit;                          /* == its index in stages[] */
    char texture[HT_COMBINER_NAME_SIZE]; /* "fixed-lut" (the LUT) or a plan texture ("albedo") */
    GLenum target;                     /* GL_TEXTURE_2D or GL_TEXTURE_3D */
    GLenum filter;                     /* GL_LINEAR or GL_NEAREST, min and mag */
    GLenum wrap;                       /* GL_CLAMP_TO_EDGE or GL_REPEAT, every axis */
    ht_combiner_coords coords;
    GLenum combine_rgb, combine_alpha; /* GL_REPLACE, GL_MODULATE, GL_ADD, GL_ADD_SIGNED,
                                          GL_INTERPOLATE, GL_SUBTRACT */
    GLenum source_rgb[3], operand_rgb[3];     /* unused arguments keep GL's defaults */
    GLenum source_alpha[3], operand_alpha[3];
    int rgb_scale, alpha_scale;        /* 1, 2 or 4 */
    float constant[4];                 /* GL_TEXTURE_ENV_COLOR, [0,1] */
} ht_combiner_stage;

typedef struct ht_combiner_program {
    ht_model_kind model;               /* which dot products index the LUT */
    int light;                         /* the key light, sub-pass 0 (0: the scene's first) */
    int add_lights[HT_MAX_LIGHTS - 1]; /* lights drawn by additive sub-passes, in order */
    int add_light_count;
    bool ao;                           /* primary = light.color * ao, else light.color (/ light_scale) */
    double light_scale;                /* [1,4]: the light colour the LUT carries (above) */
    double shift[2];                   /* Scheuermann: t1, t2 = normalize(T + shift * N); 0 for Kajiya-Kay */
    char lut_texture[HT_COMBINER_NAME_SIZE]; /* "fixed-lut" */
    int lut_size[3];                   /* texels along a, b, c; c = 1 for a 2D LUT */
    int lut_scale;                     /* 1, 2 or 4: LUT texel = dot_terms / lut_scale */
    ht_combiner_stage stages[HT_COMBINER_MAX_STAGES];
    int stage_count;
} ht_combiner_program;

/* A stage on `unit` holding GL's initial texture-environment state for
   GL_COMBINE: MODULATE(TEXTURE, PREVIOUS) for rgb and alpha, sources
   (TEXTURE, PREVIOUS, CONSTANT), operands (SRC_COLOR, SRC_COLOR, SRC_ALPHA)
   and SRC_ALPHA for alpha, scales 1, constant 0; texture 2D, linear, repeat,
   uv coordinates, no texture name. Arguments a function does not read must
   keep these values (the JSON omits them). */
void ht_combiner_stage_defaults(ht_combiner_stage *s, int unit);
/* The width rule (docs/lod.md) on a program's last stage: its alpha
   REPLACE(a) becomes MODULATE(a, the constant's alpha = opacity). False
   (out untouched) where the stage's alpha is another function or its rgb
   reads the constant's alpha, which the scale would change. */
bool ht_combiner_stage_scale_alpha(const ht_combiner_stage *in, float opacity, ht_combiner_stage *out);

/* The LUT mapping above: d of texel x's centre, and the texture coordinate
   of d (clamped to [-1,1]) on an axis of `size` texels. A size-1 axis holds
   d = 0 and reads coordinate 0.5. */
double ht_combiner_lut_centre(int x, int size);
float ht_combiner_lut_coord(double d, int size);

/* How the LUT stage's coordinates are made (HT_COORDS_UV when no stage
   reads the LUT, which validation refuses). */
ht_combiner_coords ht_combiner_lut_coords(const ht_combiner_program *p);

/* Sub-passes of a pass that writes colour: the key light's and one per
   add_lights entry. */
int ht_combiner_sub_passes(const ht_combiner_program *p);
/* The light sub-pass `sub` draws (-1 outside 0..sub_passes-1). */
int ht_combiner_sub_pass_light(const ht_combiner_program *p, int sub);

/* The names of the dot products along the LUT's axes ("N.L", "t1.H",
   "t2.H"; "T.L", "T.H"); returns how many (3 or 2). */
int ht_combiner_dot_names(ht_model_kind model, const char *names[3]);

/* Checks the program the way ht_combiner_parse does; err names the field. */
ht_result ht_combiner_validate(const ht_combiner_program *p, char *err, size_t err_size);

/* The program as JSON text (malloc'd, free()); fails with a validation error
   on an invalid program. Same program, byte-identical text. */
ht_result ht_combiner_write(const ht_combiner_program *p, char **text, char *err, size_t err_size);

/* Parses fixed.json through runtime/io/json_check.h. Errors are one line
   "FILE: FIELD: what is wrong", FIELD a JSON path ("stages[1].source_rgb[0]"),
   or "FILE: line N: malformed JSON at column C near ..."; a NULL text or
   out is HT_ERR_INVALID_ARGUMENT. */
ht_result ht_combiner_parse(const char *json_text, const char *file_name,
                            ht_combiner_program *out, char *err, size_t err_size);

#endif

/* fixed4_program.h — the `fixed4` tier: GL 1.3 texture combiners on four
   units, every dot product made by the device (Heidrich-Seidel texture
   matrices over static per-vertex vectors, GL's own per-vertex lighting
   for the diffuse term), so a frame with directional lights and an
   infinite viewer does no work proportional to the vertex count on the CPU.
   The program ("fixed4.json", format "hairtier-fixed4/1") holds the
   material constants; the stage layout is fixed and lives in code
   (fixed4.c), since it is the one layout that fits the model into four
   ARB_texture_env_combine stages (why: docs/DESIGN.md "fixed4").

   Scheuermann, two directional lights l = 0, 1, per vertex:
       static arrays   t1 = normalize(T + shift1 N), t2 = normalize(T + shift2 N)
                       (texture coordinate sets 0 and 1), colour (1, 1, 1, ao)
       unit 0  LUT over t1, texture matrix rows H0, H1:
               texel(d0, d1) = primary.color (lc0 S1(d0) + lc1 S1(d1)) / scale
               rgb = ADD(TEXTURE, PRIMARY)         alpha = PRIMARY (ao)
       unit 1  LUT over t2, rows H0, H1, secondary.color (already x the
               sparkle mean) and S2:   rgb = ADD(TEXTURE, PREVIOUS)
       unit 2  albedo (uv)           rgb = MODULATE(TEXTURE, PREVIOUS)
       unit 3  albedo again (uv)     rgb = MODULATE(PREVIOUS, PREVIOUS.alpha) x scale
                                     alpha = TEXTURE (coverage)
       primary = GL lighting: per light, ambient wrap lc kd / scale and
                 diffuse (1 - wrap) lc kd / scale along L, material alpha ao
   Kajiya-Kay: one LUT per light over T with rows L_l and H_l, texel =
   lc_l (diffuse.color sin(T.L) + primary.color S(T.H)) / scale; no GL
   lighting (primary = (0, 0, 0, ao)).

   The LUTs depend on the frame's light colours and the scale, so the
   runtime bakes them (ht_fixed4_bake_lut: O(LUT texels), only when a light
   colour changes); texel x of an axis of n holds d = 2x/(n-1) - 1
   (combiner.h's "endpoints" mapping). The scale is the smallest of 1, 2, 4
   at or above the largest value a channel can reach.

   Usage (fixed4.c does this):
       ht_fixed4_program p;
       ht_fixed4_parse(text, "fixed4.json", &p, err, sizeof err);
       ht_fixed4_vertex_arrays(&p, vertices, n, vec0, vec1, colors);     // once per mesh
       int scale = ht_fixed4_scale(&p, light_colors);                      // per frame
       ht_fixed4_bake_lut(&p, k, light_colors, scale, &image);             // when colours change
       ht_fixed4_texture_matrix(&p, k, light_dirs, view_dir, m);           // per frame */
#ifndef HT_FIXED4_PROGRAM_H
#define HT_FIXED4_PROGRAM_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include <hairtier/model.h>

#define HT_FIXED4_FORMAT "hairtier-fixed4/1"
#define HT_FIXED4_MAX_LIGHTS 2
#define HT_FIXED4_MAX_LUTS 2
#define HT_FIXED4_MAX_AXIS 256

/* Who makes the LUT coordinates. */
typedef enum ht_fixed4_viewer {
    HT_FIXED4_VIEWER_INFINITE = 0, /* "infinite": the texture matrix, V one direction per
                                      frame; no per-vertex CPU work at all */
    HT_FIXED4_VIEWER_LOCAL,        /* "local": V = eye - position per vertex, on the CPU in
                                      float (ht_fixed4_local_coords), only when the eye or a
                                      light moved */
} ht_fixed4_viewer;

typedef struct ht_fixed4_program {
    ht_shading shading;      /* secondary.color already scaled by the sparkle mean */
    int lights;              /* 1 or 2: the frame's first lights, directional */
    bool ao;                 /* primary alpha = ao, else 1 */
    ht_fixed4_viewer viewer;
    int lut_axis[3];         /* texels: Scheuermann t1.H, t2.H (one per axis of a LUT);
                                Kajiya-Kay T.L, T.H; index 2 unused */
} ht_fixed4_program;

/* LUTs the program samples: Scheuermann 2 (t1, t2), Kajiya-Kay one per light. */
int ht_fixed4_lut_count(const ht_fixed4_program *p);
/* Texture units: the LUTs, the albedo, the final stage. */
int ht_fixed4_units(const ht_fixed4_program *p);
/* LUT k's size, width x height (height 1 for Scheuermann with one light). */
void ht_fixed4_lut_size(const ht_fixed4_program *p, int k, int *width, int *height);

ht_result ht_fixed4_validate(const ht_fixed4_program *p, char *err, size_t err_size);
/* JSON text (malloc'd); same program, byte-identical text. */
ht_result ht_fixed4_write(const ht_fixed4_program *p, char **text, char *err, size_t err_size);
/* Errors "FILE: FIELD: what is wrong". */
ht_result ht_fixed4_parse(const char *json_text, const char *file_name, ht_fixed4_program *out,
                          char *err, size_t err_size);

/* The scale for these light colours (lights x 3, NULL rows count as black):
   1, 2 or 4; 4 also when the colours need more (the excess clamps). */
int ht_fixed4_scale(const ht_fixed4_program *p, const float light_colors[][3]);
/* The same over light_count rows (the vertex tier adds the lights after
   the program's into its primary colour, which the scale also divides). */
int ht_fixed4_scale_lights(const ht_fixed4_program *p, const float light_colors[][3], int light_count);

/* The slope of each light's diffuse behind the strand in GL lighting
   (fixed4.c): GL sums, per light, kd lc (wrap + (1 - wrap) max(N.L, 0)
   - back[l] max(-N.L, 0)) and clamps the sum once, where the model clamps
   each light's wrap + (1 - wrap) N.L at 0 before summing. back is
   1 - wrap (exact: the model's line) or min(wrap, 1 - wrap) (the chord
   from the model's value at N.L = -1 to its value at 0: never negative,
   so it takes nothing from another light, and at most
   wrap (1 - 2 wrap) / (1 - wrap) kd lc too bright, at the model's kink).
   The chord is the model itself when wrap is 0 or at least 1/2, and is
   taken for every light then. Otherwise one light alone takes the line,
   exact under the sum's clamp, and with two the brighter
   one (kd . lc summed over channels) is exact and the other takes the
   chord: measured on the shipped scenes it beats the chord for both
   (blond x backlit, key of colour 2 from behind: 33.3 against 31.3 dB)
   and the line for both (which lets the key's negative part darken the
   fill: 31.96 against 32.09 on blond x patches). */
void ht_fixed4_back_slopes(const ht_fixed4_program *p, const float light_colors[][3],
                           double back[HT_FIXED4_MAX_LIGHTS]);

/* Bakes LUT k for the light colours and scale into out (RGB8, allocated). */
ht_result ht_fixed4_bake_lut(const ht_fixed4_program *p, int k, const float light_colors[][3], int scale,
                             ht_image *out);

/* Unit k's GL_TEXTURE matrix, column-major, for the input (v, 1) with v the
   unit's static vector: s, t = the LUT coordinates of its two dot products.
   light_dirs: towards each light (any length); view_dir: towards the
   infinite viewer. A direction that is missing (zero, or L = -V for H)
   gives a constant row at the coordinate where the LUT holds the model's
   answer (S = 0; Kajiya-Kay sin = 0). Always finite. */
void ht_fixed4_texture_matrix(const ht_fixed4_program *p, int k, const float light_dirs[][3],
                              const float view_dir[3], float m[16]);

/* The static per-vertex arrays: vec0/vec1 (3 floats each; vec1 may be NULL
   for Kajiya-Kay, whose LUTs both read T) and colors (4 floats: rgb 1 for
   Scheuermann's lighting, 0 for Kajiya-Kay; alpha ao or 1). A vertex whose
   tangent has no direction gets colour alpha 0: black, where the model
   gives diffuse only (Scheuermann) or black (Kajiya-Kay); the matrix cannot
   tell T = 0 from a tangent perpendicular to H, which would read as the
   highlight's peak. */
void ht_fixed4_vertex_arrays(const ht_fixed4_program *p, const ht_vertex *v, size_t count, float *vec0,
                             float *vec1, float *colors);

/* Structure-of-arrays inputs of the local-viewer rule (one float array
   per component, so the loop vectorises), filled once per mesh. */
typedef struct ht_fixed4_soa {
    size_t count;
    float *px, *py, *pz;             /* positions */
    float *v[HT_FIXED4_MAX_LUTS][3]; /* each LUT's static vector (t1, t2; Kajiya-Kay: T twice) */
} ht_fixed4_soa;

ht_result ht_fixed4_soa_make(const ht_fixed4_program *p, const ht_vertex *v, size_t count, ht_fixed4_soa *out);
/* The same from vec0/vec1 already made by ht_fixed4_vertex_arrays (vec1
   NULL: vec0 for both LUTs), so a mesh's vectors are made once. */
ht_result ht_fixed4_soa_from_arrays(const ht_vertex *v, size_t count, const float *vec0, const float *vec1,
                                    ht_fixed4_soa *out);
void ht_fixed4_soa_free(ht_fixed4_soa *soa);
/* Vertices [first, first + count) of soa (within it), borrowing its
   arrays: a draw range's per-frame work. */
ht_fixed4_soa ht_fixed4_soa_range(const ht_fixed4_soa *soa, size_t first, size_t count);

/* The local-viewer rule: coords[k] (2 floats per vertex) = LUT k's texture
   coordinates with V = normalize(eye - position) per vertex, the same
   mapping and the same answers where a direction is missing as
   ht_fixed4_texture_matrix. */
void ht_fixed4_local_coords(const ht_fixed4_program *p, const ht_fixed4_soa *soa, const float light_dirs[][3],
                            const float eye[3], float *coords[HT_FIXED4_MAX_LUTS]);

#endif

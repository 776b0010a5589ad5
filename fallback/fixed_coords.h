/* fixed_coords.h — the per-vertex inputs of the fixed tier: the LUT
   texture coordinates of the model's dot products and the primary colour,
   from the mesh, the lights and the eye (Heidrich-Seidel; GL interpolates
   them per pixel). Two rules (the LUT stage's "coords", combiner.h):

   "cpu-dots": on the CPU once per frame, ht_fixed_coords_compute:

       Scheuermann: (N.L, t1.H, t2.H), t = normalize(T + shift * N)
       Kajiya-Kay:  (T.L, T.H, -)
       H = normalize(L + V), V = eye - position, L = light vector
           (directional: towards the light; point: position - vertex)
       primary = (clamp(light.color * ao / light_scale, 0, 1), 1)

   Each dot product goes through ht_combiner_lut_coord (combiner.h). Only the
   program's key light is lit (an additive sub-pass's light: the _of
   functions, and ht_fixed_soa_coords for its coordinates); the shift texture's jitter and the sparkle mask
   are not available per vertex and are dropped (the emitter lists them).
   Where the model has no direction (model.c: a vector shorter than
   sqrt(HT_MODEL_MIN_LENGTH2)) the coordinate is one where the LUT holds the
   model's answer: a highlight without t or H reads d = -1 (S = 0), a
   Kajiya-Kay diffuse without T or L reads d = 1 (sin = 0), a zero N gives
   N.L = 0 as in the model.

   Usage, every frame:
       ht_fixed_coords_compute(&program, mesh.vertices, mesh.vertex_count,
                               lights, light_count, camera.eye,
                               texcoords, colors, err, sizeof err);
       glClientActiveTexture(GL_TEXTURE0); glTexCoordPointer(3, GL_FLOAT, 0, texcoords);
       glColorPointer(4, GL_FLOAT, 0, colors);

   "texture-matrix" (Kajiya-Kay, directional key light): no per-vertex work
   for the coordinates. GL reads the unit tangents as texture coordinates
   and the 16 floats of ht_fixed_coords_texture_matrix, per frame, turn
   them into (T.L, T.H) at the LUT's texel-centre mapping, with H from the
   infinite viewer view_dir (camera target to eye, unit). The primary
   colours (ht_fixed_coords_colors) change only with the light's colour:
       glClientActiveTexture(GL_TEXTURE0);
       glTexCoordPointer(3, GL_FLOAT, sizeof(ht_vertex), &vertices[0].tangent);
       ht_fixed_coords_texture_matrix(&program, lights, light_count, view_dir, m, err, sizeof err);
       glActiveTexture(GL_TEXTURE0); glMatrixMode(GL_TEXTURE); glLoadMatrixf(m);
       glMatrixMode(GL_MODELVIEW); */
#ifndef HT_FIXED_COORDS_H
#define HT_FIXED_COORDS_H

#include <stddef.h>

#include "combiner.h"
#include <hairtier/hairtier.h>

/* Fills lut_coords[3 * count] and colors[4 * count]. With fewer lights than
   the program's light index the hair is unlit (colour 0, alpha 1). A
   non-finite vector counts as having no direction, a non-finite colour as
   0: every output is finite. Fails only on NULL arguments. */
ht_result ht_fixed_coords_compute(const ht_combiner_program *p, const ht_vertex *vertices,
                                  size_t count, const ht_light *lights, int light_count,
                                  const float eye[3], float *lut_coords, float *colors,
                                  char *err, size_t err_size);

/* Fills colors[4 * count] with the primary colours alone, as
   ht_fixed_coords_compute does. For a "texture-matrix" program a vertex
   whose tangent has no direction is black (alpha 1): the model's answer
   there, which the matrix, reading T = 0 as d = 0, cannot give. Fails only
   on NULL arguments. */
ht_result ht_fixed_coords_colors(const ht_combiner_program *p, const ht_vertex *vertices, size_t count,
                                 const ht_light *lights, int light_count, float *colors,
                                 char *err, size_t err_size);

/* The same for light `light` of lights (an additive sub-pass's, combiner.h);
   no such light: black. */
ht_result ht_fixed_coords_colors_of(const ht_combiner_program *p, int light, const ht_vertex *vertices,
                                    size_t count, const ht_light *lights, int light_count, float *colors,
                                    char *err, size_t err_size);

/* The "texture-matrix" rule's GL_TEXTURE matrix for unit 0, column-major
   (glLoadMatrixf), for the program's light and the infinite viewer
   view_dir (any length; no direction means V = 0, H = L). Rows as in
   combiner.h; without a light L = 0. Fails with HT_ERR_UNSUPPORTED when the
   program's light is a point light (L varies per vertex: use
   ht_fixed_coords_compute), HT_ERR_INVALID_ARGUMENT on NULL arguments or a
   program whose LUT stage is not "texture-matrix". m is always written
   (identity on failure) and finite. */
ht_result ht_fixed_coords_texture_matrix(const ht_combiner_program *p, const ht_light *lights,
                                         int light_count, const float view_dir[3], float m[16],
                                         char *err, size_t err_size);
/* The same for light `light` of lights (an additive sub-pass's). */
ht_result ht_fixed_coords_texture_matrix_of(const ht_combiner_program *p, int light, const ht_light *lights,
                                            int light_count, const float view_dir[3], float m[16],
                                            char *err, size_t err_size);

#endif

/* fixed_coords.h — the per-vertex inputs of the fixed tier that GL 1.x
   cannot compute: the LUT texture coordinates of the model's dot products
   and the primary colour, from the mesh, the lights and the eye, on the CPU
   once per frame (Heidrich-Seidel; GL interpolates them per pixel).

       Scheuermann: (N.L, t1.H, t2.H), t = normalize(T + shift * N)
       Kajiya-Kay:  (T.L, T.H, -)
       H = normalize(L + V), V = eye - position, L = light vector
           (directional: towards the light; point: position - vertex)
       primary = (clamp(light.color * ao, 0, 1), 1)

   Each dot product goes through ht_combiner_lut_coord (combiner.h). Only the
   program's light is lit; the shift texture's jitter and the sparkle mask
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
       glColorPointer(4, GL_FLOAT, 0, colors); */
#ifndef HT_FIXED_COORDS_H
#define HT_FIXED_COORDS_H

#include <stddef.h>

#include "combiner.h"
#include "hairtier.h"

/* Fills lut_coords[3 * count] and colors[4 * count]. With fewer lights than
   the program's light index the hair is unlit (colour 0, alpha 1). A
   non-finite vector counts as having no direction, a non-finite colour as
   0: every output is finite. Fails only on NULL arguments. */
ht_result ht_fixed_coords_compute(const ht_combiner_program *p, const ht_vertex *vertices,
                                  size_t count, const ht_light *lights, int light_count,
                                  const float eye[3], float *lut_coords, float *colors,
                                  char *err, size_t err_size);

#endif

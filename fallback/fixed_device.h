/* fixed_device.h — the fixed tier's device-only variant (hairtier.h
   ht_variant): no per-vertex CPU work while the eye or a light moves.

   The exact tier indexes its 3D LUT by (N.L, t1.H, t2.H): three dot
   products of three vectors, which one texture coordinate set (4
   components, one of them the constant the LUT mapping needs) and one
   texture matrix cannot make. The variant keeps one static vector per
   vertex, t1 = normalize(T + shift N), and makes (t1.L, t1.H) with the
   texture matrix (the Kajiya-Kay "texture-matrix" rows, infinite viewer)
   into a 2D LUT resampled once, at create, from the bundle's 3D LUT:
       t1.H  exact (for the infinite viewer)
       N.L   = sin(a1) t1.L + cos(a1) sqrt(1 - t1.L^2) cos(phi)
       t2.H  = cos(d) t1.H + sin(d) sqrt(1 - t1.H^2) cos(phi')
   with a1 = atan(shift1), d = atan(shift2) - atan(shift1) (t1, t2 and N lie
   in the strand's T-N plane) and phi, phi' the unknown angles of L and H
   around t1: each texel holds the mean over them (the least squared error
   when the ribbon's roll is uniform). What it costs is measured per
   bundle (hairgen --measure, "measured_device"). */
#ifndef HT_FIXED_DEVICE_H
#define HT_FIXED_DEVICE_H

#include <stdbool.h>
#include <stddef.h>

#include "combiner.h"
#include <hairtier/image.h>
#include <hairtier/model.h>

/* Whether p has a device-only variant: Scheuermann under "cpu-dots"
   (Kajiya-Kay under a directional light is "texture-matrix" already). */
bool ht_fixed_device_applies(const ht_combiner_program *p);

/* The variant's program: p with its LUT stage a 2D "texture-matrix" stage
   over (t1.L, t1.H) of the 3D LUT's first two axis sizes; the model reads
   as Kajiya-Kay (the rows' layout); shift and everything else kept. */
void ht_fixed_device_program(const ht_combiner_program *p, ht_combiner_program *out);

/* The variant's LUT (RGB8, allocated) from the exact program's 3D LUT
   image (width n0, height n1 * n2, slices stacked as combiner.h says). */
ht_result ht_fixed_device_lut(const ht_combiner_program *exact, const ht_image *lut3d, ht_image *out);

/* Each vertex's tangent replaced by t1 = normalize(T + shift[0] N) (zero
   when T has no direction), the variant's static vector. */
void ht_fixed_device_vectors(const ht_combiner_program *p, ht_vertex *v, size_t count);

#endif

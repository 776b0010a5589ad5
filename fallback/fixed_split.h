/* fixed_split.h — the fixed tier's 3D LUT where the device has no 3D
   textures (GL ES 1.1): two 2D textures added by two combiner stages.

   Why it is exact up to 8-bit rounding: the LUT is additive in its third
   axis (model.h: ht_model_dot_terms_d is separable, the secondary
   highlight S(c) is the only term of c), L(a,b,c) = A(a,b) + C(c), and
   trilinear filtering of such a sum is bilinear filtering of A plus
   linear filtering of C. A is the slice c = -1, where S is 0; C is one
   row of n2 texels, per slice the mean over (a,b) of L - A (texels the
   8-bit range clipped left out). An atlas of slices in one 2D texture
   cannot do this with per-vertex coordinates: where a triangle's vertices
   fall in different slices, linear interpolation of the atlas coordinate
   sweeps across the slices between them.

   The program's LUT stage k becomes three stages (two more units):
       k    C:  rgb = REPLACE(TEXTURE), alpha = REPLACE(PREVIOUS); its
                texture matrix maps the coordinates (a, b, c) to (c, 1/2)
       k+1  A:  rgb = ADD(TEXTURE, PREVIOUS), alpha = REPLACE(PREVIOUS)
       k+2  the original stage, its colour reads of TEXTURE now PREVIOUS
            (A + C), on a white texel (a unit without a texture is skipped)
   Refused (one line) when the LUT stage reads PREVIOUS's colour (the sum
   takes its place) or the stages would pass HT_COMBINER_MAX_STAGES. */
#ifndef HT_FIXED_SPLIT_H
#define HT_FIXED_SPLIT_H

#include <stddef.h>

#include "combiner.h"
#include <hairtier/image.h>

/* The index of p's stage that samples a 3D LUT, or -1. */
int ht_fixed_split_lut_stage(const ht_combiner_program *p);

/* Rewrites p in place as above (stage k = lut_stage); HT_ERR_UNSUPPORTED
   with one line in err when it cannot. */
ht_result ht_fixed_split_program(ht_combiner_program *p, int lut_stage, char *err, size_t err_size);

/* A (n0 x n1 RGB) and C (n2 x 1 RGB) from the 3D LUT image (width n0,
   height n1 * n2, slices stacked: combiner.h), and the largest texel
   error of A + C against it, in 1/255. */
ht_result ht_fixed_split_lut(const int n[3], const ht_image *lut3d, ht_image *a, ht_image *c, int *max_error);

/* The texture matrix of stage k: (s, t, r, q) -> (r, 1/2, 0, q). */
void ht_fixed_split_matrix(float m[16]);

#endif

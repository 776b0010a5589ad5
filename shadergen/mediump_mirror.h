/* mediump_mirror.h — the CPU mirror of full-es2-mediump.frag: evaluates
   the same table (mediump.h) with every step's result rounded to fp16, so
   the error of an fp16 fragment stage can be measured on hardware that runs
   mediump as fp32 (llvmpipe, NVIDIA). Rounding is ht_mp_round_half, an
   explicit round-to-nearest-even helper rather than _Float16: it builds on
   every compiler the project uses (clang 14 has no x86 _Float16), and
   test_mediump checks it against GCC's _Float16 where that exists.

   Each step computes in double from fp16 operands and rounds once; dot and
   cross products round every product and sum (a fused device rounds less);
   sqrt, inversesqrt, log2, exp2 round correctly (a device's approximations
   add a few ulp: docs/accuracy.md). */
#ifndef HT_MEDIUMP_MIRROR_H
#define HT_MEDIUMP_MIRROR_H

#include <stdbool.h>
#include <stddef.h>

#include "mediump.h"

typedef struct ht_mp_mirror ht_mp_mirror;

/* The shader's inputs as the device sees them before fp16 rounding. */
typedef struct ht_mp_inputs {
    double position[3], tangent[3], normal[3], eye[3];
    double light[HT_MAX_LIGHTS][3]; /* u_light_vector[i].xyz */
    double colour[HT_MAX_LIGHTS][3];
    double shift_texel, sparkle, base[3], ao;
} ht_mp_inputs;

/* What the rounding saw over every evaluation since the counters were 0. */
typedef struct ht_mp_stats {
    long results;    /* rounded step results, per component */
    long overflows;  /* results that rounded to +-Inf or NaN: must stay 0 */
    long subnormals; /* nonzero results below 2^-14 (zero when flushing) */
} ht_mp_stats;

/* x rounded to the nearest fp16 value, ties to even; +-Inf past 65504's
   rounding range, NaN stays NaN. */
double ht_mp_round_half(double x);

/* Resolves p's names once; NULL with err on a name no step defines. */
ht_mp_mirror *ht_mp_mirror_new(const ht_mp_program *p, char *err, size_t err_size);
void ht_mp_mirror_free(ht_mp_mirror *m);

/* shade() of the table on in: rgb before alpha, each channel an fp16
   value. flush_subnormals models a device without fp16 subnormals. */
void ht_mp_mirror_shade(const ht_mp_mirror *m, const ht_mp_inputs *in, bool flush_subnormals, double rgb[3],
                        ht_mp_stats *stats);

#endif

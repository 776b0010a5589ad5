/* mediump_measure.h — the fp16 mirror (mediump_mirror.h) against the
   oracle (ht_model_shade_d) on the same inputs, as 8-bit framebuffer
   values: one comparison, and the random sweep test_mediump pins and
   hairgen records in the manifest (docs/bundle.md "es2_mediump").

   Samples with some light within HT_MP_OPPOSITE of L = -V are counted
   apart: there |L/|L| + V/|V|| is small and the half vector's direction
   moves by fp16's ~2^-11 error of L and V over that length (in fp32 too,
   over a cone 2^13 times narrower). */
#ifndef HT_MEDIUMP_MEASURE_H
#define HT_MEDIUMP_MEASURE_H

#include <stdint.h>

#include "mediump_mirror.h"

#define HT_MP_OPPOSITE 0.0625

typedef struct ht_mp_error {
    int max_byte;   /* largest |mirror - oracle| of any channel, in 1/255 */
    long samples;
    long nonfinite; /* colours that are NaN or Inf: must stay 0 */
    ht_mp_stats stats;
    ht_mp_inputs worst; /* the inputs of max_byte */
} ht_mp_error;

typedef struct ht_mp_measurement {
    ht_mp_error regular, opposite; /* opposite: some light near L = -V */
} ht_mp_measurement;

/* One shading of in by both, into out->regular or out->opposite. */
void ht_mp_compare(const ht_mp_mirror *mm, const ht_mp_desc *d, const ht_mp_inputs *in, bool flush,
                   ht_mp_measurement *out);

/* samples random inputs from seed: T, N and directional lights 2^-4 to
   2^10 long (a shorter vector's small components fall below 2^-14 and
   flush, which no rescaling undoes; 2^20 squared would overflow a plain
   dot(v, v)), positions within 2 of the origin, the eye and point lights
   2 to 64 away (mediump positions carry 2^-11 of their size), textures and
   ao uniform in [0,1]; light colours from colours (NULL: uniform in
   [0,1]). Adds to *out; false when the mirror cannot be built. */
bool ht_mp_measure_random(const ht_mp_desc *d, long samples, uint64_t seed, bool flush,
                          const double (*colours)[3], ht_mp_measurement *out);

#endif

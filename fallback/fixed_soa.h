/* fixed_soa.h — the fixed tier's per-vertex LUT coordinates ("cpu-dots",
   fixed_coords.h gives the rule) computed fast: float, structure of arrays,
   the static part (unit T and N, the shifted tangents t1 and t2) made once
   per mesh, so a frame's loop is a few dot products per vertex that GCC's
   -O2 vectoriser takes. ht_fixed_coords_compute (double, per vertex) stays
   the reference the tests hold this against.

   Usage:
       ht_fixed_soa soa;
       ht_fixed_soa_make(&program, vertices, n, &soa);            // set_mesh
       ht_fixed_soa_coords(&program, &soa, light, eye, coords);   // when the eye or light moved
       ht_fixed_soa_free(&soa); */
#ifndef HT_FIXED_SOA_H
#define HT_FIXED_SOA_H

#include <stddef.h>

#include "combiner.h"
#include <hairtier/hairtier.h>

typedef struct ht_fixed_soa {
    size_t count;
    float *px, *py, *pz;     /* position */
    float *a[3];             /* axis 0's vector: N (Scheuermann, zero without a
                                direction) or unit T (Kajiya-Kay) */
    float *b[3], *c[3];      /* axes 1 and 2: t1 and t2 (Kajiya-Kay: T and unused);
                                zero when the strand has no direction */
} ht_fixed_soa;

ht_result ht_fixed_soa_make(const ht_combiner_program *p, const ht_vertex *v, size_t count, ht_fixed_soa *out);
void ht_fixed_soa_free(ht_fixed_soa *soa);
/* Vertices [first, first + count) of soa (within it) as a soa of their
   own, borrowing its arrays: a draw range's per-frame work. */
ht_fixed_soa ht_fixed_soa_range(const ht_fixed_soa *soa, size_t first, size_t count);

/* coords[3 * count]: the program's LUT coordinates for the light (NULL: no
   light) and the eye, the same answers as ht_fixed_coords_compute where a
   direction is missing, within float rounding elsewhere. */
void ht_fixed_soa_coords(const ht_combiner_program *p, const ht_fixed_soa *soa, const ht_light *light,
                         const float eye[3], float *coords);

#endif

/* support_lod_bound.h — whether vertices read back from lods.bin are the
   written ones within lod.h's bounds (HT_LOD_FILE_*_ERROR): what
   test_lod_file and test_measure_lod check a stored level by. */
#ifndef HT_TEST_SUPPORT_LOD_BOUND_H
#define HT_TEST_SUPPORT_LOD_BOUND_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>

/* got's n vertices against want's, the boxes those of the file's `all`
   (the vertices written): positions, uv and ao within half a step (and a
   float's rounding), normals and tangents unit and within
   HT_LOD_FILE_DIRECTION_ERROR. false with the first vertex out in why;
   either way the worst errors in why (one line). */
bool ht_test_lod_within_bound(const ht_vertex *got, const ht_vertex *want, uint32_t n, const ht_vertex *all,
                              uint32_t all_count, char *why, size_t why_size);

/* The angle between two directions, radians (atan2: exact near 0). */
double ht_test_angle(const float a[3], const float b[3]);

#endif

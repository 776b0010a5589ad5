/* mesh_internal.h — what the hair mesh builders (mesh_furball.c,
   mesh_patches.c, mesh_strands.c) share with mesh.c: storage and the sort key (their vector
   helpers are vecmath.h's). Not part of the public API. */
#ifndef HT_MESH_INTERNAL_H
#define HT_MESH_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include <hairtier/hairtier.h>
#include "vecmath.h"

/* Zeroes *m, then allocates the three arrays and sets the counts.
   HT_ERR_INVALID_ARGUMENT when a count does not fit the uint32 fields,
   HT_ERR_OUT_OF_MEMORY (with nothing left allocated) when malloc fails. */
ht_result ht_mesh_alloc(ht_mesh *m, uint64_t vertex_count, uint64_t index_count,
                        uint64_t component_count);

/* Distance from m->center to the mean position of the vertex run
   [first_vertex, first_vertex + count): the builders write each component's
   vertices contiguously, so this is the component's vertex centroid. */
float ht_mesh_centroid_distance(const ht_mesh *m, uint32_t first_vertex, uint32_t count);

/* The opaque head (mesh_head.c): a sphere of radius around center, with a
   neck under it when asked, one component. HT_ERR_OUT_OF_MEMORY leaves
   *out zeroed. */
ht_result ht_mesh_build_head(float radius, const float center[3], bool neck, ht_mesh *out);

#endif

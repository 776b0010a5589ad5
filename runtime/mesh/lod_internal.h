/* lod_internal.h — what the LOD files (lod_order.c, lod_build.c) share:
   a component as the run of vertex rows the mesh builders write. Not part
   of the public API. */
#ifndef HT_LOD_INTERNAL_H
#define HT_LOD_INTERNAL_H

#include <hairtier/lod.h>
#include "mesh_internal.h"

/* A strand's ribbon: rows r = 0 (root) .. rows - 1 (tip), row r the
   vertices first_vertex + 2 r (-w side) and + 2 r + 1 (+w side). */
typedef struct ht_lod_run {
    uint32_t first_vertex, rows;
} ht_lod_run;

/* One run per component, in component order. HT_ERR_INVALID_ARGUMENT when
   a component does not index (rows - 1) quads over 2 rows x rows vertices
   from an even offset of its first vertex, as the builders write. */
ht_result ht_lod_runs(const ht_mesh *m, ht_lod_run *runs);

/* The width rule per vertex (docs/lod.md): sides[v] = the offset of vertex
   v from its row's centre, half the row's width vector, for every vertex
   of a component laid out as ht_lod_runs takes; zero for the vertices of
   any other component (a shader then leaves them as they are). */
void ht_lod_sides(const ht_mesh *m, float (*sides)[3]);

/* The components sorted along the Z-order curve of their key points
   (lod_order.c): curve[i] = the component at curve position i. Runs of
   neighbours on it are the strata of the LOD order and the clumps of
   cards (lod_cards.c). */
ht_result ht_lod_curve_order(const ht_mesh *m, const ht_lod_run *runs, uint32_t *curve);

#endif

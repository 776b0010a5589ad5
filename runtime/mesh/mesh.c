/* mesh.c — storage of hair meshes and the static inside-to-outside sort.

   The sort key of a component is the distance from its vertex centroid (the
   mean position of the vertices it owns) to ht_mesh.center: the origin for
   the fur ball (every hair grows from it), the head centre for patches. The
   builders fill ht_component.sort_key; ht_mesh_sort_inside_out sorts by the
   stored key, so a caller building its own mesh may supply any key.

   Inside first is Scheuermann's order: with one static index buffer, hair
   near the head is drawn before the hair that covers it, which makes the
   back-to-front blending of passes 3 and 4 right from most viewpoints
   without a per-frame sort. */
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

ht_result ht_mesh_alloc(ht_mesh *m, uint64_t vertex_count, uint64_t index_count,
                        uint64_t component_count) {
    memset(m, 0, sizeof *m);
    if (vertex_count > UINT32_MAX || index_count > UINT32_MAX || component_count > UINT32_MAX)
        return HT_ERR_INVALID_ARGUMENT;
    if (SIZE_MAX / sizeof(ht_vertex) < vertex_count) return HT_ERR_OUT_OF_MEMORY;
    /* malloc(0) may return NULL: always ask for at least one element. */
    m->vertices = malloc(sizeof(ht_vertex) * (size_t)(vertex_count ? vertex_count : 1));
    m->indices = malloc(sizeof(uint32_t) * (size_t)(index_count ? index_count : 1));
    m->components = malloc(sizeof(ht_component) * (size_t)(component_count ? component_count : 1));
    if (!m->vertices || !m->indices || !m->components) {
        ht_mesh_free(m);
        return HT_ERR_OUT_OF_MEMORY;
    }
    m->vertex_count = (uint32_t)vertex_count;
    m->index_count = (uint32_t)index_count;
    m->component_count = (uint32_t)component_count;
    return HT_OK;
}

float ht_mesh_centroid_distance(const ht_mesh *m, uint32_t first_vertex, uint32_t count) {
    if (count == 0) return 0.0f;
    double sum[3] = { 0, 0, 0 };
    for (uint32_t i = 0; i < count; i++)
        for (int k = 0; k < 3; k++) sum[k] += m->vertices[first_vertex + i].position[k];
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = sum[k] / count - m->center[k];
    return (float)ht_vec3_length(d);
}

typedef struct sort_entry {
    float key;
    uint32_t index; /* position in build order: the tie breaker */
} sort_entry;

/* NaN keys (only possible in a caller-made mesh) sort last, among themselves
   in build order, so the comparison stays a total order. */
static int compare_entries(const void *pa, const void *pb) {
    const sort_entry *a = pa, *b = pb;
    int a_nan = isnan(a->key), b_nan = isnan(b->key);
    if (a_nan != b_nan) return a_nan - b_nan;
    if (!a_nan) {
        if (a->key < b->key) return -1;
        if (a->key > b->key) return 1;
    }
    return (a->index > b->index) - (a->index < b->index);
}

static int compare_runs(const void *pa, const void *pb) {
    const ht_component *a = pa, *b = pb;
    if (a->first_index != b->first_index) return a->first_index < b->first_index ? -1 : 1;
    return (a->index_count > b->index_count) - (a->index_count < b->index_count);
}

/* The components must tile the index buffer: their runs, ordered by
   first_index, start at 0 and each where the one before ends, the last
   ending at index_count (no gap, no overlap, nothing outside). runs is
   scratch space for component_count entries. */
static bool components_tile_indices(const ht_mesh *m, ht_component *runs) {
    memcpy(runs, m->components, sizeof *runs * m->component_count);
    qsort(runs, m->component_count, sizeof *runs, compare_runs);
    uint64_t cursor = 0;
    for (uint32_t c = 0; c < m->component_count; c++) {
        if (runs[c].first_index != cursor) return false;
        cursor += runs[c].index_count;
    }
    return cursor == m->index_count;
}

/* Components that do not tile the index buffer leave the mesh alone, as
   does an allocation failure (still drawable, unsorted): the function has
   no way to report either and the order is only a quality matter. */
void ht_mesh_sort_inside_out(ht_mesh *mesh) {
    if (!mesh || mesh->component_count < 2 || !mesh->components || !mesh->indices) return;

    uint32_t n = mesh->component_count;
    sort_entry *entries = malloc(sizeof *entries * n);
    ht_component *components = malloc(sizeof *components * n);
    uint32_t *indices = malloc(sizeof *indices * (mesh->index_count ? mesh->index_count : 1));
    if (!entries || !components || !indices) goto done;
    if (!components_tile_indices(mesh, components)) goto done;

    for (uint32_t c = 0; c < n; c++) entries[c] = (sort_entry){ mesh->components[c].sort_key, c };
    qsort(entries, n, sizeof *entries, compare_entries);

    uint32_t cursor = 0;
    for (uint32_t c = 0; c < n; c++) {
        ht_component src = mesh->components[entries[c].index];
        memcpy(indices + cursor, mesh->indices + src.first_index, sizeof *indices * src.index_count);
        components[c] = src;
        components[c].first_index = cursor;
        cursor += src.index_count;
    }
    /* Swap the new arrays in; the old ones are freed below. */
    ht_component *old_components = mesh->components;
    uint32_t *old_indices = mesh->indices;
    mesh->components = components;
    mesh->indices = indices;
    components = old_components;
    indices = old_indices;

done:
    free(entries);
    free(components);
    free(indices);
}

void ht_mesh_free(ht_mesh *mesh) {
    if (!mesh) return;
    free(mesh->vertices);
    free(mesh->indices);
    free(mesh->components);
    memset(mesh, 0, sizeof *mesh);
}

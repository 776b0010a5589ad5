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

/* The key as an unsigned integer in the sort's order: ascending floats
   (negative ones reversed), -0 as +0, NaN keys (only possible in a
   caller-made mesh) after everything, so the order stays total. */
static uint32_t radix_key(float key) {
    if (isnan(key)) return UINT32_MAX;
    if (key == 0.0f) key = 0.0f;
    uint32_t u;
    memcpy(&u, &key, sizeof u);
    return u & 0x80000000u ? ~u : u | 0x80000000u;
}

/* entries (in build order) into ascending radix_key order: a stable
   least-significant-byte radix sort, so equal keys keep build order, in
   linear time (a qsort of a million re-sorted segments took 5x as long;
   the C library has no radix sort). tmp: n entries of scratch. */
static void sort_entries(sort_entry *entries, sort_entry *tmp, uint32_t n) {
    for (int shift = 0; shift < 32; shift += 8) {
        uint32_t count[257] = { 0 };
        for (uint32_t i = 0; i < n; i++) count[(radix_key(entries[i].key) >> shift & 0xffu) + 1]++;
        if (count[(radix_key(entries[0].key) >> shift & 0xffu) + 1] == n) continue; /* one bucket: in order */
        for (int b = 0; b < 256; b++) count[b + 1] += count[b];
        for (uint32_t i = 0; i < n; i++) tmp[count[radix_key(entries[i].key) >> shift & 0xffu]++] = entries[i];
        memcpy(entries, tmp, sizeof *entries * n);
    }
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
    uint64_t cursor = 0;
    for (uint32_t c = 0; c < m->component_count && m->components[c].first_index == cursor; c++)
        cursor += m->components[c].index_count;
    if (cursor == m->index_count) return true; /* in index order already (a sorted mesh is) */
    memcpy(runs, m->components, sizeof *runs * m->component_count);
    qsort(runs, m->component_count, sizeof *runs, compare_runs);
    cursor = 0;
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
    sort_entry *entries = malloc(sizeof *entries * n), *scratch = malloc(sizeof *scratch * n);
    ht_component *components = malloc(sizeof *components * n);
    uint32_t *indices = malloc(sizeof *indices * (mesh->index_count ? mesh->index_count : 1));
    if (!entries || !scratch || !components || !indices) goto done;
    if (!components_tile_indices(mesh, components)) goto done;

    for (uint32_t c = 0; c < n; c++) entries[c] = (sort_entry){ mesh->components[c].sort_key, c };
    sort_entries(entries, scratch, n);

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
    free(scratch);
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

/* mesh_depth_sort.c — a mesh's segments ordered back to front from an eye,
   for the width rule and soft levels (lod.h): their strands are
   translucent, and blending translucent strands composes their coverage
   only far to near. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/lod.h>
#include "mesh_internal.h"

/* minus the distance from eye to the centroid of n indices' vertices */
static float back_to_front_key(const ht_mesh *mesh, uint32_t first, uint32_t n, const float eye[3]) {
    double sum[3] = { 0, 0, 0 };
    uint32_t used = 0;
    for (uint32_t i = 0; i < n && (uint64_t)first + i < mesh->index_count; i++) {
        const uint32_t v = mesh->indices[first + i];
        if (v >= mesh->vertex_count) continue;
        for (int k = 0; k < 3; k++) sum[k] += mesh->vertices[v].position[k];
        used++;
    }
    double d2 = 0;
    for (int k = 0; k < 3 && used; k++) {
        const double x = sum[k] / used - eye[k];
        d2 += x * x;
    }
    return (float)-sqrt(d2);
}

/* A strand's segments lie at different depths and cross other strands'
   (a dense groom's tips lie over other strands' roots), so the unit
   ordered is a segment, the builders' 6 indices between two rows; a
   component whose index count is not a multiple of 6 stays one unit. */
void ht_mesh_sort_back_to_front(ht_mesh *mesh, const float eye[3]) {
    if (!mesh || !mesh->components || !mesh->indices || !mesh->vertices || !eye) return;
    uint64_t units = 0;
    for (uint32_t c = 0; c < mesh->component_count; c++) {
        const uint32_t n = mesh->components[c].index_count;
        units += n && n % 6 == 0 ? n / 6 : 1;
    }
    /* already split (sorted before: a re-sort as the eye moves): keys in place */
    ht_component *split = units == mesh->component_count ? NULL
                          : units <= UINT32_MAX          ? malloc(sizeof *split * (size_t)(units ? units : 1))
                                                         : NULL;
    if (split) {
        uint32_t u = 0;
        for (uint32_t c = 0; c < mesh->component_count; c++) {
            const ht_component *comp = &mesh->components[c];
            const uint32_t step = comp->index_count && comp->index_count % 6 == 0 ? 6 : comp->index_count;
            uint32_t i = 0;
            do {
                split[u++] = (ht_component){ comp->first_index + i, step,
                                             back_to_front_key(mesh, comp->first_index + i, step, eye) };
                i += step;
            } while (i < comp->index_count);
        }
        free(mesh->components);
        mesh->components = split;
        mesh->component_count = u;
    } else {
        /* already segments, or out of memory for them: whole components, by their centroid */
        for (uint32_t c = 0; c < mesh->component_count; c++) {
            ht_component *comp = &mesh->components[c];
            comp->sort_key = back_to_front_key(mesh, comp->first_index, comp->index_count, eye);
        }
    }
    /* ascending keys draw first: the farthest first */
    ht_mesh_sort_inside_out(mesh);
}

static ht_result copy_mesh(const ht_mesh *mesh, ht_mesh *out) {
    if (!mesh || !mesh->vertices || !mesh->indices || !mesh->components) {
        memset(out, 0, sizeof *out);
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_result r = ht_mesh_alloc(out, mesh->vertex_count, mesh->index_count, mesh->component_count);
    if (r != HT_OK) return r;
    memcpy(out->vertices, mesh->vertices, sizeof *mesh->vertices * mesh->vertex_count);
    memcpy(out->indices, mesh->indices, sizeof *mesh->indices * mesh->index_count);
    memcpy(out->components, mesh->components, sizeof *mesh->components * mesh->component_count);
    memcpy(out->center, mesh->center, sizeof out->center);
    return HT_OK;
}

ht_result ht_mesh_widen_back_to_front(const ht_mesh *mesh, double factor, const float eye[3], ht_mesh *out) {
    if (!eye) {
        if (out) memset(out, 0, sizeof *out);
        return HT_ERR_INVALID_ARGUMENT;
    }
    /* factor 1 (the width rule per vertex): the mesh as it is, copied, not rebuilt */
    ht_result r = factor == 1.0 ? copy_mesh(mesh, out) : ht_mesh_widen(mesh, factor, out);
    if (r == HT_OK) ht_mesh_sort_back_to_front(out, eye);
    return r;
}

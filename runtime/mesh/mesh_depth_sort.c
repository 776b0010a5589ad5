/* mesh_depth_sort.c — components ordered back to front from an eye, for
   the width rule (lod.h): its strands are translucent, and blending
   translucent strands composes their coverage only far to near. */
#include <math.h>
#include <string.h>

#include <hairtier/lod.h>

void ht_mesh_sort_back_to_front(ht_mesh *mesh, const float eye[3]) {
    if (!mesh || !mesh->components || !mesh->indices || !mesh->vertices || !eye) return;
    for (uint32_t c = 0; c < mesh->component_count; c++) {
        ht_component *comp = &mesh->components[c];
        double sum[3] = { 0, 0, 0 };
        uint32_t n = 0;
        for (uint32_t i = 0; i < comp->index_count && (uint64_t)comp->first_index + i < mesh->index_count; i++) {
            const uint32_t v = mesh->indices[comp->first_index + i];
            if (v >= mesh->vertex_count) continue;
            for (int k = 0; k < 3; k++) sum[k] += mesh->vertices[v].position[k];
            n++;
        }
        double d2 = 0;
        for (int k = 0; k < 3 && n; k++) {
            const double x = sum[k] / n - eye[k];
            d2 += x * x;
        }
        /* ascending keys draw first: the farthest centroid first */
        comp->sort_key = (float)-sqrt(d2);
    }
    ht_mesh_sort_inside_out(mesh);
}

ht_result ht_mesh_widen_back_to_front(const ht_mesh *mesh, double factor, const float eye[3], ht_mesh *out) {
    if (!eye) {
        if (out) memset(out, 0, sizeof *out);
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_result r = ht_mesh_widen(mesh, factor, out);
    if (r == HT_OK) ht_mesh_sort_back_to_front(out, eye);
    return r;
}

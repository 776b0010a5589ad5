/* fuzz_lod_file.c — ht_lod_file_parse (the stored ladder, lods.bin) on
   arbitrary bytes; what it accepts is split into its levels and written
   back, which must be accepted again as the same levels, indices and
   components, its vertices within lod.h's bounds of the first reading
   (the boxes the first file's: the second's lie inside them). */
#include "fuzz_common.h"
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <hairtier/lod.h>

static float f32_at(const uint8_t *p) {
    const uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static double angle(const float a[3], const float b[3]) {
    const double c[3] = { (double)a[1] * b[2] - (double)a[2] * b[1], (double)a[2] * b[0] - (double)a[0] * b[2],
                          (double)a[0] * b[1] - (double)a[1] * b[0] };
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]);
}

#define BOXES_AT 60 /* the position box's extent at +12, the (u, v, ao) box's at +36 */

static bool within_bound(const ht_vertex *a, const ht_vertex *b, const uint8_t *file) {
    const float x[6] = { a->position[0], a->position[1], a->position[2], a->uv[0], a->uv[1], a->ao };
    const float y[6] = { b->position[0], b->position[1], b->position[2], b->uv[0], b->uv[1], b->ao };
    for (int k = 0; k < 6; k++) {
        const double extent = f32_at(file + BOXES_AT + (k < 3 ? 12 + 4 * k : 36 + 4 * (k - 3)));
        const double bound = extent * (k < 3 ? HT_LOD_FILE_POSITION_ERROR : HT_LOD_FILE_ATTRIBUTE_ERROR);
        if (fabs((double)x[k] - y[k]) > bound * 1.0001 + 2 * fabs(x[k]) * FLT_EPSILON) return false;
    }
    return angle(a->normal, b->normal) <= HT_LOD_FILE_DIRECTION_ERROR + 1e-6 &&
           angle(a->tangent, b->tangent) <= HT_LOD_FILE_DIRECTION_ERROR + 1e-6;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    ht_lod_file f, g;
    char err[512];
    if (ht_lod_file_parse(data, size, "fuzz.bin", &f, err, sizeof err) != HT_OK) return 0;
    for (int l = 0; l < f.level_count; l++) {
        ht_mesh m;
        if (ht_lod_file_level_mesh(&f, l, &m) == HT_OK) ht_mesh_free(&m);
    }
    unsigned char *out;
    size_t out_size;
    if (ht_lod_file_encode(&f, &out, &out_size) != HT_OK) abort();
    if (ht_lod_file_parse(out, out_size, "again.bin", &g, err, sizeof err) != HT_OK) abort();
    const ht_mesh *a = &f.mesh, *b = &g.mesh;
    if (g.level_count != f.level_count || memcmp(g.levels, f.levels, sizeof f.levels) != 0 ||
        b->vertex_count != a->vertex_count || b->index_count != a->index_count ||
        b->component_count != a->component_count ||
        memcmp(b->indices, a->indices, sizeof *a->indices * a->index_count) != 0 ||
        memcmp(b->components, a->components, sizeof *a->components * a->component_count) != 0)
        abort();
    for (uint32_t v = 0; v < a->vertex_count; v++)
        if (!within_bound(&a->vertices[v], &b->vertices[v], data)) abort();
    free(out);
    ht_lod_file_free(&g);
    ht_lod_file_free(&f);
    return 0;
}

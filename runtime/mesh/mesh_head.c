/* mesh_head.c — the opaque head drawn under hair (patches, strands):
   a UV sphere of HEAD_SLICES x HEAD_STACKS around a centre, normals radial,
   tangent the azimuth direction, uv = (φ / 2π, θ / π) with θ from +y and φ
   from +z, ao = 1, one component; with a neck, an open cylinder of
   NECK_RADIUS x R about the vertical axis from NECK_TOP x R (inside the
   sphere) down to NECK_BOTTOM x R, normals horizontal, in the same
   component. Triangles are counter-clockwise seen from outside. */
#include <string.h>

#include "mesh_internal.h"

#define HEAD_SLICES 48
#define HEAD_STACKS 24
#define HEAD_VERTICES ((HEAD_STACKS + 1) * (HEAD_SLICES + 1))
#define HEAD_INDICES (6 * HEAD_SLICES * (HEAD_STACKS - 1))
#define NECK_RINGS 4
#define NECK_VERTICES (NECK_RINGS * (HEAD_SLICES + 1))
#define NECK_INDICES (6 * HEAD_SLICES * (NECK_RINGS - 1))
#define NECK_RADIUS 0.42
#define NECK_TOP (-0.7)
#define NECK_BOTTOM (-2.2)

static void build_neck(float radius, const float center[3], ht_vertex *v, uint32_t first_vertex, uint32_t *idx) {
    for (int i = 0; i < NECK_RINGS; i++) {
        const double y = radius * (NECK_TOP + (NECK_BOTTOM - NECK_TOP) * i / (NECK_RINGS - 1));
        for (int j = 0; j <= HEAD_SLICES; j++) {
            const double phi = 2.0 * M_PI * j / HEAD_SLICES;
            ht_vertex *vx = &v[i * (HEAD_SLICES + 1) + j];
            const double n[3] = { sin(phi), 0.0, cos(phi) }, e[3] = { cos(phi), 0.0, -sin(phi) };
            const double pos[3] = { center[0] + NECK_RADIUS * radius * n[0], center[1] + y,
                                    center[2] + NECK_RADIUS * radius * n[2] };
            ht_vec3_store(vx->position, pos);
            ht_vec3_store(vx->normal, n);
            ht_vec3_store(vx->tangent, e);
            vx->uv[0] = (float)j / HEAD_SLICES;
            vx->uv[1] = (float)i / (NECK_RINGS - 1);
            vx->ao = 1.0f;
        }
    }
    uint32_t k = 0;
    for (uint32_t i = 0; i + 1 < NECK_RINGS; i++)
        for (uint32_t j = 0; j < HEAD_SLICES; j++) {
            const uint32_t a = first_vertex + i * (HEAD_SLICES + 1) + j, b = a + HEAD_SLICES + 1;
            const uint32_t quad[6] = { a, b, a + 1, a + 1, b, b + 1 };
            memcpy(idx + k, quad, sizeof quad);
            k += 6;
        }
}

ht_result ht_mesh_build_head(float radius, const float center[3], bool neck, ht_mesh *out) {
    ht_result r = ht_mesh_alloc(out, HEAD_VERTICES + (neck ? NECK_VERTICES : 0),
                                HEAD_INDICES + (neck ? NECK_INDICES : 0), 1);
    if (r != HT_OK) return r;
    for (int i = 0; i <= HEAD_STACKS; i++) {
        const double theta = M_PI * i / HEAD_STACKS;
        for (int j = 0; j <= HEAD_SLICES; j++) {
            const double phi = 2.0 * M_PI * j / HEAD_SLICES;
            double n[3], e[3], pos[3], c[3];
            ht_vec3_set(n, sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi));
            ht_vec3_set(e, cos(phi), 0.0, -sin(phi));
            ht_vec3_from_float(c, center);
            ht_vec3_mad(pos, c, radius, n);
            ht_vertex *vx = &out->vertices[i * (HEAD_SLICES + 1) + j];
            ht_vec3_store(vx->position, pos);
            ht_vec3_store(vx->normal, n);
            ht_vec3_store(vx->tangent, e);
            vx->uv[0] = (float)j / HEAD_SLICES;
            vx->uv[1] = (float)i / HEAD_STACKS;
            vx->ao = 1.0f;
        }
    }
    /* Quads between rows i and i + 1; at the poles one triangle of each
       quad would have zero area and is left out. */
    uint32_t k = 0, *idx = out->indices;
    for (uint32_t i = 0; i < HEAD_STACKS; i++)
        for (uint32_t j = 0; j < HEAD_SLICES; j++) {
            const uint32_t a = i * (HEAD_SLICES + 1) + j, b = a + HEAD_SLICES + 1;
            if (i != 0) { idx[k++] = a; idx[k++] = b; idx[k++] = a + 1; }
            if (i != HEAD_STACKS - 1) { idx[k++] = a + 1; idx[k++] = b; idx[k++] = b + 1; }
        }
    if (neck) build_neck(radius, center, out->vertices + HEAD_VERTICES, HEAD_VERTICES, out->indices + HEAD_INDICES);
    out->components[0] = (ht_component){ 0, out->index_count, 0.0f };
    memcpy(out->center, center, sizeof out->center);
    return HT_OK;
}

/* test_mesh.c — hair meshes: the fur ball and the patches around a head are
   what their descs say (counts, widths, frames, uv, ao, no NaN), the
   degenerate gravity cases stay finite, bad descs are refused, allocation
   failure frees everything, and the inside-out sort is a stable reordering
   of whole components that keeps every triangle. */
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairtier.h>
#include "rng.h"
#include "support_child.h"

#define UNIT_TOL 1e-4
#define PERP_TOL 1e-4

static double dot3(const float a[3], const float b[3]) {
    return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}
static double len3(const float a[3]) { return sqrt(dot3(a, a)); }
static double dist3(const float a[3], const float b[3]) {
    float d[3] = { a[0] - b[0], a[1] - b[1], a[2] - b[2] };
    return len3(d);
}

static int vertex_is_finite(const ht_vertex *v) {
    const float *f = (const float *)v;
    for (size_t i = 0; i < sizeof *v / sizeof(float); i++)
        if (!isfinite(f[i])) return 0;
    return 1;
}

/* Every property every mesh must have, whatever built it. */
static void assert_mesh_well_formed(const ht_mesh *m) {
    assert_non_null(m->vertices);
    assert_non_null(m->indices);
    assert_non_null(m->components);
    assert_int_equal(m->index_count % 3, 0);
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const ht_vertex *v = &m->vertices[i];
        assert_true(vertex_is_finite(v));
        assert_true(fabs(len3(v->normal) - 1) < UNIT_TOL);
        assert_true(fabs(len3(v->tangent) - 1) < UNIT_TOL);
        assert_true(fabs(dot3(v->normal, v->tangent)) < PERP_TOL);
        assert_true(v->uv[0] >= 0 && v->uv[0] <= 1);
        assert_true(v->uv[1] >= 0 && v->uv[1] <= 1);
        assert_true(v->ao >= 0 && v->ao <= 1);
    }
    for (uint32_t i = 0; i < m->index_count; i++) assert_true(m->indices[i] < m->vertex_count);

    /* Component runs tile the index buffer: each index in exactly one run. */
    unsigned char *seen = calloc(m->index_count ? m->index_count : 1, 1);
    assert_non_null(seen);
    for (uint32_t c = 0; c < m->component_count; c++) {
        const ht_component *cp = &m->components[c];
        assert_true(isfinite(cp->sort_key));
        assert_true(cp->index_count > 0 && cp->index_count % 3 == 0);
        assert_true((uint64_t)cp->first_index + cp->index_count <= m->index_count);
        for (uint32_t i = 0; i < cp->index_count; i++) {
            assert_int_equal(seen[cp->first_index + i], 0);
            seen[cp->first_index + i] = 1;
        }
    }
    for (uint32_t i = 0; i < m->index_count; i++) assert_int_equal(seen[i], 1);
    free(seen);
}

static void assert_ao_varies(const ht_mesh *m) {
    float lo = m->vertices[0].ao, hi = lo;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        lo = fminf(lo, m->vertices[i].ao);
        hi = fmaxf(hi, m->vertices[i].ao);
    }
    assert_true(hi - lo > 0.1f);
}

/* The builders lay out each component as rows of two vertices (one per
   side of the ribbon), root row first: pairs (2k, 2k+1). Checks, along every
   component, that the tangent points to the next row, v rises root to tip
   and the ribbon is `width(v)` wide when width is given. */
static void assert_ribbons_run_root_to_tip(const ht_mesh *m, uint32_t rows) {
    for (uint32_t c = 0; c < m->component_count; c++) {
        const ht_vertex *v = &m->vertices[c * rows * 2];
        assert_true(v[0].uv[1] == 0.0f && v[2 * rows - 1].uv[1] == 1.0f);
        for (uint32_t r = 0; r + 1 < rows; r++) {
            float mid[3], next[3], step[3];
            for (int k = 0; k < 3; k++) {
                mid[k] = 0.5f * (v[2 * r].position[k] + v[2 * r + 1].position[k]);
                next[k] = 0.5f * (v[2 * r + 2].position[k] + v[2 * r + 3].position[k]);
                step[k] = next[k] - mid[k];
            }
            assert_true(dot3(v[2 * r].tangent, step) > 0);
            assert_true(dot3(v[2 * r + 2].tangent, step) > 0);
            assert_true(v[2 * r + 2].uv[1] > v[2 * r].uv[1]);
        }
    }
}

/* Independent of the library: the distance from the mesh centre to the mean
   of the distinct vertices a component's triangles use. */
static double component_centroid_distance(const ht_mesh *m, const ht_component *cp) {
    unsigned char *used = calloc(m->vertex_count, 1);
    assert_non_null(used);
    double sum[3] = { 0, 0, 0 };
    uint32_t count = 0;
    for (uint32_t i = 0; i < cp->index_count; i++) {
        uint32_t vi = m->indices[cp->first_index + i];
        if (used[vi]) continue;
        used[vi] = 1;
        count++;
        for (int k = 0; k < 3; k++) sum[k] += m->vertices[vi].position[k];
    }
    free(used);
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = sum[k] / count - m->center[k];
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

typedef struct tri { uint32_t v[3]; } tri;

static int compare_tris(const void *pa, const void *pb) {
    const tri *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
    return 0;
}

/* Triangles as a sorted list: equal lists mean the same multiset, windings
   included. */
static tri *sorted_triangles(const ht_mesh *m) {
    uint32_t n = m->index_count / 3;
    tri *t = malloc(sizeof *t * (n ? n : 1));
    assert_non_null(t);
    for (uint32_t i = 0; i < n; i++) memcpy(t[i].v, m->indices + 3 * i, sizeof t[i].v);
    qsort(t, n, sizeof *t, compare_tris);
    return t;
}

static void assert_sort_is_a_stable_reordering(ht_mesh *m) {
    tri *before = sorted_triangles(m);
    uint32_t n = m->component_count;
    ht_component *old = malloc(sizeof *old * n);
    uint32_t *old_indices = malloc(sizeof *old_indices * m->index_count);
    assert_non_null(old);
    assert_non_null(old_indices);
    memcpy(old, m->components, sizeof *old * n);
    memcpy(old_indices, m->indices, sizeof *old_indices * m->index_count);

    ht_mesh_sort_inside_out(m);
    assert_mesh_well_formed(m);

    /* Reference: a stable insertion order of build positions by key. */
    uint32_t *order = malloc(sizeof *order * n);
    assert_non_null(order);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = i;
        while (j > 0 && old[order[j - 1]].sort_key > old[i].sort_key) {
            order[j] = order[j - 1];
            j--;
        }
        order[j] = i;
    }
    uint32_t cursor = 0;
    for (uint32_t c = 0; c < n; c++) {
        const ht_component *now = &m->components[c], *was = &old[order[c]];
        if (c > 0) assert_true(m->components[c - 1].sort_key <= now->sort_key);
        assert_true(now->sort_key == was->sort_key);
        assert_int_equal(now->first_index, cursor);
        assert_int_equal(now->index_count, was->index_count);
        assert_memory_equal(m->indices + now->first_index, old_indices + was->first_index,
                            sizeof(uint32_t) * was->index_count);
        cursor += now->index_count;
    }

    tri *after = sorted_triangles(m);
    assert_memory_equal(before, after, sizeof(tri) * (m->index_count / 3));
    free(before);
    free(after);
    free(order);
    free(old);
    free(old_indices);
}

/* ---- fur ball ---- */

static void test_furball_counts_follow_desc(void **state) {
    (void)state;
    ht_mesh m;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 37, .joints = 5 }, &m), HT_OK);
    assert_int_equal(m.component_count, 37);
    assert_int_equal(m.vertex_count, 37 * 5 * 2);
    assert_int_equal(m.index_count, 37 * 4 * 6);
    assert_mesh_well_formed(&m);
    ht_mesh_free(&m);

    /* Zero means the documented defaults: 2000 hairs of 16 joints. */
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ 0 }, &m), HT_OK);
    assert_int_equal(m.component_count, 2000);
    assert_int_equal(m.vertex_count, 2000 * 16 * 2);
    assert_int_equal(m.index_count, 2000 * 15 * 6);
    ht_mesh_free(&m);

    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 1, .joints = 2 }, &m), HT_OK);
    assert_int_equal(m.index_count, 6);
    assert_mesh_well_formed(&m);
    ht_mesh_free(&m);
}

static void test_furball_frames_are_unit_perpendicular_and_finite(void **state) {
    (void)state;
    const ht_furball_desc descs[] = {
        { .hairs = 300, .seed = 1 },
        { .hairs = 300, .gravity = { 0, -0.3f, 0 }, .seed = 2 },
        { .hairs = 300, .gravity = { 0, -0.3f, 0 }, .inertia = { 0.2f, 0, 0.4f }, .seed = 3 },
        /* inertia along the widening axis of many hairs: tangents swing
           towards it */
        { .hairs = 300, .joints = 40, .gravity = { 0, -0.05f, 0 }, .inertia = { 5, 0, 0 }, .seed = 4 },
        { .hairs = 300, .gravity = { 0, -1000, 0 }, .inertia = { 1000, 0, -1000 }, .seed = 5 },
    };
    for (size_t i = 0; i < sizeof descs / sizeof descs[0]; i++) {
        ht_mesh m;
        assert_int_equal(ht_mesh_build_furball(&descs[i], &m), HT_OK);
        assert_mesh_well_formed(&m);
        assert_ao_varies(&m);
        assert_ribbons_run_root_to_tip(&m, (uint32_t)(descs[i].joints ? descs[i].joints : 16));
        ht_mesh_free(&m);
    }
}

static void test_furball_hairs_grow_from_origin_with_segment_length(void **state) {
    (void)state;
    ht_mesh m;
    const float length = 0.05f;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 50, .joints = 6, .length = length,
                                                                .gravity = { 0, -0.2f, 0 } }, &m),
                     HT_OK);
    assert_true(m.center[0] == 0 && m.center[1] == 0 && m.center[2] == 0);
    for (uint32_t h = 0; h < m.component_count; h++) {
        const ht_vertex *v = &m.vertices[h * 12];
        for (int k = 0; k < 3; k++) assert_true(fabsf(v[0].position[k] + v[1].position[k]) < 1e-6f);
        for (int j = 0; j + 1 < 6; j++) {
            float a[3], b[3];
            for (int k = 0; k < 3; k++) {
                a[k] = 0.5f * (v[2 * j].position[k] + v[2 * j + 1].position[k]);
                b[k] = 0.5f * (v[2 * j + 2].position[k] + v[2 * j + 3].position[k]);
            }
            assert_true(fabs(dist3(a, b) - length) < 1e-5);
        }
    }
    ht_mesh_free(&m);
}

static void test_furball_ribbon_tapers_from_width_to_a_quarter(void **state) {
    (void)state;
    ht_mesh m;
    const float width = 0.02f;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 20, .joints = 9, .width = width,
                                                                .gravity = { 0.1f, -0.2f, 0 } }, &m),
                     HT_OK);
    for (uint32_t h = 0; h < m.component_count; h++) {
        const ht_vertex *v = &m.vertices[h * 18];
        assert_true(fabs(dist3(v[0].position, v[1].position) - width) < 1e-6);
        assert_true(fabs(dist3(v[16].position, v[17].position) - width / 4) < 1e-6);
        for (int j = 0; j + 1 < 9; j++)
            assert_true(dist3(v[2 * j + 2].position, v[2 * j + 3].position) <
                        dist3(v[2 * j].position, v[2 * j + 1].position));
    }
    ht_mesh_free(&m);
}

static void test_furball_hairs_have_own_streak_column_and_brighten_to_tip(void **state) {
    (void)state;
    ht_mesh m;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 200, .joints = 8 }, &m), HT_OK);
    int distinct = 0;
    for (uint32_t h = 0; h < m.component_count; h++) {
        const ht_vertex *v = &m.vertices[h * 16];
        for (int i = 1; i < 16; i++) assert_true(v[i].uv[0] == v[0].uv[0]);
        assert_true(v[0].uv[0] < 1.0f);
        if (h > 0 && v[0].uv[0] != m.vertices[(h - 1) * 16].uv[0]) distinct++;
        /* Without gravity the hair is straight: ao rises joint by joint. */
        for (int j = 0; j + 1 < 8; j++) assert_true(v[2 * j + 2].ao > v[2 * j].ao);
    }
    assert_true(distinct > 190);
    ht_mesh_free(&m);
}

/* The hair's first direction does not depend on gravity (the generator
   draws the same numbers), so reading it from a gravity-free build lets the
   test aim gravity exactly along, against and half against it. */
static void test_furball_gravity_zero_or_parallel_stays_finite(void **state) {
    (void)state;
    ht_mesh m;
    const ht_furball_desc base = { .hairs = 1, .joints = 8, .length = 0.1f, .seed = 99 };
    assert_int_equal(ht_mesh_build_furball(&base, &m), HT_OK);
    assert_mesh_well_formed(&m);
    float d0[3];
    for (int k = 0; k < 3; k++)
        d0[k] = (m.vertices[2].position[k] + m.vertices[3].position[k]) * 0.5f / base.length;
    ht_mesh_free(&m);
    assert_true(fabs(len3(d0) - 1) < 1e-5);

    const float scales[] = { 0.5f, 3.0f, -0.5f, -1.0f, -2.0f };
    for (size_t i = 0; i < sizeof scales / sizeof scales[0]; i++) {
        ht_furball_desc d = base;
        for (int k = 0; k < 3; k++) d.gravity[k] = scales[i] * d0[k];
        assert_int_equal(ht_mesh_build_furball(&d, &m), HT_OK);
        assert_mesh_well_formed(&m);
        /* The ribbon still has its full width at the root. */
        assert_true(fabs(dist3(m.vertices[0].position, m.vertices[1].position) - 0.01) < 1e-6);
        ht_mesh_free(&m);
    }
}

static void test_furball_same_seed_same_bytes_other_seed_differs(void **state) {
    (void)state;
    ht_mesh a, b, c;
    ht_furball_desc d = { .hairs = 500, .gravity = { 0, -0.1f, 0 }, .inertia = { 0.05f, 0, 0 }, .seed = 7 };
    assert_int_equal(ht_mesh_build_furball(&d, &a), HT_OK);
    assert_int_equal(ht_mesh_build_furball(&d, &b), HT_OK);
    d.seed = 8;
    assert_int_equal(ht_mesh_build_furball(&d, &c), HT_OK);
    assert_int_equal(a.vertex_count, b.vertex_count);
    assert_memory_equal(a.vertices, b.vertices, sizeof(ht_vertex) * a.vertex_count);
    assert_memory_equal(a.indices, b.indices, sizeof(uint32_t) * a.index_count);
    assert_memory_equal(a.components, b.components, sizeof(ht_component) * a.component_count);
    assert_int_equal(a.vertex_count, c.vertex_count);
    assert_memory_not_equal(a.vertices, c.vertices, sizeof(ht_vertex) * a.vertex_count);
    ht_mesh_free(&a);
    ht_mesh_free(&b);
    ht_mesh_free(&c);
}

/* ---- patches ---- */

static void test_patches_counts_follow_desc(void **state) {
    (void)state;
    ht_mesh m;
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = 2, .strips = 9, .segments = 4 },
                                           &m, NULL),
                     HT_OK);
    assert_int_equal(m.component_count, 2 * 9);
    assert_int_equal(m.vertex_count, 2 * 9 * 5 * 2);
    assert_int_equal(m.index_count, 2 * 9 * 4 * 6);
    assert_mesh_well_formed(&m);
    ht_mesh_free(&m);

    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ 0 }, &m, NULL), HT_OK);
    assert_int_equal(m.component_count, 3 * 64);
    assert_int_equal(m.vertex_count, 3 * 64 * 13 * 2);
    assert_int_equal(m.index_count, 3 * 64 * 12 * 6);
    ht_mesh_free(&m);
}

static void test_patches_frames_point_away_from_head(void **state) {
    (void)state;
    const ht_patches_desc descs[] = {
        { .seed = 1 },
        { .head_radius = 0.25f, .layers = 1, .strips = 1, .segments = 1, .seed = 2 },
        { .head_radius = 3, .layers = 5, .strips = 7, .segments = 30, .seed = 3 },
        { .layers = 1, .strips = 2000, .segments = 2, .seed = 4 },
    };
    for (size_t i = 0; i < sizeof descs / sizeof descs[0]; i++) {
        ht_mesh m;
        assert_int_equal(ht_mesh_build_patches(&descs[i], &m, NULL), HT_OK);
        assert_mesh_well_formed(&m);
        assert_ao_varies(&m);
        const uint32_t rows = (uint32_t)(descs[i].segments ? descs[i].segments : 12) + 1;
        assert_ribbons_run_root_to_tip(&m, rows);
        const double radius = descs[i].head_radius ? descs[i].head_radius : 1.0;
        for (uint32_t v = 0; v < m.vertex_count; v++) {
            const ht_vertex *vx = &m.vertices[v];
            assert_true(dot3(vx->normal, vx->position) > 0);
            assert_true(len3(vx->position) > radius); /* outside the head */
            assert_true(vx->uv[0] == (float)(v & 1)); /* u: 0 on one side, 1 on the other */
        }
        ht_mesh_free(&m);
    }
}

static void test_patches_inner_layers_and_roots_are_darker(void **state) {
    (void)state;
    ht_mesh m;
    const int layers = 4, strips = 32, segments = 10, rows = segments + 1;
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = layers, .strips = strips,
                                                                .segments = segments }, &m, NULL),
                     HT_OK);
    double layer_ao[4] = { 0 }, root_ao = 0, tip_ao = 0;
    for (int l = 0; l < layers; l++)
        for (int s = 0; s < strips; s++) {
            const ht_vertex *v = &m.vertices[(uint32_t)(l * strips + s) * rows * 2];
            for (int i = 0; i < rows * 2; i++) layer_ao[l] += v[i].ao;
            root_ao += v[0].ao;
            tip_ao += v[rows * 2 - 1].ao;
        }
    for (int l = 0; l + 1 < layers; l++) assert_true(layer_ao[l] < layer_ao[l + 1]);
    assert_true(root_ao < tip_ao);
    ht_mesh_free(&m);
}

static void test_patches_neighbouring_strips_overlap(void **state) {
    (void)state;
    ht_mesh m;
    const int strips = 24, segments = 8, rows = segments + 1;
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = 1, .strips = strips,
                                                                .segments = segments }, &m, NULL),
                     HT_OK);
    const int row = rows / 2;
    for (int s = 0; s < strips; s++) {
        const ht_vertex *a = &m.vertices[(uint32_t)(s * rows + row) * 2];
        float ca[3], nearest = INFINITY, nearest_width = 0;
        for (int k = 0; k < 3; k++) ca[k] = 0.5f * (a[0].position[k] + a[1].position[k]);
        for (int o = 0; o < strips; o++) {
            if (o == s) continue;
            const ht_vertex *b = &m.vertices[(uint32_t)(o * rows + row) * 2];
            float cb[3];
            for (int k = 0; k < 3; k++) cb[k] = 0.5f * (b[0].position[k] + b[1].position[k]);
            if (dist3(ca, cb) < nearest) {
                nearest = (float)dist3(ca, cb);
                nearest_width = (float)dist3(b[0].position, b[1].position);
            }
        }
        const double half_widths = 0.5 * (dist3(a[0].position, a[1].position) + nearest_width);
        assert_true(nearest < half_widths);
    }
    ht_mesh_free(&m);
}

static void test_patches_fill_head_sphere(void **state) {
    (void)state;
    ht_mesh m, head;
    const float radius = 0.7f;
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .head_radius = radius }, &m, &head), HT_OK);
    assert_true(head.vertex_count > 100);
    assert_int_equal(head.component_count, 1);
    assert_int_equal(head.components[0].first_index, 0);
    assert_int_equal(head.components[0].index_count, head.index_count);
    assert_mesh_well_formed(&head);
    /* The sphere, and under it the neck: a vertical cylinder of 0.42 R
       from inside the sphere (y = -0.7 R) down to y = -2.2 R. */
    uint32_t neck = 0;
    for (uint32_t i = 0; i < head.vertex_count; i++) {
        const ht_vertex *v = &head.vertices[i];
        const float horizontal[3] = { v->position[0], 0, v->position[2] };
        if (fabs(len3(horizontal) - 0.42 * radius) < 1e-5 && v->position[1] <= -0.7 * radius + 1e-5) {
            neck++;
            assert_true(v->position[1] >= -2.2 * radius - 1e-5);
            assert_true(dot3(v->normal, horizontal) > 0.42 * radius * 0.9999 && v->normal[1] == 0);
        } else {
            assert_true(fabs(len3(v->position) - radius) < 1e-5);
            assert_true(dot3(v->normal, v->position) > radius * 0.9999);
        }
        assert_true(v->ao == 1.0f);
    }
    assert_true(neck > 0);
    /* Outward winding (from the axis, for the neck) and no zero-area triangle. */
    for (uint32_t t = 0; t < head.index_count; t += 3) {
        const float *a = head.vertices[head.indices[t]].position;
        const float *b = head.vertices[head.indices[t + 1]].position;
        const float *c = head.vertices[head.indices[t + 2]].position;
        float e1[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, e2[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
        float n[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0] };
        const bool on_neck = a[1] < -radius + 1e-4f && b[1] < -radius + 1e-4f && c[1] < -radius + 1e-4f;
        const float out[3] = { a[0], on_neck ? 0 : a[1], a[2] };
        assert_true(len3(n) > 1e-8);
        assert_true(dot3(n, out) > 0);
    }
    ht_mesh_free(&m);
    ht_mesh_free(&head);
}

static void test_patches_same_seed_same_bytes_other_seed_differs(void **state) {
    (void)state;
    ht_mesh a, b, c;
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .seed = 5 }, &a, NULL), HT_OK);
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .seed = 5 }, &b, NULL), HT_OK);
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .seed = 6 }, &c, NULL), HT_OK);
    assert_memory_equal(a.vertices, b.vertices, sizeof(ht_vertex) * a.vertex_count);
    assert_memory_equal(a.indices, b.indices, sizeof(uint32_t) * a.index_count);
    assert_memory_equal(a.components, b.components, sizeof(ht_component) * a.component_count);
    assert_memory_not_equal(a.vertices, c.vertices, sizeof(ht_vertex) * a.vertex_count);
    ht_mesh_free(&a);
    ht_mesh_free(&b);
    ht_mesh_free(&c);
}

/* The shape of a head of hair. Row centres are the midpoints of a row's two
   vertices; a strip's root azimuth is measured from its root centre (the
   face is +z, the back -z). */
static void row_centre(const ht_mesh *m, uint32_t strip, uint32_t rows, uint32_t row, double c[3]) {
    const ht_vertex *v = &m->vertices[(strip * rows + row) * 2];
    for (int k = 0; k < 3; k++) c[k] = 0.5 * ((double)v[0].position[k] + v[1].position[k]);
}
static double length3d(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
static double horizontal3d(const double a[3]) { return hypot(a[0], a[2]); }

static const ht_patches_desc shape_descs[] = {
    { 0 },
    { .layers = 3, .strips = 48, .segments = 12, .seed = 5 }, /* scenes/patches.json */
    { .head_radius = 3, .layers = 5, .strips = 7, .segments = 30, .seed = 3 },
    { .head_radius = 0.25f, .layers = 1, .strips = 1, .segments = 1, .seed = 2 },
    { .layers = 2, .strips = 2000, .segments = 2, .seed = 4 },
};
#define SHAPE_DESCS (sizeof shape_descs / sizeof shape_descs[0])

static void resolved(const ht_patches_desc *in, double *radius, int *layers, int *strips, uint32_t *rows) {
    *radius = in->head_radius ? in->head_radius : 1.0;
    *layers = in->layers ? in->layers : 3;
    *strips = in->strips ? in->strips : 64;
    *rows = (uint32_t)(in->segments ? in->segments : 12) + 1;
}

static void test_patches_roots_sit_on_the_upper_scalp_in_layer_shells(void **state) {
    (void)state;
    for (size_t i = 0; i < SHAPE_DESCS; i++) {
        double R;
        int layers, strips;
        uint32_t rows;
        resolved(&shape_descs[i], &R, &layers, &strips, &rows);
        ht_mesh m;
        assert_int_equal(ht_mesh_build_patches(&shape_descs[i], &m, NULL), HT_OK);
        double previous_outermost = R;
        for (int l = 0; l < layers; l++) {
            double innermost = INFINITY, outermost = 0;
            for (int s = 0; s < strips; s++) {
                double c[3];
                row_centre(&m, (uint32_t)(l * strips + s), rows, 0, c);
                const double r = length3d(c);
                assert_true(c[1] > 0.5 * r);          /* the top of the head */
                assert_true(r > R && r < 1.2 * R);     /* on the scalp */
                innermost = fmin(innermost, r);
                outermost = fmax(outermost, r);
            }
            assert_true(innermost > previous_outermost); /* each layer a shell outside the last */
            previous_outermost = outermost;
        }
        ht_mesh_free(&m);
    }
}

/* A strip whose tip is below the equator lies on the scalp above it and
   hangs below it: roughly straight down, outside the head's vertical
   cylinder, ending well below its root and fanned out past its scalp
   shell. With narrow ribbons (24 strips or more) most strips are such
   strips; wide ones widen the fringe that keeps them off the face. */
static void test_patches_long_strips_follow_the_scalp_then_hang_down(void **state) {
    (void)state;
    for (size_t i = 0; i < SHAPE_DESCS; i++) {
        double R;
        int layers, strips;
        uint32_t rows;
        resolved(&shape_descs[i], &R, &layers, &strips, &rows);
        ht_mesh m;
        assert_int_equal(ht_mesh_build_patches(&shape_descs[i], &m, NULL), HT_OK);
        uint32_t hanging = 0;
        for (uint32_t s = 0; s < m.component_count; s++) {
            double root[3], tip[3];
            row_centre(&m, s, rows, 0, root);
            row_centre(&m, s, rows, rows - 1, tip);
            if (tip[1] >= 0) continue;
            hanging++;
            assert_true(tip[1] < root[1] - R && tip[1] < -0.5 * R);
            double scalp_shell = 0;
            for (uint32_t r = 0; r < rows; r++) {
                double c[3];
                row_centre(&m, s, rows, r, c);
                if (c[1] > 0) {
                    assert_true(length3d(c) > R && length3d(c) < 1.2 * R); /* hugs the scalp */
                    scalp_shell = fmax(scalp_shell, length3d(c));
                    continue;
                }
                assert_true(horizontal3d(c) > R); /* beside the head, not under it */
                if (r == 0) continue;
                double above[3], step[3];
                row_centre(&m, s, rows, r - 1, above);
                for (int k = 0; k < 3; k++) step[k] = c[k] - above[k];
                if (above[1] <= 0) assert_true(-step[1] > 0.75 * length3d(step)); /* falls along -y */
            }
            assert_true(horizontal3d(tip) > scalp_shell); /* the tip fans out */
            assert_true(horizontal3d(tip) < 1.5 * R);     /* but hangs, not sticks out */
        }
        if (strips >= 24) assert_true(hanging > m.component_count / 2);
        else assert_true(hanging < m.component_count); /* the face side always has a fringe */
        ht_mesh_free(&m);
    }
}

static void test_patches_back_hair_falls_behind_side_hair_beside_front_hair_stops_above(void **state) {
    (void)state;
    for (size_t i = 0; i < SHAPE_DESCS; i++) {
        double R;
        int layers, strips;
        uint32_t rows;
        resolved(&shape_descs[i], &R, &layers, &strips, &rows);
        ht_mesh m;
        assert_int_equal(ht_mesh_build_patches(&shape_descs[i], &m, NULL), HT_OK);
        int back = 0, side = 0, front = 0;
        for (uint32_t s = 0; s < m.component_count; s++) {
            double root[3], tip[3];
            row_centre(&m, s, rows, 0, root);
            row_centre(&m, s, rows, rows - 1, tip);
            const double phi = atan2(root[0], root[2]);
            if (fabs(phi) > 2.5) {
                back++;
                assert_true(tip[2] < -0.7 * R && tip[1] < -0.5 * R);
            } else if (fabs(fabs(phi) - M_PI / 2) < 0.3 && strips >= 24) { /* see above */
                side++;
                assert_true(tip[0] * phi > 0 && fabs(tip[0]) > 0.9 * R && tip[1] < -0.5 * R);
            } else if (fabs(phi) < 0.5) {
                front++;
                assert_true(tip[2] > 0.5 * R && tip[1] > 0.3 * R); /* a fringe over the forehead */
            }
        }
        if (strips >= 24) assert_true(back > 0 && side > 0 && front > 0);
        ht_mesh_free(&m);
    }
}

/* Beside the face the long strips frame it: they sweep back (their tips
   are farther round from the face than their roots) and hang shorter than
   the strips at the sides, so the hair's edge runs diagonally back from
   the hairline instead of straight down one meridian. */
static void test_patches_strips_beside_the_face_sweep_back_and_hang_shorter(void **state) {
    (void)state;
    const ht_patches_desc d = { .layers = 3, .strips = 48, .segments = 12, .seed = 5 };
    ht_mesh m;
    assert_int_equal(ht_mesh_build_patches(&d, &m, NULL), HT_OK);
    int beside = 0;
    double beside_tip = 0, side_tip = 0;
    int side = 0;
    for (uint32_t s = 0; s < m.component_count; s++) {
        double root[3], tip[3];
        row_centre(&m, s, 13, 0, root);
        row_centre(&m, s, 13, 12, tip);
        if (tip[1] >= 0) continue; /* a fringe */
        const double phi = fabs(atan2(root[0], root[2])), tip_phi = fabs(atan2(tip[0], tip[2]));
        if (phi < 1.1) {
            beside++;
            assert_true(tip_phi > phi + 0.2);
            beside_tip += tip[1];
        } else if (fabs(phi - M_PI / 2) < 0.2) {
            side++;
            side_tip += tip[1];
        }
    }
    assert_true(beside > 0 && side > 0);
    assert_true(beside_tip / beside > side_tip / side + 0.15); /* tips higher: shorter hair */
    ht_mesh_free(&m);
}

/* Points spread over a triangle: its corners, edge midpoints and inner
   points, so a triangle crossing a region is seen even when no vertex is in it. */
#define TRIANGLE_SAMPLES 8
static void triangle_point(const ht_mesh *m, uint32_t t, int i, int j, double p[3]) {
    const float *a = m->vertices[m->indices[t]].position, *b = m->vertices[m->indices[t + 1]].position,
                *c = m->vertices[m->indices[t + 2]].position;
    const double u = (double)i / TRIANGLE_SAMPLES, v = (double)j / TRIANGLE_SAMPLES, w = 1 - u - v;
    for (int k = 0; k < 3; k++) p[k] = u * a[k] + v * b[k] + w * c[k];
}

/* Seen from the front, a window over the face, under the hairline, has no
   hair in front of the head: nothing outside the head with z > 0,
   |x| < 0.55 R, y < 0.3 R, whatever the strip count. */
static void test_patches_leave_the_face_bare(void **state) {
    (void)state;
    for (size_t i = 0; i < SHAPE_DESCS; i++) {
        double R;
        int layers, strips;
        uint32_t rows;
        resolved(&shape_descs[i], &R, &layers, &strips, &rows);
        ht_mesh m;
        assert_int_equal(ht_mesh_build_patches(&shape_descs[i], &m, NULL), HT_OK);
        for (uint32_t t = 0; t < m.index_count; t += 3)
            for (int a = 0; a <= TRIANGLE_SAMPLES; a++)
                for (int b = 0; a + b <= TRIANGLE_SAMPLES; b++) {
                    double p[3];
                    triangle_point(&m, t, a, b, p);
                    if (length3d(p) <= R) continue; /* hidden by the head */
                    assert_false(p[2] > 0 && fabs(p[0]) < 0.55 * R && p[1] < 0.3 * R);
                }
        ht_mesh_free(&m);
    }
}

/* With a dozen segments or more the chords between rows stay outside the
   head too, not only the vertices. */
static void test_patches_triangles_clear_the_head_with_enough_segments(void **state) {
    (void)state;
    const ht_patches_desc descs[] = {
        { 0 },
        { .layers = 1, .strips = 5, .segments = 12, .seed = 9 },
        { .head_radius = 3, .layers = 5, .strips = 7, .segments = 30, .seed = 3 },
    };
    for (size_t i = 0; i < sizeof descs / sizeof descs[0]; i++) {
        const double R = descs[i].head_radius ? descs[i].head_radius : 1.0;
        ht_mesh m;
        assert_int_equal(ht_mesh_build_patches(&descs[i], &m, NULL), HT_OK);
        for (uint32_t t = 0; t < m.index_count; t += 3)
            for (int a = 0; a <= TRIANGLE_SAMPLES; a++)
                for (int b = 0; a + b <= TRIANGLE_SAMPLES; b++) {
                    double p[3];
                    triangle_point(&m, t, a, b, p);
                    assert_true(length3d(p) > R);
                }
        ht_mesh_free(&m);
    }
}

/* ---- sort ---- */

static void test_sort_keys_are_centroid_distances(void **state) {
    (void)state;
    ht_mesh m;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 64, .gravity = { 0, -0.2f, 0 } }, &m),
                     HT_OK);
    for (uint32_t c = 0; c < m.component_count; c++)
        assert_true(fabs(m.components[c].sort_key - component_centroid_distance(&m, &m.components[c])) < 1e-5);
    ht_mesh_free(&m);
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .strips = 16 }, &m, NULL), HT_OK);
    for (uint32_t c = 0; c < m.component_count; c++)
        assert_true(fabs(m.components[c].sort_key - component_centroid_distance(&m, &m.components[c])) < 1e-5);
    ht_mesh_free(&m);
}

static void test_sort_orders_components_inside_out_keeping_triangles(void **state) {
    (void)state;
    ht_mesh m;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 3000, .joints = 6,
                                                                .gravity = { 0, -0.4f, 0 } }, &m),
                     HT_OK);
    assert_sort_is_a_stable_reordering(&m);
    ht_mesh_free(&m);

    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = 4 }, &m, NULL), HT_OK);
    assert_sort_is_a_stable_reordering(&m);
    /* Layers are shells: after the sort the outermost layer comes last. */
    assert_true(m.components[0].sort_key < m.components[m.component_count - 1].sort_key);
    ht_mesh_free(&m);
}

/* A hand-made mesh of one-triangle components whose keys take three values:
   equal keys must come out in build order. */
static void test_sort_is_stable_for_ties(void **state) {
    (void)state;
    enum { N = 600 };
    ht_mesh m = { 0 };
    m.vertices = calloc(3, sizeof *m.vertices);
    assert_non_null(m.vertices);
    for (int i = 0; i < 3; i++) {
        m.vertices[i].position[i] = 1;
        m.vertices[i].normal[2] = 1;
        m.vertices[i].tangent[1] = 1;
    }
    m.indices = malloc(sizeof *m.indices * 3 * N);
    m.components = malloc(sizeof *m.components * N);
    assert_non_null(m.indices);
    assert_non_null(m.components);
    m.vertex_count = 3;
    m.index_count = 3 * N;
    m.component_count = N;
    ht_rng rng = ht_rng_seed(3);
    for (uint32_t c = 0; c < N; c++) {
        /* Each triangle differs by rotation of its three indices. */
        for (int k = 0; k < 3; k++) m.indices[3 * c + k] = (c + (uint32_t)k) % 3;
        m.components[c] = (ht_component){ 3 * c, 3, (float)(ht_rng_next(&rng) % 3) };
    }
    assert_sort_is_a_stable_reordering(&m);
    ht_mesh_free(&m);
}

/* Every kind of float key a caller may give, in a mesh of one-triangle
   components: ascending, negative ones too, -0 and +0 equal (build order
   between them), infinities at the ends, NaN after everything in build
   order; then 100 000 keys of few distinct values against a reference
   stable sort (the radix sort's bytes, ties and skipped passes). */
static void test_sort_orders_every_float_key(void **state) {
    (void)state;
    static const float keys[] = { 3, -2, NAN, -0.0f, 0.0f, -INFINITY, INFINITY, 1e-40f, -1e-40f, NAN, -3e38f, 2, -0.0f };
    static const uint32_t want[] = { 5, 10, 1, 8, 3, 4, 12, 7, 11, 0, 6, 2, 9 };
    static const float values[] = { -1e6f, -1.5f, -1e-3f, 0.0f, 1e-3f, 2.5f, 1e7f };
    enum { K = sizeof keys / sizeof keys[0], N = 100000 };
    for (int round = 0; round < 2; round++) {
        const uint32_t n = round ? N : K;
        ht_mesh m = { .vertices = calloc(3, sizeof(ht_vertex)), .vertex_count = 3, .indices = malloc(sizeof(uint32_t) * 3 * n),
                      .index_count = 3 * n, .components = malloc(sizeof(ht_component) * n), .component_count = n };
        assert_true(m.vertices && m.indices && m.components);
        ht_rng rng = ht_rng_seed(11);
        float *key = malloc(sizeof *key * n);
        assert_non_null(key);
        for (uint32_t c = 0; c < n; c++) {
            /* the sort moves indices without reading them: each names its component */
            for (int k = 0; k < 3; k++) m.indices[3 * c + k] = c;
            key[c] = round ? values[ht_rng_next(&rng) % 7] : keys[c];
            m.components[c] = (ht_component){ 3 * c, 3, key[c] };
        }
        ht_mesh_sort_inside_out(&m);
        /* the reference: per value (round 0: per wanted position) in build order */
        uint32_t at = 0;
        for (uint32_t v = 0; v < (round ? 7u : K); v++)
            for (uint32_t c = 0; c < n; c++) {
                if (round ? key[c] != values[v] : c != want[v]) continue;
                const uint32_t got = m.indices[m.components[at].first_index];
                if (got != c) fail_msg("round %d, position %u: component %u (key %g), expected %u (key %g)", round, at,
                                       got, key[got], c, key[c]);
                at++;
            }
        assert_int_equal(at, n);
        free(key);
        ht_mesh_free(&m);
    }
}

static void test_sort_leaves_meshes_it_cannot_sort_alone(void **state) {
    (void)state;
    ht_mesh empty = { 0 };
    ht_mesh_sort_inside_out(&empty);
    ht_mesh_sort_inside_out(NULL);
    assert_null(empty.indices);

    /* Components that do not tile the index buffer: untouched. */
    ht_mesh m;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 10, .joints = 3 }, &m), HT_OK);
    m.components[3].index_count += 3;
    m.components[0].sort_key = 1e9f;
    ht_mesh copy = m;
    uint32_t *indices = malloc(sizeof *indices * m.index_count);
    assert_non_null(indices);
    memcpy(indices, m.indices, sizeof *indices * m.index_count);
    ht_mesh_sort_inside_out(&m);
    assert_ptr_equal(m.indices, copy.indices);
    assert_memory_equal(m.indices, indices, sizeof *indices * m.index_count);
    assert_true(m.components[0].sort_key == 1e9f);
    free(indices);
    ht_mesh_free(&m);
}

/* Six vertices, indices 0..5, room for count components. */
static ht_mesh six_index_mesh(uint32_t count) {
    ht_mesh m = { 0 };
    m.vertices = calloc(6, sizeof *m.vertices);
    m.indices = malloc(sizeof *m.indices * 6);
    m.components = calloc(count, sizeof *m.components);
    assert_non_null(m.vertices);
    assert_non_null(m.indices);
    assert_non_null(m.components);
    m.vertex_count = m.index_count = 6;
    m.component_count = count;
    for (uint32_t i = 0; i < 6; i++) m.indices[i] = i;
    return m;
}

/* The components as given, keys descending so a sort would reverse them:
   the mesh must come out untouched. */
static void expect_left_alone(const ht_component *components, uint32_t count, const char *what) {
    ht_mesh m = six_index_mesh(count);
    for (uint32_t c = 0; c < count; c++) {
        m.components[c] = components[c];
        m.components[c].sort_key = (float)(count - c);
    }
    uint32_t *indices = m.indices;
    ht_mesh_sort_inside_out(&m);
    if (m.indices != indices) fail_msg("%s: the index buffer was replaced", what);
    for (uint32_t i = 0; i < 6; i++)
        if (m.indices[i] != i) fail_msg("%s: indices[%u] became %u", what, i, m.indices[i]);
    for (uint32_t c = 0; c < count; c++)
        if (memcmp(&m.components[c], &components[c], offsetof(ht_component, sort_key)) != 0 ||
            m.components[c].sort_key != (float)(count - c))
            fail_msg("%s: components[%u] changed", what, c);
    ht_mesh_free(&m);
}

static void test_sort_leaves_overlapping_or_gapped_components_alone(void **state) {
    (void)state;
    /* Lengths that add up to index_count are not enough: the runs must
       tile the buffer. */
    expect_left_alone((const ht_component[]){ { 0, 3, 0 }, { 0, 3, 0 } }, 2, "the same run twice");
    expect_left_alone((const ht_component[]){ { 0, 4, 0 }, { 2, 2, 0 } }, 2, "a run inside another");
    expect_left_alone((const ht_component[]){ { 3, 3, 0 }, { 0, 3, 0 }, { 1, 0, 0 } }, 3, "an empty run inside one");
    expect_left_alone((const ht_component[]){ { 1, 3, 0 }, { 4, 2, 0 } }, 2, "a gap at the start, one past the end");
    expect_left_alone((const ht_component[]){ { 0, 3, 0 }, { UINT32_MAX, 3, 0 } }, 2, "a run past the end");

    /* The same buffer tiled out of order, with an empty run at its end:
       sorted by key. */
    ht_mesh m = six_index_mesh(3);
    m.components[0] = (ht_component){ 3, 3, 1.0f };
    m.components[1] = (ht_component){ 6, 0, 3.0f };
    m.components[2] = (ht_component){ 0, 3, 2.0f };
    ht_mesh_sort_inside_out(&m);
    const uint32_t want[6] = { 3, 4, 5, 0, 1, 2 };
    assert_memory_equal(m.indices, want, sizeof want);
    assert_int_equal(m.components[0].first_index, 0);
    assert_int_equal(m.components[1].first_index, 3);
    assert_int_equal(m.components[2].first_index, 6);
    assert_int_equal(m.components[2].index_count, 0);
    ht_mesh_free(&m);
}

/* ---- bad input and failure ---- */

static void assert_mesh_zeroed(const ht_mesh *m) {
    ht_mesh zero;
    memset(&zero, 0, sizeof zero);
    assert_memory_equal(m, &zero, sizeof zero);
}

static void test_furball_rejects_invalid_desc(void **state) {
    (void)state;
    const ht_furball_desc bad[] = {
        { .hairs = -1 },
        { .joints = 1 },
        { .joints = -16 },
        { .joints = INT_MAX },
        { .hairs = INT_MAX },          /* more indices than uint32 holds */
        { .hairs = 40000000, .joints = 64 },
        { .length = -0.1f },
        { .length = NAN },
        { .length = INFINITY },
        { .length = 1e30f },
        { .length = 1e-30f },
        { .width = -1 },
        { .width = NAN },
        { .width = 1e-9f },
        { .gravity = { 0, NAN, 0 } },
        { .gravity = { 0, -INFINITY, 0 } },
        { .inertia = { 1e20f, 0, 0 } },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ht_mesh m;
        memset(&m, 0xab, sizeof m);
        assert_int_equal(ht_mesh_build_furball(&bad[i], &m), HT_ERR_INVALID_ARGUMENT);
        assert_mesh_zeroed(&m);
        ht_mesh_free(&m);
    }
    ht_mesh m;
    assert_int_equal(ht_mesh_build_furball(NULL, &m), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ 0 }, NULL), HT_ERR_INVALID_ARGUMENT);
}

static void test_patches_rejects_invalid_desc(void **state) {
    (void)state;
    const ht_patches_desc bad[] = {
        { .head_radius = -1 },
        { .head_radius = NAN },
        { .head_radius = INFINITY },
        { .head_radius = 1e30f },
        { .head_radius = 1e-20f },
        { .layers = -1 },
        { .layers = 100000 },
        { .strips = -3 },
        { .strips = INT_MAX },
        { .segments = -12 },
        { .segments = INT_MAX },
        { .layers = 256, .strips = 1 << 20, .segments = 4096 }, /* overflows uint32 */
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ht_mesh m, head;
        memset(&m, 0xab, sizeof m);
        memset(&head, 0xab, sizeof head);
        assert_int_equal(ht_mesh_build_patches(&bad[i], &m, &head), HT_ERR_INVALID_ARGUMENT);
        assert_mesh_zeroed(&m);
        assert_mesh_zeroed(&head);
    }
    ht_mesh m;
    assert_int_equal(ht_mesh_build_patches(NULL, &m, NULL), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ 0 }, NULL, NULL), HT_ERR_INVALID_ARGUMENT);
}

static void test_free_of_zeroed_mesh_is_a_no_op(void **state) {
    (void)state;
    ht_mesh m = { 0 };
    ht_mesh_free(&m);
    ht_mesh_free(&m);
    ht_mesh_free(NULL);
    assert_mesh_zeroed(&m);
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 3 }, &m), HT_OK);
    ht_mesh_free(&m);
    assert_mesh_zeroed(&m);
    ht_mesh_free(&m);
}

/* In a child process whose address space is capped just above what it
   already uses, a mesh of a few hundred megabytes cannot be allocated: the
   builders must say so and leave nothing behind, the sort must leave the
   mesh as it was. AddressSanitizer reserves terabytes and aborts instead of
   returning NULL, so it skips this test. */
#ifndef HT_UNDER_ASAN
static int out_of_memory_child(void) {
    ht_mesh small;
    if (ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 20000, .joints = 4 }, &small) != HT_OK) return 10;
    if (!ht_test_limit_address_space((size_t)16 << 20)) return 11;

    ht_mesh m, head;
    memset(&m, 0xab, sizeof m);
    if (ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 400000 }, &m) != HT_ERR_OUT_OF_MEMORY) return 1;
    if (m.vertices || m.indices || m.components || m.vertex_count) return 2;
    memset(&head, 0xab, sizeof head);
    if (ht_mesh_build_patches(&(ht_patches_desc){ .layers = 64, .strips = 4096, .segments = 16 }, &m, &head) !=
        HT_ERR_OUT_OF_MEMORY)
        return 3;
    if (m.vertices || head.vertices || head.indices || m.index_count) return 4;

    /* The sort needs a copy of the index buffer (~2.9 MB) and the limit is
       filled first, so the sort cannot allocate and must not change a thing. */
    void *filler[HT_TEST_FILL_BLOCKS];
    const int fills = ht_test_fill_memory(filler);
    small.components[0].sort_key = 1e9f;
    uint32_t first = small.indices[0];
    ht_mesh_sort_inside_out(&small);
    if (small.components[0].sort_key != 1e9f || small.indices[0] != first) return 5;
    ht_test_unfill(filler, fills);
    ht_mesh_free(&small);
    return 0;
}
#endif

static void test_allocation_failure_frees_everything(void **state) {
    (void)state;
    HT_TEST_FORK_MEMORY_CHILD(out_of_memory_child);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_furball_counts_follow_desc),
        cmocka_unit_test(test_furball_frames_are_unit_perpendicular_and_finite),
        cmocka_unit_test(test_furball_hairs_grow_from_origin_with_segment_length),
        cmocka_unit_test(test_furball_ribbon_tapers_from_width_to_a_quarter),
        cmocka_unit_test(test_furball_hairs_have_own_streak_column_and_brighten_to_tip),
        cmocka_unit_test(test_furball_gravity_zero_or_parallel_stays_finite),
        cmocka_unit_test(test_furball_same_seed_same_bytes_other_seed_differs),
        cmocka_unit_test(test_patches_counts_follow_desc),
        cmocka_unit_test(test_patches_frames_point_away_from_head),
        cmocka_unit_test(test_patches_inner_layers_and_roots_are_darker),
        cmocka_unit_test(test_patches_neighbouring_strips_overlap),
        cmocka_unit_test(test_patches_fill_head_sphere),
        cmocka_unit_test(test_patches_same_seed_same_bytes_other_seed_differs),
        cmocka_unit_test(test_patches_roots_sit_on_the_upper_scalp_in_layer_shells),
        cmocka_unit_test(test_patches_long_strips_follow_the_scalp_then_hang_down),
        cmocka_unit_test(test_patches_back_hair_falls_behind_side_hair_beside_front_hair_stops_above),
        cmocka_unit_test(test_patches_leave_the_face_bare),
        cmocka_unit_test(test_patches_strips_beside_the_face_sweep_back_and_hang_shorter),
        cmocka_unit_test(test_patches_triangles_clear_the_head_with_enough_segments),
        cmocka_unit_test(test_sort_keys_are_centroid_distances),
        cmocka_unit_test(test_sort_orders_components_inside_out_keeping_triangles),
        cmocka_unit_test(test_sort_is_stable_for_ties),
        cmocka_unit_test(test_sort_orders_every_float_key),
        cmocka_unit_test(test_sort_leaves_overlapping_or_gapped_components_alone),
        cmocka_unit_test(test_sort_leaves_meshes_it_cannot_sort_alone),
        cmocka_unit_test(test_furball_rejects_invalid_desc),
        cmocka_unit_test(test_patches_rejects_invalid_desc),
        cmocka_unit_test(test_free_of_zeroed_mesh_is_a_no_op),
        cmocka_unit_test(test_allocation_failure_frees_everything),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

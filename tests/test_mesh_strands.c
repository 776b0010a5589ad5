/* test_mesh_strands — strands as ribbons (mesh_strands.c): unit tangents
   root to tip (repeated points and strands of no length included), normals
   facing away from the head centre (or the given facing), widths, uv, AO in
   [0, 1] darker under hair than over it, the inside-out order, bad descs
   refused; the scene's "strands" geometry reads and checks every field and
   resolves its file against the scene's folder; and the shipped mohawk and
   scene build finite meshes. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/scene.h>
#include <hairtier/strands.h>

static double dot3(const float a[3], const float b[3]) {
    return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
}
static double len3(const float a[3]) { return sqrt(dot3(a, a)); }

/* count strands of n points each, point j of strand i from fn. */
static ht_strands make_strands(uint32_t count, uint32_t n, void (*fn)(uint32_t, uint32_t, uint32_t, float[3])) {
    ht_strands s = { count, count * n, malloc(sizeof(uint32_t) * (count + 1)), malloc(sizeof(float[3]) * count * n),
                     NULL };
    assert_non_null(s.first_point);
    assert_non_null(s.points);
    for (uint32_t i = 0; i <= count; i++) s.first_point[i] = i * n;
    for (uint32_t i = 0; i < count; i++)
        for (uint32_t j = 0; j < n; j++) fn(count, i, j, s.points[i * n + j]);
    return s;
}

/* Strands growing out of a unit sphere and bending over it, around the
   upper half: a small scalp. */
static void scalp_point(uint32_t count, uint32_t i, uint32_t j, float p[3]) {
    const double phi = 2.0 * M_PI * i / count, theta = 0.3 + 0.8 * (double)(i % 7) / 7.0;
    const double r = 1.0 + 0.05 * j, t = theta + 0.08 * j;
    p[0] = (float)(r * sin(t) * sin(phi));
    p[1] = (float)(r * cos(t));
    p[2] = (float)(r * sin(t) * cos(phi));
}

static const ht_strands_ribbon_desc plain = {
    .scale = 1, .width = 0.02f, .tip_width = 0.25f, .ao = 0.3f,
};

static void assert_finite_mesh(const ht_mesh *m) {
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *f = (const float *)&m->vertices[v];
        for (size_t k = 0; k < sizeof(ht_vertex) / sizeof(float); k++) assert_true(isfinite(f[k]));
    }
}

/* The centre line point of vertex pair i: the mean of its two edges. */
static void centre(const ht_mesh *m, uint32_t pair, float c[3]) {
    for (int k = 0; k < 3; k++) c[k] = 0.5f * (m->vertices[2 * pair].position[k] + m->vertices[2 * pair + 1].position[k]);
}

static void test_ribbons_have_unit_tangents_root_to_tip_and_face_away_from_the_head(void **state) {
    (void)state;
    ht_strands s = make_strands(50, 9, scalp_point);
    ht_mesh m;
    char err[256];
    assert_int_equal(ht_mesh_build_strands(&s, &plain, &m, err, sizeof err), HT_OK);
    assert_int_equal(m.vertex_count, 2 * 450);
    assert_int_equal(m.index_count, 6 * 50 * 8);
    assert_int_equal(m.component_count, 50);
    assert_finite_mesh(&m);
    for (uint32_t i = 0; i < 50; i++)
        for (uint32_t j = 0; j < 9; j++) {
            const uint32_t pair = i * 9 + j;
            const ht_vertex *a = &m.vertices[2 * pair], *b = &m.vertices[2 * pair + 1];
            assert_true(fabs(len3(a->tangent) - 1) < 1e-5);
            assert_true(fabs(len3(a->normal) - 1) < 1e-5);
            assert_true(fabs(dot3(a->tangent, a->normal)) < 1e-5);
            /* root to tip: along the next point minus the previous */
            const float *p0 = s.points[i * 9 + (j ? j - 1 : 0)], *p1 = s.points[i * 9 + (j < 8 ? j + 1 : 8)];
            const float d[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
            assert_true(dot3(a->tangent, d) > 0);
            /* away from the head centre (the origin) */
            float c[3];
            centre(&m, pair, c);
            assert_true(dot3(a->normal, c) >= 0);
            /* the file's points are the centre line */
            for (int k = 0; k < 3; k++) assert_true(fabsf(c[k] - s.points[pair][k]) < 1e-5f);
            /* width: 0.02 at the root tapering to 0.005, across the tangent */
            const float e[3] = { b->position[0] - a->position[0], b->position[1] - a->position[1],
                                 b->position[2] - a->position[2] };
            assert_true(fabs(dot3(e, a->tangent)) < 1e-6);
            if (j == 0) assert_true(fabs(len3(e) - 0.02) < 1e-6);
            if (j == 8) assert_true(fabs(len3(e) - 0.005) < 1e-6);
            assert_true(a->uv[0] == 0 && b->uv[0] == 1);
            assert_true(a->uv[1] == b->uv[1]);
            if (j == 0) assert_true(a->uv[1] == 0);
            if (j == 8) assert_true(a->uv[1] == 1);
            if (j > 0) assert_true(a->uv[1] > m.vertices[2 * pair - 2].uv[1]);
            assert_true(a->ao >= 0 && a->ao <= 1);
        }
    ht_mesh_free(&m);
    free(s.first_point);
    free(s.points);
}

/* Strand 0 repeats its points (zero-length segments at root, middle, tip),
   strand 1 stands straight out of the head (tangent along the outward
   direction), strand 2 has no length at all. */
static void awkward_point(uint32_t count, uint32_t i, uint32_t j, float p[3]) {
    (void)count;
    static const uint32_t repeat[6] = { 0, 0, 1, 2, 2, 3 };
    if (i == 0) { p[0] = 0.1f * repeat[j]; p[1] = 1.0f; p[2] = 0.2f * repeat[j] * repeat[j] * 0.1f; }
    else if (i == 1) { p[0] = 0; p[1] = 0; p[2] = 1.0f + 0.1f * j; }
    else { p[0] = 0.5f; p[1] = 0.5f; p[2] = 0.5f; }
}

static void test_repeated_points_standing_and_empty_strands_keep_unit_frames(void **state) {
    (void)state;
    ht_strands s = make_strands(3, 6, awkward_point);
    ht_mesh m;
    char err[256];
    assert_int_equal(ht_mesh_build_strands(&s, &plain, &m, err, sizeof err), HT_OK);
    assert_finite_mesh(&m);
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const ht_vertex *x = &m.vertices[v];
        assert_true(fabs(len3(x->tangent) - 1) < 1e-5);
        assert_true(fabs(len3(x->normal) - 1) < 1e-5);
        assert_true(fabs(dot3(x->tangent, x->normal)) < 1e-5);
        assert_true(x->ao >= 0 && x->ao <= 1);
    }
    /* strand 0 runs +x: every tangent, the repeated points' too */
    for (uint32_t v = 0; v < 12; v++) assert_true(m.vertices[v].tangent[0] > 0.5f);
    /* strand 1 runs +z, straight out; its ribbon keeps one axis */
    for (uint32_t v = 12; v < 24; v++) assert_true(m.vertices[v].tangent[2] > 0.999f);
    for (uint32_t v = 14; v < 24; v++) assert_true(dot3(m.vertices[v].normal, m.vertices[12].normal) > 0.999);
    /* strand 2: v by index when there is no length */
    assert_true(fabsf(m.vertices[24 + 2 * 3].uv[1] - 0.6f) < 1e-6f);
    ht_mesh_free(&m);
    free(s.first_point);
    free(s.points);
}

static void test_facing_turns_every_ribbon_that_way(void **state) {
    (void)state;
    ht_strands s = make_strands(40, 7, scalp_point);
    ht_strands_ribbon_desc d = plain;
    d.facing[0] = 1;
    ht_mesh m;
    char err[256];
    assert_int_equal(ht_mesh_build_strands(&s, &d, &m, err, sizeof err), HT_OK);
    for (uint32_t v = 0; v < m.vertex_count; v++) assert_true(m.vertices[v].normal[0] >= 0);
    ht_mesh_free(&m);
    free(s.first_point);
    free(s.points);
}

/* Two shells of strands lying on spheres of radius 1 and 1.15: the inner
   shell is under the outer, so it must be darker; ao 0 turns it off. */
static void shell_point(uint32_t count, uint32_t i, uint32_t j, float p[3]) {
    const uint32_t half = count / 2, k = i % half;
    const double r = i < half ? 1.0 : 1.15;
    const double phi = 2.0 * M_PI * (k % 40) / 40, theta = 0.2 + 1.2 * (k / 40) / (double)(half / 40);
    const double t = theta + 0.03 * j;
    p[0] = (float)(r * sin(t) * sin(phi));
    p[1] = (float)(r * cos(t));
    p[2] = (float)(r * sin(t) * cos(phi));
}

static void test_ao_is_darker_under_hair_and_off_at_zero(void **state) {
    (void)state;
    ht_strands s = make_strands(1600, 6, shell_point);
    ht_mesh m;
    char err[256];
    ht_strands_ribbon_desc d = plain;
    d.ao = 0.5f;
    assert_int_equal(ht_mesh_build_strands(&s, &d, &m, err, sizeof err), HT_OK);
    double inner = 0, outer = 0;
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        const ht_vertex *x = &m.vertices[v];
        assert_true(x->ao >= 0 && x->ao <= 1);
        *(len3(x->position) < 1.07 ? &inner : &outer) += x->ao;
    }
    inner /= m.vertex_count / 2.0;
    outer /= m.vertex_count / 2.0;
    printf("ao: inner shell mean %.3f, outer shell mean %.3f\n", inner, outer);
    assert_true(inner < outer - 0.2);
    assert_true(outer > 0.9);
    ht_mesh_free(&m);
    d.ao = 0;
    assert_int_equal(ht_mesh_build_strands(&s, &d, &m, err, sizeof err), HT_OK);
    for (uint32_t v = 0; v < m.vertex_count; v++) assert_true(m.vertices[v].ao == 1.0f);
    ht_mesh_free(&m);
    free(s.first_point);
    free(s.points);
}

static void test_components_are_sorted_inside_out_from_the_head_centre(void **state) {
    (void)state;
    ht_strands s = make_strands(1600, 6, shell_point);
    ht_strands_ribbon_desc d = plain;
    d.head_center[1] = 0.25f;
    ht_mesh m;
    char err[256];
    assert_int_equal(ht_mesh_build_strands(&s, &d, &m, err, sizeof err), HT_OK);
    assert_true(m.center[1] == 0.25f);
    uint64_t covered = 0;
    for (uint32_t c = 0; c < m.component_count; c++) {
        const ht_component *k = &m.components[c];
        if (c) assert_true(k->sort_key >= m.components[c - 1].sort_key);
        assert_int_equal(k->first_index, covered);
        covered += k->index_count;
        /* the key is the distance of the ribbon's centroid from the head centre */
        const uint32_t first = m.indices[k->first_index] & ~1u;
        double sum[3] = { 0, 0, 0 };
        for (uint32_t v = first; v < first + 12; v++)
            for (int a = 0; a < 3; a++) sum[a] += m.vertices[v].position[a];
        const double dy = sum[1] / 12 - 0.25;
        assert_true(fabs(sqrt(sum[0] * sum[0] / 144 + dy * dy + sum[2] * sum[2] / 144) - k->sort_key) < 1e-4);
    }
    assert_int_equal(covered, m.index_count);
    ht_mesh_free(&m);
    free(s.first_point);
    free(s.points);
}

static void test_thickness_gives_the_width_and_bad_descs_are_refused(void **state) {
    (void)state;
    ht_strands s = make_strands(4, 5, scalp_point);
    ht_strands_ribbon_desc d = plain;
    ht_mesh m;
    char err[256];
    d.use_thickness = true;
    memset(&m, 0xab, sizeof m);
    assert_int_equal(ht_mesh_build_strands(&s, &d, &m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "thickness"));
    assert_null(m.vertices);
    s.thickness = malloc(sizeof(float) * 20);
    for (int i = 0; i < 20; i++) s.thickness[i] = 0.01f * (float)(i + 1);
    d.scale = 2;
    assert_int_equal(ht_mesh_build_strands(&s, &d, &m, err, sizeof err), HT_OK);
    for (uint32_t v = 0; v < m.vertex_count; v += 2) {
        const float *a = m.vertices[v].position, *b = m.vertices[v + 1].position;
        const float e[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
        /* sorting moved the components, not the vertices: vertex pair v / 2 is point v / 2 */
        assert_true(fabs(len3(e) - 2 * 0.01 * (v / 2 + 1)) < 1e-5);
    }
    ht_mesh_free(&m);

    const struct {
        ht_strands_ribbon_desc d;
        const char *field;
    } bad[] = {
        { { .scale = 0, .width = 0.01f }, "scale" },
        { { .scale = NAN, .width = 0.01f }, "scale" },
        { { .scale = 1, .width = 0 }, "width" },
        { { .scale = 1, .width = 0.01f, .tip_width = 2 }, "width" },
        { { .scale = 1, .width = 0.01f, .ao = -1 }, "ao" },
        { { .scale = 1, .width = 0.01f, .center = { NAN, 0, 0 } }, "center" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        assert_int_equal(ht_mesh_build_strands(&s, &bad[i].d, &m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(err, bad[i].field));
    }
    s.first_point[2] = s.first_point[1] + 1; /* a strand of one point */
    assert_int_equal(ht_mesh_build_strands(&s, &plain, &m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    free(s.first_point);
    free(s.points);
    free(s.thickness);
}

static void test_shipped_scene_builds_the_mohawk_and_a_head(void **state) {
    (void)state;
    ht_scene scene;
    ht_mesh hair, head;
    char err[512];
    assert_int_equal(ht_scene_load("scenes/ratboy.json", &scene, err, sizeof err), HT_OK);
    assert_int_equal(scene.geometry, HT_GEOMETRY_STRANDS);
    assert_string_equal(scene.strands.file, "scenes/ratboy-mohawk.tfx");
    assert_int_equal(ht_scene_build_meshes(&scene, "scenes/ratboy.json", &hair, &head, err, sizeof err), HT_OK);
    assert_int_equal(hair.component_count, 2226);
    assert_int_equal(hair.vertex_count, 2 * 2226 * 32);
    assert_true(head.index_count > 0);
    assert_finite_mesh(&hair);
    double ao_min = 1, ao_max = 0;
    for (uint32_t v = 0; v < hair.vertex_count; v++) {
        ao_min = fmin(ao_min, hair.vertices[v].ao);
        ao_max = fmax(ao_max, hair.vertices[v].ao);
    }
    printf("ratboy: ao %.3f to %.3f\n", ao_min, ao_max);
    assert_true(ao_min >= 0 && ao_max <= 1 && ao_max - ao_min > 0.3 && ao_min >= 0.25);
    ht_mesh_free(&hair);
    ht_mesh_free(&head);

    /* A file that is not there: one line naming it. */
    snprintf(scene.strands.file, sizeof scene.strands.file, "data/no-such.tfx");
    assert_int_equal(ht_scene_build_meshes(&scene, "scenes/ratboy.json", &hair, &head, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "data/no-such.tfx"));
    assert_null(hair.vertices);
    assert_null(head.vertices);
}

static ht_result parse_geometry(const char *geometry, const char *file_name, ht_scene *s, char *err, size_t size) {
    char text[2048];
    snprintf(text, sizeof text,
             "{\"format\": \"hairtier-scene/1\", \"resolution\": [64, 64],"
             " \"camera\": {\"eye\": [0, 0, 3], \"target\": [0, 0, 0]},"
             " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1]}],"
             " \"geometry\": %s}",
             geometry);
    return ht_scene_parse(text, file_name, s, err, size);
}

static void test_scene_strands_fields_are_read_and_checked(void **state) {
    (void)state;
    ht_scene s;
    char err[512];
    assert_int_equal(parse_geometry("{\"type\": \"strands\", \"file\": \"hair/a.tfx\"}", "dir/s.json", &s, err,
                                    sizeof err),
                     HT_OK);
    assert_int_equal(s.geometry, HT_GEOMETRY_STRANDS);
    assert_string_equal(s.strands.file, "dir/hair/a.tfx");
    assert_true(s.strands.ribbon.scale == 1 && s.strands.ribbon.width == 0.01f && s.strands.ribbon.tip_width == 0.25f);
    assert_true(s.strands.ribbon.ao == 0.3f && !s.strands.ribbon.use_thickness && s.strands.head_radius == 0);
    assert_true(ht_scene_memory_estimate(&s) <= (4ull << 30));

    assert_int_equal(parse_geometry("{\"type\": \"strands\", \"file\": \"/abs/a.hair\", \"scale\": 0.5,"
                                    " \"center\": [1, 2, 3], \"width\": 0.02, \"tip_width\": 1,"
                                    " \"thickness\": true, \"ao\": 0, \"facing\": [1, 0, 0],"
                                    " \"head\": {\"radius\": 0.9, \"center\": [0, 0.1, 0]}}",
                                    "dir/s.json", &s, err, sizeof err),
                     HT_OK);
    assert_string_equal(s.strands.file, "/abs/a.hair");
    assert_true(s.strands.ribbon.scale == 0.5f && s.strands.ribbon.center[2] == 3 && s.strands.ribbon.width == 0.02f);
    assert_true(s.strands.ribbon.tip_width == 1 && s.strands.ribbon.use_thickness && s.strands.ribbon.ao == 0);
    assert_true(s.strands.ribbon.facing[0] == 1 && s.strands.head_radius == 0.9f);
    assert_true(s.strands.ribbon.head_center[1] == 0.1f);

    const struct {
        const char *geometry, *field;
    } bad[] = {
        { "{\"type\": \"strands\"}", "geometry.file" },
        { "{\"type\": \"strands\", \"file\": \"\"}", "geometry.file" },
        { "{\"type\": \"strands\", \"file\": 3}", "geometry.file" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"scale\": 0}", "geometry.scale" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"center\": [1e8, 0, 0]}", "geometry.center" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"width\": 2}", "geometry.width" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"tip_width\": 1.5}", "geometry.tip_width" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"thickness\": 1}", "geometry.thickness" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"ao\": -1}", "geometry.ao" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"facing\": [2, 0, 0]}", "geometry.facing" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"head\": {\"radius\": -1}}", "geometry.head.radius" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"head\": {\"centre\": [0, 0, 0]}}",
          "geometry.head.centre" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"hairs\": 10}", "geometry.hairs" },
        { "{\"type\": \"strands\", \"file\": \"a.tfx\", \"layers\": 2}", "geometry.layers" },
        { "{\"type\": \"furball\", \"file\": \"a.tfx\"}", "geometry.file" },
        { "{\"type\": \"patches\", \"ao\": 1}", "geometry.ao" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ht_result r = parse_geometry(bad[i].geometry, "s.json", &s, err, sizeof err);
        if (r != HT_ERR_PARSE || !strstr(err, bad[i].field)) fail_msg("%s: got %d: %s", bad[i].geometry, (int)r, err);
    }
    /* A key of another type says which type it belongs to. */
    assert_int_equal(parse_geometry("{\"type\": \"strands\", \"file\": \"a.tfx\", \"hairs\": 10}", "s.json", &s,
                                    err, sizeof err),
                     HT_ERR_PARSE);
    assert_non_null(strstr(err, "belongs to \"type\": \"furball\""));
    /* A path too long once resolved. */
    char geometry[1400], scene_name[700];
    memset(scene_name, 'd', 600);
    strcpy(scene_name + 600, "/s.json");
    char long_file[500];
    memset(long_file, 'f', 450);
    strcpy(long_file + 450, ".tfx");
    snprintf(geometry, sizeof geometry, "{\"type\": \"strands\", \"file\": \"%s\"}", long_file);
    char long_err[2048]; /* the scene's 600-byte name comes first */
    assert_int_equal(parse_geometry(geometry, scene_name, &s, long_err, sizeof long_err), HT_ERR_PARSE);
    assert_non_null(strstr(long_err, "geometry.file: path longer than 1023"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ribbons_have_unit_tangents_root_to_tip_and_face_away_from_the_head),
        cmocka_unit_test(test_repeated_points_standing_and_empty_strands_keep_unit_frames),
        cmocka_unit_test(test_facing_turns_every_ribbon_that_way),
        cmocka_unit_test(test_ao_is_darker_under_hair_and_off_at_zero),
        cmocka_unit_test(test_components_are_sorted_inside_out_from_the_head_centre),
        cmocka_unit_test(test_thickness_gives_the_width_and_bad_descs_are_refused),
        cmocka_unit_test(test_scene_strands_fields_are_read_and_checked),
        cmocka_unit_test(test_shipped_scene_builds_the_mohawk_and_a_head),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_transmission.c — the Scheuermann transmission lobe (model.h's
   ht_transmission): the model computes the rule as written, its documented
   answers at the undefined points, float near double; a material without
   the lobe mentions it nowhere, whatever its shape constants while its
   colour is 0, and shades bit for bit alike (its bundles, compared once
   with hairgen 5's for the four shipped materials: every shader, program
   and LUT the same bytes; only the manifest's version and hash differ); a
   material with one gets it in full and vertex (glslang-validated by
   the generator) and gl11 (its program carries it; test_gl11 holds the
   colours to the oracle), a "dropped" line in fixed4 and fixed; the material
   reader refuses it where the model has none and out of range. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairgen.h>
#include <hairtier/model.h>
#include "rng.h"

static const ht_transmission lobe = { { 1.8, 1.0, 0.3 }, 0.06, 700, 3 };

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The rule of model.h written out for unit vectors with a direction and
   L, V not along T. */
static double ref_transmission(const ht_transmission *t, const double T[3], const double L[3], const double V[3]) {
    double tl = dot(T, L), tv = dot(T, V), lp[3], vp[3];
    for (int i = 0; i < 3; i++) lp[i] = L[i] - tl * T[i], vp[i] = V[i] - tv * T[i];
    double cos_phi = dot(lp, vp) / sqrt(dot(lp, lp) * dot(vp, vp));
    double u = (asin(fmin(1, fmax(-1, tl))) + asin(fmin(1, fmax(-1, tv)))) / 2 - t->centre;
    return exp2(-t->sharpness * u * u) * pow((1 - cos_phi) / 2, t->azimuth);
}

static void random_unit(ht_rng *r, double v[3]) {
    double len2;
    do {
        for (int i = 0; i < 3; i++) v[i] = ht_rng_range(r, -1, 1);
        len2 = dot(v, v);
    } while (len2 > 1 || len2 < 1e-4);
    for (int i = 0; i < 3; i++) v[i] /= sqrt(len2);
}

static ht_shading scheuermann(void) {
    return (ht_shading){ .model = HT_MODEL_SCHEUERMANN, .diffuse_color = { 0.3, 0.2, 0.1 }, .wrap = 0.25,
                         .primary = { { 1, 1, 1 }, 80, -0.1 }, .secondary = { { 0.5, 0.4, 0.3 }, 20, 0.1 } };
}

static void test_the_lobe_is_its_rule_and_adds_to_the_shading(void **state) {
    (void)state;
    ht_shading without = scheuermann(), with = without;
    with.transmission = lobe;
    ht_rng rng = ht_rng_seed(7);
    double worst_rule = 0, worst_sum = 0, worst_float = 0, most = 0;
    for (int n = 0; n < 20000; n++) {
        ht_surface s = { .base = { 0.9, 0.8, 0.7 }, .shift_tex = 0.5, .sparkle = 1, .ao = 0.75 };
        ht_light_ray light = { .color = { 2, 1.9, 1.75 } };
        random_unit(&rng, s.T);
        random_unit(&rng, s.N);
        random_unit(&rng, light.L);
        random_unit(&rng, s.V);
        if (n % 2) /* half near the cone and behind the fibre, where the lobe is large */
            for (int i = 0; i < 3; i++) light.L[i] = -s.V[i] + 0.3 * light.L[i];
        double tt = ht_model_transmission_d(&lobe, s.T, light.L, s.V);
        double l_unit[3], len = sqrt(dot(light.L, light.L));
        for (int i = 0; i < 3; i++) l_unit[i] = light.L[i] / len;
        worst_rule = fmax(worst_rule, fabs(tt - ref_transmission(&lobe, s.T, l_unit, s.V)));
        most = fmax(most, tt);
        double a[3], b[3], f[3];
        ht_model_shade_d(&without, &s, &light, 1, a);
        ht_model_shade_d(&with, &s, &light, 1, b);
        ht_model_shade_f(&with, &s, &light, 1, f);
        for (int c = 0; c < 3; c++) {
            double want = tt * lobe.color[c] * s.base[c] * light.color[c] * s.ao;
            worst_sum = fmax(worst_sum, fabs(b[c] - a[c] - want));
            assert_true(isfinite(f[c]));
            worst_float = fmax(worst_float, fabs(f[c] - b[c]));
        }
    }
    print_message("rule %.3g, sum %.3g, float %.3g; largest tt %.3f\n", worst_rule, worst_sum, worst_float, most);
    assert_true(most > 0.9); /* the samples reach the peak */
    assert_true(worst_rule < 1e-12);
    assert_true(worst_sum < 1e-12);
    assert_true(worst_float < 2e-4); /* measured 8.5e-5: asin and exp2 of a sharp lobe in float */
}

static void test_the_lobe_at_its_undefined_points(void **state) {
    (void)state;
    const double T[3] = { 0, 1, 0 }, zero[3] = { 0, 0, 0 }, V[3] = { 0, 0, 1 }, back[3] = { 0, 0, -1 };
    assert_true(ht_model_transmission_d(&lobe, zero, back, V) == 0);
    assert_true(ht_model_transmission_d(&lobe, T, zero, V) == 0);
    assert_true(ht_model_transmission_d(&lobe, T, back, zero) == 0);
    /* exactly behind, on the cone: u = 0, a = 1 */
    assert_true(fabs(ht_model_transmission_d(&lobe, T, back, V) - exp2(-lobe.sharpness * lobe.centre * lobe.centre)) <
                1e-15);
    /* L along T has no azimuth: cos phi = 0, a = 1/2 */
    ht_transmission flat = lobe;
    flat.sharpness = 0;
    assert_true(fabs(ht_model_transmission_d(&flat, T, T, V) - pow(0.5, lobe.azimuth)) < 1e-15);
    /* a^0 = 1 also at a = 0 (L = V: phi = 0) */
    flat.azimuth = 0;
    assert_true(ht_model_transmission_d(&flat, T, V, V) == 1);
    flat.azimuth = 5;
    assert_true(ht_model_transmission_d(&flat, T, V, V) == 0);
}

/* Every text and the manifest of a generated bundle, concatenated. */
static void bundle_has(const ht_material *m, const char *needle, bool expected) {
    ht_generated g;
    char err[512];
    assert_int_equal(ht_generate(&(ht_generate_desc){ .material = m }, &g, err, sizeof err), HT_OK);
    bool found = strstr(g.manifest, needle) != NULL;
    for (int i = 0; i < g.file_count; i++)
        if (g.files[i].text && strstr(g.files[i].text, needle)) found = true;
    if (found != expected) fail_msg("%s: \"%s\" %s", m->name, needle, expected ? "missing" : "present");
    ht_generated_free(&g);
}

static void test_without_a_colour_there_is_no_lobe_anywhere(void **state) {
    (void)state;
    ht_material m = { .name = "plain", .shading = scheuermann() };
    bundle_has(&m, "transmission", false);
    /* its shape alone draws nothing: the shading is bit for bit the same */
    ht_material shaped = m;
    shaped.shading.transmission = lobe;
    memset(shaped.shading.transmission.color, 0, sizeof shaped.shading.transmission.color);
    assert_false(ht_model_has_transmission(&shaped.shading));
    bundle_has(&shaped, "transmission", false);
    ht_surface s = { .T = { 0, 1, 0 }, .N = { 0, 0, 1 }, .V = { 0, 0, 1 }, .base = { 1, 1, 1 }, .shift_tex = 0.5,
                     .sparkle = 1, .ao = 1 };
    ht_light_ray light = { .L = { 0, 0.05, -1 }, .color = { 2, 2, 2 } };
    double a[3], b[3];
    ht_model_shade_f(&m.shading, &s, &light, 1, a);
    ht_model_shade_f(&shaped.shading, &s, &light, 1, b);
    assert_memory_equal(a, b, sizeof a);
}

static void test_with_a_colour_full_vertex_and_gl11_draw_it_and_fixed4_and_fixed_say_they_drop_it(void **state) {
    (void)state;
    ht_material m = { .name = "glow", .shading = scheuermann() };
    m.shading.transmission = lobe;
    ht_generated g;
    char err[512];
    assert_int_equal(ht_generate(&(ht_generate_desc){ .material = &m }, &g, err, sizeof err), HT_OK);
    const char *drawing[] = { "full.frag", "full-es2.frag", "full-es3.frag", "vertex.vert", "vertex-es2.vert",
                              "vertex-es3.vert" };
    for (size_t i = 0; i < sizeof drawing / sizeof *drawing; i++) {
        const ht_generated_file *f = ht_generated_find(&g, drawing[i]);
        assert_non_null(f);
        if (!strstr(f->text, "transmission(T, L")) fail_msg("%s draws no transmission", drawing[i]);
    }
    const ht_generated_file *gl11 = ht_generated_find(&g, "gl11.json"); /* per vertex on the CPU */
    assert_non_null(gl11);
    assert_non_null(strstr(gl11->text, "\"transmission\""));
    assert_non_null(strstr(g.manifest, "transmission: its azimuth needs")); /* fixed4 and fixed drop it */
    ht_generated_free(&g);
}

static void test_the_reader_checks_the_lobe(void **state) {
    (void)state;
    static const char head[] =
        "{\"format\": \"hairtier-material/1\", \"name\": \"t\", \"model\": \"%s\", \"diffuse\": {\"color\": [0.2, 0.1, "
        "0.1]}, \"primary\": {\"color\": [1, 1, 1], \"exponent\": 80}%s, \"transmission\": %s}";
    char text[1024], err[512];
    ht_material m;
    snprintf(text, sizeof text, head, "scheuermann", ", \"secondary\": {\"color\": [1, 1, 1], \"exponent\": 20}",
             "{\"color\": [1.8, 1, 0.3], \"centre\": 0.05, \"sharpness\": 800, \"azimuth\": 5}");
    assert_int_equal(ht_material_parse(text, "t.json", &m, err, sizeof err), HT_OK);
    assert_true(m.shading.transmission.color[0] == 1.8 && m.shading.transmission.sharpness == 800);
    snprintf(text, sizeof text, head, "scheuermann", ", \"secondary\": {\"color\": [1, 1, 1], \"exponent\": 20}",
             "{\"color\": [5, 1, 0.3]}");
    assert_int_not_equal(ht_material_parse(text, "t.json", &m, err, sizeof err), HT_OK);
    assert_non_null(strstr(err, "transmission"));
    snprintf(text, sizeof text, head, "kajiya-kay", "", "{\"color\": [1, 1, 1]}");
    assert_int_not_equal(ht_material_parse(text, "t.json", &m, err, sizeof err), HT_OK);
    assert_non_null(strstr(err, "only model \"scheuermann\" has a transmission lobe"));
    /* the one shading check refuses what the reader would (ht_material_check) */
    ht_material bad = { .name = "bad", .shading = scheuermann() };
    bad.shading.transmission = lobe;
    bad.shading.transmission.centre = 2;
    assert_int_not_equal(ht_material_check(&bad, err, sizeof err), HT_OK);
    assert_non_null(strstr(err, "transmission.centre"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_lobe_is_its_rule_and_adds_to_the_shading),
        cmocka_unit_test(test_the_lobe_at_its_undefined_points),
        cmocka_unit_test(test_without_a_colour_there_is_no_lobe_anywhere),
        cmocka_unit_test(test_with_a_colour_full_vertex_and_gl11_draw_it_and_fixed4_and_fixed_say_they_drop_it),
        cmocka_unit_test(test_the_reader_checks_the_lobe),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

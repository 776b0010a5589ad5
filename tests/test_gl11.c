/* test_gl11.c — the gl11 tier's pure parts (fallback/gl11_program.h,
   shadergen/emit_gl11.c): the program round-trips through JSON and rejects
   bad fields by name; the per-vertex colours (float, structure of arrays)
   track the double oracle ht_model_shade_d at the vertices, for both
   models, directional and point lights, the model's undefined points and
   mesh sizes that are not a whole block; the emitter asks for GL 1.1, no
   extension, one unit, and hairgen lists the tier last. The render side
   (selection, passes, the colour cache) is test_render_gl11.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emit.h"
#include "gl11_program.h"
#include "hairgen_internal.h"
#include "rng.h"

/* Per channel, relative to the largest value a channel can take (sum over
   lights of light colour x (diffuse + primary + secondary colour)): the
   model's own float-vs-double bound (docs/DESIGN.md: (1.5e-5 + 1e-7 e))
   with room for the pow made of exp2/log2 polynomials. Measured below:
   printed per run. */
#define REL_TOL(e) (4e-5 + 4e-7 * (e))

static ht_gl11_program sample_program(ht_model_kind model) {
    ht_gl11_program p;
    memset(&p, 0, sizeof p);
    p.shading.model = model;
    const double kd[3] = { 0.23, 0.14, 0.08 }, k1[3] = { 1.0, 0.95, 0.9 }, k2[3] = { 0.55, 0.4, 0.28 };
    for (int i = 0; i < 3; i++) {
        p.shading.diffuse_color[i] = kd[i];
        p.shading.primary.color[i] = k1[i];
        p.shading.secondary.color[i] = model == HT_MODEL_SCHEUERMANN ? k2[i] : 0.0;
    }
    p.shading.wrap = 0.25;
    p.shading.primary.exponent = 80;
    p.shading.primary.shift = -0.1;
    p.shading.secondary.exponent = model == HT_MODEL_SCHEUERMANN ? 24 : 0;
    p.shading.secondary.shift = model == HT_MODEL_SCHEUERMANN ? 0.15 : 0;
    p.lights = 2;
    p.ao = true;
    p.albedo_scale = 1.0;
    return p;
}

/* ---- the program file ---- */

static void test_program_round_trips_byte_identical(void **state) {
    (void)state;
    for (int m = 0; m < 2; m++) {
        ht_gl11_program p = sample_program(m ? HT_MODEL_KAJIYA_KAY : HT_MODEL_SCHEUERMANN), q;
        p.albedo_scale = 1.75;
        p.lights = 3;
        char *text = NULL, *again = NULL, err[256] = "";
        assert_int_equal(ht_gl11_write(&p, &text, err, sizeof err), HT_OK);
        assert_non_null(strstr(text, "\"format\":\t\"hairtier-gl11/1\""));
        if (ht_gl11_parse(text, "gl11.json", &q, err, sizeof err) != HT_OK) fail_msg("%s", err);
        assert_int_equal(q.shading.model, p.shading.model);
        assert_int_equal(q.lights, 3);
        assert_true(q.ao);
        assert_true(q.albedo_scale == 1.75);
        assert_true(q.shading.primary.exponent == p.shading.primary.exponent);
        assert_true(q.shading.secondary.color[1] == p.shading.secondary.color[1]);
        assert_int_equal(ht_gl11_write(&q, &again, err, sizeof err), HT_OK);
        assert_string_equal(text, again);
        free(text);
        free(again);
    }
}

static void expect_error(const char *edit_from, const char *edit_to, const char *want) {
    ht_gl11_program p = sample_program(HT_MODEL_SCHEUERMANN), q;
    char *text = NULL, err[256] = "";
    assert_int_equal(ht_gl11_write(&p, &text, err, sizeof err), HT_OK);
    char *at = strstr(text, edit_from);
    if (!at) fail_msg("no '%s' in\n%s", edit_from, text);
    char edited[4096];
    snprintf(edited, sizeof edited, "%.*s%s%s", (int)(at - text), text, edit_to, at + strlen(edit_from));
    free(text);
    assert_int_not_equal(ht_gl11_parse(edited, "b/gl11.json", &q, err, sizeof err), HT_OK);
    if (strncmp(err, want, strlen(want)) != 0) fail_msg("error '%s', expected it to start with '%s'", err, want);
    assert_null(strchr(err, '\n'));
}

static void test_program_rejects_bad_fields_naming_them(void **state) {
    (void)state;
    expect_error("hairtier-gl11/1", "hairtier-fixed4/1", "b/gl11.json: format");
    expect_error("\"lights\":\t2", "\"lights\":\t5", "b/gl11.json: lights");
    expect_error("\"lights\":\t2", "\"lights\":\t1.5", "b/gl11.json: lights");
    expect_error("\"ao\":\ttrue", "\"ao\":\t1", "b/gl11.json: ao");
    expect_error("\"albedo_scale\":\t1", "\"albedo_scale\":\t0.5", "b/gl11.json: albedo_scale");
    expect_error("\"albedo_scale\":\t1", "\"albedo_scale\":\t5", "b/gl11.json: albedo_scale");
    expect_error("\"exponent\":\t80", "\"exponent\":\t-1", "b/gl11.json: primary.exponent");
    expect_error("\"wrap\":\t0.25", "\"wrap\":\t2", "b/gl11.json: diffuse.wrap");
    expect_error("\"model\":\t\"scheuermann\"", "\"model\":\t\"marschner\"", "b/gl11.json: model");
    expect_error("\"model\":\t\"scheuermann\"", "\"model\":\t\"kajiya-kay\"", "b/gl11.json: secondary");
    expect_error("\"format\"", "\"extra\": 1, \"format\"", "b/gl11.json: extra");
    ht_gl11_program q;
    char err[256];
    assert_int_not_equal(ht_gl11_parse("{", "b/gl11.json", &q, err, sizeof err), HT_OK);
    assert_int_equal(strncmp(err, "b/gl11.json", 11), 0);
}

static void test_albedo_scale_is_the_headroom_the_albedo_leaves(void **state) {
    (void)state;
    assert_true(ht_gl11_albedo_scale(1.0) == 1.0);
    assert_true(fabs(ht_gl11_albedo_scale(0.5) - 2.0) < 1e-12);
    assert_true(ht_gl11_albedo_scale(0.1) == HT_GL11_MAX_SCALE);
    assert_true(ht_gl11_albedo_scale(0.0) == HT_GL11_MAX_SCALE);
}

/* ---- the per-vertex colours against the oracle ---- */

static void random_unit(ht_rng *r, float v[3]) {
    double d[3], len;
    do {
        for (int i = 0; i < 3; i++) d[i] = ht_rng_range(r, -1, 1);
        len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    } while (len < 0.1 || len > 1);
    for (int i = 0; i < 3; i++) v[i] = (float)(d[i] / len);
}

/* The oracle's colour of vertex v, as the tier defines it: shift texture at
   0.5, sparkle 1 (its mean is in secondary.color), base 1, V = eye - p,
   L = the vector (directional) or position - p (point). */
static void oracle(const ht_gl11_program *p, const ht_vertex *v, const ht_light *lights, int n, const float eye[3],
                   double rgb[3]) {
    ht_surface s;
    memset(&s, 0, sizeof s);
    for (int i = 0; i < 3; i++) {
        s.T[i] = v->tangent[i];
        s.N[i] = v->normal[i];
        s.V[i] = (double)eye[i] - (double)v->position[i];
        s.base[i] = 1.0;
    }
    s.shift_tex = 0.5;
    s.sparkle = 1.0;
    s.ao = p->ao ? v->ao : 1.0;
    ht_light_ray rays[HT_MAX_LIGHTS];
    for (int l = 0; l < n; l++)
        for (int i = 0; i < 3; i++) {
            rays[l].L[i] = lights[l].type == HT_LIGHT_POINT ? (double)lights[l].vector[i] - (double)v->position[i]
                                                            : (double)lights[l].vector[i];
            rays[l].color[i] = lights[l].color[i];
        }
    ht_model_shade_d(&p->shading, &s, rays, n, rgb);
}

static double channel_bound(const ht_gl11_program *p, const ht_light *lights, int n) {
    double most = 0;
    for (int c = 0; c < 3; c++) {
        double sum = 0;
        for (int l = 0; l < n; l++)
            sum += lights[l].color[c] * (p->shading.diffuse_color[c] + p->shading.primary.color[c] +
                                         p->shading.secondary.color[c] + p->shading.transmission.color[c]);
        most = sum > most ? sum : most;
    }
    return most > 0 ? most : 1;
}

/* Shades `count` vertices and compares each with the oracle; returns the
   worst error relative to the bound. */
static double compare(const ht_gl11_program *p, const ht_vertex *v, size_t count, const ht_light *lights, int n,
                      const float eye[3]) {
    ht_gl11_soa soa;
    assert_int_equal(ht_gl11_soa_make(p, v, count, &soa), HT_OK);
    assert_int_equal(soa.padded % HT_GL11_BLOCK, 0);
    assert_true(soa.padded >= count);
    float *rgba = malloc(4 * soa.padded * sizeof(float));
    assert_non_null(rgba);
    ht_gl11_shade(p, &soa, lights, n, eye, rgba);
    const double bound = channel_bound(p, lights, n);
    const double e = fmax(p->shading.primary.exponent, p->shading.secondary.exponent);
    double worst = 0;
    for (size_t i = 0; i < count; i++) {
        double want[3];
        oracle(p, &v[i], lights, n, eye, want);
        for (int c = 0; c < 3; c++) {
            float got = rgba[4 * i + (size_t)c] * (float)p->albedo_scale;
            assert_true(isfinite(got));
            double err = fabs((double)got - want[c]) / bound;
            if (err > REL_TOL(e))
                fail_msg("vertex %zu channel %d: %.9g, oracle %.9g (relative error %.3g, bound %.3g)", i, c,
                         (double)got, want[c], err, REL_TOL(e));
            worst = err > worst ? err : worst;
        }
        assert_true(rgba[4 * i + 3] == 1.0f);
    }
    ht_gl11_soa_free(&soa);
    free(rgba);
    return worst;
}

static void random_vertices(ht_rng *r, ht_vertex *v, size_t count) {
    for (size_t i = 0; i < count; i++) {
        for (int k = 0; k < 3; k++) v[i].position[k] = (float)ht_rng_range(r, -1, 1);
        random_unit(r, v[i].tangent);
        random_unit(r, v[i].normal);
        v[i].uv[0] = (float)ht_rng_unit(r);
        v[i].uv[1] = (float)ht_rng_unit(r);
        v[i].ao = (float)ht_rng_unit(r);
    }
}

static void test_colours_track_the_double_oracle_at_the_vertices(void **state) {
    (void)state;
    ht_rng r = ht_rng_seed(11);
    enum { COUNT = 2003 }; /* not a whole block */
    static ht_vertex v[COUNT];
    for (int trial = 0; trial < 40; trial++) {
        ht_gl11_program p = sample_program(trial % 2 ? HT_MODEL_KAJIYA_KAY : HT_MODEL_SCHEUERMANN);
        /* exponents over the file range, including 0 and fractional ones */
        static const double exps[] = { 0, 0.5, 1, 8, 80, 300, 1000, 10000 };
        p.shading.primary.exponent = exps[trial % 8];
        if (p.shading.model == HT_MODEL_SCHEUERMANN) {
            p.shading.secondary.exponent = exps[(trial / 2) % 8];
            p.shading.secondary.shift = ht_rng_range(&r, -2, 2);
            if (trial % 4 == 2) { /* half the Scheuermann trials glow through the strand */
                static const double sharp[] = { 0, 50, 1000, 10000 }, azimuth[] = { 0, 3, 20, 0.5 };
                p.shading.transmission = (ht_transmission){ { 1.8, 1.0, 0.3 }, ht_rng_range(&r, -0.3, 0.3),
                                                            sharp[(trial / 4) % 4], azimuth[(trial / 8) % 4] };
            }
        }
        p.shading.primary.shift = ht_rng_range(&r, -2, 2);
        p.shading.wrap = ht_rng_unit(&r);
        p.ao = trial % 3 != 0;
        p.albedo_scale = trial % 4 == 0 ? 2.5 : 1.0;
        p.lights = 1 + trial % HT_MAX_LIGHTS;
        ht_light lights[HT_MAX_LIGHTS];
        for (int l = 0; l < p.lights; l++) {
            lights[l].type = (trial + l) % 2 ? HT_LIGHT_POINT : HT_LIGHT_DIRECTIONAL;
            random_unit(&r, lights[l].vector);
            for (int k = 0; k < 3; k++) {
                if (lights[l].type == HT_LIGHT_POINT) lights[l].vector[k] *= 3.0f;
                lights[l].color[k] = (float)ht_rng_range(&r, 0, 4);
            }
        }
        float eye[3];
        random_unit(&r, eye);
        for (int k = 0; k < 3; k++) eye[k] *= 4.0f;
        random_vertices(&r, v, COUNT);
        double worst = compare(&p, v, COUNT, lights, p.lights, eye);
        if (trial % 8 == 7 || trial % 4 == 2)
            printf("trial %d%s: worst relative error %.3g\n", trial,
                   ht_model_has_transmission(&p.shading) ? " (transmission)" : "", worst);
    }
}

static void test_colours_give_the_models_answers_at_its_undefined_points(void **state) {
    (void)state;
    for (int m = 0; m < 2; m++) {
        ht_gl11_program p = sample_program(m ? HT_MODEL_KAJIYA_KAY : HT_MODEL_SCHEUERMANN);
        const float eye[3] = { 0, 0, 3 };
        /* L = -V (no half vector), a zero tangent, a zero normal, T = -shift N
           (no direction after the shift), a vertex at the eye, a point light
           at the vertex */
        ht_light lights[2] = { { HT_LIGHT_DIRECTIONAL, { 0, 0, -1 }, { 1, 1, 1 } },
                               { HT_LIGHT_POINT, { 0.5f, 0, 0 }, { 2, 2, 2 } } };
        ht_vertex v[6];
        memset(v, 0, sizeof v);
        for (int i = 0; i < 6; i++) {
            v[i].tangent[1] = 1;
            v[i].normal[2] = 1;
            v[i].ao = 1;
        }
        v[1].tangent[1] = 0;
        v[2].normal[2] = 0;
        v[3].tangent[1] = 0; /* T = -shift N: no direction after the primary shift */
        v[3].tangent[2] = 0.1f;
        v[4].position[2] = 3;   /* at the eye: V has no direction */
        v[5].position[0] = 0.5f; /* at the point light */
        for (int n = 1; n <= 2; n++) compare(&p, v, 6, lights, n, eye);
        /* exponent 0 with a zero sine: 0^0 = 1 */
        p.shading.primary.exponent = 0;
        compare(&p, v, 6, lights, 2, eye);
    }
}

static void test_lights_beyond_the_program_and_none_are_handled(void **state) {
    (void)state;
    ht_gl11_program p = sample_program(HT_MODEL_SCHEUERMANN);
    p.lights = 1;
    ht_rng r = ht_rng_seed(5);
    ht_vertex v[9];
    random_vertices(&r, v, 9);
    ht_light lights[2] = { { HT_LIGHT_DIRECTIONAL, { 0, 1, 0 }, { 1, 1, 1 } },
                           { HT_LIGHT_DIRECTIONAL, { 1, 0, 0 }, { 4, 4, 4 } } };
    const float eye[3] = { 0, 0, 3 };
    /* the second light is beyond the program's: not shaded */
    ht_gl11_soa soa;
    assert_int_equal(ht_gl11_soa_make(&p, v, 9, &soa), HT_OK);
    float one[4 * 16], two[4 * 16], none[4 * 16];
    ht_gl11_shade(&p, &soa, lights, 1, eye, one);
    ht_gl11_shade(&p, &soa, lights, 2, eye, two);
    assert_memory_equal(one, two, sizeof(float) * 4 * 9);
    ht_gl11_shade(&p, &soa, NULL, 0, eye, none);
    for (int i = 0; i < 9; i++) {
        for (int c = 0; c < 3; c++) assert_true(none[4 * i + c] == 0.0f);
        assert_true(none[4 * i + 3] == 1.0f);
    }
    ht_gl11_soa_free(&soa);
    /* an empty mesh still has one (zero) block */
    assert_int_equal(ht_gl11_soa_make(&p, NULL, 0, &soa), HT_OK);
    assert_int_equal(soa.padded, HT_GL11_BLOCK);
    ht_gl11_shade(&p, &soa, lights, 1, eye, none);
    ht_gl11_soa_free(&soa);
}

/* ---- the emitter ---- */

static void test_emitter_asks_for_gl11_one_unit_and_no_extension(void **state) {
    (void)state;
    ht_material m;
    ht_scene scene;
    char err[512] = "";
    if (ht_material_load("materials/dark-brown.json", &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    if (ht_scene_load("scenes/furball.json", &scene, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_generated g;
    if (ht_generate(&(ht_generate_desc){ .material = &m, .scene = &scene }, &g, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    /* listed last, after fixed */
    const char *gl11 = strstr(g.manifest, "\"name\":\t\"gl11\"");
    const char *fixed = strstr(g.manifest, "\"name\":\t\"fixed\"");
    assert_non_null(gl11);
    assert_non_null(fixed);
    assert_true(gl11 > fixed);
    assert_null(strstr(gl11 + 1, "\"name\":"));
    assert_non_null(strstr(gl11, "\"gl\":\t\"1.1\""));
    assert_non_null(strstr(gl11, "\"extensions\":\t[]"));
    assert_non_null(strstr(gl11, "\"texture_units\":\t1"));
    assert_non_null(strstr(gl11, "\"program\":\t\"gl11.json\""));
    assert_non_null(strstr(gl11, "lighting above"));
    ht_generated_free(&g);

    ht_plan plan;
    ht_plan_make(&m, &scene, &plan);
    plan.sparkle_mean = 0.5;
    plan.albedo_max = 0.4;
    ht_tier_output out;
    assert_int_equal(ht_emit_gl11(&plan, &out, err, sizeof err), HT_OK);
    assert_int_equal(out.tier, HT_TIER_GL11);
    assert_string_equal(out.requires.gl, "1.1");
    assert_int_equal(out.requires.extension_count, 0);
    assert_int_equal(out.requires.texture_units, 1);
    assert_int_equal(out.text_count, 1);
    ht_gl11_program p;
    if (ht_gl11_parse(out.texts[0].text, out.texts[0].file, &p, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_int_equal(p.lights, plan.light_count);
    assert_true(fabs(p.albedo_scale - 2.5) < 1e-12);
    assert_true(fabs(p.shading.secondary.color[0] - 0.5 * m.shading.secondary.color[0]) < 1e-12);
    ht_tier_output_free(&out);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_program_round_trips_byte_identical),
        cmocka_unit_test(test_program_rejects_bad_fields_naming_them),
        cmocka_unit_test(test_albedo_scale_is_the_headroom_the_albedo_leaves),
        cmocka_unit_test(test_colours_track_the_double_oracle_at_the_vertices),
        cmocka_unit_test(test_colours_give_the_models_answers_at_its_undefined_points),
        cmocka_unit_test(test_lights_beyond_the_program_and_none_are_handled),
        cmocka_unit_test(test_emitter_asks_for_gl11_one_unit_and_no_extension),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

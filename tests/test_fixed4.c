/* test_fixed4 — the fixed4 tier's program and the numbers it feeds the
   device, held against runtime/shading/model.c without GL: the program's JSON, the
   runtime-baked LUTs at texel centres, the texture matrices' coordinates,
   the local-viewer loop and the static per-vertex arrays. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "combiner.h"
#include "fixed4_program.h"
#include "rng.h"

static ht_fixed4_program scheuermann(int lights) {
    ht_fixed4_program p;
    memset(&p, 0, sizeof p);
    p.shading.model = HT_MODEL_SCHEUERMANN;
    p.shading.diffuse_color[0] = 0.23, p.shading.diffuse_color[1] = 0.14, p.shading.diffuse_color[2] = 0.08;
    p.shading.wrap = 0.25;
    p.shading.primary = (ht_lobe){ { 1.0, 0.95, 0.9 }, 80, -0.1 };
    p.shading.secondary = (ht_lobe){ { 0.55, 0.4, 0.28 }, 24, 0.15 };
    p.lights = lights;
    p.ao = true;
    p.lut_axis[0] = 128;
    p.lut_axis[1] = 64;
    return p;
}

static ht_fixed4_program kajiya_kay(int lights) {
    ht_fixed4_program p = scheuermann(lights);
    p.shading.model = HT_MODEL_KAJIYA_KAY;
    p.shading.secondary = (ht_lobe){ { 0, 0, 0 }, 0, 0 };
    p.shading.primary.shift = 0;
    p.lut_axis[0] = 256;
    return p;
}

static void test_program_round_trips_byte_identically(void **state) {
    (void)state;
    const ht_fixed4_program programs[3] = { scheuermann(2), scheuermann(1), kajiya_kay(2) };
    for (int i = 0; i < 3; i++) {
        ht_fixed4_program p = programs[i];
        p.viewer = i == 1 ? HT_FIXED4_VIEWER_LOCAL : HT_FIXED4_VIEWER_INFINITE;
        char *text = NULL, *again = NULL, err[256] = "";
        assert_int_equal(ht_fixed4_write(&p, &text, err, sizeof err), HT_OK);
        ht_fixed4_program back;
        if (ht_fixed4_parse(text, "fixed4.json", &back, err, sizeof err) != HT_OK) fail_msg("%s", err);
        assert_int_equal(back.lights, p.lights);
        assert_int_equal(back.viewer, p.viewer);
        assert_int_equal(back.shading.model, p.shading.model);
        assert_int_equal(back.lut_axis[0], p.lut_axis[0]);
        assert_int_equal(back.lut_axis[1], p.lut_axis[1]);
        assert_true(back.shading.primary.exponent == p.shading.primary.exponent);
        assert_int_equal(ht_fixed4_write(&back, &again, err, sizeof err), HT_OK);
        assert_string_equal(text, again);
        free(text);
        free(again);
    }
}

/* Each bad field is refused with one line naming it. */
static void test_bad_programs_name_the_field(void **state) {
    (void)state;
    ht_fixed4_program p = scheuermann(2);
    char *text = NULL, err[256];
    assert_int_equal(ht_fixed4_write(&p, &text, err, sizeof err), HT_OK);
    static const struct {
        const char *from, *to, *field;
    } cases[] = {
        { "\"lights\":\t2", "\"lights\":\t3", "lights" },
        { "\"lights\":\t2", "\"lights\":\t0", "lights" },
        { "\"viewer\":\t\"infinite\"", "\"viewer\":\t\"near\"", "viewer" },
        { "\"ao\":\ttrue", "\"ao\":\t1", "ao" },
        { "\"wrap\":\t0.25", "\"wrap\":\t1.5", "diffuse.wrap" },
        { "\"exponent\":\t80", "\"exponent\":\t1e9", "primary.exponent" },
        { "[128, 64]", "[100, 64]", "lut_axis[0]" },
        { "[128, 64]", "[128, 512]", "lut_axis" },
        { "\"format\":\t\"hairtier-fixed4/1\"", "\"format\":\t\"hairtier-fixed4/2\"", "format" },
        { "\"model\":", "\"modle\":", "modle" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const char *at = strstr(text, cases[i].from);
        if (!at) fail_msg("case %zu: \"%s\" not in:\n%s", i, cases[i].from, text);
        char bad[4096];
        snprintf(bad, sizeof bad, "%.*s%s%s", (int)(at - text), text, cases[i].to, at + strlen(cases[i].from));
        ht_fixed4_program out;
        err[0] = '\0';
        assert_int_equal(ht_fixed4_parse(bad, "f.json", &out, err, sizeof err), HT_ERR_PARSE);
        char want[96];
        snprintf(want, sizeof want, "f.json: %s", cases[i].field);
        if (strncmp(err, want, strlen(want)) != 0) fail_msg("case %zu: want \"%s...\", got \"%s\"", i, want, err);
        assert_null(strchr(err, '\n'));
    }
    /* Kajiya-Kay has one lobe. */
    ht_fixed4_program kk = kajiya_kay(1);
    char *kk_text = NULL;
    assert_int_equal(ht_fixed4_write(&kk, &kk_text, err, sizeof err), HT_OK);
    char *with_secondary = malloc(strlen(kk_text) + 128);
    char *close = strrchr(kk_text, '}');
    sprintf(with_secondary, "%.*s, \"secondary\": {\"color\": [0,0,0], \"exponent\": 1, \"shift\": 0}}\n",
            (int)(close - kk_text - 1), kk_text);
    ht_fixed4_program out;
    assert_int_equal(ht_fixed4_parse(with_secondary, "kk.json", &out, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "kk.json: secondary"));
    free(with_secondary);
    free(kk_text);
    free(text);
}

static uint8_t expected_texel(double v) { return v <= 0 ? 0 : (v >= 1 ? 255 : (uint8_t)lround(v * 255.0)); }

/* Every texel holds the model's highlight at its centre d = 2x/(n-1) - 1,
   weighted by the two lights' colours and divided by the scale. */
static void test_luts_hold_the_model_at_texel_centres(void **state) {
    (void)state;
    const float colors[2][3] = { { 1.0f, 0.97f, 0.92f }, { 0.35f, 0.4f, 0.5f } };
    ht_fixed4_program p = scheuermann(2);
    int scale = ht_fixed4_scale(&p, colors);
    assert_int_equal(scale, 4); /* red: (0.23 + 1 + 0.55) x (1 + 0.35) = 2.40, above 2 */
    for (int k = 0; k < 2; k++) {
        ht_image img;
        assert_int_equal(ht_fixed4_bake_lut(&p, k, colors, scale, &img), HT_OK);
        const ht_lobe *lobe = k == 0 ? &p.shading.primary : &p.shading.secondary;
        assert_int_equal(img.width, p.lut_axis[k]);
        assert_int_equal(img.height, p.lut_axis[k]);
        for (int y = 0; y < img.height; y += 7)
            for (int x = 0; x < img.width; x += 5)
                for (int ch = 0; ch < 3; ch++) {
                    double s0 = ht_model_highlight_of_cos_d(ht_combiner_lut_centre(x, img.width), lobe->exponent);
                    double s1 = ht_model_highlight_of_cos_d(ht_combiner_lut_centre(y, img.height), lobe->exponent);
                    double v = lobe->color[ch] * (colors[0][ch] * s0 + colors[1][ch] * s1) / scale;
                    assert_int_equal(img.pixels[((size_t)y * (size_t)img.width + (size_t)x) * 3 + (size_t)ch],
                                     expected_texel(v));
                }
        ht_image_free(&img);
    }
    /* One light: a single row. */
    ht_fixed4_program one = scheuermann(1);
    ht_image row;
    assert_int_equal(ht_fixed4_bake_lut(&one, 1, colors, 1, &row), HT_OK);
    assert_int_equal(row.height, 1);
    ht_image_free(&row);
    /* Kajiya-Kay: light k's LUT, sin(T,L) along x, S(T.H) along y. */
    ht_fixed4_program kk = kajiya_kay(2);
    ht_image img;
    assert_int_equal(ht_fixed4_bake_lut(&kk, 1, colors, 2, &img), HT_OK);
    for (int y = 0; y < img.height; y += 9)
        for (int x = 0; x < img.width; x += 11) {
            double a = ht_combiner_lut_centre(x, img.width), b = ht_combiner_lut_centre(y, img.height);
            double v = colors[1][0] * (kk.shading.diffuse_color[0] * sqrt(fmax(0, 1 - a * a)) +
                                       kk.shading.primary.color[0] * ht_model_highlight_of_cos_d(b, 80)) / 2;
            assert_int_equal(img.pixels[((size_t)y * (size_t)img.width + (size_t)x) * 3], expected_texel(v));
        }
    ht_image_free(&img);
}

static void random_unit(ht_rng *rng, double v[3]) {
    double len;
    do {
        for (int i = 0; i < 3; i++) v[i] = 2.0 * ht_rng_unit(rng) - 1.0;
        len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (len < 0.1 || len > 1.0);
    for (int i = 0; i < 3; i++) v[i] /= len;
}

static void apply(const float m[16], const double v[3], double out[4]) {
    for (int r = 0; r < 4; r++) out[r] = m[r] * v[0] + m[4 + r] * v[1] + m[8 + r] * v[2] + m[12 + r];
}

static void half_vector(const double L[3], const double V[3], double H[3]) {
    double n = 0;
    for (int i = 0; i < 3; i++) n += (H[i] = L[i] + V[i]) * (L[i] + V[i]);
    for (int i = 0; i < 3; i++) H[i] /= sqrt(n);
}

/* The matrix turns a static unit vector into the LUT coordinates of its dot
   products with the frame's H0 and H1 (L and H for Kajiya-Kay). */
static void test_texture_matrix_gives_the_lut_coordinates_of_the_dot_products(void **state) {
    (void)state;
    ht_rng rng = ht_rng_seed(7);
    ht_fixed4_program p = scheuermann(2), kk = kajiya_kay(2);
    for (int trial = 0; trial < 2000; trial++) {
        double L[2][3], V[3], t[3], H[2][3], c[4];
        random_unit(&rng, L[0]);
        random_unit(&rng, L[1]);
        random_unit(&rng, V);
        random_unit(&rng, t);
        half_vector(L[0], V, H[0]);
        half_vector(L[1], V, H[1]);
        float Lf[2][3], Vf[3], m[16];
        for (int i = 0; i < 3; i++) Lf[0][i] = (float)L[0][i], Lf[1][i] = (float)L[1][i], Vf[i] = (float)V[i];
        ht_fixed4_texture_matrix(&p, trial % 2, Lf, Vf, m);
        apply(m, t, c);
        int n = p.lut_axis[trial % 2];
        double d0 = t[0] * H[0][0] + t[1] * H[0][1] + t[2] * H[0][2];
        double d1 = t[0] * H[1][0] + t[1] * H[1][1] + t[2] * H[1][2];
        assert_float_equal(c[0], ht_combiner_lut_coord(d0, n), 2e-6);
        assert_float_equal(c[1], ht_combiner_lut_coord(d1, n), 2e-6);
        assert_float_equal(c[3], 1.0, 0);
        ht_fixed4_texture_matrix(&kk, 1, Lf, Vf, m);
        apply(m, t, c);
        double tl = t[0] * L[1][0] + t[1] * L[1][1] + t[2] * L[1][2];
        assert_float_equal(c[0], ht_combiner_lut_coord(tl, kk.lut_axis[0]), 2e-6);
        assert_float_equal(c[1], ht_combiner_lut_coord(d1, kk.lut_axis[1]), 2e-6);
    }
    /* L = -V leaves H without a direction: the model's S = 0, read at d = -1. */
    const float L[2][3] = { { 0, 0, 1 }, { 0, 1, 0 } }, V[3] = { 0, 0, -1 };
    float m[16];
    ht_fixed4_texture_matrix(&p, 0, L, V, m);
    const double any[3] = { 0.3, 0.4, 0.866 };
    double c[4];
    apply(m, any, c);
    assert_float_equal(c[0], ht_combiner_lut_coord(-1.0, p.lut_axis[0]), 1e-7);
    for (int i = 0; i < 16; i++) assert_true(isfinite(m[i]));
}

/* The local-viewer loop, in float, against the same dot products in double
   with V = normalize(eye - position) per vertex. */
static void test_local_viewer_coordinates_track_the_double_dot_products(void **state) {
    (void)state;
    ht_rng rng = ht_rng_seed(11);
    enum { N = 500 };
    ht_vertex v[N];
    for (int i = 0; i < N; i++) {
        double T[3], B[3], Nn[3];
        random_unit(&rng, T);
        random_unit(&rng, B);
        Nn[0] = T[1] * B[2] - T[2] * B[1], Nn[1] = T[2] * B[0] - T[0] * B[2], Nn[2] = T[0] * B[1] - T[1] * B[0];
        double nl = sqrt(Nn[0] * Nn[0] + Nn[1] * Nn[1] + Nn[2] * Nn[2]);
        for (int k = 0; k < 3; k++) {
            v[i].position[k] = (float)(2.0 * ht_rng_unit(&rng) - 1.0);
            v[i].tangent[k] = (float)T[k];
            v[i].normal[k] = (float)(Nn[k] / nl);
        }
        v[i].ao = (float)ht_rng_unit(&rng);
    }
    memset(v[0].tangent, 0, sizeof v[0].tangent); /* a strand without a direction */
    ht_fixed4_program p = scheuermann(2);
    p.viewer = HT_FIXED4_VIEWER_LOCAL;
    ht_fixed4_soa soa;
    assert_int_equal(ht_fixed4_soa_make(&p, v, N, &soa), HT_OK);
    float *coords[2] = { malloc(2 * N * sizeof(float)), malloc(2 * N * sizeof(float)) };
    const float L[2][3] = { { 0.6f, 0.8f, 0.0f }, { -0.7f, 0.2f, -0.6f } }, eye[3] = { 0.8f, 1.6f, 2.7f };
    ht_fixed4_local_coords(&p, &soa, L, eye, coords);
    float vec[2][3 * N], colors[4 * N];
    ht_fixed4_vertex_arrays(&p, v, N, vec[0], vec[1], colors);
    assert_float_equal(colors[3], 0.0, 0); /* no tangent: black */
    for (int i = 1; i < N; i++) {
        double V[3], Ld[2][3];
        for (int k = 0; k < 3; k++) V[k] = eye[k] - v[i].position[k];
        double vl = sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
        for (int k = 0; k < 3; k++) V[k] /= vl;
        for (int l = 0; l < 2; l++) {
            double ll = sqrt(L[l][0] * L[l][0] + L[l][1] * L[l][1] + L[l][2] * L[l][2]);
            for (int k = 0; k < 3; k++) Ld[l][k] = L[l][k] / ll;
        }
        for (int lut = 0; lut < 2; lut++)
            for (int l = 0; l < 2; l++) {
                double H[3], d = 0;
                half_vector(Ld[l], V, H);
                for (int k = 0; k < 3; k++) d += vec[lut][3 * i + k] * H[k];
                assert_float_equal(coords[lut][2 * i + l], ht_combiner_lut_coord(d, p.lut_axis[lut]), 2e-5);
            }
        assert_float_equal(colors[4 * i + 3], v[i].ao, 1e-7);
    }
    free(coords[0]);
    free(coords[1]);
    ht_fixed4_soa_free(&soa);
}

static void test_static_tangents_are_the_models_shifted_tangents(void **state) {
    (void)state;
    ht_fixed4_program p = scheuermann(2);
    ht_vertex v = { .tangent = { 0, 2, 0 }, .normal = { 0, 0, 3 }, .ao = 0.5f };
    float t1[3], t2[3], c[4];
    ht_fixed4_vertex_arrays(&p, &v, 1, t1, t2, c);
    const double s1 = -0.1, s2 = 0.15;
    assert_float_equal(t1[1], 1 / sqrt(1 + s1 * s1), 1e-6);
    assert_float_equal(t1[2], s1 / sqrt(1 + s1 * s1), 1e-6);
    assert_float_equal(t2[2], s2 / sqrt(1 + s2 * s2), 1e-6);
    assert_float_equal(c[0], 1.0, 0);
    assert_float_equal(c[3], 0.5, 1e-7);
    ht_fixed4_program kk = kajiya_kay(1);
    ht_fixed4_vertex_arrays(&kk, &v, 1, t1, NULL, c);
    assert_float_equal(t1[1], 1.0, 1e-7);
    assert_float_equal(c[0], 0.0, 0); /* Kajiya-Kay's diffuse is in the LUT: no GL lighting */
}

/* set_mesh makes the vectors once and hands them over: vec1 NULL reads
   vec0 for both LUTs (Kajiya-Kay), as ht_fixed4_soa_make does. */
static void test_soa_from_arrays_keeps_each_luts_vector(void **state) {
    (void)state;
    ht_vertex v[2] = { { .position = { 1, 2, 3 } }, { .position = { -4, 5, -6 } } };
    const float vec0[6] = { 0, 1, 0, 1, 0, 0 }, vec1[6] = { 0, 0, 1, 0, -1, 0 };
    ht_fixed4_soa soa;
    assert_int_equal(ht_fixed4_soa_from_arrays(v, 2, vec0, vec1, &soa), HT_OK);
    assert_int_equal(soa.count, 2);
    assert_float_equal(soa.px[1], -4.0, 0);
    assert_float_equal(soa.pz[0], 3.0, 0);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 3; j++) {
            assert_float_equal(soa.v[0][j][i], vec0[3 * i + j], 0);
            assert_float_equal(soa.v[1][j][i], vec1[3 * i + j], 0);
        }
    ht_fixed4_soa_free(&soa);
    assert_int_equal(ht_fixed4_soa_from_arrays(v, 2, vec0, NULL, &soa), HT_OK);
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 3; j++) assert_float_equal(soa.v[1][j][i], vec0[3 * i + j], 0);
    ht_fixed4_soa_free(&soa);
}

static void test_scale_covers_the_brightest_channel(void **state) {
    (void)state;
    ht_fixed4_program p = scheuermann(1);
    const float dim[1][3] = { { 0.4f, 0.4f, 0.4f } }, bright[1][3] = { { 3.0f, 3.0f, 3.0f } };
    assert_int_equal(ht_fixed4_scale(&p, dim), 1);   /* 1.78 x 0.4 */
    assert_int_equal(ht_fixed4_scale(&p, bright), 4); /* above 4: clamps, documented */
    assert_int_equal(ht_fixed4_scale(&p, NULL), 1);
}

/* What GL lighting sums for one channel (fixed4.c's set_lighting): per
   light kd lc (wrap + (1 - wrap) max(x, 0) - back max(-x, 0)), the sum
   clamped at 0. */
static double gl_diffuse(const ht_fixed4_program *p, const double back[], const double x[], const double k[]) {
    const double w = p->shading.wrap;
    double sum = 0.0;
    for (int l = 0; l < p->lights; l++) sum += k[l] * (w + (1.0 - w) * fmax(x[l], 0.0) - back[l] * fmax(-x[l], 0.0));
    return fmax(sum, 0.0);
}

/* GL clamps the lights' sum once, the model each light: one light is exact
   for any wrap; with two, the brighter light is exact and the other's term
   never negative and at most wrap (1 - 2 wrap) / (1 - wrap) kd lc above
   the model's; wrap 0 is exact for both. */
static void test_gl_lighting_slopes_keep_each_light_near_the_models_wrapped_diffuse(void **state) {
    (void)state;
    const double wraps[] = { 0.0, 0.25, 0.35, 0.6 };
    for (size_t i = 0; i < sizeof wraps / sizeof wraps[0]; i++) {
        const double w = wraps[i];
        for (int lights = 1; lights <= 2; lights++) {
            ht_fixed4_program p = scheuermann(lights);
            p.shading.wrap = w;
            /* the second light twice the first: it is the exact one */
            const float colors[2][3] = { { 0.3f, 0.3f, 0.3f }, { 0.6f, 0.5f, 0.7f } };
            double back[HT_FIXED4_MAX_LIGHTS];
            ht_fixed4_back_slopes(&p, colors, back);
            const double chord = fmin(w, 1.0 - w), excess = w > 0.0 && w < 0.5 ? w * (1.0 - 2.0 * w) / (1.0 - w) : 0.0;
            assert_true(back[lights - 1] == (w > 0.0 && w < 0.5 ? 1.0 - w : chord));
            if (lights == 2) assert_true(back[0] == chord);
            const double k[2] = { p.shading.diffuse_color[0] * colors[0][0], p.shading.diffuse_color[0] * colors[1][0] };
            for (int a = 0; a <= 40; a++)
                for (int b = 0; b <= (lights == 2 ? 40 : 0); b++) {
                    const double x[2] = { a / 20.0 - 1.0, b / 20.0 - 1.0 };
                    double model = 0.0, exact_other = 0.0;
                    for (int l = 0; l < lights; l++) model += k[l] * ht_model_wrap_diffuse_d(x[l], w);
                    const double got = gl_diffuse(&p, back, x, k);
                    if (lights == 1 || w == 0.0 || w >= 0.5) {
                        assert_true(fabs(got - model) < 1e-12);
                        continue;
                    }
                    /* light 0 alone (light 1 exact by itself): a chord, never below the model */
                    const double x0[2] = { x[0], 1.0 };
                    const double kd0[2] = { k[0], 0.0 };
                    exact_other = gl_diffuse(&p, back, x0, kd0) - k[0] * ht_model_wrap_diffuse_d(x[0], w);
                    assert_true(exact_other >= -1e-12 && exact_other <= excess * k[0] + 1e-12);
                    /* both lit on their wrapped side: exact */
                    if (w + (1.0 - w) * x[1] >= 0.0) assert_true(fabs(got - model) <= excess * k[0] + 1e-12);
                    /* the brighter light behind its kink can only take from the other */
                    else assert_true(got <= model + excess * k[0] + 1e-12);
                }
        }
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_program_round_trips_byte_identically),
        cmocka_unit_test(test_bad_programs_name_the_field),
        cmocka_unit_test(test_luts_hold_the_model_at_texel_centres),
        cmocka_unit_test(test_texture_matrix_gives_the_lut_coordinates_of_the_dot_products),
        cmocka_unit_test(test_local_viewer_coordinates_track_the_double_dot_products),
        cmocka_unit_test(test_static_tangents_are_the_models_shifted_tangents),
        cmocka_unit_test(test_soa_from_arrays_keeps_each_luts_vector),
        cmocka_unit_test(test_scale_covers_the_brightest_channel),
        cmocka_unit_test(test_gl_lighting_slopes_keep_each_light_near_the_models_wrapped_diffuse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

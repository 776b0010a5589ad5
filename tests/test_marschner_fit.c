/* test_marschner_fit.c — Scheuermann constants fitted to a Marschner
   material (shadergen/marschner_fit.c): the fit is deterministic, its
   constants are a valid Scheuermann material, its error is what it reports
   (recomputed here on samples of our own) and no worse than the best of
   a few hand-picked constants, and hairgen writes it into the manifest and
   the lower tiers of a Marschner bundle. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairgen.h>
#include "marschner_fit.h"
#include "rng.h"

#define DEG (HT_PI / 180)

static ht_shading brown(void) {
    return (ht_shading){ .model = HT_MODEL_MARSCHNER, .diffuse_color = { 0.06, 0.035, 0.02 },
                         .marschner = { { 0.42, 0.70, 1.25 }, -7 * DEG, 7 * DEG, 1.55 } };
}

/* RMS over our own samples (another seed, the same distribution). */
static double rms_against(const ht_shading *fibre, const ht_shading *fit) {
    ht_rng rng = ht_rng_seed(99);
    double sum = 0;
    int n = 0;
    while (n < 4000) {
        double T[3], N[3], L[3], V[3];
        for (int i = 0; i < 3; i++) T[i] = ht_rng_range(&rng, -1, 1), N[i] = ht_rng_range(&rng, -1, 1),
                                    L[i] = ht_rng_range(&rng, -1, 1), V[i] = ht_rng_range(&rng, -1, 1);
        double t2 = T[0] * T[0] + T[1] * T[1] + T[2] * T[2];
        double d = (N[0] * T[0] + N[1] * T[1] + N[2] * T[2]) / t2;
        for (int i = 0; i < 3; i++) N[i] -= d * T[i];
        double nl = N[0] * L[0] + N[1] * L[1] + N[2] * L[2], nv = N[0] * V[0] + N[1] * V[1] + N[2] * V[2];
        double ln = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]), nn = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
        if (nn < 1e-3 || ln < 1e-3 || ln > 1 || nl / (ln * nn) < -0.25 || nv <= 0) continue;
        ht_surface s = { .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = 1 };
        memcpy(s.T, T, sizeof T);
        memcpy(s.N, N, sizeof N);
        memcpy(s.V, V, sizeof V);
        ht_light_ray light = { .color = { 1, 1, 1 } };
        memcpy(light.L, L, sizeof L);
        double want[3], got[3];
        ht_model_shade_d(fibre, &s, &light, 1, want);
        ht_model_shade_d(fit, &s, &light, 1, got);
        for (int c = 0; c < 3; c++) {
            double e = got[c] - fmin(want[c], 1);
            sum += e * e;
        }
        n++;
    }
    return sqrt(sum / (3.0 * n));
}

static void fit_is_a_valid_deterministic_scheuermann_material(void **state) {
    (void)state;
    ht_shading m = brown();
    ht_marschner_fit a, b;
    assert_int_equal(ht_marschner_fit_scheuermann(&m, &a), HT_OK);
    assert_int_equal(ht_marschner_fit_scheuermann(&m, &b), HT_OK);
    assert_memory_equal(&a, &b, sizeof a);
    assert_int_equal(a.shading.model, HT_MODEL_SCHEUERMANN);
    ht_material mat = { .name = "fit", .shading = a.shading };
    char err[256];
    assert_int_equal(ht_material_check(&mat, err, sizeof err), HT_OK);
    print_message("brown fit: rms %.4f (%.1f/255), max %.3f; diffuse %.3f %.3f %.3f wrap %.2f; primary %.3f e %.1f "
                  "s %.3f; secondary %.3f e %.1f s %.3f\n", a.rms, a.rms * 255, a.max_error, a.shading.diffuse_color[0],
                  a.shading.diffuse_color[1], a.shading.diffuse_color[2], a.shading.wrap, a.shading.primary.color[0],
                  a.shading.primary.exponent, a.shading.primary.shift, a.shading.secondary.color[0],
                  a.shading.secondary.exponent, a.shading.secondary.shift);
    /* A Scheuermann material is not fitted. */
    ht_shading s = a.shading;
    assert_int_equal(ht_marschner_fit_scheuermann(&s, &b), HT_ERR_INVALID_ARGUMENT);
}

static void fit_error_holds_on_other_samples_and_beats_hand_picked_constants(void **state) {
    (void)state;
    ht_shading m = brown();
    ht_marschner_fit fit;
    assert_int_equal(ht_marschner_fit_scheuermann(&m, &fit), HT_OK);
    double own = rms_against(&m, &fit.shading);
    print_message("rms on the fit's samples %.4f, on others %.4f\n", fit.rms, own);
    assert_true(fabs(own - fit.rms) < 0.25 * fit.rms); /* no overfitting to its own 3000 points */
    /* dark-brown's constants and a black material are worse */
    ht_shading dark = { .model = HT_MODEL_SCHEUERMANN, .diffuse_color = { 0.23, 0.14, 0.08 }, .wrap = 0.25,
                        .primary = { { 1.0, 0.95, 0.9 }, 80, -0.1 }, .secondary = { { 0.55, 0.40, 0.28 }, 24, 0.15 } };
    ht_shading black = { .model = HT_MODEL_SCHEUERMANN };
    assert_true(own < rms_against(&m, &dark));
    assert_true(own < rms_against(&m, &black));
}

static void hairgen_writes_the_fit_into_the_manifest_and_every_lower_tier(void **state) {
    (void)state;
    ht_material mat;
    char err[512];
    assert_int_equal(ht_material_load("materials/brown-marschner.json", &mat, err, sizeof err), HT_OK);
    ht_generated g;
    assert_int_equal(ht_generate(&(ht_generate_desc){ .material = &mat }, &g, err, sizeof err), HT_OK);
    const char *files[] = { "marschner.frag", "full.frag", "vertex.vert", "fixed.json", "gl11.json" };
    for (size_t i = 0; i < sizeof files / sizeof *files; i++)
        if (!ht_generated_find(&g, files[i])) fail_msg("no %s", files[i]);
    assert_non_null(strstr(g.manifest, "\"fit\":"));
    assert_non_null(strstr(g.manifest, "\"rms_error\":"));
    assert_non_null(strstr(g.manifest, "Scheuermann constants fitted to it"));
    ht_generated_free(&g);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fit_is_a_valid_deterministic_scheuermann_material),
        cmocka_unit_test(fit_error_holds_on_other_samples_and_beats_hand_picked_constants),
        cmocka_unit_test(hairgen_writes_the_fit_into_the_manifest_and_every_lower_tier),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

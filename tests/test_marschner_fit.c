/* test_marschner_fit.c — Scheuermann constants with a transmission lobe
   fitted to a Marschner material under a scene's lights
   (shadergen/marschner_fit.c): the fit is deterministic, its constants are
   a valid Scheuermann material, its error is held to the measured level
   per scene (rms and max over its samples, the lobe's shape against M_TT
   N_TT), is what it reports (recomputed here on samples of our own) and no
   worse than a few hand-picked constants, and hairgen writes it into the
   manifest and the lower tiers of a Marschner bundle. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairgen.h>
#include <hairtier/scene.h>
#include "marschner_fit.h"
#include "rng.h"

#define DEG (HT_PI / 180)

static ht_shading brown(void) {
    return (ht_shading){ .model = HT_MODEL_MARSCHNER, .diffuse_color = { 0.06, 0.035, 0.02 },
                         .marschner = { { 0.42, 0.70, 1.25 }, -7 * DEG, 7 * DEG, 1.55 } };
}

static ht_scene scene(const char *path) {
    ht_scene sc;
    char err[512];
    if (ht_scene_load(path, &sc, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return sc;
}

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void unit(double v[3]) {
    double len = sqrt(dot(v, v));
    for (int i = 0; i < 3; i++) v[i] /= len;
}

/* RMS over our own samples of the scene's layout (another seed, the
   distribution marschner_fit.c's header states: its view directions, its
   lights, T anywhere, N perpendicular to T towards the viewer), both sides
   clamped to [0, 1]. */
static double rms_against(const ht_shading *fibre, const ht_shading *fit, const ht_scene *sc) {
    ht_rng rng = ht_rng_seed(99);
    const ht_camera *cam = &sc->camera;
    double fwd[3], right[3], up[3];
    for (int i = 0; i < 3; i++) fwd[i] = (double)cam->target[i] - cam->eye[i];
    unit(fwd);
    right[0] = fwd[1] * cam->up[2] - fwd[2] * cam->up[1];
    right[1] = fwd[2] * cam->up[0] - fwd[0] * cam->up[2];
    right[2] = fwd[0] * cam->up[1] - fwd[1] * cam->up[0];
    unit(right);
    up[0] = right[1] * fwd[2] - right[2] * fwd[1];
    up[1] = right[2] * fwd[0] - right[0] * fwd[2];
    up[2] = right[0] * fwd[1] - right[1] * fwd[0];
    const double k = tan((double)cam->fov_y * HT_PI / 360);
    double sum = 0;
    int n = 0;
    while (n < 4000) {
        double T[3], N[3], V[3], x = ht_rng_range(&rng, -k, k), y = ht_rng_range(&rng, -k, k);
        for (int i = 0; i < 3; i++) T[i] = ht_rng_range(&rng, -1, 1), N[i] = ht_rng_range(&rng, -1, 1);
        for (int i = 0; i < 3; i++) V[i] = -(fwd[i] + x * right[i] + y * up[i]);
        unit(V);
        double t2 = dot(T, T), d = dot(N, T) / t2;
        if (t2 > 1 || t2 < 1e-4) continue;
        for (int i = 0; i < 3; i++) N[i] -= d * T[i];
        if (dot(N, N) < 1e-3 || dot(N, V) <= 0) continue;
        ht_surface s = { .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = 1 };
        memcpy(s.T, T, sizeof T);
        memcpy(s.N, N, sizeof N);
        memcpy(s.V, V, sizeof V);
        ht_light_ray lights[HT_MAX_LIGHTS];
        for (int l = 0; l < sc->light_count; l++)
            for (int i = 0; i < 3; i++) lights[l].L[i] = sc->lights[l].vector[i], lights[l].color[i] = sc->lights[l].color[i];
        double want[3], got[3];
        ht_model_shade_d(fibre, &s, lights, sc->light_count, want);
        ht_model_shade_d(fit, &s, lights, sc->light_count, got);
        for (int c = 0; c < 3; c++) {
            double e = fmin(got[c], 1) - fmin(want[c], 1);
            sum += e * e;
        }
        n++;
    }
    return sqrt(sum / (3.0 * n));
}

/* The measured error of brown's fit per scene (build/tests/test_marschner_fit
   prints it), each bound the measurement plus 2 %: the fit is deterministic,
   so a change that moves it past the bound changed the fit. */
static const struct {
    const char *scene;
    double rms, max, tt_rms; /* [0, 1] units */
} pins[] = {
    { "scenes/backlit.json", 0.1349, 0.9059, 0.0370 },
    { "scenes/furball.json", 0.0218, 0.6095, 0.0051 },
};

/* brown's fit under backlit.json, made once (a fit takes seconds). */
static const ht_marschner_fit *backlit_fit(void) {
    static ht_marschner_fit fit;
    static bool made;
    if (!made) {
        ht_shading m = brown();
        ht_scene sc = scene("scenes/backlit.json");
        assert_int_equal(ht_marschner_fit_scheuermann(&m, &sc, &fit), HT_OK);
        made = true;
    }
    return &fit;
}

static void fit_is_a_valid_deterministic_scheuermann_material_within_its_measured_error(void **state) {
    (void)state;
    ht_shading m = brown();
    for (size_t p = 0; p < sizeof pins / sizeof *pins; p++) {
        ht_scene sc = scene(pins[p].scene);
        ht_marschner_fit a;
        assert_int_equal(ht_marschner_fit_scheuermann(&m, &sc, &a), HT_OK);
        if (p == 0) assert_memory_equal(&a, backlit_fit(), sizeof a); /* the same twice */
        assert_int_equal(a.shading.model, HT_MODEL_SCHEUERMANN);
        ht_material mat = { .name = "fit", .shading = a.shading };
        char err[256];
        assert_int_equal(ht_material_check(&mat, err, sizeof err), HT_OK);
        const ht_transmission *t = &a.shading.transmission;
        print_message("%s: rms %.4f (%.1f/255), max %.4f (%.0f/255), tt shape rms %.4f; diffuse %.3f %.3f %.3f wrap "
                      "%.2f; primary %.3f e %.1f s %.3f; secondary %.3f e %.1f s %.3f; transmission %.3f %.3f %.3f "
                      "centre %.3f sharpness %.0f azimuth %.2f\n",
                      pins[p].scene, a.rms, a.rms * 255, a.max_error, a.max_error * 255, a.tt_rms,
                      a.shading.diffuse_color[0], a.shading.diffuse_color[1], a.shading.diffuse_color[2],
                      a.shading.wrap, a.shading.primary.color[0], a.shading.primary.exponent, a.shading.primary.shift,
                      a.shading.secondary.color[0], a.shading.secondary.exponent, a.shading.secondary.shift,
                      t->color[0], t->color[1], t->color[2], t->centre, t->sharpness, t->azimuth);
        assert_true(ht_model_has_transmission(&a.shading));
        assert_true(a.rms <= pins[p].rms * 1.02);
        assert_true(a.max_error <= pins[p].max * 1.02);
        assert_true(a.tt_rms <= pins[p].tt_rms * 1.02);
    }
    /* A Scheuermann material is not fitted. */
    ht_shading s = brown();
    s.model = HT_MODEL_SCHEUERMANN;
    ht_scene sc = scene("scenes/backlit.json");
    ht_marschner_fit b;
    assert_int_equal(ht_marschner_fit_scheuermann(&s, &sc, &b), HT_ERR_INVALID_ARGUMENT);
}

static void fit_error_holds_on_other_samples_and_beats_hand_picked_constants(void **state) {
    (void)state;
    ht_shading m = brown();
    ht_scene sc = scene("scenes/backlit.json");
    const ht_marschner_fit fit = *backlit_fit();
    double own = rms_against(&m, &fit.shading, &sc);
    print_message("rms on the fit's samples %.4f, on others %.4f\n", fit.rms, own);
    assert_true(fabs(own - fit.rms) < 0.25 * fit.rms); /* no overfitting to its own samples */
    /* dark-brown's constants, a black material, the fit without its lobe are worse */
    ht_shading dark = { .model = HT_MODEL_SCHEUERMANN, .diffuse_color = { 0.23, 0.14, 0.08 }, .wrap = 0.25,
                        .primary = { { 1.0, 0.95, 0.9 }, 80, -0.1 }, .secondary = { { 0.55, 0.40, 0.28 }, 24, 0.15 } };
    ht_shading black = { .model = HT_MODEL_SCHEUERMANN }, no_lobe = fit.shading;
    memset(&no_lobe.transmission, 0, sizeof no_lobe.transmission);
    double without = rms_against(&m, &no_lobe, &sc);
    print_message("without its transmission lobe %.4f\n", without);
    assert_true(own < rms_against(&m, &dark, &sc));
    assert_true(own < rms_against(&m, &black, &sc));
    assert_true(own < without);
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
        cmocka_unit_test(fit_is_a_valid_deterministic_scheuermann_material_within_its_measured_error),
        cmocka_unit_test(fit_error_holds_on_other_samples_and_beats_hand_picked_constants),
        cmocka_unit_test(hairgen_writes_the_fit_into_the_manifest_and_every_lower_tier),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_marschner_fit.c — Scheuermann constants with a transmission lobe
   fitted to a Marschner material under a scene's lights
   (shadergen/marschner_fit.c): the fit is deterministic, its constants are
   a valid Scheuermann material (the same in hairgen's manifest, made in
   another process), its error is held to the measured level
   per scene (rms and max over its samples, the lobe's shape against M_TT
   N_TT), is what it reports (recomputed here on samples of our own) and no
   worse than a few hand-picked constants, and hairgen writes it into the
   manifest and the lower tiers of a Marschner bundle. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <cJSON.h>

#include <hairtier/hairgen.h>
#include <hairtier/scene.h>
#include "marschner_fit.h"
#include "rng.h"
#include "support_render.h"
#include "support_scratch.h"

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

/* Our own samples of the scene's layout (another seed, the distribution
   marschner_fit.c's header states: its view directions, its lights, T
   anywhere, N perpendicular to T towards the viewer) with the fibre's
   colour there clamped to [0, 1], made once: each rms_against reads them. */
enum { OWN_SAMPLES = 4000 };
static struct own_sample {
    ht_surface s;
    double want[3];
} own[OWN_SAMPLES];
static ht_light_ray own_lights[HT_MAX_LIGHTS];
static int own_light_count;

static void make_own_samples(const ht_shading *fibre, const ht_scene *sc) {
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
    own_light_count = sc->light_count;
    for (int l = 0; l < sc->light_count; l++)
        for (int i = 0; i < 3; i++) own_lights[l].L[i] = sc->lights[l].vector[i], own_lights[l].color[i] = sc->lights[l].color[i];
    int n = 0;
    while (n < OWN_SAMPLES) {
        double T[3], N[3], V[3], x = ht_rng_range(&rng, -k, k), y = ht_rng_range(&rng, -k, k);
        for (int i = 0; i < 3; i++) T[i] = ht_rng_range(&rng, -1, 1), N[i] = ht_rng_range(&rng, -1, 1);
        for (int i = 0; i < 3; i++) V[i] = -(fwd[i] + x * right[i] + y * up[i]);
        unit(V);
        double t2 = dot(T, T), d = dot(N, T) / t2;
        if (t2 > 1 || t2 < 1e-4) continue;
        for (int i = 0; i < 3; i++) N[i] -= d * T[i];
        if (dot(N, N) < 1e-3 || dot(N, V) <= 0) continue;
        struct own_sample *o = &own[n++];
        o->s = (ht_surface){ .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = 1 };
        memcpy(o->s.T, T, sizeof T);
        memcpy(o->s.N, N, sizeof N);
        memcpy(o->s.V, V, sizeof V);
        ht_model_shade_d(fibre, &o->s, own_lights, own_light_count, o->want);
        for (int c = 0; c < 3; c++) o->want[c] = fmin(o->want[c], 1);
    }
}

/* RMS of fit against the fibre over our own samples, fit's side clamped to
   [0, 1] too. */
static double rms_against(const ht_shading *fit) {
    double sum = 0;
    for (int n = 0; n < OWN_SAMPLES; n++) {
        double got[3];
        ht_model_shade_d(fit, &own[n].s, own_lights, own_light_count, got);
        for (int c = 0; c < 3; c++) {
            double e = fmin(got[c], 1) - own[n].want[c];
            sum += e * e;
        }
    }
    return sqrt(sum / (3.0 * OWN_SAMPLES));
}

/* The measured error of brown's fit per scene (build/tests/test_marschner_fit
   prints it), each bound the measurement plus 2 %: the fit is deterministic,
   so a change that moves it past the bound changed the fit. */
static const struct {
    const char *scene;
    double rms, max, tt_rms; /* [0, 1] units */
} pins[] = {
    { "scenes/furball.json", 0.0218, 0.6095, 0.0051 },
    { "scenes/backlit.json", 0.1349, 0.9059, 0.0370 }, /* second: made after another fit in this process */
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

/* brown-marschner's bundle for backlit.json, hairgen's work in another
   process: make's fixture, else generated into work (ht_test_bundle). */
static char work[64], backlit_bundle[1024];

static int setup(void **state) {
    (void)state;
    char err[512];
    if (!ht_test_scratch_create(work, sizeof work, "marschner-fit")) return -1;
    snprintf(backlit_bundle, sizeof backlit_bundle, "%s/brown-marschner", work);
    if (ht_test_bundle("materials/brown-marschner.json", "backlit", "scenes/backlit.json", backlit_bundle,
                       sizeof backlit_bundle, err, sizeof err) != HT_OK) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static double number(const cJSON *o, const char *key) {
    const cJSON *v = cJSON_GetObjectItem(o, key);
    if (!cJSON_IsNumber(v)) fail_msg("manifest fit: no number %s", key);
    return v->valuedouble;
}

static void colour(const cJSON *o, double out[3]) {
    const cJSON *c = cJSON_GetObjectItem(o, "color");
    assert_int_equal(cJSON_GetArraySize(c), 3);
    for (int i = 0; i < 3; i++) out[i] = cJSON_GetArrayItem(c, i)->valuedouble;
}

/* x and y within cJSON's round trip: it prints 15 digits where they read
   back within DBL_EPSILON relative, else 17. */
static bool same_number(double x, double y) { return fabs(x - y) <= fmax(fabs(x), fabs(y)) * DBL_EPSILON; }

/* The fit hairgen wrote against a: the fit made twice, in two processes,
   is the same to the manifest's precision. */
static void same_as_the_manifest(const ht_marschner_fit *a) {
    cJSON *root = ht_test_read_json(backlit_bundle, "manifest.json"), *fit = cJSON_GetObjectItem(root, "fit");
    assert_non_null(fit);
    ht_marschner_fit b = { .shading = { .model = HT_MODEL_SCHEUERMANN } };
    const cJSON *d = cJSON_GetObjectItem(fit, "diffuse"), *p = cJSON_GetObjectItem(fit, "primary"),
                *q = cJSON_GetObjectItem(fit, "secondary"), *t = cJSON_GetObjectItem(fit, "transmission");
    b.rms = number(fit, "rms_error");
    b.max_error = number(fit, "max_error");
    colour(d, b.shading.diffuse_color);
    b.shading.wrap = number(d, "wrap");
    colour(p, b.shading.primary.color);
    b.shading.primary.exponent = number(p, "exponent");
    b.shading.primary.shift = number(p, "shift");
    colour(q, b.shading.secondary.color);
    b.shading.secondary.exponent = number(q, "exponent");
    b.shading.secondary.shift = number(q, "shift");
    colour(t, b.shading.transmission.color);
    b.shading.transmission.centre = number(t, "centre");
    b.shading.transmission.sharpness = number(t, "sharpness");
    b.shading.transmission.azimuth = number(t, "azimuth");
    b.tt_rms = number(t, "rms_error");
    cJSON_Delete(root);
    const double got[] = { a->rms, a->max_error, a->tt_rms, a->shading.wrap, a->shading.primary.exponent,
                           a->shading.primary.shift, a->shading.secondary.exponent, a->shading.secondary.shift,
                           a->shading.transmission.centre, a->shading.transmission.sharpness,
                           a->shading.transmission.azimuth },
                 want[] = { b.rms, b.max_error, b.tt_rms, b.shading.wrap, b.shading.primary.exponent,
                            b.shading.primary.shift, b.shading.secondary.exponent, b.shading.secondary.shift,
                            b.shading.transmission.centre, b.shading.transmission.sharpness,
                            b.shading.transmission.azimuth };
    /* a fixture older than hairgen differs too: make rebuilds it, a hand-run test does not */
    for (size_t i = 0; i < sizeof got / sizeof *got; i++)
        if (!same_number(got[i], want[i]))
            fail_msg("fit number %zu: %.17g, %s/manifest.json %.17g", i, got[i], backlit_bundle, want[i]);
    const double *colours[4][2] = { { a->shading.diffuse_color, b.shading.diffuse_color },
                                    { a->shading.primary.color, b.shading.primary.color },
                                    { a->shading.secondary.color, b.shading.secondary.color },
                                    { a->shading.transmission.color, b.shading.transmission.color } };
    for (int i = 0; i < 4; i++)
        for (int c = 0; c < 3; c++)
            if (!same_number(colours[i][0][c], colours[i][1][c]))
                fail_msg("fit colour %d.%d: %.17g, %s/manifest.json %.17g", i, c, colours[i][0][c], backlit_bundle,
                         colours[i][1][c]);
}

static void fit_is_a_valid_deterministic_scheuermann_material_within_its_measured_error(void **state) {
    (void)state;
    ht_shading m = brown();
    for (size_t p = 0; p < sizeof pins / sizeof *pins; p++) {
        ht_scene sc = scene(pins[p].scene);
        ht_marschner_fit a;
        if (strcmp(pins[p].scene, "scenes/backlit.json") == 0) {
            a = *backlit_fit();
            same_as_the_manifest(&a);
        } else {
            assert_int_equal(ht_marschner_fit_scheuermann(&m, &sc, &a), HT_OK);
        }
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
    make_own_samples(&m, &sc);
    double own_rms = rms_against(&fit.shading);
    print_message("rms on the fit's samples %.4f, on others %.4f\n", fit.rms, own_rms);
    assert_true(fabs(own_rms - fit.rms) < 0.25 * fit.rms); /* no overfitting to its own samples */
    /* dark-brown's constants, a black material, the fit without its lobe are worse */
    ht_shading dark = { .model = HT_MODEL_SCHEUERMANN, .diffuse_color = { 0.23, 0.14, 0.08 }, .wrap = 0.25,
                        .primary = { { 1.0, 0.95, 0.9 }, 80, -0.1 }, .secondary = { { 0.55, 0.40, 0.28 }, 24, 0.15 } };
    ht_shading black = { .model = HT_MODEL_SCHEUERMANN }, no_lobe = fit.shading;
    memset(&no_lobe.transmission, 0, sizeof no_lobe.transmission);
    double without = rms_against(&no_lobe);
    print_message("without its transmission lobe %.4f\n", without);
    assert_true(own_rms < rms_against(&dark));
    assert_true(own_rms < rms_against(&black));
    assert_true(own_rms < without);
}

/* hairgen's bundle of brown-marschner (setup): the fit in its manifest
   (checked number for number above) and every lower tier's files. */
static void hairgen_writes_the_fit_into_the_manifest_and_every_lower_tier(void **state) {
    (void)state;
    const char *files[] = { "marschner.frag", "full.frag", "vertex.vert", "fixed.json", "gl11.json" };
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        char path[1100];
        snprintf(path, sizeof path, "%s/%s", backlit_bundle, files[i]);
        if (!ht_test_path_exists(path)) fail_msg("no %s", path);
    }
    const char *manifest = ht_test_read_file(backlit_bundle, "manifest.json");
    assert_non_null(strstr(manifest, "\"fit\":"));
    assert_non_null(strstr(manifest, "\"rms_error\":"));
    assert_non_null(strstr(manifest, "Scheuermann constants fitted to it"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fit_is_a_valid_deterministic_scheuermann_material_within_its_measured_error),
        cmocka_unit_test(fit_error_holds_on_other_samples_and_beats_hand_picked_constants),
        cmocka_unit_test(hairgen_writes_the_fit_into_the_manifest_and_every_lower_tier),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

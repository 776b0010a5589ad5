/* test_render_variants — the device-only variants of fixed4 and fixed
   (hairtier.h ht_variant): with the camera orbiting and a light moving,
   they do no per-vertex CPU work (ht_renderer_get_stats), where the exact
   variants redo every vertex; the renderer picks the device variant by the
   manifest's measured numbers (within HT_VARIANT_DEVICE_DB of exact), and
   desc.variant / HAIRTIER_VARIANT force either. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "metrics.h"
#include "select.h"
#include "support_log.h"
#include "support_render.h"
#include "support_scratch.h"

enum { SIZE = 128, ORBIT_FRAMES = 6 };

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    unsetenv("HAIRTIER_VARIANT");
    return ht_test_furball_setup(&fx, "variants", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static ht_renderer *forced(ht_tier tier, ht_variant variant, const char *dir) {
    return ht_test_renderer_create((ht_renderer_desc){ .tier = tier, .strict = true, .variant = variant },
                                   dir ? dir : fx.bundle_dir, HT_OK);
}

/* Frame k of the orbit: the eye 4 degrees further round the fur ball each
   frame, the key light turning the other way (both directional, as every
   shipped scene's). */
static ht_frame_desc orbit_frame(int k, ht_light lights[2]) {
    const float a = 0.07f * (float)k, b = -0.05f * (float)k;
    lights[0] = (ht_light){ .type = HT_LIGHT_DIRECTIONAL, .vector = { 0.6f * cosf(b) + 0.7f * sinf(b), 0.8f,
                                                                      0.7f * cosf(b) - 0.6f * sinf(b) },
                            .color = { 1.0f, 0.97f, 0.92f } };
    lights[1] = (ht_light){ .type = HT_LIGHT_DIRECTIONAL, .vector = { -0.7f, 0.2f, -0.6f },
                            .color = { 0.35f, 0.4f, 0.5f } };
    ht_frame_desc f = ht_test_furball_frame(3.0f);
    f.camera.eye[0] = 3.0f * sinf(a);
    f.camera.eye[2] = 3.0f * cosf(a);
    f.lights = lights;
    f.light_count = 2;
    return f;
}

/* Draws the orbit; the last frame stays in last (may be NULL). Answers
   the CPU vertices of the frames after the first (which may make what
   depends only on the light colours: fixed's primary colours). */
static uint64_t orbit(ht_renderer *r, ht_image *last) {
    uint64_t after_first = 0;
    for (int k = 0; k < ORBIT_FRAMES; k++) {
        ht_light lights[2];
        ht_frame_desc f = orbit_frame(k, lights);
        ht_image img;
        ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
        ht_test_pixel_stats st = ht_test_pixel_stats_of(&img, ht_test_background);
        assert_true(st.changed > 500);
        assert_int_equal(st.magenta, 0);
        if (last && k == ORBIT_FRAMES - 1) *last = img;
        else ht_image_free(&img);
        if (k == 0) after_first = ht_renderer_get_stats(r).cpu_vertices;
    }
    return ht_renderer_get_stats(r).cpu_vertices - after_first;
}

static double psnr_between(const ht_image *a, const ht_image *b) {
    ht_metrics whole;
    char err[256];
    if (ht_metrics_compare(&(ht_metrics_desc){ .reference = a->pixels, .test = b->pixels, .width = a->width,
                                               .height = a->height },
                           &whole, NULL, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    return whole.psnr_db;
}

/* The exact variant redoes every vertex each frame of the orbit; the
   device variant none in any frame after the first, and draws nearly the
   same hair. */
static void check_orbit(ht_tier tier) {
    const uint64_t n = fx.mesh.vertex_count;
    ht_image exact_img, device_img;
    ht_renderer *exact = forced(tier, HT_VARIANT_EXACT, NULL);
    assert_int_equal(ht_renderer_variant(exact), HT_VARIANT_EXACT);
    assert_int_equal(ht_renderer_set_mesh(exact, &fx.mesh), HT_OK);
    assert_true(orbit(exact, &exact_img) >= (ORBIT_FRAMES - 1) * n);
    ht_renderer_destroy(exact);

    ht_renderer *device = forced(tier, HT_VARIANT_DEVICE, NULL);
    assert_int_equal(ht_renderer_variant(device), HT_VARIANT_DEVICE);
    assert_true(ht_test_logged("device-only variant"));
    assert_int_equal(ht_renderer_set_mesh(device, &fx.mesh), HT_OK);
    assert_true(orbit(device, &device_img) == 0);
    ht_renderer_stats st = ht_renderer_get_stats(device);
    assert_true(st.frames == ORBIT_FRAMES);
    /* fixed4: nothing at all; fixed: its primary colours, once */
    assert_true(st.cpu_vertices == (tier == HT_TIER_FIXED ? n : 0));
    ht_renderer_destroy(device);
    /* an approximation of the same picture (its cost against the top tier
       is what hairgen --measure records) */
    double db = psnr_between(&exact_img, &device_img);
    print_message("%s: device variant against exact on the orbit's last frame: %.2f dB\n", ht_tier_name(tier), db);
    assert_true(db > 22.0);
    ht_image_free(&exact_img);
    ht_image_free(&device_img);
}

static void test_fixed4_device_variant_orbits_with_no_cpu_vertices(void **state) {
    (void)state;
    check_orbit(HT_TIER_FIXED4);
}

static void test_fixed_device_variant_orbits_with_no_cpu_vertices(void **state) {
    (void)state;
    check_orbit(HT_TIER_FIXED);
}

/* ---- choosing the variant ---- */

static ht_manifest_tier measured_tier(double exact_db, double exact_cost, double device_db, double device_cost) {
    ht_manifest_tier t;
    memset(&t, 0, sizeof t);
    t.tier = HT_TIER_FIXED;
    t.measured = (ht_manifest_measured){ .present = true, .psnr_db = exact_db, .cost_ratio = exact_cost };
    t.measured_device = (ht_manifest_measured){ .present = true, .psnr_db = device_db, .cost_ratio = device_cost };
    return t;
}

static ht_variant pick(const ht_manifest_tier *t, const char *policy_text, ht_variant requested) {
    ht_policy p;
    char err[256], reason[HT_SELECT_REASON];
    if (ht_policy_parse(policy_text, &p, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_variant v = ht_select_variant(t, &p, requested, reason, sizeof reason);
    assert_true(reason[0] != '\0');
    return v;
}

static void test_policy_takes_the_device_variant_within_half_a_decibel(void **state) {
    (void)state;
    ht_manifest_tier within = measured_tier(31.0, 0.9, 30.0 + 0.6, 0.7);
    ht_manifest_tier beyond = measured_tier(31.0, 0.9, 30.0 + 0.4, 0.7);
    ht_manifest_tier on_edge = measured_tier(31.0, 0.9, 31.0 - HT_VARIANT_DEVICE_DB, 0.7);
    assert_int_equal(pick(&within, "best", HT_VARIANT_AUTO), HT_VARIANT_DEVICE);
    assert_int_equal(pick(&on_edge, "best", HT_VARIANT_AUTO), HT_VARIANT_DEVICE);
    assert_int_equal(pick(&beyond, "best", HT_VARIANT_AUTO), HT_VARIANT_EXACT);
    assert_int_equal(pick(&beyond, "frame:16", HT_VARIANT_AUTO), HT_VARIANT_EXACT);
    /* error:DB: the device variant when it reaches DB */
    assert_int_equal(pick(&beyond, "error:30", HT_VARIANT_AUTO), HT_VARIANT_DEVICE);
    assert_int_equal(pick(&beyond, "error:30.5", HT_VARIANT_AUTO), HT_VARIANT_EXACT);
    /* fastest: the cheaper */
    assert_int_equal(pick(&beyond, "fastest", HT_VARIANT_AUTO), HT_VARIANT_DEVICE);
    ht_manifest_tier dearer = measured_tier(31.0, 0.6, 30.9, 0.7);
    assert_int_equal(pick(&dearer, "fastest", HT_VARIANT_AUTO), HT_VARIANT_EXACT);
    /* a request wins; nothing measured: exact */
    assert_int_equal(pick(&within, "best", HT_VARIANT_EXACT), HT_VARIANT_EXACT);
    assert_int_equal(pick(&beyond, "best", HT_VARIANT_DEVICE), HT_VARIANT_DEVICE);
    ht_manifest_tier none = within;
    none.measured_device.present = false;
    assert_int_equal(pick(&none, "best", HT_VARIANT_AUTO), HT_VARIANT_EXACT);
}

/* A copy of the fixture's bundle whose fixed and fixed4 tiers carry
   measured numbers: exact at 31 dB, the device variant at device_db. */
static void measured_bundle(const char *name, double device_db, char *dir, size_t size) {
    ht_test_furball_copy_bundle(&fx, name, dir, size);
    cJSON *root = cJSON_Parse(ht_test_read_file(dir, "manifest.json"));
    assert_non_null(root);
    cJSON *tier;
    cJSON_ArrayForEach(tier, cJSON_GetObjectItemCaseSensitive(root, "tiers")) {
        const char *tier_name = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(tier, "name"));
        const double db[2] = { 31.0, device_db };
        const char *keys[2] = { "measured", "measured_device" };
        for (int k = 0; k < 2; k++) {
            cJSON *m = cJSON_CreateObject();
            cJSON_AddNumberToObject(m, "psnr_db", strcmp(tier_name, "full") == 0 ? 99.0 : db[k]);
            cJSON_AddNumberToObject(m, "ssim", 0.95);
            cJSON_AddNumberToObject(m, "delta_e00_mean", 1.0);
            cJSON_AddNumberToObject(m, "delta_e00_p95", 3.0);
            cJSON_AddNumberToObject(m, "cost_ratio", 0.8);
            if (k == 0 || strcmp(tier_name, "fixed") == 0 || strcmp(tier_name, "fixed4") == 0)
                cJSON_AddItemToObject(tier, keys[k], m);
            else
                cJSON_Delete(m);
        }
    }
    char *text = cJSON_Print(root);
    ht_test_write_file(dir, "manifest.json", text);
    cJSON_free(text);
    cJSON_Delete(root);
}

static void test_renderer_picks_the_variant_by_the_manifests_numbers(void **state) {
    (void)state;
    char near[256], far[256];
    measured_bundle("near", 31.0 - 0.3, near, sizeof near);
    measured_bundle("far", 31.0 - 0.7, far, sizeof far);
    for (int t = 0; t < 2; t++) {
        const ht_tier tier = t ? HT_TIER_FIXED : HT_TIER_FIXED4;
        ht_renderer *r = forced(tier, HT_VARIANT_AUTO, near);
        assert_int_equal(ht_renderer_variant(r), HT_VARIANT_DEVICE);
        assert_true(ht_test_logged("within 0.5 dB"));
        ht_renderer_destroy(r);
        r = forced(tier, HT_VARIANT_AUTO, far);
        assert_int_equal(ht_renderer_variant(r), HT_VARIANT_EXACT);
        assert_true(ht_test_logged("more than 0.5 dB"));
        ht_renderer_destroy(r);
        /* HAIRTIER_VARIANT forces it; the desc wins over the environment */
        setenv("HAIRTIER_VARIANT", "device", 1);
        r = forced(tier, HT_VARIANT_AUTO, far);
        assert_int_equal(ht_renderer_variant(r), HT_VARIANT_DEVICE);
        ht_renderer_destroy(r);
        r = forced(tier, HT_VARIANT_EXACT, near);
        assert_int_equal(ht_renderer_variant(r), HT_VARIANT_EXACT);
        ht_renderer_destroy(r);
        unsetenv("HAIRTIER_VARIANT");
    }
    /* the full tier has no device variant: it runs as it is */
    ht_renderer *r = forced(HT_TIER_FULL, HT_VARIANT_DEVICE, near);
    assert_int_equal(ht_renderer_variant(r), HT_VARIANT_EXACT);
    ht_renderer_destroy(r);
    setenv("HAIRTIER_VARIANT", "sometimes", 1);
    ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FIXED }, near, HT_ERR_INVALID_ARGUMENT);
    assert_true(ht_test_logged("HAIRTIER_VARIANT: variant \"sometimes\": expected exact or device"));
    unsetenv("HAIRTIER_VARIANT");
}

static void test_manifest_reads_measured_device_and_refuses_a_bad_one(void **state) {
    (void)state;
    char dir[256];
    measured_bundle("read", 30.25, dir, sizeof dir);
    ht_manifest m;
    char err[512];
    assert_int_equal(ht_manifest_load(dir, &m, err, sizeof err), HT_OK);
    const ht_manifest_tier *fixed = ht_manifest_find_tier(&m, HT_TIER_FIXED);
    assert_true(fixed->measured_device.present);
    assert_true(fixed->measured_device.psnr_db == 30.25);
    assert_false(ht_manifest_find_tier(&m, HT_TIER_FULL)->measured_device.present);
    char *text = ht_test_read_file(dir, "manifest.json");
    char *at = strstr(text, "\"measured_device\"");
    assert_non_null(at);
    char *cost = strstr(at, "\"cost_ratio\":");
    assert_non_null(cost);
    memcpy(cost, "\"cost_ratiX\":", 13);
    assert_int_not_equal(ht_manifest_parse(text, dir, "manifest.json", &m, err, sizeof err), HT_OK);
    assert_non_null(strstr(err, "measured_device"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixed4_device_variant_orbits_with_no_cpu_vertices),
        cmocka_unit_test(test_fixed_device_variant_orbits_with_no_cpu_vertices),
        cmocka_unit_test(test_policy_takes_the_device_variant_within_half_a_decibel),
        cmocka_unit_test(test_renderer_picks_the_variant_by_the_manifests_numbers),
        cmocka_unit_test(test_manifest_reads_measured_device_and_refuses_a_bad_one),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

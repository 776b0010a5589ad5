/* test_render_context — the two ways a context is made (platform/offscreen.h)
   and the device profiles that stand in for old hardware on any driver:
   - OSMesa and EGL (pbuffer, Mesa's surfaceless platform) on the same
     llvmpipe draw every tier of the fur ball to the same pixels, rows in
     the same order;
   - hairview, tier_sheet and bench_frame refuse a bad --context or
     --egl-device with a usage line, and say in one line, with a non-zero
     exit and no output file, when EGL has no driver or the device does
     not exist;
   - HAIRTIER_DEVICE_PROFILE=gl11|gl13|gl20 picks the tier the matching
     Mesa override picks, a bad value fails creation with one line, and a
     profile in the desc wins over it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "metrics.h"
#include "offscreen.h"
#include "support_log.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE 128

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    if (!ht_test_furball_setup(&fx, "context", 16)) return -1;
    /* Every test here opens the contexts it needs: the fixture's would
       stop being current at the first one. */
    ht_test_gl_destroy(&fx.gl);
    return 0;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

/* The fur ball drawn with `tier` forced (strict) on a fresh context of
   `kind`, read back top row first. */
static void draw_tier(offscreen_kind kind, ht_tier tier, ht_image *out) {
    char err[512];
    offscreen *gl = offscreen_open(&(offscreen_desc){ .kind = kind, .width = SIZE, .height = SIZE, .egl_device = -1 },
                                   err, sizeof err);
    if (!gl) fail_msg("%s", err);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .getproc = offscreen_getproc, .tier = tier,
                                                                 .strict = true }, fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    const ht_frame_desc f = ht_test_furball_frame(2.4f);
    gl->gl.ClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
    gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    assert_int_equal(ht_renderer_draw(r, &f), HT_OK);
    const unsigned char *rgba = offscreen_read(gl);
    assert_int_equal(ht_image_alloc(out, SIZE, SIZE, 4), HT_OK);
    for (int y = 0; y < SIZE; y++)
        memcpy(out->pixels + (size_t)y * SIZE * 4, offscreen_row(rgba, SIZE, SIZE, y), (size_t)SIZE * 4);
    ht_renderer_destroy(r);
    offscreen_close(gl);
}

/* Measured on Mesa 22.3.6 llvmpipe: every tier's two images are identical
   (PSNR infinite), so the bound is identity: EGL adds no difference of its
   own, and any later one (a config with other bits, a flipped read-back)
   shows here first. */
static void test_egl_and_osmesa_on_llvmpipe_draw_every_tier_identically(void **state) {
    (void)state;
    const ht_tier tiers[] = { HT_TIER_FULL, HT_TIER_VERTEX, HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
    for (size_t i = 0; i < sizeof tiers / sizeof tiers[0]; i++) {
        ht_image osmesa, egl;
        draw_tier(OFFSCREEN_OSMESA, tiers[i], &osmesa);
        draw_tier(OFFSCREEN_EGL, tiers[i], &egl);
        ht_test_pixel_stats st = ht_test_pixel_stats_of(&osmesa, ht_test_background);
        assert_true(st.changed > SIZE * SIZE / 20);   /* something was drawn */
        ht_metrics whole;
        char err[256];
        assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = osmesa.pixels, .test = egl.pixels,
                                                                .width = SIZE, .height = SIZE }, &whole, NULL,
                                            err, sizeof err), HT_OK);
        int max = 0;
        for (size_t k = 0; k < (size_t)SIZE * SIZE * 4; k++)
            if (k % 4 != 3 && abs(osmesa.pixels[k] - egl.pixels[k]) > max) max = abs(osmesa.pixels[k] - egl.pixels[k]);
        printf("%-6s egl vs osmesa: PSNR %s dB, max %d/255, %d pixels drawn\n", ht_tier_name(tiers[i]),
               isinf(whole.psnr_db) ? "inf" : "finite", max, st.changed);
        if (max != 0) fail_msg("%s: egl and osmesa differ by up to %d/255 (PSNR %.1f dB)", ht_tier_name(tiers[i]), max,
                               whole.psnr_db);
        ht_image_free(&osmesa);
        ht_image_free(&egl);
    }
}

/* ---- the programs ---- */

/* `ENV build/PROGRAM ARGS`, stderr into err; the exit status. */
static int run(const char *env, const char *program, const char *args, char *err, size_t size) {
    char cmd[4096], err_path[256];
    snprintf(err_path, sizeof err_path, "%s/stderr.txt", fx.work);
    snprintf(cmd, sizeof cmd, "%s %s/%s %s >/dev/null 2>%s", env, ht_test_build_dir(), program, args, err_path);
    int status = system(cmd);
    assert_true(WIFEXITED(status));
    FILE *f = fopen(err_path, "rb");
    assert_non_null(f);
    size_t n = fread(err, 1, size - 1, f);
    err[n] = '\0';
    fclose(f);
    return WEXITSTATUS(status);
}

/* Exits `status`, stderr's first line starts with `start` and names
   `mentions`, and out (may be NULL) does not exist. */
static void expect_fails(const char *env, const char *program, const char *args, const char *out, int status,
                         const char *start, const char *mentions) {
    char err[8192];
    int got = run(env, program, args, err, sizeof err);
    if (got != status) fail_msg("%s %s %s: exit %d, expected %d; stderr:\n%s", env, program, args, got, status, err);
    size_t len = strcspn(err, "\n");
    if (strncmp(err, start, strlen(start)) != 0 || !strstr(err, mentions) || (size_t)(strstr(err, mentions) - err) > len)
        fail_msg("%s %s %s: first line \"%.*s\" does not start \"%s\" and name \"%s\"", env, program, args, (int)len,
                 err, start, mentions);
    if (out && ht_test_path_exists(out)) fail_msg("%s %s: %s left behind", program, args, out);
}

/* glvnd reads the vendor list from this variable: a file that does not
   exist leaves EGL without a driver, as on a machine without one. */
#define NO_EGL_DRIVER "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/egl_vendor.json"

static void write_scene(char *path, size_t size) {
    snprintf(path, size, "%s/scene.json", fx.work);
    ht_test_write_file(fx.work, "scene.json",
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [48, 40],\n"
        " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]}],\n"
        " \"background\": [0.1, 0.2, 0.3],\n"
        " \"geometry\": {\"type\": \"furball\", \"hairs\": 200, \"joints\": 6, \"length\": 0.1, \"width\": 0.02}}\n");
}

static void test_hairview_draws_the_same_png_on_egl_and_osmesa(void **state) {
    (void)state;
    char scene[256], args[2048], err[8192], png[2][256];
    write_scene(scene, sizeof scene);
    const char *kinds[2] = { "osmesa", "egl" };
    for (int k = 0; k < 2; k++) {
        snprintf(png[k], sizeof png[k], "%s/view-%s.png", fx.work, kinds[k]);
        snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 --context %s -o '%s'", fx.bundle_dir, scene,
                 kinds[k], png[k]);
        if (run("", "hairview", args, err, sizeof err) != 0) fail_msg("hairview %s:\n%s", args, err);
    }
    /* Same pixels, same row order (a read-back upside down would differ). */
    ht_image img[2];
    for (int k = 0; k < 2; k++)
        if (ht_image_read_png(png[k], &img[k], err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_int_equal(img[0].width, 48);
    assert_int_equal(img[0].height, 40);
    assert_int_equal(img[1].width, 48);
    assert_int_equal(img[1].height, 40);
    assert_memory_equal(img[0].pixels, img[1].pixels, (size_t)48 * 40 * (size_t)img[0].channels);
    ht_image_free(&img[0]);
    ht_image_free(&img[1]);
    /* The same through the environment and through device 0. */
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 --egl-device 0 -o '%s/view-dev.png'",
             fx.bundle_dir, scene, fx.work);
    if (run("", "hairview", args, err, sizeof err) != 0) fail_msg("hairview %s:\n%s", args, err);
}

static void test_programs_refuse_a_bad_context_in_one_line(void **state) {
    (void)state;
    char scene[256], args[2048], png[256];
    write_scene(scene, sizeof scene);
    snprintf(png, sizeof png, "%s/bad.png", fx.work);
    const char *base_fmt = "--bundle '%s' --scene '%s' --frames 1 %s -o '%s'";

    /* Usage errors: exit 2, the reason first. */
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--context foo", png);
    expect_fails("", "hairview", args, png, 2, "hairview: --context: ", "osmesa or egl");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--context osmesa --egl-device 0", png);
    expect_fails("", "hairview", args, png, 2, "hairview: --egl-device: ", "--context egl");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--egl-device -1", png);
    expect_fails("", "hairview", args, png, 2, "hairview: --egl-device: ", "0..255");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' -o '%s' --context", fx.bundle_dir, scene, png);
    expect_fails("", "hairview", args, png, 2, "hairview: --context: ", "missing value");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--context EGL", png);
    expect_fails("", "tier_sheet", args, png, 2, "tier_sheet: --context: ", "osmesa or egl");
    expect_fails("", "bench_frame", "--context vulkan", NULL, 2, "bench_frame: --context: ", "osmesa or egl");

    /* No context: exit 1, one line, no PNG. */
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--context egl", png);
    expect_fails(NO_EGL_DRIVER, "hairview", args, png, 1, "hairview: egl: no display: ", "default display failed");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "", png);
    expect_fails(NO_EGL_DRIVER " HAIRTIER_CONTEXT=egl", "hairview", args, png, 1, "hairview: egl: no display: ",
                 "EGL_MESA_platform_surfaceless");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--egl-device 99", png);
    expect_fails("", "hairview", args, png, 1, "hairview: egl: device 99: ", "(0..");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "", png);
    expect_fails("HAIRTIER_CONTEXT=gles", "hairview", args, png, 1, "hairview: HAIRTIER_CONTEXT: ", "osmesa or egl");
    snprintf(args, sizeof args, base_fmt, fx.bundle_dir, scene, "--context egl", png);
    expect_fails(NO_EGL_DRIVER, "tier_sheet", args, png, 1, "tier_sheet: no tier ran: egl: no display: ", "failed");
    expect_fails(NO_EGL_DRIVER, "bench_frame", "--context egl --hairs 10 --size 16 --frames 1", NULL, 1,
                 "bench_frame: egl: no display: ", "failed");
}

/* ---- device profiles by name ---- */

static ht_tier tier_under_profile(const char *env, ht_device_profile desc_profile, ht_result expect) {
    ht_test_gl gl;
    char err[256];
    if (!ht_test_gl_create(&gl, 16, 16, NULL, err, sizeof err)) fail_msg("%s", err);
    if (env) setenv("HAIRTIER_DEVICE_PROFILE", env, 1);
    else unsetenv("HAIRTIER_DEVICE_PROFILE");
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .profile = desc_profile }, fx.bundle_dir, expect);
    unsetenv("HAIRTIER_DEVICE_PROFILE");
    ht_tier t = r ? ht_renderer_tier(r) : HT_TIER_COUNT;
    ht_renderer_destroy(r);
    ht_test_gl_destroy(&gl);
    return t;
}

static void test_device_profile_env_picks_the_tier_of_its_gl_version(void **state) {
    (void)state;
    const ht_device_profile none = { 0 };
    assert_int_equal(tier_under_profile("gl20", none, HT_OK), HT_TIER_VERTEX);
    assert_true(ht_test_logged("hairtier: device profile gl20 (HAIRTIER_DEVICE_PROFILE)"));
    assert_true(ht_test_logged("hairtier: device GL 2.0, GLSL 1.10,"));
    assert_true(ht_test_logged("skipped full: needs GL 2.1, have 2.0"));
    /* As MESA_GL_VERSION_OVERRIDE=1.3 does (test_render_passes): llvmpipe's 8 units stay. */
    assert_int_equal(tier_under_profile("gl13", none, HT_OK), HT_TIER_FIXED4);
    assert_true(ht_test_logged("skipped vertex: needs GL 2.0, have 1.3"));
    assert_int_equal(tier_under_profile("gl11", none, HT_OK), HT_TIER_GL11);
    assert_true(ht_test_logged("hairtier: device GL 1.1, GLSL 0.00, 1 texture units"));
    assert_int_equal(tier_under_profile("none", none, HT_OK), HT_TIER_FULL);
    assert_int_equal(tier_under_profile("", none, HT_OK), HT_TIER_FULL);
    /* A profile in the desc wins over the environment. */
    assert_int_equal(tier_under_profile("gl11", (ht_device_profile){ .gl_major = 2, .gl_minor = 0 }, HT_OK),
                     HT_TIER_VERTEX);
    assert_false(ht_test_logged("HAIRTIER_DEVICE_PROFILE"));
}

static void test_device_profile_env_with_a_bad_name_fails_creation_in_one_line(void **state) {
    (void)state;
    const ht_device_profile none = { 0 };
    assert_int_equal(tier_under_profile("gl15", none, HT_ERR_INVALID_ARGUMENT), HT_TIER_COUNT);
    assert_string_equal(ht_test_log_text,
                        "hairtier: HAIRTIER_DEVICE_PROFILE: \"gl15\" is not none, gl11, gl13, gl20, videocore4, mali400 or videocore6\n");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_egl_and_osmesa_on_llvmpipe_draw_every_tier_identically),
        cmocka_unit_test(test_hairview_draws_the_same_png_on_egl_and_osmesa),
        cmocka_unit_test(test_programs_refuse_a_bad_context_in_one_line),
        cmocka_unit_test(test_device_profile_env_picks_the_tier_of_its_gl_version),
        cmocka_unit_test(test_device_profile_env_with_a_bad_name_fails_creation_in_one_line),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

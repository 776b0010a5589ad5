/* test_render_hostile — docs/robustness.md's runtime rows on OSMesa: a shader source
   over its size cap or a FIFO (C1), a combiner program naming a light the
   bundle does not plan (F), a non-power-of-two fixed-tier texture on a
   GL 1.3 device without NPOT (E). Each drops the tier (or fails a strict
   one) with one line naming the file; each failed before its fix (the
   FIFO one hung, so it runs under alarm()). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE 32

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "hostile", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static void expect_logged(const char *what) {
    if (!strstr(ht_test_log_text, what)) fail_msg("no \"%s\" in the log:\n%s", what, ht_test_log_text);
}

/* C1: a shader source is read only as a regular file of at most 1 MiB. */
static void test_oversized_shader_drops_full_naming_the_cap(void **state) {
    (void)state;
    char dir[256];
    ht_test_furball_copy_bundle(&fx, "big-shader", dir, sizeof dir);
    size_t n = (1u << 20) + 1;
    char *text = malloc(n + 1);
    memset(text, ' ', n);
    text[n] = '\0';
    ht_test_write_file(dir, "full.frag", text);
    free(text);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ 0 }, dir, HT_OK);
    assert_int_not_equal(ht_renderer_tier(r), HT_TIER_FULL);
    expect_logged("full.frag: file is 1048577 bytes, more than the 1048576 this kind of file may have");
    ht_renderer_destroy(r);
}

static void test_shader_that_is_a_fifo_drops_full_without_blocking(void **state) {
    (void)state;
    char dir[256], path[512];
    ht_test_furball_copy_bundle(&fx, "fifo-shader", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/full.frag", dir);
    assert_int_equal(unlink(path), 0);
    assert_int_equal(mkfifo(path, 0600), 0);
    alarm(60);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ 0 }, dir, HT_OK);
    alarm(0);
    assert_int_not_equal(ht_renderer_tier(r), HT_TIER_FULL);
    expect_logged("full.frag: not a regular file (a FIFO)");
    ht_renderer_destroy(r);
}

/* F: the program's primary colour named light 3 of a 2-light bundle; the
   fixed tier drew unlit hair and said nothing. */
static void test_combiner_light_beyond_the_bundle_refuses_the_fixed_tier(void **state) {
    (void)state;
    char dir[256];
    ht_test_furball_copy_bundle(&fx, "light3", dir, sizeof dir);
    char *text = strdup(ht_test_read_file(dir, "fixed.json"));
    char *at = strstr(text, "light0.color");
    assert_non_null(at);
    at[5] = '3';
    ht_test_write_file(dir, "fixed.json", text);
    free(text);
    assert_null(ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FIXED, .strict = true }, dir,
                                        HT_ERR_UNSUPPORTED));
    expect_logged("fixed.json: primary_color: light 3, the bundle has 2 lights");
}

/* E: a 48x48 albedo is fine for GL 2.0 but not for GL 1.3 without
   ARB_texture_non_power_of_two: the fixed tier refuses it by name. */
static void test_npot_albedo_refuses_the_fixed_tier_without_npot(void **state) {
    (void)state;
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, 48, 48, 3), HT_OK);
    memset(img.pixels, 128, 48 * 48 * 3);
    char png[256], material[256], dir[256], err[512];
    snprintf(png, sizeof png, "%s/npot.png", fx.work);
    assert_int_equal(ht_image_write_png(png, &img, err, sizeof err), HT_OK);
    ht_image_free(&img);
    ht_test_write_file(fx.work, "npot.json",
                       "{\"format\": \"hairtier-material/1\", \"name\": \"npot\", \"model\": \"scheuermann\",\n"
                       " \"diffuse\": {\"color\": [0.2, 0.1, 0.1], \"wrap\": 0.25},\n"
                       " \"primary\": {\"color\": [1, 1, 1], \"exponent\": 80, \"shift\": -0.1},\n"
                       " \"secondary\": {\"color\": [0.5, 0.4, 0.3], \"exponent\": 24, \"shift\": 0.15},\n"
                       " \"textures\": {\"base\": {\"file\": \"npot.png\"}}}\n");
    snprintf(material, sizeof material, "%s/npot.json", fx.work);
    snprintf(dir, sizeof dir, "%s/npot-bundle", fx.work);
    assert_int_equal(ht_generate_bundle(material, "scenes/furball.json", dir, NULL, err, sizeof err), HT_OK);

    ht_device_profile gl13 = { .gl_major = 1, .gl_minor = 3, .hide_extensions = "GL_ARB_texture_non_power_of_two" };
    assert_null(ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FIXED, .strict = true, .profile = gl13 },
                                        dir, HT_ERR_UNSUPPORTED));
    expect_logged("albedo.png: 48x48 is not a power of two; needs GL 2.0 or GL_ARB_texture_non_power_of_two, "
                  "have GL 1.3 without it");
    /* With the extension the same device runs it. */
    gl13.hide_extensions = NULL;
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FIXED, .strict = true,
                                                                 .profile = gl13 }, dir, HT_OK);
    ht_renderer_destroy(r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_oversized_shader_drops_full_naming_the_cap),
        cmocka_unit_test(test_shader_that_is_a_fifo_drops_full_without_blocking),
        cmocka_unit_test(test_combiner_light_beyond_the_bundle_refuses_the_fixed_tier),
        cmocka_unit_test(test_npot_albedo_refuses_the_fixed_tier_without_npot),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

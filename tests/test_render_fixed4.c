/* test_render_fixed4 — the fixed4 tier on OSMesa: it draws the full tier's
   passes over the same index ranges, calls no shader, does its per-vertex
   CPU work only when the eye or a light moves (local-viewer rule) or none
   at all (texture-matrix rule), and is what a GL 1.3 device with four
   units gets, by the renderer's own choice and under Mesa's override. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "hairgen.h"
#include "support_log.h"
#include "support_render.h"
#include "support_scratch.h"

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "fixed4", 128) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static ht_renderer *forced(ht_tier tier, const char *dir) {
    return ht_test_renderer_create((ht_renderer_desc){ .tier = tier, .strict = true }, dir ? dir : fx.bundle_dir,
                                   HT_OK);
}

static void draw(ht_renderer *r, const ht_frame_desc *f, ht_image *img) {
    ht_test_draw(&fx.gl, r, f, ht_test_background, img);
}

static void test_fixed4_draws_the_full_tiers_passes_over_the_same_ranges(void **state) {
    (void)state;
    ht_frame_desc f = ht_test_furball_frame(3.0f);
    ht_image img;
    ht_renderer *full = forced(HT_TIER_FULL, NULL);
    assert_int_equal(ht_renderer_set_mesh(full, &fx.mesh), HT_OK);
    draw(full, &f, &img);
    ht_image_free(&img);
    ht_trace want = *ht_renderer_trace(full);
    ht_renderer_destroy(full);

    ht_renderer *r = forced(HT_TIER_FIXED4, NULL);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    draw(r, &f, &img);
    const ht_trace *got = ht_renderer_trace(r);
    assert_int_equal(got->count, want.count);
    assert_int_equal(got->count, HT_PASS_COUNT);
    for (int i = 0; i < got->count; i++) {
        const ht_trace_entry *a = &got->entries[i], *b = &want.entries[i];
        assert_int_equal(a->pass, b->pass);
        assert_int_equal(a->sub_pass, b->sub_pass);
        assert_int_equal(a->cull, b->cull);
        assert_int_equal(a->cull_face, b->cull_face);
        assert_int_equal(a->depth_func, b->depth_func);
        assert_int_equal(a->depth_write, b->depth_write);
        assert_int_equal(a->color_write, b->color_write);
        assert_int_equal(a->blend, b->blend);
        assert_int_equal(a->alpha_test, b->alpha_test);
        assert_int_equal(a->alpha_func, b->alpha_func);
        assert_true(a->alpha_ref == b->alpha_ref);
        assert_int_equal(a->first_index, b->first_index);
        assert_int_equal(a->index_count, b->index_count);
        assert_int_equal(a->gl_error, GL_NO_ERROR);
    }
    ht_test_pixel_stats st = ht_test_pixel_stats_of(&img, ht_test_background);
    assert_true(st.changed > 500);
    assert_int_equal(st.magenta, 0);
    ht_image_free(&img);
    ht_renderer_destroy(r);
}

/* The shipped fur-ball scene is close to its camera: the generator picks
   the local-viewer rule, whose CPU work happens once per eye or light
   position, never per frame of a still camera. */
static void test_fixed4_local_viewer_works_only_when_the_eye_moves(void **state) {
    (void)state;
    assert_non_null(strstr(ht_test_read_file(fx.bundle_dir, "fixed4.json"), "\"viewer\":\t\"local\""));
    ht_renderer *r = forced(HT_TIER_FIXED4, NULL);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_image img;
    ht_frame_desc still = ht_test_furball_frame(3.0f), moved = ht_test_furball_frame(3.5f);
    const uint64_t n = fx.mesh.vertex_count;
    draw(r, &still, &img);
    ht_image_free(&img);
    assert_true(ht_renderer_get_stats(r).cpu_vertices == n);
    for (int i = 0; i < 3; i++) {
        draw(r, &still, &img);
        ht_image_free(&img);
    }
    assert_true(ht_renderer_get_stats(r).cpu_vertices == n);
    draw(r, &moved, &img);
    ht_image_free(&img);
    ht_renderer_stats st = ht_renderer_get_stats(r);
    assert_true(st.cpu_vertices == 2 * n);
    assert_true(st.frames == 5);
    ht_renderer_destroy(r);
}

/* A camera far from the hair: one V per frame is enough, the texture
   matrices make every coordinate, and no frame costs the CPU anything per
   vertex, whatever the camera and lights do. */
static void test_fixed4_texture_matrix_rule_does_no_per_vertex_cpu_work(void **state) {
    (void)state;
    char scene[256], dir[256], err[512];
    snprintf(scene, sizeof scene, "%s/far.json", fx.work);
    ht_test_write_file(fx.work, "far.json",
                       "{\"format\": \"hairtier-scene/1\", \"resolution\": [128, 128],\n"
                       " \"camera\": {\"eye\": [0, 6, 120], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 1.5,"
                       " \"near\": 50, \"far\": 300},\n"
                       " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]},\n"
                       "            {\"type\": \"directional\", \"direction\": [-0.7, 0.2, -0.6], \"color\": [0.3, 0.4, 0.5]}],\n"
                       " \"background\": [0, 0, 0],\n"
                       " \"geometry\": {\"type\": \"furball\", \"hairs\": 400, \"joints\": 16, \"length\": 0.0625}}\n");
    snprintf(dir, sizeof dir, "%s/far-bundle", fx.work);
    if (ht_generate_bundle("materials/dark-brown.json", scene, dir, NULL, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    assert_non_null(strstr(ht_test_read_file(dir, "fixed4.json"), "\"viewer\":\t\"infinite\""));
    ht_renderer *r = forced(HT_TIER_FIXED4, dir);
    assert_true(ht_test_logged("coordinates by the texture matrix"));
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    for (int i = 0; i < 4; i++) {
        ht_frame_desc f = ht_test_furball_frame(3.0f + 0.25f * (float)i);
        ht_light lights[2] = { f.lights[0], f.lights[0] };
        lights[1].vector[0] = -lights[1].vector[0] + 0.1f * (float)i;
        f.lights = lights;
        f.light_count = 2;
        ht_image img;
        draw(r, &f, &img);
        ht_test_pixel_stats st = ht_test_pixel_stats_of(&img, ht_test_background);
        assert_true(st.changed > 500);
        ht_image_free(&img);
    }
    ht_renderer_stats st = ht_renderer_get_stats(r);
    assert_true(st.frames == 4);
    assert_true(st.cpu_vertices == 0);
    ht_renderer_destroy(r);
}

static void test_fixed4_needs_four_units_and_says_so(void **state) {
    (void)state;
    ht_test_log_clear();
    ht_renderer *r = ht_test_renderer_create(
        (ht_renderer_desc){ .tier = HT_TIER_FIXED4, .strict = true, .profile = { .texture_units = 3 } }, fx.bundle_dir,
        HT_ERR_UNSUPPORTED);
    assert_null(r);
    assert_true(ht_test_logged("fixed4: needs 4 texture units, have 3"));
    r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FIXED4, .strict = true,
                                                    .profile = { .hide_extensions = "GL_ARB_texture_env_combine",
                                                                 .gl_major = 1, .gl_minor = 2 } },
                                fx.bundle_dir, HT_ERR_UNSUPPORTED);
    assert_null(r);
    assert_true(ht_test_logged("fixed4: needs GL_ARB_texture_env_combine"));
}

static void test_mesa_gl13_override_picks_fixed4(void **state) {
    (void)state;
    char out[8192];
    ht_test_run_child("1.3", fx.bundle_dir, out, sizeof out);
    if (!strstr(out, "hairtier: device GL 1.3")) fail_msg("child did not see GL 1.3:\n%s", out);
    assert_non_null(strstr(out, "skipped full: needs GL 2.1, have 1.3"));
    assert_non_null(strstr(out, "skipped vertex: needs GL 2.0, have 1.3"));
    if (!strstr(out, "result=ok tier=fixed4\n")) fail_msg("no fixed4 in:\n%s", out);
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "--child") == 0) return ht_test_child_select_only(argv[2]); /* under MESA_GL_VERSION_OVERRIDE */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixed4_draws_the_full_tiers_passes_over_the_same_ranges),
        cmocka_unit_test(test_fixed4_local_viewer_works_only_when_the_eye_moves),
        cmocka_unit_test(test_fixed4_texture_matrix_rule_does_no_per_vertex_cpu_work),
        cmocka_unit_test(test_fixed4_needs_four_units_and_says_so),
        cmocka_unit_test(test_mesa_gl13_override_picks_fixed4),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

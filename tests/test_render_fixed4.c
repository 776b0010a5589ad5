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

#include "fixed4_program.h"
#include <hairtier/hairgen.h>
#include "support_log.h"
#include "support_probe.h"
#include "support_render.h"
#include "support_scratch.h"

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    /* the probe's size, so its flat cells can be drawn here too */
    return ht_test_furball_setup(&fx, "fixed4", HT_PROBE_SIZE) ? 0 : -1;
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

/* GL lighting's wrapped diffuse with two lights, on the probe's flat cells
   (support_probe.h: one T, N and ao per cell) under a diffuse-only
   material, so every pixel is the primary colour: each cell as
   ht_fixed4_back_slopes says GL sums it (the brighter light exact, the
   other's chord), and within that chord's bound of the model. */
static void test_fixed4_two_lights_diffuse_follows_the_documented_slopes(void **state) {
    (void)state;
    char material[256], scene[256], dir[256], err[1024];
    snprintf(material, sizeof material, "%s/diffuse-only.json", fx.work);
    snprintf(scene, sizeof scene, "%s/two-lights.json", fx.work);
    snprintf(dir, sizeof dir, "%s/diffuse-bundle", fx.work);
    ht_test_write_file(fx.work, "diffuse-only.json",
                       "{ \"format\": \"hairtier-material/1\", \"name\": \"diffuse-only\", \"model\": \"scheuermann\",\n"
                       "  \"diffuse\": {\"color\": [0.8, 0.6, 0.4], \"wrap\": 0.3},\n"
                       "  \"primary\": {\"color\": [0, 0, 0], \"exponent\": 60, \"shift\": 0},\n"
                       "  \"secondary\": {\"color\": [0, 0, 0], \"exponent\": 20, \"shift\": 0} }\n");
    const ht_light lights[2] = { { HT_LIGHT_DIRECTIONAL, { 0.3f, 0.5f, 0.8f }, { 0.5f, 0.45f, 0.4f } },
                                 { HT_LIGHT_DIRECTIONAL, { -0.6f, -0.2f, -0.7f }, { 0.9f, 0.95f, 1.0f } } };
    char text[1024];
    snprintf(text, sizeof text,
             "{ \"format\": \"hairtier-scene/1\", \"resolution\": [%d, %d],\n"
             "  \"camera\": {\"eye\": [0, 0, %g], \"target\": [0, 0, 0], \"fov_y\": %g},\n"
             "  \"lights\": [{\"type\": \"directional\", \"direction\": [0.3, 0.5, 0.8], \"color\": [0.5, 0.45, 0.4]},\n"
             "             {\"type\": \"directional\", \"direction\": [-0.6, -0.2, -0.7], \"color\": [0.9, 0.95, 1.0]}],\n"
             "  \"geometry\": {\"type\": \"furball\"} }\n", HT_PROBE_SIZE, HT_PROBE_SIZE, HT_PROBE_EYE_Z, HT_PROBE_FOV_Y);
    ht_test_write_file(fx.work, "two-lights.json", text);
    if (ht_generate_bundle(material, scene, dir, NULL, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_fixed4_program p;
    if (ht_fixed4_parse(ht_test_read_file(dir, "fixed4.json"), "fixed4.json", &p, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    assert_int_equal(p.lights, 2);
    const float colors[2][3] = { { 0.5f, 0.45f, 0.4f }, { 0.9f, 0.95f, 1.0f } };
    double back[HT_FIXED4_MAX_LIGHTS];
    ht_fixed4_back_slopes(&p, colors, back);
    const int scale = ht_fixed4_scale(&p, colors);
    const double w = p.shading.wrap, excess = w * (1.0 - 2.0 * w) / (1.0 - w);

    ht_probe_make_cells();
    ht_mesh mesh;
    ht_probe_build_mesh(&mesh);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FIXED4, .strict = true }, dir, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &mesh), HT_OK);
    ht_frame_desc f = ht_probe_frame(&lights[0]);
    f.lights = lights;
    f.light_count = 2;
    ht_image img;
    static const float black[3] = { 0, 0, 0 };
    ht_test_draw(&fx.gl, r, &f, black, &img);
    int worst_gl = 0, worst_model = 0, pixels = 0, behind = 0;
    for (int row = 0; row < HT_PROBE_SIZE; row++)
        for (int x = 0; x < HT_PROBE_SIZE; x++) {
            double P[3];
            int ci = ht_probe_cell_at(x, HT_PROBE_SIZE - 1 - row, P);
            if (ci < 0) continue;
            const ht_probe_cell *c = &ht_probe_cells[ci];
            /* a vertex without a tangent is black, documented (fixed4_program.h) */
            if (c->T[0] == 0 && c->T[1] == 0 && c->T[2] == 0) continue;
            double N[3] = { c->N[0], c->N[1], c->N[2] }, len = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
            double n_dot_l[2] = { 0, 0 };
            for (int l = 0; l < 2 && len > 0; l++) {
                double L[3] = { lights[l].vector[0], lights[l].vector[1], lights[l].vector[2] };
                double ll = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
                n_dot_l[l] = (N[0] * L[0] + N[1] * L[1] + N[2] * L[2]) / (len * ll);
            }
            behind += n_dot_l[0] < 0.0 || n_dot_l[1] < 0.0;
            const uint8_t *got = img.pixels + ((size_t)row * HT_PROBE_SIZE + x) * 4;
            for (int k = 0; k < 3; k++) {
                double sum = 0.0, model = 0.0, chord_room = 0.0, deficit = 0.0;
                for (int l = 0; l < 2; l++) {
                    const double kl = p.shading.diffuse_color[k] * colors[l][k], xl = n_dot_l[l];
                    sum += kl * (w + (1.0 - w) * fmax(xl, 0.0) - back[l] * fmax(-xl, 0.0));
                    model += kl * ht_model_wrap_diffuse_d(xl, w);
                    /* the chord light may be too bright by up to excess; the
                       exact one, past its kink, takes from the other */
                    if (back[l] < 1.0 - w) chord_room += kl * excess;
                    else deficit += kl * fmax(0.0, -(w + (1.0 - w) * xl));
                }
                /* GL: the sum over the scale, clamped, then x scale x ao on the last stage */
                const double gl_value = fmin(1.0, fmin(1.0, fmax(0.0, sum) / scale) * scale * c->ao);
                const int e_gl = abs(got[k] - ht_probe_to_byte(gl_value));
                worst_gl = e_gl > worst_gl ? e_gl : worst_gl;
                /* the model, give or take what the slopes document */
                const double lo = (model - deficit) * c->ao - 2.0 / 255.0,
                             hi = (model + chord_room) * c->ao + 2.0 / 255.0;
                const double v = got[k] / 255.0;
                const int e_model = v < lo ? (int)lround((lo - v) * 255.0) : v > hi ? (int)lround((v - hi) * 255.0) : 0;
                worst_model = e_model > worst_model ? e_model : worst_model;
            }
            pixels++;
        }
    printf("fixed4 two-light diffuse: %d pixels (%d behind a light), max %d/255 from the documented GL sum, "
           "%d/255 outside the model's chord bound\n", pixels, behind, worst_gl, worst_model);
    assert_true(pixels > HT_PROBE_GRID * HT_PROBE_GRID * 20);
    assert_true(behind > pixels / 4);
    assert_true(worst_gl <= 2);
    assert_int_equal(worst_model, 0);
    ht_image_free(&img);
    ht_renderer_destroy(r);
    ht_mesh_free(&mesh);
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
        cmocka_unit_test(test_fixed4_two_lights_diffuse_follows_the_documented_slopes),
        cmocka_unit_test(test_fixed4_needs_four_units_and_says_so),
        cmocka_unit_test(test_mesa_gl13_override_picks_fixed4),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

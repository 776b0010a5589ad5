/* test_render_passes — the renderer on OSMesa: the four passes in order with
   the same state and draw ranges in every tier (read back from GL by the
   trace), no GL error after any pass, the depth-EQUAL pass really colours
   opaque texels, low-end devices (a device profile, or Mesa's own
   MESA_GL_VERSION_OVERRIDE in a re-executed child) get a lower tier with the
   reason logged, the GLSL tiers draw the same image on one or two texture
   units as on all of the device's, a broken shader drops to the next tier without drawing
   magenta or nothing, and bad bundles fail with one line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <math.h>

#include <GL/gl.h>

#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "manifest.h"
#include "support_driver.h"
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE 96

static ht_test_furball fx;

/* ---- fixtures ---- */

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "render", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static ht_frame_desc frame(void) { return ht_test_furball_frame(2.4f); }

/* A renderer on the fur ball, the fixture's bundle unless desc names one. */
static ht_renderer *create(ht_renderer_desc desc, ht_result expect) {
    ht_renderer *r = ht_test_renderer_create(desc, fx.bundle_dir, expect);
    if (r) assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    return r;
}

/* Clears, draws one frame, reads it back. */
static void render(ht_renderer *r, ht_image *img) {
    ht_frame_desc f = frame();
    ht_test_draw(&fx.gl, r, &f, ht_test_background, img);
}

static ht_test_pixel_stats stats(const ht_image *img) { return ht_test_pixel_stats_of(img, ht_test_background); }

/* Scheuermann's passes as DESIGN.md lists them. */
/* in_order: the blended passes as under an opacity scale or
   ht_renderer_set_back_to_front (both faces in the back pass, in the
   mesh's order; none in the front), else split by facing. */
static void check_pass_state(const ht_trace_entry *e, float cutoff, bool in_order) {
    assert_true(e->alpha_test);
    assert_float_equal(e->alpha_ref, cutoff, 1e-6f);
    assert_int_equal(e->gl_error, GL_NO_ERROR);
    switch (e->pass) {
    case HT_PASS_PRIME_Z:
        assert_false(e->cull);
        assert_true(e->depth_write);
        assert_int_equal(e->depth_func, GL_LESS);
        assert_false(e->color_write);
        assert_false(e->blend);
        assert_int_equal(e->alpha_func, GL_GEQUAL);
        break;
    case HT_PASS_OPAQUE:
        assert_false(e->cull);
        assert_false(e->depth_write);
        assert_int_equal(e->depth_func, GL_EQUAL);
        assert_true(e->color_write);
        assert_false(e->blend);
        assert_int_equal(e->alpha_func, GL_GEQUAL);
        break;
    case HT_PASS_BACK:
    case HT_PASS_FRONT:
        if (in_order) {
            assert_int_equal(e->cull, e->pass == HT_PASS_FRONT);
            if (e->cull) assert_int_equal(e->cull_face, GL_FRONT_AND_BACK);
            assert_false(e->depth_write);
        } else {
            assert_true(e->cull);
            assert_int_equal(e->cull_face, e->pass == HT_PASS_BACK ? GL_FRONT : GL_BACK);
            assert_int_equal(e->depth_write, e->pass == HT_PASS_FRONT);
        }
        assert_int_equal(e->depth_func, GL_LESS);
        assert_true(e->color_write);
        assert_true(e->blend);
        assert_int_equal(e->alpha_func, GL_LESS);
        break;
    default:
        fail_msg("unknown pass %d", (int)e->pass);
    }
}

static void check_trace(const ht_trace *t, float cutoff, bool in_order) {
    assert_int_equal(t->count, HT_PASS_COUNT);
    for (int i = 0; i < t->count; i++) {
        assert_int_equal(t->entries[i].pass, i);
        assert_int_equal(t->entries[i].sub_pass, 0);
        assert_int_equal(t->entries[i].first_index, 0);
        assert_int_equal(t->entries[i].index_count, fx.mesh.index_count);
        check_pass_state(&t->entries[i], cutoff, in_order);
    }
}

static bool same_pass_list(const ht_trace *a, const ht_trace *b) {
    if (a->count != b->count) return false;
    for (int i = 0; i < a->count; i++)
        if (memcmp(&a->entries[i], &b->entries[i], sizeof a->entries[i]) != 0) return false;
    return true;
}

/* ---- tests ---- */

static void test_render_flat_mode_draws_the_four_passes_in_order(void **state) {
    (void)state;
    ht_renderer *r = create((ht_renderer_desc){ .flat = true, .flat_color = { 0.9f, 0.8f, 0.1f } }, HT_OK);
    ht_image img;
    render(r, &img);
    check_trace(ht_renderer_trace(r), 0.98f, false);
    /* Flat colour has alpha 1: every hair pixel comes from the depth-EQUAL pass. */
    ht_test_pixel_stats s = stats(&img);
    assert_true(s.changed > SIZE * SIZE / 20);
    ht_image_free(&img);
    ht_renderer_destroy(r);
}

/* r, expected to draw `tier`, draws the flat renderer's pass list (same
   passes, state and ranges) and hair without a failed shader's magenta;
   r is destroyed. */
static void expect_flat_pass_list(const ht_renderer *flat, ht_renderer *r, ht_tier tier) {
    ht_image img;
    assert_int_equal(ht_renderer_tier(r), tier);
    render(r, &img);
    check_trace(ht_renderer_trace(r), 0.98f, false);
    if (!same_pass_list(ht_renderer_trace(flat), ht_renderer_trace(r)))
        fail_msg("%s tier's pass list differs from flat mode's", ht_tier_name(tier));
    ht_test_pixel_stats s = stats(&img);
    assert_true(s.changed > 0);
    assert_int_equal(s.magenta, 0);
    ht_image_free(&img);
    ht_renderer_destroy(r);
}

static void test_render_glsl_tiers_share_the_flat_pass_list(void **state) {
    (void)state;
    ht_renderer *flat = create((ht_renderer_desc){ .flat = true }, HT_OK);
    ht_image img;
    render(flat, &img);
    ht_image_free(&img);
    const ht_tier tiers[2] = { HT_TIER_FULL, HT_TIER_VERTEX };
    for (int i = 0; i < 2; i++)
        expect_flat_pass_list(flat, create((ht_renderer_desc){ .tier = tiers[i], .strict = true }, HT_OK), tiers[i]);
    ht_renderer_destroy(flat);
}

/* How far the image is from the background, summed over every channel. */
static double ink(const ht_image *img) {
    double sum = 0;
    for (int i = 0; i < img->width * img->height; i++)
        for (int c = 0; c < 3; c++)
            sum += fabs(img->pixels[i * img->channels + c] / 255.0 - ht_test_background[c]);
    return sum;
}

/* The width rule's opacity (lod.h) in every tier: the same four passes
   with the reference at 1 (the Z-prime and opaque passes take no scaled
   fragment, the blended ones every one) and about half the ink at half
   the opacity: a tier that ignored the scale would keep all of it, one
   that dropped scaled strands would lose nearly all. */
static void test_render_opacity_scale_blends_every_strand_in_every_tier(void **state) {
    (void)state;
    const ht_tier tiers[] = { HT_TIER_FULL, HT_TIER_VERTEX, HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
    for (size_t i = 0; i < sizeof tiers / sizeof tiers[0]; i++) {
        ht_renderer *r = create((ht_renderer_desc){ .tier = tiers[i], .strict = true }, HT_OK);
        assert_int_equal(ht_renderer_set_opacity_scale(r, 0.0f), HT_ERR_INVALID_ARGUMENT);
        assert_int_equal(ht_renderer_set_opacity_scale(r, 1.5f), HT_ERR_INVALID_ARGUMENT);
        assert_int_equal(ht_renderer_set_opacity_scale(r, NAN), HT_ERR_INVALID_ARGUMENT);
        ht_image whole, half;
        render(r, &whole);
        assert_int_equal(ht_renderer_set_opacity_scale(r, 0.5f), HT_OK);
        render(r, &half);
        check_trace(ht_renderer_trace(r), 1.0f, true);
        const double ratio = ink(&half) / ink(&whole);
        printf("%s: ink at opacity 0.5 / at 1: %.3f\n", ht_tier_name(tiers[i]), ratio);
        assert_true(ratio > 0.3 && ratio < 0.7);
        ht_image_free(&whole);
        ht_image_free(&half);
        ht_renderer_destroy(r);
    }
}

/* The width rule per vertex (lod.h): full and gl11 (its CPU colours) do
   it, the desktop vertex, fixed4 and fixed tiers cannot (the caller keeps
   it per draw) and say so. Where it is on and the mesh back to front: the
   passes with one blended pass in mesh order and the material's reference
   (0.98: lod.h's HT_WIDTH_RULE_VERTEX_REF), more pixels touched (the thin
   tips and far strands widened to 1.5 px) and the ink kept within a
   quarter (their alpha scaled by the ratio): a tier that widened without
   scaling would gain ink with the pixels, one that did neither would touch
   no more pixels. Inside out the hair is drawn as it is, pixel for pixel. */
static void test_render_width_rule_per_vertex_where_the_tier_can(void **state) {
    (void)state;
    const struct { ht_tier tier; bool per_vertex; } tiers[] = {
        { HT_TIER_FULL, true }, { HT_TIER_GL11, true }, { HT_TIER_VERTEX, false },
        { HT_TIER_FIXED4, false }, { HT_TIER_FIXED, false },
    };
    for (size_t i = 0; i < sizeof tiers / sizeof tiers[0]; i++) {
        ht_renderer *r = create((ht_renderer_desc){ .tier = tiers[i].tier, .strict = true }, HT_OK);
        ht_image off, on;
        render(r, &off);
        assert_false(ht_renderer_width_rule_per_vertex(r));
        ht_renderer_set_width_rule(r, true);
        assert_false(ht_renderer_width_rule_per_vertex(r)); /* from the next ht_renderer_set_mesh on */
        assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
        assert_int_equal(ht_renderer_width_rule_per_vertex(r), tiers[i].per_vertex);
        render(r, &on);
        /* inside out it is not drawn (lod.h: it applies where the mesh is back to front) */
        assert_int_equal(stats(&on).changed, stats(&off).changed);
        assert_true(fabs(ink(&on) / ink(&off) - 1.0) < 1e-9);
        /* the mesh said to be back to front: widened, one blended pass in its order */
        if (tiers[i].per_vertex) {
            ht_image_free(&on);
            ht_renderer_set_back_to_front(r, true);
            render(r, &on);
        }
        const double ratio = ink(&on) / ink(&off);
        const int pixels[2] = { stats(&off).changed, stats(&on).changed };
        printf("%s: per vertex %d, hair pixels %d -> %d, ink x %.3f\n", ht_tier_name(tiers[i].tier),
               tiers[i].per_vertex, pixels[0], pixels[1], ratio);
        if (tiers[i].per_vertex) {
            check_trace(ht_renderer_trace(r), HT_WIDTH_RULE_VERTEX_REF, true);
            assert_true(pixels[1] > pixels[0] * 1.05);
            assert_true(ratio > 0.75 && ratio < 1.25);
            ht_image inside_out;
            ht_renderer_set_back_to_front(r, false);
            render(r, &inside_out);
            check_trace(ht_renderer_trace(r), HT_WIDTH_RULE_VERTEX_REF, false);
            assert_int_equal(stats(&inside_out).changed, pixels[0]);
            ht_image_free(&inside_out);
        } else {
            assert_int_equal(pixels[1], pixels[0]);
        }
        ht_image_free(&off);
        ht_image_free(&on);
        ht_renderer_destroy(r);
    }
}

/* A Marschner material's bundle: its tier draws the same passes, same
   state, same ranges as flat mode on the same mesh. */
static void test_render_marschner_tier_shares_the_flat_pass_list(void **state) {
    (void)state;
    /* the pass list is the runtime's; the marschner shader on softpipe is
       test_render_marschner's softpipe run */
    HT_TEST_DRIVER_INDEPENDENT();
    char dir[200], err[1024];
    snprintf(dir, sizeof dir, "%s/marschner-bundle", fx.work);
    assert_int_equal(ht_test_bundle("materials/brown-marschner.json", "furball", "scenes/furball.json", dir, sizeof dir,
                                    err, sizeof err), HT_OK);
    ht_renderer *flat = create((ht_renderer_desc){ .flat = true }, HT_OK);
    ht_image img;
    render(flat, &img);
    ht_image_free(&img);
    expect_flat_pass_list(flat, create((ht_renderer_desc){ .bundle_dir = dir }, HT_OK), HT_TIER_MARSCHNER);
    ht_renderer_destroy(flat);
}

static void test_render_depth_equal_pass_colours_opaque_texels(void **state) {
    (void)state;
    /* With a tiny cutoff almost every texel is opaque: the transparent passes
       draw (nearly) nothing, so what shows is the depth-EQUAL pass's work. A
       transform that is not bit-identical across passes leaves it blank. */
    char dir[256];
    ht_test_furball_copy_bundle(&fx, "low-cutoff", dir, sizeof dir);
    ht_test_set_json_number(dir, "manifest.json", "opaque_cutoff", 0.004);
    ht_image flat_img, img;
    ht_renderer *flat = create((ht_renderer_desc){ .flat = true, .bundle_dir = dir }, HT_OK);
    render(flat, &flat_img);
    ht_test_pixel_stats coverage = stats(&flat_img);
    ht_renderer_destroy(flat);
    const ht_tier tiers[2] = { HT_TIER_FULL, HT_TIER_VERTEX };
    for (int i = 0; i < 2; i++) {
        ht_renderer *r = create((ht_renderer_desc){ .tier = tiers[i], .strict = true, .bundle_dir = dir }, HT_OK);
        render(r, &img);
        check_trace(ht_renderer_trace(r), 0.004f, false);
        ht_test_pixel_stats s = stats(&img);
        if (s.changed < coverage.changed / 4 || s.changed < SIZE * SIZE / 20)
            fail_msg("%s: %d pixels shaded, flat coverage %d", ht_tier_name(tiers[i]), s.changed, coverage.changed);
        ht_image_free(&img);
        ht_renderer_destroy(r);
    }
    ht_image_free(&flat_img);
}

static void test_render_broken_full_shader_drops_to_vertex(void **state) {
    (void)state;
    char dir[256];
    ht_test_furball_copy_bundle(&fx, "broken-frag", dir, sizeof dir);
    ht_test_write_file(dir, "full.frag", "#version 120\nvoid main() { gl_FragColor = vec4(1.0, 0.0, 1.0, 1.0) }\n");
    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    assert_true(ht_test_logged("skipped full: compile failed: full.frag: "));
    assert_non_null(strstr(ht_renderer_reason(r), "full: compile failed"));
    ht_image img;
    render(r, &img);
    ht_test_pixel_stats s = stats(&img);
    assert_true(s.changed > 0);
    assert_int_equal(s.magenta, 0);
    ht_image_free(&img);
    ht_renderer_destroy(r);

    /* Forced and strict, the same failure is an error. */
    r = create((ht_renderer_desc){ .bundle_dir = dir, .tier = HT_TIER_FULL, .strict = true }, HT_ERR_UNSUPPORTED);
    assert_null(r);
    assert_true(ht_test_logged("full: compile failed"));
}

static void test_render_missing_shader_file_drops_to_vertex(void **state) {
    (void)state;
    char dir[256], path[512];
    ht_test_furball_copy_bundle(&fx, "missing-frag", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/full.frag", dir);
    assert_int_equal(unlink(path), 0);
    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    assert_true(ht_test_logged("full.frag: cannot read"));
    ht_renderer_destroy(r);
}

static void test_render_gl20_profile_picks_vertex_with_the_reason(void **state) {
    (void)state;
    ht_renderer *r = create((ht_renderer_desc){ .profile = { .gl_major = 2, .gl_minor = 0 } }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    assert_true(ht_test_logged("skipped full: needs GL 2.1, have 2.0"));
    ht_image img;
    render(r, &img);
    check_trace(ht_renderer_trace(r), 0.98f, false);
    ht_image_free(&img);
    ht_renderer_destroy(r);
}

/* GL 1.3 leaves the combiner tiers: four units pick fixed4, two pick fixed. */
static void test_render_gl13_profile_picks_fixed4_with_four_units_and_fixed_with_two(void **state) {
    (void)state;
    const int units[2] = { 4, 2 };
    const ht_tier want[2] = { HT_TIER_FIXED4, HT_TIER_FIXED };
    for (int i = 0; i < 2; i++) {
        ht_test_log_clear();
        ht_renderer *r = NULL;
        ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc,
                                                                .bundle_dir = fx.bundle_dir,
                                                                .log = ht_test_log_capture,
                                                                .profile = { .gl_major = 1, .gl_minor = 3,
                                                                             .texture_units = units[i] } }, &r);
        assert_true(ht_test_logged("skipped full: needs GL 2.1, have 1.3"));
        assert_true(ht_test_logged("skipped vertex: needs GL 2.0, have 1.3"));
        if (units[i] < 4) assert_true(ht_test_logged("skipped fixed4: needs 4 texture units, have 2"));
        assert_int_equal(res, HT_OK);
        assert_int_equal(ht_renderer_tier(r), want[i]);
        ht_renderer_destroy(r);
    }
}

/* Pixels brighter than black in some channel: hair that is lit, on the
   black background these tests clear to. */
static int lit_pixels(const ht_image *img) {
    int lit = 0;
    for (int i = 0; i < img->width * img->height; i++) {
        const uint8_t *p = img->pixels + 4 * i;
        lit += p[0] > 8 || p[1] > 8 || p[2] > 8;
    }
    return lit;
}

/* Tangent and ao are generic attributes, not texture coordinates: a device
   with just the units a GLSL tier samples shades it as one with eight. The
   full tier needs a sampler per unit, so with one unit it runs the
   Kajiya-Kay material (albedo only); the vertex tier runs fixed4's four
   combiner stages (two LUTs, albedo, final), one coordinate set each. */
static void test_render_glsl_tiers_on_just_their_units_match_the_eight_unit_image(void **state) {
    (void)state;
    static const float black[3] = { 0, 0, 0 };
    char kk[256], err[1024];
    snprintf(kk, sizeof kk, "%s/kajiya-kay", fx.work);
    if (ht_test_bundle("materials/kajiya-kay.json", "furball", "scenes/furball.json", kk, sizeof kk, err, sizeof err) !=
        HT_OK)
        fail_msg("%s", err);
    const struct { ht_tier tier; const char *dir; int units; } cases[] = {
        { HT_TIER_FULL, kk, 1 },           { HT_TIER_FULL, fx.bundle_dir, 2 },
        { HT_TIER_VERTEX, fx.bundle_dir, 4 }, { HT_TIER_VERTEX, kk, 4 },
    };
    const ht_frame_desc f = frame();
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ht_image eight, few;
        ht_renderer *r = create((ht_renderer_desc){ .tier = cases[i].tier, .strict = true, .bundle_dir = cases[i].dir },
                                HT_OK);
        assert_true(ht_renderer_caps(r)->texture_units > cases[i].units);
        ht_test_draw(&fx.gl, r, &f, black, &eight);
        ht_renderer_destroy(r);
        r = create((ht_renderer_desc){ .tier = cases[i].tier, .strict = true, .bundle_dir = cases[i].dir,
                                       .profile = { .texture_units = cases[i].units } }, HT_OK);
        assert_int_equal(ht_renderer_caps(r)->texture_units, cases[i].units);
        ht_test_draw(&fx.gl, r, &f, black, &few);
        ht_renderer_destroy(r);
        int lit_eight = lit_pixels(&eight), lit_few = lit_pixels(&few);
        printf("%s tier, %d unit%s: %d lit pixels, %d with the device's units\n", ht_tier_name(cases[i].tier),
               cases[i].units, cases[i].units == 1 ? "" : "s", lit_few, lit_eight);
        /* not blank; the softpipe run's fur ball has half the hairs (support_driver.h) */
        assert_true(lit_eight > SIZE * SIZE / (ht_test_driver_cases_only() ? 20 : 10));
        if (memcmp(eight.pixels, few.pixels, (size_t)SIZE * SIZE * 4) != 0)
            fail_msg("%s tier with %d units: the image differs from the device's (%d vs %d lit pixels)",
                     ht_tier_name(cases[i].tier), cases[i].units, lit_few, lit_eight);
        ht_image_free(&eight);
        ht_image_free(&few);
    }
}

/* The vertex tier's fragment stage is GL_COMBINE: a device without it does
   not get the tier, and the log says why. */
static void test_render_vertex_tier_needs_texture_env_combine(void **state) {
    (void)state;
    const ht_device_profile no_combine = { .no_fragment_shaders = true,
                                           .hide_extensions = "GL_ARB_texture_env_combine GL_EXT_texture_env_combine" };
    /* Without combine only the last resort, gl11, runs. */
    ht_renderer *last = create((ht_renderer_desc){ .profile = no_combine }, HT_OK);
    assert_int_equal(ht_renderer_tier(last), HT_TIER_GL11);
    ht_renderer_destroy(last);
    assert_true(ht_test_logged("hairtier: skipped vertex: needs GL_ARB_texture_env_combine"));
    assert_true(ht_test_logged("hairtier: skipped fixed: needs GL_ARB_texture_env_combine"));
    /* With combine the same device runs the vertex tier. */
    ht_renderer *r = create((ht_renderer_desc){ .profile = { .no_fragment_shaders = true } }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    ht_renderer_destroy(r);
}

static void test_render_environment_forces_a_tier_and_desc_wins(void **state) {
    (void)state;
    setenv("HAIRTIER_TIER", "vertex", 1);
    ht_renderer *r = create((ht_renderer_desc){ 0 }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    assert_string_equal(ht_renderer_reason(r), "forced by HAIRTIER_TIER");
    ht_renderer_destroy(r);
    r = create((ht_renderer_desc){ .tier = HT_TIER_FULL }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL);
    ht_renderer_destroy(r);
    unsetenv("HAIRTIER_TIER");
}

static void test_render_missing_bundle_is_one_line_error(void **state) {
    (void)state;
    char dir[256];
    snprintf(dir, sizeof dir, "%s/no-such-bundle", fx.work);
    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir }, HT_ERR_IO);
    assert_null(r);
    char *line = strstr(ht_test_log_text, "no-such-bundle/manifest.json: cannot read");
    assert_non_null(line);
    /* one line: nothing after its newline */
    assert_string_equal(strchr(line, '\n'), "\n");
}

static void test_render_corrupt_manifest_is_one_line_error(void **state) {
    (void)state;
    char dir[256];
    ht_test_furball_copy_bundle(&fx, "corrupt-manifest", dir, sizeof dir);
    ht_test_write_file(dir, "manifest.json", "{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": ");
    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir }, HT_ERR_PARSE);
    assert_null(r);
    char *line = strstr(ht_test_log_text, "corrupt-manifest/manifest.json: line 1: malformed JSON");
    assert_non_null(line);
    assert_string_equal(strchr(line, '\n'), "\n");

    ht_test_write_file(dir, "manifest.json",
               "{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"directional\"],"
               " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": 2.1}, \"files\": {}}]}");
    r = create((ht_renderer_desc){ .bundle_dir = dir }, HT_ERR_PARSE);
    assert_true(ht_test_logged("manifest.json: tiers[0].requires.gl: expected a string"));
}

static void test_render_head_and_hair_draw_without_gl_errors(void **state) {
    (void)state;
    ht_mesh hair = { 0 }, head = { 0 };
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = 1, .strips = 16, .segments = 6, .seed = 1 },
                                           &hair, &head), HT_OK);
    ht_mesh_sort_inside_out(&hair);
    ht_renderer *r = create((ht_renderer_desc){ 0 }, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &hair), HT_OK);
    ht_frame_desc f = frame();
    f.camera.eye[2] = 4;
    f.opaque = &head;
    ht_image img;
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    for (int i = 0; i < ht_renderer_trace(r)->count; i++)
        assert_int_equal(ht_renderer_trace(r)->entries[i].gl_error, GL_NO_ERROR);
    const uint8_t *centre = img.pixels + 4 * ((SIZE / 2) * SIZE + SIZE / 2);
    assert_true(abs(centre[0] - (int)(ht_test_background[0] * 255 + 0.5f)) > 8 ||
                abs(centre[2] - (int)(ht_test_background[2] * 255 + 0.5f)) > 8); /* the lit head */
    ht_image_free(&img);
    ht_renderer_destroy(r);
    assert_int_equal(ht_renderer_set_mesh(NULL, &hair), HT_ERR_INVALID_ARGUMENT);
    ht_mesh_free(&hair);
    ht_mesh_free(&head);
}

static void test_render_rejects_degenerate_cameras(void **state) {
    (void)state;
    ht_renderer *r = create((ht_renderer_desc){ .flat = true }, HT_OK);
    ht_frame_desc f = frame();
    memcpy(f.camera.target, f.camera.eye, sizeof f.camera.eye);
    assert_int_equal(ht_renderer_draw(r, &f), HT_ERR_INVALID_ARGUMENT);
    f = frame();
    f.camera.fov_y = 180;
    assert_int_equal(ht_renderer_draw(r, &f), HT_ERR_INVALID_ARGUMENT);
    f = frame();
    f.light_count = HT_MAX_LIGHTS + 1;
    assert_int_equal(ht_renderer_draw(r, &f), HT_ERR_INVALID_ARGUMENT);
    ht_renderer_destroy(r);
}

/* ---- Mesa's own version override, in a fresh process ---- */

static void test_render_mesa_gl20_override_picks_vertex(void **state) {
    (void)state;
    char out[8192];
    ht_test_run_child("2.0", fx.bundle_dir, out, sizeof out);
    if (!strstr(out, "hairtier: device GL 2.0")) fail_msg("child did not see GL 2.0:\n%s", out);
    assert_non_null(strstr(out, "skipped full: needs GL 2.1, have 2.0"));
    assert_non_null(strstr(out, "result=ok tier=vertex"));
}

static void test_render_mesa_gl13_override_skips_glsl_tiers(void **state) {
    (void)state;
    char out[8192];
    ht_test_run_child("1.3", fx.bundle_dir, out, sizeof out);
    if (!strstr(out, "hairtier: device GL 1.3")) fail_msg("child did not see GL 1.3:\n%s", out);
    assert_non_null(strstr(out, "skipped full: needs GL 2.1, have 1.3"));
    assert_non_null(strstr(out, "skipped vertex: needs GL 2.0, have 1.3"));
    /* llvmpipe keeps 8 units under the override: the four-unit tier */
    assert_non_null(strstr(out, "result=ok tier=fixed4\n"));
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "--child") == 0) return ht_test_child_select_only(argv[2]); /* under MESA_GL_VERSION_OVERRIDE */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_render_flat_mode_draws_the_four_passes_in_order),
        cmocka_unit_test(test_render_glsl_tiers_share_the_flat_pass_list),
        cmocka_unit_test(test_render_marschner_tier_shares_the_flat_pass_list),
        cmocka_unit_test(test_render_opacity_scale_blends_every_strand_in_every_tier),
        cmocka_unit_test(test_render_width_rule_per_vertex_where_the_tier_can),
        cmocka_unit_test(test_render_depth_equal_pass_colours_opaque_texels),
        cmocka_unit_test(test_render_broken_full_shader_drops_to_vertex),
        cmocka_unit_test(test_render_missing_shader_file_drops_to_vertex),
        cmocka_unit_test(test_render_gl20_profile_picks_vertex_with_the_reason),
        cmocka_unit_test(test_render_gl13_profile_picks_fixed4_with_four_units_and_fixed_with_two),
        cmocka_unit_test(test_render_glsl_tiers_on_just_their_units_match_the_eight_unit_image),
        cmocka_unit_test(test_render_vertex_tier_needs_texture_env_combine),
        cmocka_unit_test(test_render_environment_forces_a_tier_and_desc_wins),
        cmocka_unit_test(test_render_missing_bundle_is_one_line_error),
        cmocka_unit_test(test_render_corrupt_manifest_is_one_line_error),
        cmocka_unit_test(test_render_head_and_hair_draw_without_gl_errors),
        cmocka_unit_test(test_render_rejects_degenerate_cameras),
        cmocka_unit_test(test_render_mesa_gl20_override_picks_vertex),
        cmocka_unit_test(test_render_mesa_gl13_override_skips_glsl_tiers),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

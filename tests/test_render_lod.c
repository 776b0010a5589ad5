/* test_render_lod — every geometry LOD (lod.h) of the fixture's fur ball is
   drawn by the same four passes with the same state in every tier (the
   trace: only the draw range differs, and it is the LOD's whole index
   buffer), without a GL error, and still covers about as many pixels as
   full detail at a quarter of the size (the width rule on a real raster). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "support_render.h"

#define SIZE 48
/* Hair pixels at each LOD against full detail, at SIZE (the fixture's fur
   ball is about 1/10 of the scene's projected size here). */
#define PIXEL_BOUND 0.15

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "render_lod", SIZE) ? 0 : -1;
}
static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static int draw_lod(ht_renderer *r, const ht_mesh *mesh, ht_trace *trace) {
    assert_int_equal(ht_renderer_set_mesh(r, mesh), HT_OK);
    const ht_frame_desc frame = ht_test_furball_frame(3.0f);
    ht_image img;
    ht_test_draw(&fx.gl, r, &frame, ht_test_background, &img);
    *trace = *ht_renderer_trace(r);
    const int changed = ht_test_pixel_stats_of(&img, ht_test_background).changed;
    ht_image_free(&img);
    return changed;
}

static void same_passes_every_lod(ht_tier tier) {
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = tier, .strict = true }, fx.bundle_dir, HT_OK);
    ht_trace full;
    const int full_pixels = draw_lod(r, &fx.mesh, &full);
    assert_int_equal(full.count, HT_PASS_COUNT);
    for (int level = 1; level <= ht_lod_max_level(&fx.mesh); level++) {
        ht_lod_desc d;
        ht_mesh lod;
        ht_lod_level(level, &d);
        assert_int_equal(ht_mesh_build_lod(&fx.mesh, &d, &lod), HT_OK);
        ht_trace t;
        const int pixels = draw_lod(r, &lod, &t);
        printf("%s level %d: %d hair pixels, full detail %d\n", ht_tier_name(tier), level, pixels, full_pixels);
        assert_int_equal(t.count, full.count);
        for (int i = 0; i < t.count; i++) {
            assert_int_equal(t.entries[i].gl_error, GL_NO_ERROR);
            assert_int_equal(t.entries[i].index_count, lod.index_count);
            ht_trace_entry e = t.entries[i];
            e.index_count = full.entries[i].index_count;
            if (memcmp(&e, &full.entries[i], sizeof e) != 0)
                fail_msg("%s level %d: pass %d differs from full detail's", ht_tier_name(tier), level, i);
        }
        assert_true(abs(pixels - full_pixels) <= PIXEL_BOUND * full_pixels);
        ht_mesh_free(&lod);
    }
    ht_renderer_destroy(r);
}

static void full_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_FULL); }
static void vertex_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_VERTEX); }
static void fixed_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_FIXED); }
static void gl11_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_GL11); }

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(full_tier),
        cmocka_unit_test(vertex_tier),
        cmocka_unit_test(fixed_tier),
        cmocka_unit_test(gl11_tier),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

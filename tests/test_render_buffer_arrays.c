/* test_render_buffer_arrays — the fixed and gl11 tiers draw from buffer
   objects uploaded once (client arrays only where the device has no VBOs:
   NVIDIA copies client arrays across the bus at every draw). Through the GL fault
   layer (support_gl_fault.h, which counts every gl*Pointer call and those
   made with no GL_ARRAY_BUFFER bound), on the fur ball:

   - with VBOs, a steady frame (the camera and lights of the frame before)
     points every vertex array at buffer memory and uploads nothing;
   - with the device profile's no_vbo, every array is client memory, still
     nothing uploaded, and the pixels are those of the VBO run, exactly;
   - gl11: a moved eye uploads the recomputed colours once (glBufferSubData
     into the buffer set_mesh sized), and the frame after it none again;
   - an upload GL refuses (the fault layer's GL_OUT_OF_MEMORY) in a frame
     is one line naming the error, and that frame draws the same pixels
     from client arrays.
   Every buffer the tier made is deleted with the renderer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "support_gl_fault.h"
#include "support_log.h"
#include "support_render.h"

#define SIZE 96

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "buffer_arrays", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

typedef struct counted_frame {
    ht_image img;
    long pointers, client_pointers, uploads;
} counted_frame;

/* One frame, counted; refuse_upload: its n-th glBufferData fails (0: none). */
static counted_frame count_frame_refusing(ht_renderer *r, const ht_frame_desc *f, long refuse_upload) {
    counted_frame c;
    ht_fault_arm(refuse_upload ? HT_FAULT_BUFFER_DATA : HT_FAULT_NONE, refuse_upload);
    ht_test_draw(&fx.gl, r, f, ht_test_background, &c.img);
    const ht_fault_state *st = ht_fault_state_get();
    c.pointers = st->array_pointers;
    c.client_pointers = st->client_array_pointers;
    c.uploads = st->calls[HT_FAULT_BUFFER_DATA];
    return c;
}

static counted_frame count_frame(ht_renderer *r, const ht_frame_desc *f) { return count_frame_refusing(r, f, 0); }

static ht_renderer *create(ht_tier tier, bool no_vbo) {
    ht_fault_arm(HT_FAULT_NONE, 0);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .getproc = ht_test_fault_getproc, .tier = tier,
                                                                 .strict = true, .profile = { .no_vbo = no_vbo } },
                                             fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), tier);
    assert_int_equal(ht_renderer_caps(r)->has_vbo, !no_vbo);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    return r;
}

/* The steady frame of tier, with VBOs and without. */
static void steady_frames_point_at_buffers_and_match_client_arrays(ht_tier tier) {
    ht_frame_desc f = ht_test_furball_frame(2.0f);
    ht_image images[2];
    for (int no_vbo = 0; no_vbo < 2; no_vbo++) {
        ht_renderer *r = create(tier, no_vbo);
        counted_frame first = count_frame(r, &f);
        ht_image_free(&first.img);
        counted_frame steady = count_frame(r, &f);
        printf("%s, %s: steady frame: %ld array pointers, %ld client, %ld uploads (first frame: %ld, %ld, %ld)\n",
               ht_tier_name(tier), no_vbo ? "no VBOs" : "VBOs", steady.pointers, steady.client_pointers,
               steady.uploads, first.pointers, first.client_pointers, first.uploads);
        assert_true(steady.pointers > 0);
        assert_int_equal(steady.uploads, 0);
        /* with VBOs no array is client memory; without, every one is */
        assert_int_equal(steady.client_pointers, no_vbo ? steady.pointers : 0);
        ht_test_pixel_stats s = ht_test_pixel_stats_of(&steady.img, ht_test_background);
        assert_int_equal(s.magenta, 0);
        assert_true(s.changed > SIZE * SIZE / 20);
        images[no_vbo] = steady.img;
        ht_fault_arm(HT_FAULT_NONE, 0);
        ht_renderer_destroy(r);
        const ht_fault_state *st = ht_fault_state_get();
        assert_int_equal(st->live[HT_FAULT_BUFFERS], 0);
        assert_int_equal(st->stray_deletes, 0);
    }
    assert_memory_equal(images[0].pixels, images[1].pixels, (size_t)SIZE * SIZE * 4);
    ht_image_free(&images[0]);
    ht_image_free(&images[1]);
}

static void test_fixed_steady_frame_reads_buffers_only(void **state) {
    (void)state;
    steady_frames_point_at_buffers_and_match_client_arrays(HT_TIER_FIXED);
}

static void test_gl11_steady_frame_reads_buffers_only(void **state) {
    (void)state;
    steady_frames_point_at_buffers_and_match_client_arrays(HT_TIER_GL11);
}

static void test_gl11_uploads_colours_only_when_it_recomputes_them(void **state) {
    (void)state;
    ht_renderer *r = create(HT_TIER_GL11, false);
    ht_frame_desc f = ht_test_furball_frame(2.0f), moved = ht_test_furball_frame(2.2f);
    counted_frame c = count_frame(r, &f);
    ht_image_free(&c.img);
    assert_int_equal(c.uploads, 1);
    c = count_frame(r, &moved);
    ht_image_free(&c.img);
    assert_int_equal(c.uploads, 1);
    assert_int_equal(c.client_pointers, 0);
    c = count_frame(r, &moved);
    ht_image_free(&c.img);
    assert_int_equal(c.uploads, 0);
    ht_renderer_destroy(r);
}

/* The first frame uploads what it computed; its first upload refused. */
static void refused_upload_draws_from_client_arrays(ht_tier tier, const char *line) {
    ht_frame_desc f = ht_test_furball_frame(2.0f);
    ht_renderer *r = create(tier, false);
    counted_frame clean = count_frame(r, &f);
    assert_true(clean.uploads > 0);
    ht_renderer_destroy(r);
    r = create(tier, false);
    ht_test_log_clear();
    counted_frame refused = count_frame_refusing(r, &f, 1);
    assert_true(ht_fault_state_get()->fired);
    assert_true(ht_test_logged(line));
    assert_true(refused.client_pointers > 0);
    assert_memory_equal(clean.img.pixels, refused.img.pixels, (size_t)SIZE * SIZE * 4);
    ht_image_free(&clean.img);
    ht_image_free(&refused.img);
    ht_renderer_destroy(r);
    assert_int_equal(ht_fault_state_get()->live[HT_FAULT_BUFFERS], 0);
}

static void test_fixed_refused_upload_draws_from_client_arrays(void **state) {
    (void)state;
    refused_upload_draws_from_client_arrays(HT_TIER_FIXED,
                                            "hairtier: fixed: glBufferSubData: GL_OUT_OF_MEMORY: client arrays instead");
}

static void test_gl11_refused_upload_draws_from_client_arrays(void **state) {
    (void)state;
    refused_upload_draws_from_client_arrays(HT_TIER_GL11,
                                            "hairtier: gl11: glBufferSubData: GL_OUT_OF_MEMORY: client arrays instead");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fixed_steady_frame_reads_buffers_only),
        cmocka_unit_test(test_gl11_steady_frame_reads_buffers_only),
        cmocka_unit_test(test_gl11_uploads_colours_only_when_it_recomputes_them),
        cmocka_unit_test(test_fixed_refused_upload_draws_from_client_arrays),
        cmocka_unit_test(test_gl11_refused_upload_draws_from_client_arrays),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

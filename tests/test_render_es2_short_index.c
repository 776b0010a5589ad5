/* test_render_es2_short_index — a GL ES 2.0 device without 32-bit indices
   (VideoCore IV, Mesa vc4) drawing a hair mesh of more than 65536
   vertices: llvmpipe restricted by MESA_GLES_VERSION_OVERRIDE=2.0 and
   MESA_EXTENSION_OVERRIDE=-GL_OES_element_index_uint (Mesa then leaves the
   extension out of GL_EXTENSIONS, which is what the runtime reads; it
   warns that the functionality itself stays). The mesh goes up split into
   16-bit chunks (index_chunks.h) and draws the image the same context
   type draws with 32-bit indices, drawn in a child process before this
   one's first context (Mesa reads the override once per process); with
   the width rule per vertex too (each chunk's a_side split as its
   vertices are). */
#define _POSIX_C_SOURCE 200809L
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support_child.h"
#include "support_es.h"
#include "support_scratch.h"

/* More hairs than 65536 vertices hold, few pixels. */
#define HAIRS 4000

static char work[64], reference_png[256]; /* the reference in a scratch folder: the bundle may be a shared fixture */

static char rule_png[256];

static int draw_reference(void) {
    unsetenv("MESA_EXTENSION_OVERRIDE");
    ht_test_es_draw d, w;
    char err[256];
    if (!ht_test_es_draw_scene_hairs(ht_test_es_bundle(0), "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS,
                                     &d))
        return 1;
    if (d.trace.count != 4) return 2; /* one draw a pass: 32-bit indices */
    if (ht_image_write_png(reference_png, &d.image, err, sizeof err) != HT_OK) return 3;
    ht_test_es_draw_free(&d);
    if (!ht_test_es_draw_scene_ordered(ht_test_es_bundle(0), "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS,
                                       HT_TEST_ES_WIDTH_RULE, &w) ||
        !w.width_rule_vertex)
        return 4;
    if (ht_image_write_png(rule_png, &w.image, err, sizeof err) != HT_OK) return 5;
    ht_test_es_draw_free(&w);
    return 0;
}

static void test_es2_without_uint_indices_draws_a_large_mesh_in_chunks(void **state) {
    (void)state;
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    assert_true(ht_test_scratch_create(work, sizeof work, "short_index"));
    snprintf(reference_png, sizeof reference_png, "%s/uint-indices.png", work);
    snprintf(rule_png, sizeof rule_png, "%s/uint-indices-width-rule.png", work);
    ht_test_fork_child(draw_reference);

    setenv("MESA_EXTENSION_OVERRIDE", "-GL_OES_element_index_uint", 1);
    ht_test_es_draw d;
    if (!ht_test_es_draw_scene_hairs(bundle, "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS, &d))
        fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "device GL ES 2.0"));
    /* Each pass: the chunks in order, tiling the sorted index list. */
    const int chunks = d.trace.count / 4;
    printf("%u indices in %d chunks a pass\n", d.index_count, chunks);
    assert_true(chunks >= 2);
    assert_int_equal(d.trace.count, 4 * chunks);
    for (int p = 0; p < 4; p++) {
        uint32_t next = 0;
        for (int c = 0; c < chunks; c++) {
            const ht_trace_entry *e = &d.trace.entries[p * chunks + c];
            assert_int_equal(e->pass, p);
            assert_int_equal(e->gl_error, 0);
            assert_int_equal(e->first_index, next);
            assert_true(e->index_count > 0);
            next += e->index_count;
        }
        assert_int_equal(next, d.index_count);
    }
    ht_test_es_draw ref = { 0 };
    char err[256];
    assert_int_equal(ht_image_read_png(reference_png, &ref.image, err, sizeof err), HT_OK);
    long differ = 0;
    for (size_t i = 0; i < (size_t)ref.image.width * ref.image.height * 4; i++)
        differ += ref.image.pixels[i] != d.image.pixels[i];
    const double db = ht_test_es_psnr(&ref, &d);
    printf("16-bit chunks against 32-bit indices: %ld of %d bytes differ, %.2f dB\n", differ,
           ref.image.width * ref.image.height * 4, db);
    assert_true(differ == 0 || db >= HT_TEST_ES_MIN_PSNR_DB);
    ht_test_es_draw_free(&ref);
    ht_test_es_draw_free(&d);
    /* A new order (ht_renderer_set_mesh_order) of a mesh in chunks goes up
       whole, split again: what an upload of that order draws, byte for byte. */
    ht_test_es_draw sorted, reordered;
    if (!ht_test_es_draw_scene_ordered(bundle, "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS,
                                       HT_TEST_ES_BACK_TO_FRONT, &sorted) ||
        !ht_test_es_draw_scene_ordered(bundle, "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS,
                                       HT_TEST_ES_REORDERED, &reordered))
        fail_msg("%s%s", sorted.log, reordered.log);
    assert_true(reordered.uploads_order && reordered.trace.count >= 8);
    assert_memory_equal(sorted.image.pixels, reordered.image.pixels,
                        (size_t)sorted.image.width * sorted.image.height * 4);
    ht_test_es_draw_free(&sorted);
    ht_test_es_draw_free(&reordered);
    /* The width rule per vertex on the chunks: each chunk's a_side block
       split as its vertices are, the image 32-bit indices draw with it
       (a side of another vertex would move strands: tens of dB off). */
    ht_test_es_draw rule, unruled;
    if (!ht_test_es_draw_scene_ordered(bundle, "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS,
                                       HT_TEST_ES_WIDTH_RULE, &rule))
        fail_msg("%s", rule.log);
    assert_true(rule.width_rule_vertex);
    assert_true(rule.trace.count >= 8);
    ht_test_es_draw uint_rule = { 0 };
    assert_int_equal(ht_image_read_png(rule_png, &uint_rule.image, err, sizeof err), HT_OK);
    const double rule_db = ht_test_es_psnr(&uint_rule, &rule);
    if (!ht_test_es_draw_scene_ordered(bundle, "furball", OFFSCREEN_API_GLES2, HT_TIER_FULL, NULL, HAIRS,
                                       HT_TEST_ES_BACK_TO_FRONT, &unruled))
        fail_msg("%s", unruled.log);
    printf("width rule per vertex, 16-bit chunks against 32-bit indices: %.2f dB (without the rule: %.2f dB)\n",
           rule_db, ht_test_es_psnr(&uint_rule, &unruled));
    assert_true(rule_db >= HT_TEST_ES_MIN_PSNR_DB);
    assert_true(ht_test_es_psnr(&uint_rule, &unruled) < HT_TEST_ES_MIN_PSNR_DB); /* the rule shows */
    ht_test_es_draw_free(&uint_rule);
    ht_test_es_draw_free(&rule);
    ht_test_es_draw_free(&unruled);
    assert_int_equal(ht_test_scratch_remove(work), 0);
}

int main(void) {
    setenv("MESA_GLES_VERSION_OVERRIDE", "2.0", 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_es2_without_uint_indices_draws_a_large_mesh_in_chunks),
    };
    return cmocka_run_group_tests(tests, NULL, ht_test_es_teardown);
}

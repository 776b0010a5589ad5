/* test_render_es2 — hairtier on a real GL ES 2.0 context: Mesa's llvmpipe
   restricted by MESA_GLES_VERSION_OVERRIDE=2.0 (set before the first
   context: Mesa reads it once per process), so the driver itself reports
   "OpenGL ES 2.0" and ESSL 1.00 and refuses ES 3 programs. The scenes
   that carry every distinct GLSL text (fur ball, backlit:
   HT_TEST_ES_TEXT_SCENES) with each GLSL tier forced and auto match the
   same tier on desktop GL (support_es.h), drawn with the ESSL 1.00 texts. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support_driver.h"
#include "support_es.h"

static void test_es2_context_is_es2_and_draws_the_essl100_text(void **state) {
    (void)state;
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    ht_test_es_draw d;
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES2, HT_TIER_AUTO, NULL, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "device GL ES 2.0, ESSL 1.00, fragment highp"));
    assert_non_null(strstr(d.log, "full: GL ES 2.0 text full-es2.vert + full-es2.frag (ESSL 1.00, fragment highp)"));
    assert_int_equal(d.tier, HT_TIER_FULL);
    ht_test_es_draw_free(&d);
}

static void test_es2_every_scene_and_glsl_tier_matches_desktop_gl(void **state) {
    (void)state;
    ht_test_es_scenes_match_desktop(OFFSCREEN_API_GLES2, NULL, HT_TEST_ES_TEXT_SCENES);
}

int main(void) {
    setenv("MESA_GLES_VERSION_OVERRIDE", "2.0", 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_es2_context_is_es2_and_draws_the_essl100_text),
        cmocka_unit_test(test_es2_every_scene_and_glsl_tier_matches_desktop_gl),
    };
    return cmocka_run_group_tests(tests, NULL, ht_test_es_teardown);
}

/* test_render_es3 — hairtier on a real GL ES 3.x context (EGL,
   EGL_OPENGL_ES_API, client version 3: llvmpipe's OpenGL ES 3.2): the
   scenes that carry every distinct GLSL text (fur ball, backlit) with each
   tier forced and auto match the same tier on desktop GL (support_es.h);
   the patches (the head's ES program) record the same passes and pixels as
   on desktop GL; the application's GL state comes back after a frame; a
   device without fragment highp gets a mediump text (matching desktop GL's
   full tier) or the highp one is
   refused with its reason; mismatched profiles are refused with one line
   (ES 1.1 has its own test: test_render_es1). On softpipe (support_driver.h) the fur ball's full tier
   only. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "support_driver.h"
#include "support_es.h"
#include "support_scratch.h"

/* softpipe's case: on llvmpipe the scenes case below draws the same. */
static void test_es3_furball_full_matches_desktop_gl(void **state) {
    (void)state;
    if (!ht_test_driver_cases_only()) skip();
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    ht_test_es_draw desk, es;
    assert_true(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GL, HT_TIER_FULL, NULL, &desk));
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES3, HT_TIER_FULL, NULL, &es)) fail_msg("%s", es.log);
    assert_non_null(strstr(es.log, "device GL ES 3."));
    assert_non_null(strstr(es.log, "full-es3.frag (ESSL 3.00, fragment highp)"));
    double db = ht_test_es_psnr(&desk, &es);
    printf("furball full: ES 3 %.2f dB against desktop GL\n", db);
    assert_true(db >= HT_TEST_ES_MIN_PSNR_DB);
    ht_test_es_draw_free(&desk);
    ht_test_es_draw_free(&es);
}

static void test_es3_every_scene_and_glsl_tier_matches_desktop_gl(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT(); /* the case above draws on softpipe */
    /* furball full first: the case above's check on llvmpipe */
    ht_test_es_scenes_match_desktop(OFFSCREEN_API_GLES3, NULL, HT_TEST_ES_TEXT_SCENES);
}

/* Same passes, same fixed state, same ranges: the alpha test is the ES
   texts' discard, recorded from the one rule. */
static void test_es3_passes_record_the_desktop_state(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(HT_TEST_ES_PATCHES);
    assert_non_null(bundle);
    static const ht_tier tiers[] = { HT_TIER_FULL, HT_TIER_VERTEX };
    for (size_t i = 0; i < 2; i++) {
        ht_test_es_draw desk, es;
        assert_true(ht_test_es_draw_scene(bundle, "patches", OFFSCREEN_API_GL, tiers[i], NULL, &desk));
        assert_true(ht_test_es_draw_scene(bundle, "patches", OFFSCREEN_API_GLES3, tiers[i], NULL, &es));
        assert_int_equal(es.trace.count, 4);
        ht_test_es_assert_same_passes(&desk, &es);
        /* The scenes case draws the first HT_TEST_ES_TEXT_SCENES only: the
           head's GL ES program is compared here. */
        double db = ht_test_es_psnr(&desk, &es);
        printf("patches %s: ES 3 %.2f dB against desktop GL\n", ht_tier_name(tiers[i]), db);
        assert_true(db >= HT_TEST_ES_MIN_PSNR_DB);
        ht_test_es_draw_free(&desk);
        ht_test_es_draw_free(&es);
    }
    /* Flat mode, the benchmarks' floor: the same passes and pixels. */
    ht_test_es_draw desk, es;
    assert_true(ht_test_es_draw_scene(bundle, "patches", OFFSCREEN_API_GL, HT_TIER_COUNT, NULL, &desk));
    if (!ht_test_es_draw_scene(bundle, "patches", OFFSCREEN_API_GLES3, HT_TIER_COUNT, NULL, &es)) fail_msg("%s", es.log);
    assert_int_equal(es.trace.count, 4);
    double db = ht_test_es_psnr(&desk, &es);
    printf("patches flat: ES 3 %.2f dB against desktop GL\n", db);
    assert_true(db >= HT_TEST_ES_MIN_PSNR_DB);
    ht_test_es_draw_free(&desk);
    ht_test_es_draw_free(&es);
}

static void keep_line(void *user, const char *line) {
    ht_test_es_draw *d = user;
    size_t n = strlen(d->log);
    snprintf(d->log + n, sizeof d->log - n, "%s\n", line);
}

static void quiet(void *user, const char *line) {
    (void)user;
    (void)line;
}

/* ht_renderer_draw's contract without glPushAttrib: what the application
   set before the frame is what it reads after it. */
static void test_es3_application_state_survives_a_frame(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    char err[512];
    offscreen *gl = offscreen_open(&(offscreen_desc){ .kind = OFFSCREEN_EGL, .api = OFFSCREEN_API_GLES3,
                                                      .width = 32, .height = 32, .egl_device = -1 }, err, sizeof err);
    if (!gl) fail_msg("%s", err);
    ht_renderer *r = NULL;
    assert_int_equal(ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle,
                                                             .log = quiet }, &r), HT_OK);
    ht_mesh hair = { 0 };
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 50 }, &hair), HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &hair), HT_OK);

    void (*Enable)(GLenum) = (void (*)(GLenum))offscreen_getproc("glEnable");
    void (*BlendFunc)(GLenum, GLenum) = (void (*)(GLenum, GLenum))offscreen_getproc("glBlendFunc");
    void (*DepthFunc)(GLenum) = (void (*)(GLenum))offscreen_getproc("glDepthFunc");
    void (*CullFace)(GLenum) = (void (*)(GLenum))offscreen_getproc("glCullFace");
    void (*DepthMask)(GLboolean) = (void (*)(GLboolean))offscreen_getproc("glDepthMask");
    void (*ActiveTexture)(GLenum) = (void (*)(GLenum))offscreen_getproc("glActiveTexture");
    void (*GenTextures)(GLsizei, GLuint *) = (void (*)(GLsizei, GLuint *))offscreen_getproc("glGenTextures");
    void (*BindTexture)(GLenum, GLuint) = (void (*)(GLenum, GLuint))offscreen_getproc("glBindTexture");
    void (*EnableVertexAttribArray)(GLuint) = (void (*)(GLuint))offscreen_getproc("glEnableVertexAttribArray");
    void (*GetIntegerv)(GLenum, GLint *) = (void (*)(GLenum, GLint *))offscreen_getproc("glGetIntegerv");
    void (*GetBooleanv)(GLenum, GLboolean *) = (void (*)(GLenum, GLboolean *))offscreen_getproc("glGetBooleanv");
    GLboolean (*IsEnabled)(GLenum) = (GLboolean (*)(GLenum))offscreen_getproc("glIsEnabled");
    void (*GetVertexAttribiv)(GLuint, GLenum, GLint *) =
        (void (*)(GLuint, GLenum, GLint *))offscreen_getproc("glGetVertexAttribiv");
    GLuint tex = 0;
    GenTextures(1, &tex);
    Enable(GL_BLEND);
    BlendFunc(GL_ONE, GL_ONE);
    Enable(GL_CULL_FACE);
    CullFace(GL_FRONT_AND_BACK);
    DepthFunc(GL_GREATER);
    DepthMask(GL_FALSE);
    ActiveTexture(GL_TEXTURE2);
    BindTexture(GL_TEXTURE_2D, tex);
    EnableVertexAttribArray(5);

    ht_frame_desc frame = { .camera = { .eye = { 0, 0, 3 }, .up = { 0, 1, 0 }, .fov_y = 40 },
                            .lights = &(ht_light){ .type = HT_LIGHT_DIRECTIONAL, .vector = { 0, 0, 1 },
                                                   .color = { 1, 1, 1 } },
                            .light_count = 1, .aspect = 1 };
    assert_int_equal(ht_renderer_draw(r, &frame), HT_OK);

    GLint v = 0;
    GLboolean b = GL_TRUE;
    assert_true(IsEnabled(GL_BLEND));
    assert_true(IsEnabled(GL_CULL_FACE));
    assert_false(IsEnabled(GL_DEPTH_TEST)); /* the app never enabled it */
    GetIntegerv(GL_BLEND_SRC_RGB, &v);
    assert_int_equal(v, GL_ONE);
    GetIntegerv(GL_BLEND_DST_ALPHA, &v);
    assert_int_equal(v, GL_ONE);
    GetIntegerv(GL_CULL_FACE_MODE, &v);
    assert_int_equal(v, GL_FRONT_AND_BACK);
    GetIntegerv(GL_DEPTH_FUNC, &v);
    assert_int_equal(v, GL_GREATER);
    GetBooleanv(GL_DEPTH_WRITEMASK, &b);
    assert_false(b);
    GetIntegerv(GL_ACTIVE_TEXTURE, &v);
    assert_int_equal(v, GL_TEXTURE2);
    GetIntegerv(GL_TEXTURE_BINDING_2D, &v);
    assert_int_equal(v, (GLint)tex);
    GetIntegerv(GL_CURRENT_PROGRAM, &v);
    assert_int_equal(v, 0);
    GetIntegerv(GL_ARRAY_BUFFER_BINDING, &v);
    assert_int_equal(v, 0);
    GetVertexAttribiv(5, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &v);
    assert_int_equal(v, 1);
    GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &v);
    assert_int_equal(v, 0);
    ht_renderer_destroy(r);
    ht_mesh_free(&hair);
    offscreen_close(gl);
}

/* A device without fragment highp: auto skips the marschner tier (no
   mediump text) and draws full through the bundle's all-mediump ES 2.0
   text, the same picture as desktop GL's full tier (brown-marschner's full
   tier has a transmission lobe: the larger mediump text, which stands for
   dark-brown's too: one compile, the costly one on llvmpipe); with that
   entry removed from the manifest, the highp text refused with the reason
   and the vertex tier's mediump text drawn. */
static void test_es3_no_fragment_highp_takes_mediump_or_refuses_with_reason(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(HT_TEST_ES_FURBALL);
    assert_non_null(bundle);
    ht_device_profile mali;
    char err[256];
    assert_int_equal(ht_device_profile_parse("mali400", &mali, err, sizeof err), HT_OK);
    ht_test_es_draw d, desk;
    const char *backlit = ht_test_es_bundle(HT_TEST_ES_BACKLIT);
    assert_non_null(backlit);
    if (!ht_test_es_draw_scene(backlit, "backlit", OFFSCREEN_API_GLES3, HT_TIER_AUTO, &mali, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "device GL ES 2.0, ESSL 1.00, fragment mediump only"));
    assert_non_null(strstr(d.log, "skipped marschner: marschner-es2.frag needs fragment highp"));
    assert_int_equal(d.tier, HT_TIER_FULL);
    assert_non_null(strstr(d.log, "full-es2-mediump.frag (ESSL 1.00, fragment mediump)"));
    assert_true(ht_test_es_draw_scene(backlit, "backlit", OFFSCREEN_API_GL, HT_TIER_FULL, NULL, &desk));
    const double db = ht_test_es_psnr(&desk, &d);
    printf("backlit full, mediump text: %.2f dB against desktop GL\n", db);
    assert_true(db >= HT_TEST_ES_MIN_PSNR_DB);
    ht_test_es_draw_free(&desk);
    ht_test_es_draw_free(&d);
    /* With highp the highp texts stay first. */
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES3, HT_TIER_AUTO, NULL, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "full-es3.frag (ESSL 3.00, fragment highp)"));
    /* and the reason the fixed-function tiers are not there */
    assert_non_null(strstr(d.log, "skipped fixed4, fixed, gl11: fixed function: GL ES 2.0 and later have none "
                                  "(desktop GL or GL ES 1.1 runs it)\n"));
    ht_test_es_draw_free(&d);

    /* The same bundle without its mediump entry. */
    char work[64], copy[160];
    assert_true(ht_test_scratch_create(work, sizeof work, "es3-highp-only"));
    snprintf(copy, sizeof copy, "%s/furball", work);
    ht_test_copy_dir(bundle, copy);
    cJSON *root = ht_test_read_json(copy, "manifest.json");
    cJSON *full = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "tiers"), 0);
    assert_string_equal(cJSON_GetObjectItem(full, "name")->valuestring, "full");
    cJSON *es = cJSON_GetObjectItem(full, "es");
    assert_int_equal(cJSON_GetArraySize(es), 3);
    assert_string_equal(cJSON_GetObjectItem(cJSON_GetArrayItem(es, 2), "fragment_precision")->valuestring, "mediump");
    cJSON_DeleteItemFromArray(es, 2);
    char *text = cJSON_Print(root);
    ht_test_write_file(copy, "manifest.json", text);
    free(text);
    cJSON_Delete(root);
    if (!ht_test_es_draw_scene(copy, "furball", OFFSCREEN_API_GLES3, HT_TIER_AUTO, &mali, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "skipped full: full-es2.frag needs fragment highp, the device's fragment stage "
                                  "has none (glGetShaderPrecisionFormat), and the bundle has no mediump variant"));
    assert_int_equal(d.tier, HT_TIER_VERTEX);
    assert_non_null(strstr(d.log, "vertex-es2.frag (ESSL 1.00, fragment mediump)"));
    ht_test_es_draw_free(&d);
    /* Forced and strict, the refusal is the error. */
    assert_false(ht_test_es_draw_scene(copy, "furball", OFFSCREEN_API_GLES3, HT_TIER_FULL, &mali, &d));
    assert_non_null(strstr(d.log, "needs fragment highp"));
    ht_test_es_draw_free(&d);
    ht_test_scratch_remove(work);
}

/* VideoCore IV (vc4) has no 32-bit indices: the mesh goes up as 16-bit
   ones and draws what desktop GL draws; a mesh beyond 65536 vertices is
   drawn in chunks of at most 65536. */
static void test_es3_videocore4_draws_with_16_bit_indices(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    ht_device_profile vc4;
    char err[256];
    assert_int_equal(ht_device_profile_parse("videocore4", &vc4, err, sizeof err), HT_OK);
    ht_test_es_draw desk, es;
    assert_true(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GL, HT_TIER_AUTO, NULL, &desk));
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES3, HT_TIER_AUTO, &vc4, &es)) fail_msg("%s", es.log);
    assert_non_null(strstr(es.log, "full-es2.frag (ESSL 1.00, fragment highp)"));
    double db = ht_test_es_psnr(&desk, &es);
    printf("furball on videocore4's profile: %.2f dB against desktop GL\n", db);
    assert_true(db >= HT_TEST_ES_MIN_PSNR_DB);
    ht_test_es_draw_free(&desk);
    ht_test_es_draw_free(&es);

    offscreen *gl = offscreen_open(&(offscreen_desc){ .kind = OFFSCREEN_EGL, .api = OFFSCREEN_API_GLES3,
                                                      .width = 16, .height = 16, .egl_device = -1 }, err, sizeof err);
    if (!gl) fail_msg("%s", err);
    ht_test_es_draw logged = { 0 };
    ht_renderer *r = NULL;
    assert_int_equal(ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle,
                                                             .profile = vc4, .log = keep_line, .log_user = &logged,
                                                             .record_trace = true },
                                        &r), HT_OK);
    ht_mesh big = { 0 };
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 4000 }, &big), HT_OK);
    assert_true(big.vertex_count > 65536);
    assert_int_equal(ht_renderer_set_mesh(r, &big), HT_OK);
    ht_camera cam = { .eye = { 0, 0, 4 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_y = 45.0f };
    ht_light light = { .type = HT_LIGHT_DIRECTIONAL, .vector = { 0, 0, 1 }, .color = { 1, 1, 1 } };
    assert_int_equal(ht_renderer_draw(r, &(ht_frame_desc){ .camera = cam, .lights = &light, .light_count = 1,
                                                           .aspect = 1.0f }),
                     HT_OK);
    /* Each pass drawn chunk by chunk (test_render_es2_short_index compares the image). */
    const ht_trace *t = ht_renderer_trace(r);
    assert_true(t->count > 4 && t->count % 4 == 0);
    assert_int_equal(t->entries[t->count - 1].first_index + t->entries[t->count - 1].index_count, big.index_count);
    ht_mesh_free(&big);
    ht_renderer_destroy(r);
    offscreen_close(gl);
}

static void test_es3_mismatched_profiles_are_refused_with_one_line(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    ht_test_es_draw d;
    ht_device_profile p;
    char err[256];
    assert_int_equal(ht_device_profile_parse("videocore4", &p, err, sizeof err), HT_OK);
    assert_false(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GL, HT_TIER_AUTO, &p, &d));
    assert_non_null(strstr(d.log, "device profile: a GL ES 2.0 device, the context is desktop GL"));
    assert_int_equal(ht_device_profile_parse("gl20", &p, err, sizeof err), HT_OK);
    assert_false(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES3, HT_TIER_AUTO, &p, &d));
    assert_non_null(strstr(d.log, "device profile: a desktop GL 2.0 device, the context is OpenGL ES 3."));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_es3_furball_full_matches_desktop_gl),
        cmocka_unit_test(test_es3_every_scene_and_glsl_tier_matches_desktop_gl),
        cmocka_unit_test(test_es3_passes_record_the_desktop_state),
        cmocka_unit_test(test_es3_application_state_survives_a_frame),
        cmocka_unit_test(test_es3_no_fragment_highp_takes_mediump_or_refuses_with_reason),
        cmocka_unit_test(test_es3_videocore4_draws_with_16_bit_indices),
        cmocka_unit_test(test_es3_mismatched_profiles_are_refused_with_one_line),
    };
    return cmocka_run_group_tests(tests, NULL, ht_test_es_teardown);
}

/* test_render_es1 — hairtier on a real GL ES 1.1 context (EGL,
   EGL_OPENGL_ES_API, client version 1: llvmpipe's OpenGL ES-CM 1.1, fixed
   function, no 3D textures): the fur ball, backlit and patches with
   fixed4, fixed and gl11 forced (auto on the fur ball) match the same tier on desktop GL with the same
   passes (support_es.h); the GLSL tiers are skipped with their reason; the
   application's fixed-function state comes back after a frame; an ES 1.0
   device, too few units and mismatched profiles are refused with one
   line, or the next tier is drawn with the reason logged. On softpipe
   (support_driver.h) the scenes and the state case only. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "support_driver.h"
#include "gl_api.h"
#include "support_es.h"

static void test_es1_context_is_es11_and_skips_the_glsl_tiers(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    ht_test_es_draw d;
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_AUTO, NULL, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "device GL ES 1.1 (fixed function)"));
    assert_non_null(strstr(d.log, "skipped full, vertex: shaders: GL ES 1.x has none (desktop GL 2.0 or GL ES 2.0 "
                                  "runs it)\n"));
    assert_int_equal(d.tier, HT_TIER_FIXED4);
    /* Without GL_OES_element_index_uint: 16-bit indices, the same pixels. */
    const ht_device_profile no_uint = { .hide_extensions = "GL_OES_element_index_uint" };
    ht_test_es_draw shorts;
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_AUTO, &no_uint, &shorts))
        fail_msg("%s", shorts.log);
    assert_true(isinf(ht_test_es_psnr(&d, &shorts)));
    ht_test_es_draw_free(&shorts);
    /* A new order with 16-bit indices (ht_renderer_set_mesh_order: the
       indices alone, as 16 bits): what an upload of that order draws */
    ht_test_es_draw sorted, reordered;
    if (!ht_test_es_draw_scene_ordered(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_GL11, &no_uint,
                                       HT_TEST_ES_FURBALL_HAIRS, HT_TEST_ES_BACK_TO_FRONT, &sorted) ||
        !ht_test_es_draw_scene_ordered(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_GL11, &no_uint,
                                       HT_TEST_ES_FURBALL_HAIRS, HT_TEST_ES_REORDERED, &reordered))
        fail_msg("%s%s", sorted.log, reordered.log);
    assert_true(reordered.uploads_order);
    assert_true(isinf(ht_test_es_psnr(&sorted, &reordered)));
    ht_test_es_draw_free(&sorted);
    ht_test_es_draw_free(&reordered);
    ht_test_es_draw_free(&d);
    /* The fixed tier's 3D LUT: two 2D textures, the error said once. */
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_FIXED, NULL, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "2D textures (no 3D textures: texel error up to 1/255)"));
    ht_test_es_draw_free(&d);
    /* An ES 3 context's reason for skipping them: test_render_es3. */
}

static void test_es1_every_scene_and_fixed_tier_matches_desktop_gl(void **state) {
    (void)state;
    /* The scenes with distinct programs, and the patches' head lit by GL ES
       1.1's fixed function: ratboy's fixed4/fixed/gl11 programs are the fur
       ball's with other constants (the same dark-brown structure), its
       strands a CPU mesh drawn as any other. softpipe: the fur ball. */
    ht_test_es_scenes_match_desktop(OFFSCREEN_API_GLES1, NULL,
                                    ht_test_driver_cases_only() ? 1 : HT_TEST_ES_TEXT_SCENES + 1);
}

static void quiet(void *user, const char *line) {
    (void)user;
    (void)line;
}

/* ht_renderer_draw's contract on ES 1.1 (no glPushAttrib): the
   fixed-function state an application set before a frame of each tier is
   what it reads after it. */
static void test_es1_application_state_survives_a_frame(void **state) {
    (void)state;
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    static const ht_tier tiers[] = { HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
    for (size_t t = 0; t < sizeof tiers / sizeof tiers[0]; t++) {
        char err[512];
        offscreen *gl = offscreen_open(&(offscreen_desc){ .kind = OFFSCREEN_EGL, .api = OFFSCREEN_API_GLES1,
                                                          .width = 32, .height = 32, .egl_device = -1 },
                                       err, sizeof err);
        if (!gl) fail_msg("%s", err);
        ht_renderer *r = NULL;
        assert_int_equal(ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle,
                                                                 .tier = tiers[t], .strict = true, .log = quiet },
                                            &r), HT_OK);
        ht_mesh hair = { 0 }, head = { 0 };
        assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = 2, .strips = 9, .segments = 4 }, &hair,
                                               &head), HT_OK);
        assert_int_equal(ht_renderer_set_mesh(r, &hair), HT_OK);

        ht_gl g;
        assert_int_equal(ht_gl_load(&g, offscreen_getproc, err, sizeof err), HT_OK);
        static const float coords[8] = { 0 };
        const float diffuse[4] = { 0.25f, 0.5f, 0.75f, 1 }, ambient[4] = { 0.1f, 0.2f, 0.3f, 1 };
        static const float shift_s[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5f, 0, 0, 1 };
        static const float shift_t[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.25f, 0, 1 };
        GLuint tex = 0;
        g.GenTextures(1, &tex);
        g.Enable(GL_BLEND);
        g.BlendFunc(GL_ONE, GL_ONE);
        g.Enable(GL_CULL_FACE);
        g.CullFace(GL_FRONT_AND_BACK);
        g.DepthFunc(GL_GREATER);
        g.DepthMask(GL_FALSE);
        g.Enable(GL_FOG);
        g.Enable(GL_LIGHTING);
        g.Enable(GL_LIGHT3);
        g.Lightfv(GL_LIGHT1, GL_DIFFUSE, diffuse);
        g.LightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
        g.AlphaFunc(GL_NOTEQUAL, 0.25f);
        g.Color4f(0.5f, 0.25f, 0.125f, 1.0f);
        g.ActiveTexture(GL_TEXTURE1);
        g.BindTexture(GL_TEXTURE_2D, tex);
        g.Enable(GL_TEXTURE_2D);
        g.TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
        g.TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, GL_DOT3_RGB);
        g.MatrixMode(GL_TEXTURE);
        g.LoadMatrixf(shift_s);
        g.ClientActiveTexture(GL_TEXTURE2);
        g.EnableClientState(GL_TEXTURE_COORD_ARRAY);
        g.TexCoordPointer(2, GL_FLOAT, 8, coords);
        g.MatrixMode(GL_PROJECTION);
        g.LoadMatrixf(shift_t);
        assert_int_equal(g.GetError(), GL_NO_ERROR);

        ht_frame_desc frame = { .camera = { .eye = { 0, 0, 3 }, .up = { 0, 1, 0 }, .fov_y = 40 },
                                .lights = &(ht_light){ .type = HT_LIGHT_DIRECTIONAL, .vector = { 0, 0, 1 },
                                                       .color = { 1, 1, 1 } },
                                .light_count = 1, .aspect = 1, .opaque = &head };
        assert_int_equal(ht_renderer_draw(r, &frame), HT_OK);
        assert_int_equal(g.GetError(), GL_NO_ERROR);

        GLint v = 0;
        GLfloat f[16] = { 0 };
        GLboolean b = GL_TRUE;
        void *p = NULL;
        assert_true(g.IsEnabled(GL_BLEND));
        assert_true(g.IsEnabled(GL_CULL_FACE));
        assert_true(g.IsEnabled(GL_FOG));
        assert_true(g.IsEnabled(GL_LIGHTING));
        assert_true(g.IsEnabled(GL_LIGHT3));
        assert_false(g.IsEnabled(GL_LIGHT0));
        assert_false(g.IsEnabled(GL_DEPTH_TEST)); /* the app never enabled it */
        assert_false(g.IsEnabled(GL_ALPHA_TEST));
        g.GetIntegerv(GL_BLEND_SRC, &v);
        assert_int_equal(v, GL_ONE);
        g.GetIntegerv(GL_CULL_FACE_MODE, &v);
        assert_int_equal(v, GL_FRONT_AND_BACK);
        g.GetIntegerv(GL_DEPTH_FUNC, &v);
        assert_int_equal(v, GL_GREATER);
        g.GetBooleanv(GL_DEPTH_WRITEMASK, &b);
        assert_false(b);
        g.GetIntegerv(GL_ALPHA_TEST_FUNC, &v);
        assert_int_equal(v, GL_NOTEQUAL);
        g.GetFloatv(GL_ALPHA_TEST_REF, f);
        assert_true(f[0] == 0.25f);
        g.GetFloatv(GL_CURRENT_COLOR, f);
        assert_true(f[0] == 0.5f && f[1] == 0.25f && f[2] == 0.125f);
        g.GetLightfv(GL_LIGHT1, GL_DIFFUSE, f);
        assert_true(f[0] == 0.25f && f[1] == 0.5f && f[2] == 0.75f);
        g.GetLightfv(GL_LIGHT0, GL_DIFFUSE, f); /* GL's initial light 0: white */
        assert_true(f[0] == 1.0f && f[1] == 1.0f && f[2] == 1.0f);
        g.GetFloatv(GL_LIGHT_MODEL_AMBIENT, f);
        assert_true(f[0] == 0.1f && f[1] == 0.2f && f[2] == 0.3f);
        g.GetIntegerv(GL_MATRIX_MODE, &v);
        assert_int_equal(v, GL_PROJECTION);
        g.GetFloatv(GL_PROJECTION_MATRIX, f);
        assert_true(f[13] == 0.25f && f[0] == 1.0f);
        g.GetFloatv(GL_MODELVIEW_MATRIX, f);
        assert_true(f[0] == 1.0f && f[12] == 0.0f && f[14] == 0.0f);
        g.GetIntegerv(GL_ACTIVE_TEXTURE, &v);
        assert_int_equal(v, GL_TEXTURE1);
        g.GetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &v);
        assert_int_equal(v, GL_TEXTURE2);
        g.GetIntegerv(GL_TEXTURE_BINDING_2D, &v);
        assert_int_equal(v, (GLint)tex);
        assert_true(g.IsEnabled(GL_TEXTURE_2D));
        g.GetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &v);
        assert_int_equal(v, GL_COMBINE);
        g.GetTexEnviv(GL_TEXTURE_ENV, GL_COMBINE_RGB, &v);
        assert_int_equal(v, GL_DOT3_RGB);
        g.GetFloatv(GL_TEXTURE_MATRIX, f);
        assert_true(f[12] == 0.5f);
        assert_true(g.IsEnabled(GL_TEXTURE_COORD_ARRAY));
        g.GetPointerv(GL_TEXTURE_COORD_ARRAY_POINTER, &p);
        assert_ptr_equal(p, coords);
        g.GetIntegerv(GL_TEXTURE_COORD_ARRAY_STRIDE, &v);
        assert_int_equal(v, 8);
        g.ClientActiveTexture(GL_TEXTURE0);
        assert_false(g.IsEnabled(GL_TEXTURE_COORD_ARRAY));
        assert_false(g.IsEnabled(GL_VERTEX_ARRAY));
        assert_false(g.IsEnabled(GL_COLOR_ARRAY));
        g.ActiveTexture(GL_TEXTURE0);
        assert_false(g.IsEnabled(GL_TEXTURE_2D));
        g.GetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &v);
        assert_int_equal(v, GL_MODULATE);
        g.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &v);
        assert_int_equal(v, 0);
        g.GetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &v);
        assert_int_equal(v, 0);
        ht_renderer_destroy(r);
        ht_mesh_free(&hair);
        ht_mesh_free(&head);
        offscreen_close(gl);
    }
}

/* What ES 1.1 cannot give: ES 1.0 (a profile), too few units for a tier
   (forced: refused; auto: the next tier, the reason logged), and profiles
   of the other ES generation. */
static void test_es1_what_it_cannot_run_is_refused_with_reason(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    const char *bundle = ht_test_es_bundle(0);
    assert_non_null(bundle);
    ht_test_es_draw d;
    const ht_device_profile es10 = { .es_major = 1, .es_minor = 0 };
    assert_false(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_AUTO, &es10, &d));
    assert_non_null(strstr(d.log, "GL ES 1.0 (OpenGL ES-CM 1.1"));
    assert_non_null(strstr(d.log, "needs GL ES 1.1 (ES 1.0 has no state queries"));
    /* Three units: fixed4 lists four; the fixed tier's split LUT needs four too. */
    const ht_device_profile three = { .texture_units = 3 };
    assert_false(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_FIXED4, &three, &d));
    assert_non_null(strstr(d.log, "fixed4: needs 4 texture units, have 3"));
    if (!ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_AUTO, &three, &d)) fail_msg("%s", d.log);
    assert_non_null(strstr(d.log, "skipped fixed4: needs 4 texture units, have 3"));
    assert_non_null(strstr(d.log, "fixed.json: 4 stages need 4 texture units, have 3 (2 of them for the 3D LUT split "
                                  "in two 2D textures: no 3D textures)"));
    assert_int_equal(d.tier, HT_TIER_GL11);
    assert_true(d.trace.count == 4 && d.trace.entries[3].gl_error == 0);
    ht_test_es_draw_free(&d);
    ht_device_profile p;
    char err[256];
    assert_int_equal(ht_device_profile_parse("videocore4", &p, err, sizeof err), HT_OK);
    assert_false(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES1, HT_TIER_AUTO, &p, &d));
    assert_non_null(strstr(d.log, "device profile: a GL ES 2.0 device, the context is OpenGL ES-CM 1.1"));
    const ht_device_profile es11 = { .es_major = 1, .es_minor = 1 };
    assert_false(ht_test_es_draw_scene(bundle, "furball", OFFSCREEN_API_GLES3, HT_TIER_AUTO, &es11, &d));
    assert_non_null(strstr(d.log, "device profile: a GL ES 1.1 device, the context is OpenGL ES 3."));
    assert_non_null(strstr(d.log, "make a GL ES 1 context (hairview --api gles1)"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_es1_context_is_es11_and_skips_the_glsl_tiers),
        cmocka_unit_test(test_es1_every_scene_and_fixed_tier_matches_desktop_gl),
        cmocka_unit_test(test_es1_application_state_survives_a_frame),
        cmocka_unit_test(test_es1_what_it_cannot_run_is_refused_with_reason),
    };
    return cmocka_run_group_tests(tests, NULL, ht_test_es_teardown);
}

/* test_caps_es — GL ES devices without a context: the caps a driver's ES
   strings and precision answer give (a table of entry points that answers
   as llvmpipe's ES contexts, Mali's and an ES 1.1 layer do), and which ES
   text of a tier such a device selects (a manifest read by the runtime's
   reader). The real contexts are test_render_es1, test_render_es2 and
   test_render_es3. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "caps.h"
#include "manifest.h"
#include "select.h"

/* What the table below answers. */
static const char *version, *glsl_version;
static GLint fragment_units, highp_precision;

static const GLubyte *APIENTRY get_string(GLenum name) {
    switch (name) {
    case GL_VERSION: return (const GLubyte *)version;
    case GL_SHADING_LANGUAGE_VERSION: return (const GLubyte *)glsl_version;
    case GL_RENDERER: return (const GLubyte *)"test";
    case GL_EXTENSIONS: return (const GLubyte *)"GL_OES_element_index_uint";
    }
    return NULL;
}
static void APIENTRY get_integerv(GLenum pname, GLint *v) {
    *v = pname == GL_MAX_TEXTURE_IMAGE_UNITS ? fragment_units : pname == GL_MAX_TEXTURE_UNITS ? 2 : 0;
}
static GLenum APIENTRY get_error(void) { return GL_NO_ERROR; }
static void APIENTRY precision_format(GLenum shader, GLenum type, GLint *range, GLint *precision) {
    (void)shader;
    (void)type;
    range[0] = range[1] = highp_precision ? 127 : 0;
    *precision = highp_precision;
}
static void APIENTRY active_texture(GLenum unit) { (void)unit; }

/* An ES device's table: the entry points the probe calls, shaders and VBOs
   present (their pointers are never called by the probe). */
static ht_gl es_table(void) {
    ht_gl gl = { 0 };
    gl.GetString = get_string;
    gl.GetIntegerv = get_integerv;
    gl.GetError = get_error;
    gl.GetShaderPrecisionFormat = precision_format;
    gl.ActiveTexture = active_texture;
    gl.has_multitexture = gl.has_vbo = gl.has_shaders = gl.has_precision = gl.has_fixed = true;
    gl.es = true;
    return gl;
}

static ht_caps probe(const char *v, const char *sl, GLint units, GLint highp) {
    version = v;
    glsl_version = sl;
    fragment_units = units;
    highp_precision = highp;
    ht_gl gl = es_table();
    ht_caps c;
    assert_int_equal(ht_caps_probe_gl(&gl, &c, NULL), HT_OK);
    return c;
}

static void test_caps_es_from_llvmpipe_and_mali_strings(void **state) {
    (void)state;
    ht_caps c = probe("OpenGL ES 3.2 Mesa 22.3.6", "OpenGL ES GLSL ES 3.20", 32, 23);
    assert_true(c.es);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 32);
    assert_int_equal(c.glsl_major * 100 + c.glsl_minor, 320);
    assert_true(c.has_shaders && c.has_fragment_shaders && c.has_vbo);
    assert_false(c.has_combine); /* no texture environments from ES 2.0 on */
    assert_false(c.has_3d_textures);
    assert_true(c.fragment_highp);
    assert_int_equal(c.texture_units, 32); /* the fragment stage's, not GL_MAX_TEXTURE_UNITS */

    c = probe("OpenGL ES 2.0 Mesa 24.0 (lima)", "OpenGL ES GLSL ES 1.00", 8, 0);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 20);
    assert_int_equal(c.glsl_major * 100 + c.glsl_minor, 100);
    assert_false(c.fragment_highp); /* precision 0: no fragment highp */
    assert_int_equal(c.texture_units, 8);

    /* No version string for the language: ES 2.0's promise, ESSL 1.00. */
    c = probe("OpenGL ES 2.0", NULL, 8, 23);
    assert_int_equal(c.glsl_major * 100 + c.glsl_minor, 100);

    /* ES 1.1: fixed function with combine, no shaders. */
    c = probe("OpenGL ES-CM 1.1 Mesa 22.3.6", NULL, 0, 0);
    assert_true(c.es);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 11);
    assert_false(c.has_shaders);
    assert_true(c.has_combine);
    assert_int_equal(c.texture_units, 2);
}

/* ES 1.x: the desktop names ES 1.1 made core are met (multitexture,
   combine, DOT3, VBOs), 3D textures and the crossbar are not; ES 1.0 has
   neither combiners nor VBOs; the selection keeps the fixed-function tiers
   there and says why the others cannot run, and on ES 2.0+ why the
   fixed-function ones cannot. */
static void test_caps_es1_core_names_and_selection(void **state) {
    (void)state;
    ht_caps c = probe("OpenGL ES-CL 1.1", NULL, 0, 0);
    assert_true(ht_caps_es1(&c) && !ht_caps_es_programs(&c));
    static const char *const core[] = { "GL_ARB_multitexture", "GL_ARB_texture_env_combine", "GL_ARB_texture_env_dot3",
                                        "GL_ARB_vertex_buffer_object", "GL_EXT_texture_edge_clamp" };
    for (size_t i = 0; i < sizeof core / sizeof core[0]; i++) assert_true(ht_caps_satisfies_extension(&c, "", core[i]));
    assert_false(ht_caps_satisfies_extension(&c, "", "GL_EXT_texture3D"));
    assert_false(ht_caps_satisfies_extension(&c, "", "GL_ARB_texture_env_crossbar"));
    assert_false(ht_caps_satisfies_extension(&c, "", "GL_ARB_shader_objects"));
    assert_false(c.has_3d_textures || c.has_crossbar);

    ht_caps es10 = probe("OpenGL ES-CM 1.0", NULL, 0, 0);
    assert_true(ht_caps_es1(&es10));
    assert_false(es10.has_combine || es10.has_vbo);
    assert_false(ht_caps_satisfies_extension(&es10, "", "GL_ARB_texture_env_combine"));

    ht_manifest_tier fixed4 = { .name = "fixed4", .tier = HT_TIER_FIXED4, .gl_major = 1, .gl_minor = 3,
                                .extension_count = 2, .texture_units = 2 };
    snprintf(fixed4.extensions[0], sizeof fixed4.extensions[0], "GL_ARB_multitexture");
    snprintf(fixed4.extensions[1], sizeof fixed4.extensions[1], "GL_ARB_texture_env_combine");
    char why[256] = "";
    assert_true(ht_select_check_requirements(&c, "", &fixed4, why, sizeof why));
    fixed4.texture_units = 4;
    assert_false(ht_select_check_requirements(&c, "", &fixed4, why, sizeof why));
    assert_string_equal(why, "needs 4 texture units, have 2");
    fixed4.texture_units = 2;
    assert_false(ht_select_check_requirements(&es10, "", &fixed4, why, sizeof why));
    assert_string_equal(why, "needs GL_ARB_texture_env_combine");
    const ht_manifest_tier full = { .name = "full", .tier = HT_TIER_FULL, .gl_major = 2, .glsl_major = 1,
                                    .glsl_minor = 20 };
    assert_false(ht_select_check_requirements(&c, "", &full, why, sizeof why));
    assert_string_equal(why, "shaders: GL ES 1.x has none (desktop GL 2.0 or GL ES 2.0 runs it)");
    ht_caps es3 = probe("OpenGL ES 3.2 Mesa 22.3.6", "OpenGL ES GLSL ES 3.20", 32, 23);
    assert_false(ht_select_check_requirements(&es3, "", &fixed4, why, sizeof why));
    assert_string_equal(why, "fixed function: GL ES 2.0 and later have none (desktop GL or GL ES 1.1 runs it)");
}

static void test_caps_es_profiles_lower_an_es_context(void **state) {
    (void)state;
    ht_device_profile p;
    char err[256];
    ht_caps c = probe("OpenGL ES 3.2 Mesa 22.3.6", "OpenGL ES GLSL ES 3.20", 32, 23);
    assert_int_equal(ht_device_profile_parse("mali400", &p, err, sizeof err), HT_OK);
    assert_false(ht_device_profile_is_zero(&p));
    ht_caps_apply_profile(&c, &p);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 20);
    assert_int_equal(c.glsl_major * 100 + c.glsl_minor, 100);
    assert_false(c.fragment_highp);
    assert_int_equal(c.texture_units, 8);

    c = probe("OpenGL ES 3.2 Mesa 22.3.6", "OpenGL ES GLSL ES 3.20", 32, 23);
    assert_int_equal(ht_device_profile_parse("videocore6", &p, err, sizeof err), HT_OK);
    ht_caps_apply_profile(&c, &p);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 31);
    assert_int_equal(c.glsl_major * 100 + c.glsl_minor, 310);
    assert_true(c.fragment_highp);
    assert_int_equal(c.texture_units, 16);
}

#define MANIFEST(es) \
    "{\"format\": \"" HT_MANIFEST_FORMAT "\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.9," \
    " \"lights\": [\"directional\"], \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\"," \
    " \"glsl\": \"1.20\", \"texture_units\": 2}, \"files\": {\"vertex\": \"f.vert\", \"fragment\": \"f.frag\"}" es "}]}"
#define ES3 "{\"api\": \"gles\", \"version\": \"3.0\", \"essl\": \"3.00\", \"fragment_precision\": \"highp\", \"vertex\": \"f3.vert\", \"fragment\": \"f3.frag\"}"
#define ES2 "{\"api\": \"gles\", \"version\": \"2.0\", \"essl\": \"1.00\", \"fragment_precision\": \"highp\", \"vertex\": \"f2.vert\", \"fragment\": \"f2.frag\"}"
#define ES2M "{\"api\": \"gles\", \"version\": \"2.0\", \"essl\": \"1.00\", \"fragment_precision\": \"mediump\", \"vertex\": \"f2.vert\", \"fragment\": \"f2m.frag\"}"

static int target(const char *json, ht_caps c, char *why, size_t why_size) {
    ht_manifest m;
    char err[512];
    if (ht_manifest_parse(json, "b", "manifest.json", &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return ht_select_es_target(&c, &m.tiers[0], why, why_size);
}

static void test_select_es_text_by_version_and_fragment_precision(void **state) {
    (void)state;
    char why[256];
    ht_caps es32 = probe("OpenGL ES 3.2", "OpenGL ES GLSL ES 3.20", 16, 23);
    ht_caps es20 = probe("OpenGL ES 2.0", "OpenGL ES GLSL ES 1.00", 8, 23);
    ht_caps mali = probe("OpenGL ES 2.0", "OpenGL ES GLSL ES 1.00", 8, 0);
    assert_int_equal(target(MANIFEST(", \"es\": [" ES3 ", " ES2 ", " ES2M "]"), es32, why, sizeof why), 0);
    assert_int_equal(target(MANIFEST(", \"es\": [" ES3 ", " ES2 ", " ES2M "]"), es20, why, sizeof why), 1);
    assert_int_equal(target(MANIFEST(", \"es\": [" ES3 ", " ES2 ", " ES2M "]"), mali, why, sizeof why), 2);
    assert_int_equal(target(MANIFEST(", \"es\": [" ES3 ", " ES2 "]"), mali, why, sizeof why), -1);
    assert_string_equal(why, "f2.frag needs fragment highp, the device's fragment stage has none "
                             "(glGetShaderPrecisionFormat), and the bundle has no mediump variant");
    assert_int_equal(target(MANIFEST(", \"es\": [" ES3 "]"), es20, why, sizeof why), -1);
    assert_string_equal(why, "needs GL ES 3.0, have 2.0");
    assert_int_equal(target(MANIFEST(""), es32, why, sizeof why), -1);
    assert_string_equal(why, "no GL ES target in the bundle (this tier needs desktop GL 2.1)");
    /* Desktop requirements are not asked on ES; ES ones through the same call. */
    assert_true(ht_select_check_requirements(&es20, NULL, &(ht_manifest_tier){ .es_count = 0 }, why, sizeof why) == false);
}

static void test_manifest_es_entries_are_read_strictly(void **state) {
    (void)state;
    static const struct { const char *json, *error; } bad[] = {
        { MANIFEST(", \"es\": [{\"api\": \"gl\"}]"), "tiers[0].es[0].api: \"gl\" is not \"gles\"" },
        { MANIFEST(", \"es\": [" "{\"api\": \"gles\", \"version\": \"2.0\", \"essl\": \"3.00\", \"fragment_precision\": \"highp\", \"vertex\": \"a\", \"fragment\": \"b\"}" "]"),
          "tiers[0].es[0].essl: ES 2.0 with ESSL 3.00: expected ES 2.0 with \"1.00\" or ES 3.0 with \"3.00\"" },
        { MANIFEST(", \"es\": [" "{\"api\": \"gles\", \"version\": \"2.0\", \"essl\": \"1.00\", \"fragment_precision\": \"lowp\", \"vertex\": \"a\", \"fragment\": \"b\"}" "]"),
          "tiers[0].es[0].fragment_precision: \"lowp\" is not \"highp\" or \"mediump\"" },
        { MANIFEST(", \"es\": [" "{\"api\": \"gles\", \"version\": \"2.0\", \"essl\": \"1.00\", \"fragment_precision\": \"highp\", \"vertex\": \"../a\", \"fragment\": \"b\"}" "]"),
          "tiers[0].es[0].vertex: \"../a\" is not a plain file name inside the bundle" },
        { MANIFEST(", \"es\": [" "{\"api\": \"gles\", \"version\": \"2.0\", \"essl\": \"1.00\", \"fragment_precision\": \"highp\", \"vertex\": \"a\", \"fragment\": \"b\", \"extra\": 1}" "]"),
          "tiers[0].es[0]" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ht_manifest m;
        char err[512];
        assert_int_not_equal(ht_manifest_parse(bad[i].json, "b", "manifest.json", &m, err, sizeof err), HT_OK);
        if (!strstr(err, bad[i].error)) fail_msg("case %zu: %s", i, err);
        assert_null(strchr(err, '\n'));
    }
    /* requires.api names the desktop API, and is required. */
    ht_manifest m;
    char err[512];
    const char *no_api = "{\"format\": \"" HT_MANIFEST_FORMAT "\", \"generator\": \"" HT_MANIFEST_GENERATOR "\","
                         " \"opaque_cutoff\": 0.9, \"lights\": [\"directional\"], \"tiers\": [{\"name\": \"full\","
                         " \"requires\": {\"gl\": \"2.1\"}, \"files\": {}}]}";
    assert_int_not_equal(ht_manifest_parse(no_api, "b", "manifest.json", &m, err, sizeof err), HT_OK);
    assert_non_null(strstr(err, "tiers[0].requires.api"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_caps_es_from_llvmpipe_and_mali_strings),
        cmocka_unit_test(test_caps_es1_core_names_and_selection),
        cmocka_unit_test(test_caps_es_profiles_lower_an_es_context),
        cmocka_unit_test(test_select_es_text_by_version_and_fragment_precision),
        cmocka_unit_test(test_manifest_es_entries_are_read_strictly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

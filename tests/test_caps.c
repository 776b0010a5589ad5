/* test_caps — what a device offers, from synthetic caps and driver strings:
   version parsing, extension lookup (known names as caps bits, any other
   name in the whole list) and device profiles; no GL context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "caps.h"
#include "support_caps.h"

/* A device of the given GL version with what that version brings: 4
   texture units from GL 1.3, one before; GLSL version left 0. */
static ht_caps device(int major, int minor) {
    return ht_test_caps(major, minor, 0, 0, major * 10 + minor >= 13 ? 4 : 1);
}

static void test_caps_parse_version_survives_driver_strings(void **state) {
    (void)state;
    int ma, mi;
    assert_true(ht_parse_version("4.5 (Compatibility Profile) Mesa 22.3.6", false, &ma, &mi));
    assert_int_equal(ma * 10 + mi, 45);
    assert_true(ht_parse_version("OpenGL ES 2.0 Mesa", false, &ma, &mi));
    assert_int_equal(ma * 10 + mi, 20);
    assert_true(ht_parse_version("1.20 NVIDIA via Cg compiler", true, &ma, &mi));
    assert_int_equal(ma * 100 + mi, 120);
    assert_true(ht_parse_version("1.2", true, &ma, &mi)); /* GLSL minors are hundredths */
    assert_int_equal(ma * 100 + mi, 120);
    assert_true(ht_parse_version("OpenGL ES GLSL ES 1.00", true, &ma, &mi));
    assert_int_equal(ma * 100 + mi, 100);
    assert_true(ht_parse_version("3", false, &ma, &mi));
    assert_int_equal(ma * 10 + mi, 30);
    assert_false(ht_parse_version("", false, &ma, &mi));
    assert_false(ht_parse_version(NULL, false, &ma, &mi));
    assert_false(ht_parse_version("no digits", false, &ma, &mi));
    assert_true(ht_parse_version("99999999999999999999.9999999", false, &ma, &mi)); /* no overflow */
    assert_true(ma >= 0 && mi >= 0);
}

static void test_caps_extension_list_matches_whole_names_only(void **state) {
    (void)state;
    const char *list = "GL_ARB_texture_env_combine_x GL_EXT_bgra GL_ARB_multitexture";
    assert_false(ht_extension_list_has(list, "GL_ARB_texture_env_combine"));
    assert_false(ht_extension_list_has(list, "GL_ARB_multi"));
    assert_false(ht_extension_list_has(list, "bgra"));
    assert_true(ht_extension_list_has(list, "GL_ARB_multitexture"));
    assert_true(ht_extension_list_has(list, "GL_EXT_bgra"));
    assert_false(ht_extension_list_has(list, ""));
    assert_false(ht_extension_list_has(NULL, "GL_EXT_bgra"));
}

static void test_caps_extension_met_by_the_core_version_it_entered(void **state) {
    (void)state;
    ht_caps c = device(1, 3); /* empty extension list */
    assert_true(ht_caps_satisfies_extension(&c, NULL, "GL_ARB_texture_env_combine"));
    assert_false(ht_caps_satisfies_extension(&c, NULL, "GL_ARB_texture_env_crossbar")); /* 1.4 */
    assert_false(ht_caps_satisfies_extension(&c, NULL, "GL_ARB_fragment_shader"));      /* 2.0 */
}

static void test_caps_notes_known_names_and_looks_others_up_in_the_list(void **state) {
    (void)state;
    ht_caps c = device(1, 2);
    const char *list = "GL_EXT_bgra GL_ARB_texture_rectangle GL_ARB_texture_env_combine_x";
    ht_caps_note_extensions(&c, list);
    assert_true(ht_caps_lists_extension(&c, "GL_ARB_texture_rectangle"));
    assert_false(ht_caps_lists_extension(&c, "GL_ARB_texture_env_combine"));
    assert_false(ht_caps_lists_extension(&c, "GL_EXT_bgra")); /* not a name the runtime asks about */
    assert_true(ht_caps_satisfies_extension(&c, list, "GL_EXT_bgra"));
    assert_false(ht_caps_satisfies_extension(&c, NULL, "GL_EXT_bgra"));
    assert_false(ht_caps_satisfies_extension(&c, list, "GL_ARB_texture_env_combine"));
}

static void test_caps_profile_hides_listed_extensions_from_bits_and_list(void **state) {
    (void)state;
    ht_caps c = device(1, 2);
    c.has_multitexture = true;
    char list[] = "GL_ARB_multitexture GL_EXT_bgra GL_ARB_texture_env_combine GL_NV_fence";
    ht_caps_note_extensions(&c, list);
    c.has_combine = true;
    const ht_device_profile p = { .hide_extensions = "GL_ARB_texture_env_combine GL_NV_fence" };
    ht_caps_apply_profile(&c, &p);
    ht_caps_hide_extensions(list, p.hide_extensions);
    assert_string_equal(list, "GL_ARB_multitexture GL_EXT_bgra");
    assert_false(c.has_combine);
    assert_false(ht_caps_lists_extension(&c, "GL_ARB_texture_env_combine"));
    assert_false(ht_caps_satisfies_extension(&c, list, "GL_NV_fence"));
    assert_true(ht_caps_satisfies_extension(&c, list, "GL_ARB_multitexture"));
}

static void test_caps_profile_lowering_the_version_keeps_listed_extensions(void **state) {
    (void)state;
    ht_caps c = device(2, 1);
    ht_caps_note_extensions(&c, "GL_ARB_texture_env_combine");
    ht_caps_apply_profile(&c, &(ht_device_profile){ .gl_major = 1, .gl_minor = 2 });
    assert_true(c.has_combine);   /* listed, so still there below 1.3 */
    assert_false(c.has_crossbar); /* core only since 1.4, not listed */
    assert_false(c.has_shaders);
}

/* The names HAIRTIER_DEVICE_PROFILE takes: GL 1.1 leaves one unit and no
   combiner, 1.3 the driver's units and list, 2.0 GLSL 1.10. */
static void test_caps_named_profiles_lower_a_gl45_device_to_their_version(void **state) {
    (void)state;
    char err[128];
    ht_device_profile p;
    for (int i = 0; i < 3; i++) {
        const char *zero[] = { NULL, "", "none" };
        assert_int_equal(ht_device_profile_parse(zero[i], &p, err, sizeof err), HT_OK);
        assert_true(ht_device_profile_is_zero(&p));
    }
    const char *list = "GL_ARB_multitexture GL_ARB_texture_env_combine GL_ARB_vertex_buffer_object";
    ht_caps c = device(4, 5);
    c.glsl_major = 4;
    c.glsl_minor = 50;
    ht_caps_note_extensions(&c, list);
    assert_int_equal(ht_device_profile_parse("gl20", &p, err, sizeof err), HT_OK);
    ht_caps_apply_profile(&c, &p);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 20);
    assert_int_equal(c.glsl_major * 100 + c.glsl_minor, 110);
    assert_int_equal(c.texture_units, 4);
    c = device(4, 5);
    ht_caps_note_extensions(&c, list);
    assert_int_equal(ht_device_profile_parse("gl13", &p, err, sizeof err), HT_OK);
    ht_caps_apply_profile(&c, &p);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 13);
    assert_false(c.has_shaders);
    assert_true(c.has_combine);
    assert_int_equal(c.texture_units, 4);
    c = device(4, 5);
    ht_caps_note_extensions(&c, list);
    assert_int_equal(ht_device_profile_parse("gl11", &p, err, sizeof err), HT_OK);
    ht_caps_apply_profile(&c, &p);
    assert_int_equal(c.gl_major * 10 + c.gl_minor, 11);
    assert_false(c.has_combine);
    assert_false(c.has_multitexture);
    assert_false(c.has_vbo);
    assert_int_equal(c.texture_units, 1);
    assert_int_equal(ht_device_profile_parse("GL13", &p, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_string_equal(err, "\"GL13\" is not none, gl11, gl13, gl20, videocore4, mali400 or videocore6");
    assert_true(ht_device_profile_is_zero(&p));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_caps_parse_version_survives_driver_strings),
        cmocka_unit_test(test_caps_extension_list_matches_whole_names_only),
        cmocka_unit_test(test_caps_extension_met_by_the_core_version_it_entered),
        cmocka_unit_test(test_caps_notes_known_names_and_looks_others_up_in_the_list),
        cmocka_unit_test(test_caps_profile_hides_listed_extensions_from_bits_and_list),
        cmocka_unit_test(test_caps_profile_lowering_the_version_keeps_listed_extensions),
        cmocka_unit_test(test_caps_named_profiles_lower_a_gl45_device_to_their_version),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

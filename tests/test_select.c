/* test_select — tier selection as a pure function of synthetic device caps,
   a manifest and the request; no GL context. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "manifest.h"
#include "select.h"
#include "support_caps.h"

/* Requirements as hairgen writes them (docs/bundle.md). */
static const char manifest[] =
    "{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"material\": \"t\", \"model\": \"scheuermann\","
    " \"lights\": [\"directional\"], \"opaque_cutoff\": 0.9,"
    " \"textures\": {\"albedo\": {\"file\": \"albedo.png\", \"width\": 8, \"height\": 8, \"depth\": 1}},"
    " \"tiers\": ["
    "  {\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\", \"glsl\": \"1.20\", \"extensions\": [], \"texture_units\": 2},"
    "   \"files\": {\"vertex\": \"full.vert\", \"fragment\": \"full.frag\"},"
    "   \"samplers\": [{\"uniform\": \"u_albedo\", \"texture\": \"albedo\", \"unit\": 0}]},"
    "  {\"name\": \"vertex\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.0\", \"glsl\": \"1.10\","
    "   \"extensions\": [\"GL_ARB_texture_env_combine\"], \"texture_units\": 1},"
    "   \"files\": {\"vertex\": \"vertex.vert\"}},"
    "  {\"name\": \"fixed\", \"requires\": {\"api\": \"gl\", \"gl\": \"1.2\", \"glsl\": null,"
    "   \"extensions\": [\"GL_ARB_multitexture\", \"GL_ARB_texture_env_combine\"], \"texture_units\": 2},"
    "   \"files\": {\"program\": \"fixed.json\"}}]}";

static ht_manifest bundle;

static int setup(void **state) {
    (void)state;
    char err[256];
    return ht_manifest_parse(manifest, "/bundle", "/bundle/manifest.json", &bundle, err, sizeof err) == HT_OK ? 0 : -1;
}

static ht_select_desc request(const ht_caps *caps) {
    return (ht_select_desc){ .caps = caps, .bundle = &bundle };
}

static ht_result run(const ht_select_desc *d, ht_selection *s, char *err) {
    err[0] = '\0';
    return ht_select_tier(d, s, err, 512);
}

static void test_select_picks_full_on_a_capable_device(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FULL);
    assert_int_equal(s.skipped_count, 0);
    assert_string_equal(s.reason, "best supported");
}

static void test_select_skips_full_without_fragment_shaders(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(2, 1, 1, 20, 4);
    c.has_fragment_shaders = false;
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_int_equal(s.skipped_count, 1);
    assert_non_null(strstr(s.skipped[0], "full: needs fragment shaders"));
    assert_non_null(strstr(s.reason, "full: needs fragment shaders"));
}

static void test_select_skips_full_below_glsl_120(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(2, 1, 1, 10, 4);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_string_equal(s.skipped[0], "full: needs GLSL 1.20, have 1.10");
}

static void test_select_skips_full_below_its_gl_version(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(2, 0, 1, 10, 4);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_string_equal(s.skipped[0], "full: needs GL 2.1, have 2.0");
}

static void test_select_skips_vertex_without_shaders(void **state) {
    (void)state;
    /* GL 2.1 by its version string, but no shader entry points. */
    ht_caps c = ht_test_caps(2, 1, 0, 0, 4);
    c.has_shaders = c.has_vertex_shaders = c.has_fragment_shaders = false;
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FIXED);
    assert_int_equal(s.skipped_count, 2);
    assert_non_null(strstr(s.skipped[0], "full: needs vertex shaders"));
    assert_non_null(strstr(s.skipped[1], "vertex: needs vertex shaders"));
}

static void test_select_fixed_needs_two_units(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(1, 3, 0, 0, 1);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_NO_TIER);
    assert_int_equal(s.tier, HT_TIER_COUNT);
    assert_string_equal(s.skipped[2], "fixed: needs 2 texture units, have 1");
    assert_non_null(strstr(err, "fixed: needs 2 texture units, have 1"));
}

static void test_select_fixed_needs_texture_env_combine(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(1, 2, 0, 0, 2);
    c.has_multitexture = true;
    const char *list = "GL_EXT_bgra GL_ARB_multitexture GL_ARB_texture_env_combine_x";
    ht_caps_note_extensions(&c, list);
    ht_select_desc d = request(&c);
    d.extensions = list;
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_NO_TIER);
    assert_string_equal(s.skipped[2], "fixed: needs GL_ARB_texture_env_combine");
}

static void test_select_skips_vertex_without_texture_env_combine(void **state) {
    (void)state;
    /* A vertex-shader-only GL 2.0 device whose profile hides combine. */
    ht_caps c = ht_test_caps(2, 0, 1, 10, 4);
    c.has_fragment_shaders = false;
    c.has_combine = false;
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_NO_TIER);
    assert_string_equal(s.skipped[1], "vertex: needs GL_ARB_texture_env_combine");
    c.has_combine = true;
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
}

static void test_select_extension_met_by_its_string_on_an_older_gl(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(1, 2, 0, 0, 2);
    c.has_multitexture = c.has_combine = true;
    ht_caps_note_extensions(&c, "GL_ARB_multitexture GL_ARB_texture_env_combine");
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FIXED);
}

static void test_select_extension_met_by_the_core_version_it_entered(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(1, 3, 0, 0, 2); /* empty extension string */
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FIXED);
}

static void test_select_honours_a_forced_tier(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.requested = HT_TIER_VERTEX;
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_int_equal(s.skipped_count, 0);
    assert_string_equal(s.reason, "forced by desc.tier");
}

static void test_select_honours_the_environment(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.env_tier = "vertex";
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_string_equal(s.reason, "forced by HAIRTIER_TIER");
    d.env_tier = "auto";
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FULL);
}

static void test_select_desc_tier_wins_over_the_environment(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.env_tier = "vertex";
    d.requested = HT_TIER_FULL;
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FULL);
    assert_string_equal(s.reason, "forced by desc.tier");
}

static void test_select_rejects_an_unknown_environment_tier(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.env_tier = "fastest";
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "HAIRTIER_TIER"));
    assert_non_null(strstr(err, "fastest"));
}

/* Issue 19 row 8: a newline in HAIRTIER_TIER made the one-line message two. */
static void test_select_unknown_environment_tier_with_a_newline_stays_one_line(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.env_tier = "full\nhairtier: tier gl11 (forged)";
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_INVALID_ARGUMENT);
    if (strchr(err, '\n') || !strstr(err, "full\\nhairtier")) fail_msg("%s", err);
}

static void test_select_forced_tier_falls_back_unless_strict(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(2, 1, 1, 10, 4);
    ht_select_desc d = request(&c);
    d.requested = HT_TIER_FULL;
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_non_null(strstr(s.reason, "fell back"));
    assert_non_null(strstr(s.reason, "full: needs GLSL 1.20, have 1.10"));

    d.strict = true;
    assert_int_equal(run(&d, &s, err), HT_ERR_UNSUPPORTED);
    assert_int_equal(s.tier, HT_TIER_COUNT);
    assert_non_null(strstr(err, "full: needs GLSL 1.20, have 1.10"));
    assert_null(strchr(err, '\n'));
}

static void test_select_strict_without_a_forced_tier_takes_the_best(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(2, 1, 1, 10, 4);
    ht_select_desc d = request(&c);
    d.strict = true;
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
}

static void test_select_runtime_failure_drops_to_the_next_tier(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.failed[0] = "compile failed: full.frag: 0:1(1): error: syntax error";
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_string_equal(s.skipped[0], "full: compile failed: full.frag: 0:1(1): error: syntax error");
}

static void test_select_gives_every_skipped_tier_a_reason(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(1, 1, 0, 0, 1);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_NO_TIER);
    assert_int_equal(s.skipped_count, bundle.tier_count);
    for (int i = 0; i < s.skipped_count; i++) {
        size_t n = strlen(bundle.tiers[i].name);
        assert_memory_equal(s.skipped[i], bundle.tiers[i].name, n);
        assert_true(strncmp(s.skipped[i] + n, ": ", 2) == 0 && strlen(s.skipped[i]) > n + 2);
        assert_non_null(strstr(err, s.skipped[i]));
    }
    assert_null(strchr(err, '\n'));
}

static void test_select_forced_tier_missing_from_the_bundle(void **state) {
    (void)state;
    ht_manifest b = bundle;
    b.tier_count = 2; /* full and vertex only */
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = request(&c);
    d.bundle = &b;
    d.requested = HT_TIER_FIXED;
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_NO_TIER);
    assert_string_equal(s.skipped[0], "fixed: not in this bundle");
    d.strict = true;
    assert_int_equal(run(&d, &s, err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "fixed: not in this bundle"));
}

static void test_select_profile_lowers_a_capable_device(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_caps_note_extensions(&c, "GL_ARB_multitexture GL_ARB_texture_env_combine GL_ARB_fragment_shader");
    ht_caps_apply_profile(&c, &(ht_device_profile){ .gl_major = 1, .gl_minor = 3, .texture_units = 2 });
    assert_int_equal(c.gl_major, 1);
    assert_int_equal(c.gl_minor, 3);
    assert_false(c.has_shaders);
    assert_int_equal(c.glsl_major, 0);
    assert_false(c.has_vbo);
    assert_true(c.has_combine);
    assert_int_equal(c.texture_units, 2);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FIXED);
    assert_string_equal(s.skipped[0], "full: needs GL 2.1, have 1.3");
    assert_string_equal(s.skipped[1], "vertex: needs GL 2.0, have 1.3");
}

static void test_select_profile_hides_a_core_extension(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(1, 5, 0, 0, 4);
    ht_caps_apply_profile(&c, &(ht_device_profile){ .hide_extensions = "GL_ARB_texture_env_combine" });
    assert_false(c.has_combine);
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_ERR_NO_TIER);
    assert_string_equal(s.skipped[2], "fixed: needs GL_ARB_texture_env_combine");
}

static void test_select_profile_models_a_vertex_shader_only_device(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(2, 1, 1, 20, 4);
    ht_caps_apply_profile(&c, &(ht_device_profile){ .no_fragment_shaders = true });
    ht_select_desc d = request(&c);
    ht_selection s;
    char err[512];
    assert_int_equal(run(&d, &s, err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
}

/* Bad manifests: one line naming the file and the field. */
static void expect_manifest_error(const char *text, const char *field) {
    ht_manifest b;
    char err[512] = "";
    assert_int_equal(ht_manifest_parse(text, "/d", "/d/manifest.json", &b, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "/d/manifest.json: "));
    if (!strstr(err, field)) fail_msg("expected field %s in: %s", field, err);
    assert_null(strchr(err, '\n'));
}

static void test_bundle_rejects_bad_manifests_naming_the_field(void **state) {
    (void)state;
    expect_manifest_error("{ not json", "manifest");
    expect_manifest_error("[]", "manifest");
    expect_manifest_error("{\"format\": \"hairtier-bundle/2\"}", "format");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"lights\": [\"directional\"], \"tiers\": []}",
                          "opaque_cutoff");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 1.5, \"lights\": []}",
                          "opaque_cutoff");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"spot\"]}",
                          "lights[0]");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"point\"],"
                          " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\", \"glsl\": \"one\"},"
                          " \"files\": {}}]}",
                          "tiers[0].requires.glsl");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"point\"],"
                          " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\"},"
                          " \"files\": {\"vertex\": \"../../etc/passwd\"}}]}",
                          "tiers[0].files.vertex");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"point\"],"
                          " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\"}, \"files\": {},"
                          " \"samplers\": [{\"uniform\": \"u\", \"texture\": \"nope\", \"unit\": 0}]}]}",
                          "tiers[0].samplers[0].texture");
    expect_manifest_error("{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"point\"],"
                          " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\", \"texture_units\": -1},"
                          " \"files\": {}}]}",
                          "tiers[0].requires.texture_units");
}

static void test_bundle_reads_the_documented_fields(void **state) {
    (void)state;
    assert_int_equal(bundle.tier_count, 3);
    assert_float_equal(bundle.opaque_cutoff, 0.9f, 1e-6f);
    assert_int_equal(bundle.light_count, 1);
    const ht_manifest_tier *fixed = ht_manifest_find_tier(&bundle, HT_TIER_FIXED);
    assert_non_null(fixed);
    assert_int_equal(fixed->glsl_major, 0);
    assert_int_equal(fixed->extension_count, 2);
    assert_string_equal(ht_manifest_tier_file(fixed, "program"), "fixed.json");
    const ht_manifest_tier *full = ht_manifest_find_tier(&bundle, HT_TIER_FULL);
    assert_int_equal(full->glsl_major * 100 + full->glsl_minor, 120);
    assert_null(ht_manifest_tier_file(full, "es_vertex"));
    assert_non_null(ht_manifest_find_texture(&bundle, full, "albedo"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_select_picks_full_on_a_capable_device),
        cmocka_unit_test(test_select_skips_full_without_fragment_shaders),
        cmocka_unit_test(test_select_skips_full_below_glsl_120),
        cmocka_unit_test(test_select_skips_full_below_its_gl_version),
        cmocka_unit_test(test_select_skips_vertex_without_shaders),
        cmocka_unit_test(test_select_fixed_needs_two_units),
        cmocka_unit_test(test_select_fixed_needs_texture_env_combine),
        cmocka_unit_test(test_select_skips_vertex_without_texture_env_combine),
        cmocka_unit_test(test_select_extension_met_by_its_string_on_an_older_gl),
        cmocka_unit_test(test_select_extension_met_by_the_core_version_it_entered),
        cmocka_unit_test(test_select_honours_a_forced_tier),
        cmocka_unit_test(test_select_honours_the_environment),
        cmocka_unit_test(test_select_desc_tier_wins_over_the_environment),
        cmocka_unit_test(test_select_rejects_an_unknown_environment_tier),
        cmocka_unit_test(test_select_unknown_environment_tier_with_a_newline_stays_one_line),
        cmocka_unit_test(test_select_forced_tier_falls_back_unless_strict),
        cmocka_unit_test(test_select_strict_without_a_forced_tier_takes_the_best),
        cmocka_unit_test(test_select_runtime_failure_drops_to_the_next_tier),
        cmocka_unit_test(test_select_gives_every_skipped_tier_a_reason),
        cmocka_unit_test(test_select_forced_tier_missing_from_the_bundle),
        cmocka_unit_test(test_select_profile_lowers_a_capable_device),
        cmocka_unit_test(test_select_profile_hides_a_core_extension),
        cmocka_unit_test(test_select_profile_models_a_vertex_shader_only_device),
        cmocka_unit_test(test_bundle_rejects_bad_manifests_naming_the_field),
        cmocka_unit_test(test_bundle_reads_the_documented_fields),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}

/* test_plan.c — ht_plan_make: features follow the material's textures and
   model, units are packed in order, every absent feature is noted. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "hairgen_internal.h"

static ht_material material(ht_model_kind model, bool base, bool alpha, bool shift, bool sparkle) {
    ht_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "test");
    m.shading.model = model;
    m.opaque_cutoff = 0.9;
    const bool has[HT_TEX_COUNT] = { base, alpha, shift, sparkle };
    for (int i = 0; i < HT_TEX_COUNT; i++)
        if (has[i]) {
            m.textures[i].origin = HT_TEXTURE_PROCEDURAL;
            m.textures[i].size = 16;
        }
    return m;
}

static ht_scene scene(int count, const ht_light_type *types) {
    ht_scene s;
    memset(&s, 0, sizeof s);
    s.light_count = count;
    for (int i = 0; i < count && i < HT_MAX_LIGHTS; i++) s.lights[i].type = types[i];
    return s;
}

static const ht_light_type one_directional[] = { HT_LIGHT_DIRECTIONAL };

static const char *note_for(const ht_plan *p, const char *feature) {
    size_t n = strlen(feature);
    for (int i = 0; i < p->note_count; i++)
        if (strncmp(p->notes[i], feature, n) == 0 && p->notes[i][n] == ':') return p->notes[i];
    return NULL;
}

static void test_plan_models_every_texture_the_material_has(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, true, true, true, true);
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_true(p.base && p.alpha && p.shift && p.sparkle && p.secondary && p.ao);
    assert_int_equal(p.texture_count, 2);
    assert_string_equal(p.textures[0].name, "albedo");
    assert_string_equal(p.textures[0].sampler, "u_albedo");
    assert_string_equal(p.textures[0].contents, "base.rgb alpha.a");
    assert_int_equal(p.textures[0].unit, 0);
    assert_string_equal(p.textures[1].name, "detail");
    assert_string_equal(p.textures[1].sampler, "u_detail");
    assert_string_equal(p.textures[1].contents, "shift.r sparkle.g");
    assert_int_equal(p.textures[1].unit, 1);
    assert_int_equal(p.note_count, 0);
    assert_true(p.opaque_cutoff == 0.9);
}

static void test_plan_packs_detail_into_unit_zero_without_albedo(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, false, false, true, false);
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.texture_count, 1);
    assert_string_equal(p.textures[0].name, "detail");
    assert_int_equal(p.textures[0].unit, 0);
    assert_true(p.shift);
    assert_false(p.sparkle);
}

static void test_plan_albedo_serves_alpha_alone(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, false, true, false, true);
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.texture_count, 2);
    assert_string_equal(p.textures[0].name, "albedo");
    assert_string_equal(p.textures[1].name, "detail");
    assert_int_equal(p.textures[1].unit, 1);
    assert_false(p.base);
    assert_true(p.alpha && p.sparkle);
}

static void test_plan_notes_each_absent_feature_with_a_reason(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, false, false, false, false);
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.texture_count, 0);
    assert_false(p.base || p.alpha || p.shift || p.sparkle);
    assert_true(p.secondary && p.ao);
    const char *features[] = { "base", "alpha", "shift", "sparkle" };
    for (size_t i = 0; i < 4; i++) {
        const char *n = note_for(&p, features[i]);
        assert_non_null(n);
        assert_non_null(strstr(n, "not modelled: "));
        assert_true(strlen(strstr(n, "not modelled: ")) > strlen("not modelled: "));
    }
    assert_int_equal(p.note_count, 4);
    assert_null(note_for(&p, "secondary"));
}

static void test_plan_kajiya_kay_has_no_shift_sparkle_or_secondary(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_KAJIYA_KAY, true, true, true, true);
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.shading.model, HT_MODEL_KAJIYA_KAY);
    assert_true(p.base && p.alpha && p.ao);
    assert_false(p.shift || p.sparkle || p.secondary);
    assert_int_equal(p.texture_count, 1);
    assert_string_equal(p.textures[0].name, "albedo");
    assert_non_null(note_for(&p, "secondary"));
    assert_non_null(note_for(&p, "shift"));
    assert_non_null(note_for(&p, "sparkle"));
    assert_null(note_for(&p, "base"));
}

static void test_plan_copies_lights_in_scene_order(void **state) {
    (void)state;
    const ht_light_type types[] = { HT_LIGHT_POINT, HT_LIGHT_DIRECTIONAL, HT_LIGHT_POINT };
    ht_material m = material(HT_MODEL_SCHEUERMANN, true, true, true, true);
    ht_scene s = scene(3, types);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.light_count, 3);
    for (int i = 0; i < 3; i++) assert_int_equal(p.light_types[i], types[i]);
}

static void test_plan_keeps_light_count_within_the_arrays(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, true, true, true, true);
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    s.light_count = HT_MAX_LIGHTS + 3;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.light_count, HT_MAX_LIGHTS);
    s.light_count = -2;
    ht_plan_make(&m, &s, &p);
    assert_int_equal(p.light_count, 0);
}

static void test_plan_copies_shading_and_defaults_an_unset_cutoff(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, true, true, true, true);
    m.shading.primary.exponent = 123.0;
    m.shading.secondary.shift = -42.0;
    m.opaque_cutoff = 0.0;
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_memory_equal(&p.shading, &m.shading, sizeof m.shading);
    assert_true(p.opaque_cutoff > 0.0 && p.opaque_cutoff <= 1.0);
}

static void test_plan_is_deterministic(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, false, true, false, true);
    ht_scene s = scene(1, one_directional);
    ht_plan a, b;
    memset(&b, 0xab, sizeof b);
    ht_plan_make(&m, &s, &a);
    ht_plan_make(&m, &s, &b);
    assert_memory_equal(&a, &b, sizeof a);
}

static void test_unmasked_shading_scales_only_the_secondary_by_the_sparkle_mean(void **state) {
    (void)state;
    ht_material m = material(HT_MODEL_SCHEUERMANN, false, false, false, true);
    for (int i = 0; i < 3; i++) {
        m.shading.primary.color[i] = 0.8;
        m.shading.secondary.color[i] = 0.5;
    }
    ht_scene s = scene(1, one_directional);
    ht_plan p;
    ht_plan_make(&m, &s, &p);
    assert_true(p.sparkle_mean == 1.0); /* until the texture is measured */
    p.sparkle_mean = 0.2;
    ht_shading u = ht_plan_unmasked_shading(&p);
    for (int i = 0; i < 3; i++) {
        assert_float_equal(u.secondary.color[i], 0.1, 1e-12);
        assert_float_equal(u.primary.color[i], 0.8, 1e-12);
    }
    m = material(HT_MODEL_SCHEUERMANN, false, false, false, false);
    m.shading.secondary.color[0] = 0.5;
    ht_plan_make(&m, &s, &p);
    p.sparkle_mean = 0.2; /* ignored: no mask to stand in for */
    assert_float_equal(ht_plan_unmasked_shading(&p).secondary.color[0], 0.5, 1e-12);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_plan_models_every_texture_the_material_has),
        cmocka_unit_test(test_plan_packs_detail_into_unit_zero_without_albedo),
        cmocka_unit_test(test_plan_albedo_serves_alpha_alone),
        cmocka_unit_test(test_plan_notes_each_absent_feature_with_a_reason),
        cmocka_unit_test(test_plan_kajiya_kay_has_no_shift_sparkle_or_secondary),
        cmocka_unit_test(test_plan_copies_lights_in_scene_order),
        cmocka_unit_test(test_plan_keeps_light_count_within_the_arrays),
        cmocka_unit_test(test_plan_copies_shading_and_defaults_an_unset_cutoff),
        cmocka_unit_test(test_plan_is_deterministic),
        cmocka_unit_test(test_unmasked_shading_scales_only_the_secondary_by_the_sparkle_mean),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_emit_glsl.c — the full and vertex tier emitters and ht_glsl_validate:
   every emitted GLSL passes glslang at its version for every shipped
   material, light mix and texture subset; only what is modelled is written;
   output is deterministic; extremes stay guarded; GLSL float literals. */
#include <dirent.h>
#include <locale.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "emit.h"
#include "fixed4_program.h"
#include "mediump_glsl.h"
#include "shader_interface.h"
#include "strbuf.h"

/* ---- fixtures ---- */

static ht_material dark_brown_like(void) {
    ht_material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "dark-brown-like");
    m.shading = (ht_shading){
        .model = HT_MODEL_SCHEUERMANN,
        .diffuse_color = { 0.23, 0.14, 0.08 },
        .wrap = 0.25,
        .primary = { .color = { 1.0, 0.95, 0.9 }, .exponent = 80.0, .shift = -0.1 },
        .secondary = { .color = { 0.55, 0.40, 0.28 }, .exponent = 24.0, .shift = 0.15 },
    };
    for (int i = 0; i < HT_TEX_COUNT; i++) {
        m.textures[i].origin = HT_TEXTURE_PROCEDURAL;
        m.textures[i].size = 16;
    }
    m.opaque_cutoff = 0.98;
    return m;
}

static void set_textures(ht_material *m, unsigned mask) {
    for (int i = 0; i < HT_TEX_COUNT; i++)
        m->textures[i].origin = (mask >> i) & 1u ? HT_TEXTURE_PROCEDURAL : HT_TEXTURE_ABSENT;
}

static ht_scene lights_scene(int count, unsigned point_mask) {
    ht_scene s;
    memset(&s, 0, sizeof s);
    s.light_count = count;
    for (int i = 0; i < count; i++) {
        s.lights[i].type = (point_mask >> i) & 1u ? HT_LIGHT_POINT : HT_LIGHT_DIRECTIONAL;
        s.lights[i].vector[1] = 1.0f;
        s.lights[i].color[0] = s.lights[i].color[1] = s.lights[i].color[2] = 1.0f;
    }
    return s;
}

static ht_plan plan_of(const ht_material *m, int lights, unsigned point_mask) {
    ht_scene s = lights_scene(lights, point_mask);
    ht_plan p;
    ht_plan_make(m, &s, &p);
    return p;
}

typedef struct emitted {
    ht_tier_output full, vertex;
} emitted;

static void emit_both(const ht_plan *p, emitted *e) {
    char err[4096] = "";
    ht_result r = ht_emit_full(p, &e->full, err, sizeof err);
    if (r != HT_OK) fail_msg("ht_emit_full: %s", err);
    r = ht_emit_vertex(p, &e->vertex, err, sizeof err);
    if (r != HT_OK) fail_msg("ht_emit_vertex: %s", err);
}

static void free_both(emitted *e) {
    ht_tier_output_free(&e->full);
    ht_tier_output_free(&e->vertex);
}

static const ht_out_text *text_of(const ht_tier_output *o, const char *file) {
    for (int i = 0; i < o->text_count; i++)
        if (strcmp(o->texts[i].file, file) == 0) return &o->texts[i];
    fail_msg("no %s", file);
    return NULL;
}

static int count_of(const char *haystack, const char *needle) {
    int n = 0;
    for (const char *p = strstr(haystack, needle); p; p = strstr(p + 1, needle)) n++;
    return n;
}

static bool any_text_contains(const emitted *e, const char *needle) {
    const ht_tier_output *tiers[] = { &e->full, &e->vertex };
    for (int t = 0; t < 2; t++)
        for (int i = 0; i < tiers[t]->text_count; i++)
            if (tiers[t]->texts[i].stage != HT_STAGE_NONE && strstr(tiers[t]->texts[i].text, needle)) return true;
    return false;
}

static bool has_string(const char (*list)[64], int count, const char *s) {
    for (int i = 0; i < count; i++)
        if (strcmp(list[i], s) == 0) return true;
    return false;
}

/* What every emitted set must satisfy, whatever the plan (GLSL texts; the
   vertex tier's LUT program is checked by parsing it). */
static void check_output(const ht_plan *p, const emitted *e) {
    const ht_tier_output *tiers[] = { &e->full, &e->vertex };
    for (int t = 0; t < 2; t++) {
        for (int i = 0; i < tiers[t]->text_count; i++) {
            const ht_out_text *x = &tiers[t]->texts[i];
            char log[4096];
            if (x->stage == HT_STAGE_NONE) {
                /* the vertex tier's LUT program, in fixed4's format */
                ht_fixed4_program prog;
                if (ht_fixed4_parse(x->text, x->file, &prog, log, sizeof log) != HT_OK)
                    fail_msg("%s: %s", x->file, log);
                assert_int_equal(prog.shading.model, p->shading.model);
                continue;
            }
            if (ht_glsl_validate(x->text, x->stage, x->glsl_version, x->es, log, sizeof log) != HT_OK)
                fail_msg("%s does not validate: %s\n%s", x->file, log, x->text);
            char first[32];
            snprintf(first, sizeof first, "#version %d%s\n", x->glsl_version, x->glsl_version >= 300 ? " es" : "");
            assert_true(strncmp(x->text, first, strlen(first)) == 0);
            if (x->stage == HT_STAGE_VERTEX && !x->es) {
                /* GLSL 1.20 (full's pairs) widens per vertex when the rule is on, ftransform()
                   while it is off; the vertex tier's 1.10 texts feed combiner stages: never */
                const bool widens = x->glsl_version >= 120;
                assert_int_equal(strstr(x->text, HT_U_WIDTH_RULE) != NULL, widens);
                assert_int_equal(count_of(x->text, widens ? "gl_Position = " HT_U_WIDTH_RULE
                                                            " > 0.0 ? gl_ModelViewProjectionMatrix * position : ftransform();"
                                                          : "gl_Position = ftransform();"),
                                 1);
                assert_int_equal(count_of(x->text, "gl_Position"), widens ? 2 : 1); /* and invariant gl_Position; */
                /* Only uv is a texture coordinate: a device may have one set. */
                assert_null(strstr(x->text, "gl_MultiTexCoord1"));
                assert_null(strstr(x->text, "gl_MultiTexCoord2"));
            }
            /* pow(0, e) is undefined in GLSL: every pow must sit behind its guard. */
            assert_int_equal(count_of(x->text, "pow("), count_of(x->text, "s > 0.0 ? pow(s, "));
            assert_null(strstr(x->text, "nan"));
            assert_null(strstr(x->text, "inf"));
        }
    }
    assert_int_equal(e->full.tier, HT_TIER_FULL);
    assert_int_equal(e->full.text_count, 9); /* desktop pair, prime pair, ES 3.0 and ES 2.0 pairs, ES 2.0 mediump */
    assert_string_equal(e->full.requires.gl, "2.1");
    assert_string_equal(e->full.requires.glsl, "1.20");
    assert_int_equal(e->full.requires.texture_units, p->texture_count);
    assert_int_equal(e->full.sampler_count, p->texture_count);
    for (int i = 0; i < p->texture_count; i++) {
        assert_string_equal(e->full.samplers[i].sampler, p->textures[i].sampler);
        assert_int_equal(e->full.samplers[i].unit, p->textures[i].unit);
        assert_non_null(strstr(text_of(&e->full, "full.frag")->text, p->textures[i].sampler));
    }
    const char *roles[][2] = { { "full.vert", "vertex" }, { "full.frag", "fragment" },
                               { "full-prime.vert", "prime_vertex" }, { "full-prime.frag", "prime_fragment" },
                               /* the ES texts are named by the "es" entries, not as desktop files */
                               { "full-es3.vert", "" }, { "full-es3.frag", "" },
                               { "full-es2.vert", "" }, { "full-es2.frag", "" }, { "full-es2-mediump.frag", "" } };
    for (int i = 0; i < 9; i++) assert_string_equal(text_of(&e->full, roles[i][0])->role, roles[i][1]);
    assert_int_equal(text_of(&e->full, "full.frag")->glsl_version, 120);
    assert_true(text_of(&e->full, "full-es2.frag")->es);
    assert_int_equal(text_of(&e->full, "full-es2.frag")->glsl_version, 100);
    assert_true(text_of(&e->full, "full-es3.frag")->es);
    assert_int_equal(text_of(&e->full, "full-es3.frag")->glsl_version, 300);
    assert_true(text_of(&e->full, "full-es2-mediump.frag")->es);
    assert_int_equal(text_of(&e->full, "full-es2-mediump.frag")->glsl_version, 100);
    /* ES 3.0 first (best first), each with its ESSL version and the highp
       the shading's directions need; last the ES 2.0 all-mediump text on the
       same vertex stage, for a device without fragment highp. */
    assert_int_equal(e->full.es_count, 3);
    assert_string_equal(e->full.es[0].version, "3.0");
    assert_string_equal(e->full.es[0].essl, "3.00");
    assert_string_equal(e->full.es[0].fragment, "full-es3.frag");
    assert_string_equal(e->full.es[1].version, "2.0");
    assert_string_equal(e->full.es[1].essl, "1.00");
    assert_string_equal(e->full.es[1].vertex, "full-es2.vert");
    assert_string_equal(e->full.es[1].precision, "highp");
    assert_string_equal(e->full.es[2].version, "2.0");
    assert_string_equal(e->full.es[2].vertex, "full-es2.vert");
    assert_string_equal(e->full.es[2].fragment, "full-es2-mediump.frag");
    assert_string_equal(e->full.es[2].precision, "mediump");

    assert_int_equal(e->vertex.tier, HT_TIER_VERTEX);
    /* two desktop vertex shaders, the LUT program, two ES pairs */
    assert_int_equal(e->vertex.text_count, 7);
    /* The combiner stages as an ES fragment stage need no highp. */
    assert_int_equal(e->vertex.es_count, 2);
    assert_string_equal(e->vertex.es[1].precision, "mediump");
    assert_string_equal(e->vertex.es[1].fragment, "vertex-es2.frag");
    assert_string_equal(e->vertex.requires.gl, "2.0");
    assert_string_equal(e->vertex.requires.glsl, "1.10");
    /* Its fragment stage is fixed4's GL_COMBINE stages. */
    assert_int_equal(e->vertex.requires.extension_count, 1);
    assert_string_equal(e->vertex.requires.extensions[0], "GL_ARB_texture_env_combine");
    assert_int_equal(e->full.requires.extension_count, 0);
    /* Tangent and ao are generic attributes, the same names on desktop and ES. */
    const char *lit_vertex[] = { "full.vert", "full-es2.vert", "vertex.vert", "vertex-es2.vert" };
    for (int i = 0; i < 4; i++) {
        const ht_out_text *x = text_of(i < 2 ? &e->full : &e->vertex, lit_vertex[i]);
        assert_int_equal(count_of(x->text, "attribute vec3 " HT_ATTR_TANGENT ";"), 1);
        assert_int_equal(count_of(x->text, "attribute float " HT_ATTR_AO ";"), p->ao ? 1 : 0);
    }
    const bool albedo = p->base || p->alpha;
    /* fixed4's units: the LUTs (Scheuermann two, Kajiya-Kay one per light),
       the albedo, the final stage; the albedo after the LUTs. */
    const bool kk = p->shading.model == HT_MODEL_KAJIYA_KAY;
    const int lights = p->light_count < 2 ? p->light_count : 2, luts = kk ? lights : 2;
    assert_int_equal(e->vertex.requires.texture_units, luts + 2);
    assert_int_equal(e->vertex.sampler_count, albedo ? 1 : 0);
    if (albedo) assert_int_equal(e->vertex.samplers[0].unit, luts);
    assert_string_equal(text_of(&e->vertex, "vertex.vert")->role, "vertex");
    assert_string_equal(text_of(&e->vertex, "vertex-prime.vert")->role, "prime_vertex");
    assert_string_equal(text_of(&e->vertex, "vertex-luts.json")->role, "program");
    assert_int_equal(text_of(&e->vertex, "vertex-luts.json")->stage, HT_STAGE_NONE);
    const char *vv = text_of(&e->vertex, "vertex.vert")->text;
    /* One coordinate set per LUT and two uv sets; the primary colour is
       divided by the runtime's scale and carries ao in alpha. */
    for (int k = 0; k < luts + 2; k++) {
        char set[32];
        snprintf(set, sizeof set, "gl_TexCoord[%d] = ", k);
        assert_int_equal(count_of(vv, set), 1);
    }
    assert_non_null(strstr(vv, "gl_FrontColor = vec4(rgb / " HT_U_LUT_SCALE ", "));
    assert_non_null(strstr(text_of(&e->vertex, "vertex-prime.vert")->text, "gl_TexCoord[") );
    assert_int_equal(e->vertex.dropped_count,
                     (int)p->shift + (int)p->sparkle + (p->light_count > 2) + 2); /* + colour clamp, 8-bit LUT */

    const char *model = p->shading.model == HT_MODEL_KAJIYA_KAY ? "kajiya-kay" : "scheuermann";
    assert_string_equal(e->full.features[0], model);
    assert_string_equal(e->vertex.features[0], model);
    assert_true(has_string(e->full.features, e->full.feature_count, "ao"));
    assert_int_equal(has_string(e->full.features, e->full.feature_count, "sparkle"), p->sparkle);
    assert_int_equal(has_string(e->full.features, e->full.feature_count, "shift"), p->shift);
    assert_false(has_string(e->vertex.features, e->vertex.feature_count, "shift"));
    assert_false(has_string(e->vertex.features, e->vertex.feature_count, "sparkle"));

    /* Only what is modelled is written. */
    assert_int_equal(any_text_contains(e, "sparkle"), p->sparkle);
    assert_int_equal(any_text_contains(e, "u_detail"), p->shift || p->sparkle);
    assert_int_equal(any_text_contains(e, "jitter"), p->shift);
    assert_int_equal(any_text_contains(e, "u_albedo"), albedo);
    assert_int_equal(any_text_contains(e, "highlight_secondary"), p->secondary);
    assert_false(strstr(text_of(&e->vertex, "vertex.vert")->text, "texture2D"));
    const char *frag = text_of(&e->full, "full.frag")->text;
    assert_int_equal(strstr(frag, "albedo.rgb") != NULL, p->base);
    assert_int_equal(strstr(frag, "albedo.a") != NULL, p->alpha);
    assert_null(strstr(frag, "for ("));
    int points = 0;
    for (int i = 0; i < p->light_count; i++) points += p->light_types[i] == HT_LIGHT_POINT;
    char decl[64];
    snprintf(decl, sizeof decl, "u_light_vector[%d];", p->light_count);
    assert_non_null(strstr(frag, decl));
    assert_int_equal(count_of(frag, "u_light_color["), p->light_count + 1);
    assert_int_equal(count_of(frag, ".xyz - v_position);"), points);
}

/* ---- tests ---- */

static void test_every_light_mix_and_texture_subset_validates(void **state) {
    (void)state;
    for (int model = 0; model < 2; model++)
        for (unsigned textures = 0; textures < 16; textures++)
            for (int lights = 1; lights <= HT_MAX_LIGHTS; lights++)
                for (unsigned points = 0; points < (1u << lights); points++) {
                    ht_material m = dark_brown_like();
                    m.shading.model = (ht_model_kind)model;
                    set_textures(&m, textures);
                    ht_plan p = plan_of(&m, lights, points);
                    emitted e;
                    emit_both(&p, &e);
                    check_output(&p, &e);
                    free_both(&e);
                }
}

static void test_shipped_materials_validate(void **state) {
    (void)state;
    DIR *dir = opendir("materials");
    if (!dir) {
        skip();
        return;
    }
    int loaded = 0;
    struct dirent *d;
    char names[64][300];
    int n = 0;
    while ((d = readdir(dir)) && n < 64) {
        size_t len = strlen(d->d_name);
        if (len > 5 && strcmp(d->d_name + len - 5, ".json") == 0)
            snprintf(names[n++], sizeof names[0], "materials/%s", d->d_name);
    }
    closedir(dir);
    for (int i = 0; i < n; i++) {
        ht_material m;
        char err[512];
        if (ht_material_load(names[i], &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
        if (m.shading.model == HT_MODEL_MARSCHNER) continue; /* its own emitter: test_material_marschner */
        loaded++;
        for (int lights = 1; lights <= HT_MAX_LIGHTS; lights++) {
            ht_plan p = plan_of(&m, lights, lights == 1 ? 0u : 0x5u);
            emitted e;
            emit_both(&p, &e);
            check_output(&p, &e);
            free_both(&e);
        }
    }
    if (loaded == 0) skip();
}

static void test_validate_rejects_a_broken_shader_with_a_log(void **state) {
    (void)state;
    char log[1024];
    const char *broken = "#version 120\nvoid main() { gl_FragColor = vec4(undeclared_thing); }\n";
    assert_int_equal(ht_glsl_validate(broken, HT_STAGE_FRAGMENT, 120, false, log, sizeof log), HT_ERR_COMPILE);
    assert_non_null(strstr(log, "undeclared_thing"));
    const char *good = "#version 120\nvoid main() { gl_FragColor = vec4(1.0); }\n";
    assert_int_equal(ht_glsl_validate(good, HT_STAGE_FRAGMENT, 120, false, log, sizeof log), HT_OK);
}

static void test_validate_holds_the_version_and_profile_asked_for(void **state) {
    (void)state;
    char log[1024];
    const char *v120 = "#version 120\nvoid main() { gl_Position = ftransform(); }\n";
    assert_int_equal(ht_glsl_validate(v120, HT_STAGE_VERTEX, 120, false, log, sizeof log), HT_OK);
    assert_int_equal(ht_glsl_validate(v120, HT_STAGE_VERTEX, 110, false, log, sizeof log), HT_ERR_COMPILE);
    assert_true(log[0] != '\0');
    /* A comment before the #version line would compile, but the file must
       start with it. */
    const char *late = "// hi\n#version 120\nvoid main() { gl_Position = ftransform(); }\n";
    assert_int_equal(ht_glsl_validate(late, HT_STAGE_VERTEX, 120, false, log, sizeof log), HT_ERR_COMPILE);
    /* ESSL has no fixed-function built-ins. */
    const char *es = "#version 100\nvoid main() { gl_Position = ftransform(); }\n";
    assert_int_equal(ht_glsl_validate(es, HT_STAGE_VERTEX, 100, true, log, sizeof log), HT_ERR_COMPILE);
    /* ESSL fragment shaders need a float precision. */
    const char *no_precision = "#version 100\nvoid main() { float x = 1.0; gl_FragColor = vec4(x); }\n";
    assert_int_equal(ht_glsl_validate(no_precision, HT_STAGE_FRAGMENT, 100, true, log, sizeof log),
                     HT_ERR_COMPILE);
    /* 1.20 built-in functions are not in 1.10. */
    const char *outer = "#version 110\nvoid main() { mat3 m = outerProduct(vec3(1.0), vec3(1.0));"
                        " gl_Position = vec4(m[0], 1.0); }\n";
    assert_int_equal(ht_glsl_validate(outer, HT_STAGE_VERTEX, 110, false, log, sizeof log), HT_ERR_COMPILE);
    assert_int_equal(ht_glsl_validate(NULL, HT_STAGE_VERTEX, 110, false, log, sizeof log), HT_ERR_COMPILE);
}

static void test_add_text_fails_with_the_file_name_and_keeps_the_output_freeable(void **state) {
    (void)state;
    ht_tier_output out;
    memset(&out, 0, sizeof out);
    char err[1024];
    char *text = strdup("#version 120\nvoid main() { gl_FragColor = oops; }\n");
    assert_int_equal(ht_output_add_text(&out, "bad.frag", "fragment", text, HT_STAGE_FRAGMENT, 120, false,
                                        err, sizeof err), HT_ERR_COMPILE);
    assert_true(strncmp(err, "bad.frag: ", 10) == 0);
    assert_non_null(strstr(err, "oops"));
    assert_int_equal(out.text_count, 0);
    assert_int_equal(ht_output_add_text(&out, "x.frag", "fragment", NULL, HT_STAGE_FRAGMENT, 120, false,
                                        err, sizeof err), HT_ERR_OUT_OF_MEMORY);
    ht_tier_output_free(&out);
}

static void test_absent_sparkle_and_shift_leave_no_detail_texture(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    set_textures(&m, 1u << HT_TEX_BASE | 1u << HT_TEX_ALPHA);
    ht_plan p = plan_of(&m, 2, 0);
    emitted e;
    emit_both(&p, &e);
    assert_false(any_text_contains(&e, "sparkle"));
    assert_false(any_text_contains(&e, "u_detail"));
    assert_false(any_text_contains(&e, "detail"));
    assert_true(any_text_contains(&e, "u_albedo"));
    free_both(&e);
}

static void test_prime_shaders_sample_nothing_without_alpha(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    set_textures(&m, 1u << HT_TEX_BASE | 1u << HT_TEX_SHIFT | 1u << HT_TEX_SPARKLE);
    ht_plan p = plan_of(&m, 1, 0);
    emitted e;
    emit_both(&p, &e);
    const char *pv = text_of(&e.full, "full-prime.vert")->text, *pf = text_of(&e.full, "full-prime.frag")->text;
    assert_null(strstr(pf, "sampler"));
    assert_null(strstr(pf, "texture2D"));
    assert_null(strstr(pv, "v_uv"));
    assert_non_null(strstr(pf, "gl_FragColor = vec4(vec3(1.0), drawn_alpha);"));
    free_both(&e);

    set_textures(&m, 1u << HT_TEX_ALPHA);
    p = plan_of(&m, 1, 0);
    emit_both(&p, &e);
    pf = text_of(&e.full, "full-prime.frag")->text;
    assert_non_null(strstr(pf, "texture2D(u_albedo, v_uv).a"));
    /* The prime pass is alpha only: no lighting. */
    assert_null(strstr(pf, "u_light"));
    assert_null(strstr(pf, "normalize"));
    free_both(&e);
}

static void test_kajiya_kay_writes_one_unshifted_lobe(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    m.shading.model = HT_MODEL_KAJIYA_KAY;
    ht_plan p = plan_of(&m, 1, 0);
    emitted e;
    emit_both(&p, &e);
    assert_false(any_text_contains(&e, "secondary"));
    assert_false(any_text_contains(&e, "t2"));
    assert_false(any_text_contains(&e, "wrap"));
    assert_false(any_text_contains(&e, "gl_Normal"));
    assert_true(any_text_contains(&e, "cross(T, L)"));
    assert_true(any_text_contains(&e, "highlight_primary(T, H)"));
    free_both(&e);
}

static void test_one_light_has_no_loop_and_no_array_of_four(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 1, 0);
    emitted e;
    emit_both(&p, &e);
    assert_false(any_text_contains(&e, "for ("));
    assert_false(any_text_contains(&e, "while"));
    assert_false(any_text_contains(&e, "[4]"));
    assert_int_equal(count_of(text_of(&e.full, "full.frag")->text, "rgb += hair_light("), 1);
    /* A directional light never reads the surface position for L. */
    assert_false(any_text_contains(&e, ".xyz - "));
    free_both(&e);
}

static void test_emitting_twice_is_byte_identical(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 3, 0x2);
    emitted a, b;
    emit_both(&p, &a);
    emit_both(&p, &b);
    const ht_tier_output *ta[] = { &a.full, &a.vertex }, *tb[] = { &b.full, &b.vertex };
    for (int t = 0; t < 2; t++) {
        assert_int_equal(ta[t]->text_count, tb[t]->text_count);
        for (int i = 0; i < ta[t]->text_count; i++) assert_string_equal(ta[t]->texts[i].text, tb[t]->texts[i].text);
        assert_memory_equal(ta[t]->features, tb[t]->features, sizeof ta[t]->features);
        assert_memory_equal(ta[t]->dropped, tb[t]->dropped, sizeof ta[t]->dropped);
    }
    free_both(&a);
    free_both(&b);
}

static void test_extreme_exponents_and_shifts_validate_and_stay_guarded(void **state) {
    (void)state;
    const double exponents[] = { 0.0, 0.5, 1.0, 10000.0 };
    const double shifts[] = { -100.0, 0.0, 100.0 };
    for (size_t ei = 0; ei < 4; ei++)
        for (size_t si = 0; si < 3; si++) {
            ht_material m = dark_brown_like();
            m.shading.primary.exponent = exponents[ei];
            m.shading.secondary.exponent = exponents[3 - ei];
            m.shading.primary.shift = shifts[si];
            m.shading.secondary.shift = -shifts[si];
            m.shading.wrap = si == 0 ? 0.0 : 1.0;
            ht_plan p = plan_of(&m, 2, 0x2);
            emitted e;
            emit_both(&p, &e);
            check_output(&p, &e);
            const char *frag = text_of(&e.full, "full.frag")->text;
            /* Exponent 0: sin^0 = 1, so zero t or H must be caught before
               smoothstep alone lights them (model.c: S = 0 there). */
            int zero_lobes = (exponents[ei] == 0.0) + (exponents[3 - ei] == 0.0);
            assert_int_equal(count_of(frag, "if (dot(t, t) == 0.0 || dot(h, h) == 0.0) return 0.0;"), zero_lobes);
            assert_int_equal(count_of(frag, "pow("), 2 - zero_lobes);
            char shift[64];
            snprintf(shift, sizeof shift, "shifted_tangent(T, N, %s + jitter);",
                     shifts[si] == 0.0 ? "0.0" : shifts[si] < 0 ? "-100.0" : "100.0");
            assert_non_null(strstr(frag, shift));
            if (exponents[ei] == 10000.0) assert_non_null(strstr(frag, "pow(s, 10000.0)"));
            free_both(&e);
        }
}

static void test_es_fragment_discards_against_the_alpha_uniforms(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 1, 0);
    emitted e;
    emit_both(&p, &e);
    const char *es = text_of(&e.full, "full-es2.frag")->text;
    assert_non_null(strstr(es, "discard"));
    assert_non_null(strstr(es, "uniform mediump float u_alpha_ref;"));
    assert_non_null(strstr(es, "uniform mediump float u_alpha_pass_opaque;"));
    assert_non_null(strstr(es, "#ifdef GL_FRAGMENT_PRECISION_HIGH"));
    const char *esv = text_of(&e.full, "full-es2.vert")->text;
    assert_non_null(strstr(esv, "vec4 position = vec4(a_position, 1.0);"));
    assert_non_null(strstr(esv, "gl_Position = u_mvp * position;"));
    assert_null(strstr(esv, "gl_Vertex"));
    assert_null(strstr(esv, "ftransform"));
    /* ESSL 3.00: the same text through the one conversion rule. */
    const char *es3 = text_of(&e.full, "full-es3.frag")->text;
    assert_true(strncmp(es3, "#version 300 es\n", 16) == 0);
    assert_non_null(strstr(es3, "out vec4 " HT_ES3_FRAG_COLOR ";"));
    assert_null(strstr(es3, "gl_FragColor"));
    assert_null(strstr(es3, "texture2D"));
    assert_null(strstr(es3, "varying"));
    assert_null(strstr(text_of(&e.full, "full-es3.vert")->text, "attribute"));
    /* The vertex tier's ES fragment stage discards too, in mediump. */
    const char *vf = text_of(&e.vertex, "vertex-es2.frag")->text;
    assert_non_null(strstr(vf, "discard"));
    assert_non_null(strstr(vf, "precision mediump float;"));
    assert_null(strstr(vf, "highp"));
    /* The desktop shaders leave alpha testing to glAlphaFunc. */
    assert_null(strstr(text_of(&e.full, "full.frag")->text, "discard"));
    /* ES discards on the alpha drawn: the width rule's scale included. */
    assert_true(strstr(es, "drawn_alpha >= u_alpha_ref") && strstr(vf, "drawn_alpha >= u_alpha_ref"));
    free_both(&e);
}

/* The width rule (lod.h): every fragment text the GLSL tiers draw hair
   with, the Z-prime's included, scales its alpha by the one uniform. */
static void test_every_fragment_text_takes_the_width_rules_opacity(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 1, 0);
    emitted e;
    emit_both(&p, &e);
    const char *full[] = { "full.frag", "full-prime.frag", "full-es2.frag", "full-es3.frag" };
    for (size_t i = 0; i < sizeof full / sizeof full[0]; i++) {
        const ht_out_text *t = text_of(&e.full, full[i]);
        assert_non_null(strstr(t->text, "uniform float " HT_U_OPACITY_CUT ";"));
        assert_non_null(strstr(t->text, "drawn_alpha = "));
        assert_non_null(strstr(t->text, "(1.0 - " HT_U_OPACITY_CUT ")"));
    }
    const char *vertex[] = { "vertex-es2.frag", "vertex-es3.frag" };
    for (size_t i = 0; i < 2; i++)
        assert_non_null(strstr(text_of(&e.vertex, vertex[i])->text, "(1.0 - " HT_U_OPACITY_CUT ")"));
    free_both(&e);
}

/* The width rule per vertex (shader_interface.h): every vertex stage a
   fragment stage of the hair is paired with widens by a_side and writes
   v_width_alpha, and every fragment text multiplies its alpha by it; the
   vertex tier's desktop stages (combiner stages after them: no varying to
   scale alpha with) do neither. */
static void test_every_pair_takes_the_width_rule_per_vertex(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 2, 0);
    emitted e;
    emit_both(&p, &e);
    const ht_tier_output *tiers[] = { &e.full, &e.vertex };
    for (int t = 0; t < 2; t++)
        for (int i = 0; i < tiers[t]->text_count; i++) {
            const ht_out_text *x = &tiers[t]->texts[i];
            const bool combiner_fed = tiers[t] == &e.vertex && !x->es;
            if (x->stage == HT_STAGE_NONE) continue;
            if (x->stage == HT_STAGE_FRAGMENT) {
                assert_non_null(strstr(x->text, "* " HT_V_WIDTH_ALPHA ";"));
            } else if (combiner_fed) {
                assert_null(strstr(x->text, HT_V_WIDTH_ALPHA));
            } else {
                assert_non_null(strstr(x->text, "position.xyz += " HT_ATTR_SIDE " * (widen - 1.0);"));
                assert_non_null(strstr(x->text, HT_V_WIDTH_ALPHA " = 1.0 / widen;"));
                assert_non_null(strstr(x->text, "clamp("));
            }
        }
    free_both(&e);
}

/* The mediump text is the table the fp16 mirror evaluates, written out
   whole (no step lost or added between the two), all in mediump. */
static void test_mediump_fragment_is_the_mirrored_table(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    for (int lights = 1; lights <= 2; lights++) {
        ht_plan p = plan_of(&m, lights, 0);
        emitted e;
        emit_both(&p, &e);
        const char *text = text_of(&e.full, "full-es2-mediump.frag")->text;
        ht_mp_program *prog = malloc(sizeof *prog);
        assert_non_null(prog);
        const ht_mp_desc d = ht_mp_desc_of_plan(&p);
        ht_mp_build(&d, prog);
        ht_strbuf sb;
        ht_strbuf_init(&sb);
        ht_mp_write_functions(&sb, prog);
        char *functions = ht_strbuf_take(&sb);
        assert_non_null(strstr(text, functions));
        assert_non_null(strstr(text, "precision mediump float;\n"));
        assert_null(strstr(text, "highp"));
        assert_non_null(strstr(text, "vec3 rgb = shade(v_position, v_tangent, v_normal, u_eye, u_light_vector[0].xyz"));
        /* the manifest's measurement of it */
        assert_int_equal(e.full.mediump.samples, 0);
        ht_emit_full_mediump_error(&p, &e.full);
        assert_int_equal(e.full.mediump.samples, 2048);
        assert_true(e.full.mediump.max_byte <= 3);
        free(functions);
        free(prog);
        free_both(&e);
    }
}

static void test_vertex_tier_drops_shift_and_sparkle_with_reasons(void **state) {
    (void)state;
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 1, 0);
    emitted e;
    emit_both(&p, &e);
    assert_int_equal(e.vertex.dropped_count, 4);
    assert_true(strncmp(e.vertex.dropped[0], "shift: ", 7) == 0);
    assert_true(strncmp(e.vertex.dropped[1], "sparkle: ", 9) == 0);
    assert_true(strncmp(e.vertex.dropped[2], "light colours: ", 15) == 0);
    assert_true(strncmp(e.vertex.dropped[3], "LUT: 8-bit", 10) == 0);
    assert_int_equal(e.full.dropped_count, 0);
    assert_true(has_string(e.full.features, e.full.feature_count, "1 directional light"));
    free_both(&e);

    p = plan_of(&m, 3, 0x6);
    emit_both(&p, &e);
    assert_true(has_string(e.vertex.features, e.vertex.feature_count, "1 directional light"));
    assert_true(has_string(e.vertex.features, e.vertex.feature_count, "2 point lights"));
    /* Two lights per pixel through the LUTs, the third per vertex. */
    assert_true(strncmp(e.vertex.dropped[2], "lights: 2 of 3 per pixel", 24) == 0);
    assert_non_null(strstr(text_of(&e.vertex, "vertex.vert")->text, "rgb += hair_light(L2, "));
    free_both(&e);
}

/* ---- GLSL float literals ---- */

static void check_literal(double v) {
    char lit[HT_GLSL_FLOAT_SIZE];
    ht_glsl_float(v, lit);
    assert_true(strchr(lit, '.') != NULL);
    assert_null(strchr(lit, ','));
    assert_null(strchr(lit, 'f'));
    assert_true(strcmp(lit, "-0.0") != 0);
    for (const char *c = lit; *c; c++) assert_non_null(strchr("0123456789.-+e", *c));
    /* Reads back (in the C locale) as the float GLSL will hold. */
    char *old = strdup(setlocale(LC_NUMERIC, NULL));
    setlocale(LC_NUMERIC, "C");
    float back = strtof(lit, NULL);
    setlocale(LC_NUMERIC, old);
    free(old);
    float want = isfinite(v) ? (float)v : 0.0f;
    if (back != want) fail_msg("%.17g written as %s", v, lit);
    /* And glslang accepts it at both targets. */
    char src[256], log[1024];
    snprintf(src, sizeof src, "#version 110\nconst float k = %s;\nvoid main() { gl_Position = vec4(k); }\n", lit);
    if (ht_glsl_validate(src, HT_STAGE_VERTEX, 110, false, log, sizeof log) != HT_OK) fail_msg("%s: %s", lit, log);
    snprintf(src, sizeof src, "#version 100\nconst highp float k = %s;\nvoid main() { gl_Position = vec4(k); }\n", lit);
    if (ht_glsl_validate(src, HT_STAGE_VERTEX, 100, true, log, sizeof log) != HT_OK) fail_msg("%s: %s", lit, log);
}

static const double literal_values[] = { 0.0, -0.0, 1.0, -1.0, 0.1, -0.1, 0.25, 0.95, 1e-6, 1e-12, -1e-5,
                                         100.0, -100.0, 10000.0, 123456789.0, 3.0e38, 1.0 / 3.0, 0.0001,
                                         0.00012345, 16384.5, 2.5e-30 };

static void test_float_literals_read_back_exactly_and_validate(void **state) {
    (void)state;
    for (size_t i = 0; i < sizeof literal_values / sizeof literal_values[0]; i++) check_literal(literal_values[i]);
    char lit[HT_GLSL_FLOAT_SIZE];
    assert_string_equal(ht_glsl_float(1.0, lit), "1.0");
    assert_string_equal(ht_glsl_float(-0.1, lit), "-0.1");
    assert_string_equal(ht_glsl_float(-0.0, lit), "0.0");
    assert_string_equal(ht_glsl_float(NAN, lit), "0.0");
    assert_string_equal(ht_glsl_float(INFINITY, lit), "0.0");
    assert_string_equal(ht_glsl_float(1e300, lit), "0.0");
}

static void test_float_literals_ignore_the_locale(void **state) {
    (void)state;
    const char *locales[] = { "de_DE.UTF-8", "fr_FR.UTF-8", "de_DE", "fr_FR" };
    const char *found = NULL;
    for (size_t i = 0; i < 4 && !found; i++) found = setlocale(LC_NUMERIC, locales[i]) ? locales[i] : NULL;
    if (!found) {
        skip(); /* no comma-decimal locale installed */
        return;
    }
    for (size_t i = 0; i < sizeof literal_values / sizeof literal_values[0]; i++) check_literal(literal_values[i]);
    ht_material m = dark_brown_like();
    ht_plan p = plan_of(&m, 2, 0x1);
    emitted e;
    emit_both(&p, &e);
    check_output(&p, &e);
    free_both(&e);
    setlocale(LC_NUMERIC, "C");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_light_mix_and_texture_subset_validates),
        cmocka_unit_test(test_shipped_materials_validate),
        cmocka_unit_test(test_validate_rejects_a_broken_shader_with_a_log),
        cmocka_unit_test(test_validate_holds_the_version_and_profile_asked_for),
        cmocka_unit_test(test_add_text_fails_with_the_file_name_and_keeps_the_output_freeable),
        cmocka_unit_test(test_absent_sparkle_and_shift_leave_no_detail_texture),
        cmocka_unit_test(test_prime_shaders_sample_nothing_without_alpha),
        cmocka_unit_test(test_kajiya_kay_writes_one_unshifted_lobe),
        cmocka_unit_test(test_one_light_has_no_loop_and_no_array_of_four),
        cmocka_unit_test(test_emitting_twice_is_byte_identical),
        cmocka_unit_test(test_extreme_exponents_and_shifts_validate_and_stay_guarded),
        cmocka_unit_test(test_es_fragment_discards_against_the_alpha_uniforms),
        cmocka_unit_test(test_every_fragment_text_takes_the_width_rules_opacity),
        cmocka_unit_test(test_every_pair_takes_the_width_rule_per_vertex),
        cmocka_unit_test(test_mediump_fragment_is_the_mirrored_table),
        cmocka_unit_test(test_vertex_tier_drops_shift_and_sparkle_with_reasons),
        cmocka_unit_test(test_float_literals_read_back_exactly_and_validate),
        cmocka_unit_test(test_float_literals_ignore_the_locale),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_fixed.c — the fixed tier: the LUT holds the model's dot-product terms,
   the combiner program round-trips through JSON and rejects bad fields by
   name, the CPU emulator follows GL_COMBINE and GL's texture matrix, the
   emitter picks the texture-matrix coordinate rule exactly for Kajiya-Kay
   under a directional key light, and the whole tier (CPU coordinates or
   the texture matrix + LUT + combiners, emulated) tracks runtime/shading/model.c
   (with the infinite viewer the texture-matrix rule documents). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "combiner.h"
#include "emit.h"
#include "fixed_coords.h"
#include "fixed_soa.h"
#include "fixed_split.h"
#include "hairgen_internal.h"
#include "rng.h"
#include "support_combiner_eval.h"

/* The whole tier against the oracle, per channel after the framebuffer's
   [0,1] clamp. Measured with the seed below: max 0.0717, mean 0.00143 over
   4800 points; its texture-matrix points (Kajiya-Kay's 2D LUT) max
   0.0116, mean 0.00036. Where it comes from: 8-bit LUT texels, up to
   0.5/255 x scale (0.0078 at scale 4), plus linear interpolation between
   texels (the wrapped diffuse's kink spans one texel: up to (1 - wrap) x
   2/31 / 4 x diffuse colour ~ 0.016; highlight curvature ~ e h^2 / 8: 0.003
   at e = 100 on a 2D LUT's 8 sqrt(e) texels, but up to 0.22 on the 3D
   LUT's 16-texel t2.H axis, emit_fixed.c's budget), scaled down by light
   colour x ao x base. Each bound sits above its measured max with
   headroom, below that sum. Before the 3D LUT's budget (2^20 texels, axes
   of 8 sqrt(e)) every point was within 0.0116. */
#define TIER_MAX 0.08
#define TIER_MAX_2D 0.02
#define TIER_MEAN 0.002

/* ---- helpers ---- */

static void plan_for_material(const char *path, ht_plan *plan) {
    ht_material m;
    ht_scene scene;
    char err[512] = "";
    if (ht_material_load(path, &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_scene_default(&scene);
    ht_plan_make(&m, &scene, plan);
}

/* A plan by hand: one light, ao, base when `base` is set. */
static ht_plan simple_plan(ht_model_kind model, bool base) {
    ht_plan p;
    memset(&p, 0, sizeof p);
    p.shading.model = model;
    for (int i = 0; i < 3; i++) {
        p.shading.diffuse_color[i] = 0.3;
        p.shading.primary.color[i] = 0.8;
        p.shading.secondary.color[i] = model == HT_MODEL_SCHEUERMANN ? 0.4 : 0.0;
    }
    p.shading.wrap = 0.25;
    p.shading.primary.exponent = 60;
    p.shading.primary.shift = -0.1;
    p.shading.secondary.exponent = 20;
    p.shading.secondary.shift = 0.12;
    p.light_count = 1;
    p.light_types[0] = HT_LIGHT_DIRECTIONAL;
    p.base = base;
    p.secondary = model == HT_MODEL_SCHEUERMANN;
    p.ao = true;
    p.opaque_cutoff = 0.98;
    if (base) {
        p.texture_count = 1;
        snprintf(p.textures[0].name, sizeof p.textures[0].name, "albedo");
        snprintf(p.textures[0].sampler, sizeof p.textures[0].sampler, "u_albedo");
        snprintf(p.textures[0].contents, sizeof p.textures[0].contents, "base.rgb alpha.a");
    }
    return p;
}

static void emit(const ht_plan *plan, ht_tier_output *out, ht_combiner_program *prog) {
    char err[512] = "";
    if (ht_emit_fixed(plan, out, err, sizeof err) != HT_OK) fail_msg("ht_emit_fixed: %s", err);
    assert_int_equal(out->text_count, 1);
    assert_int_equal(out->image_count, 1);
    if (ht_combiner_parse(out->texts[0].text, "fixed.json", prog, err, sizeof err) != HT_OK)
        fail_msg("parse of emitted program: %s", err);
}

static const ht_out_image *lut_of(const ht_tier_output *out) {
    for (int i = 0; i < out->image_count; i++)
        if (strcmp(out->images[i].name, "fixed-lut") == 0) return &out->images[i];
    fail_msg("no fixed-lut image");
    return NULL;
}

/* A random unit vector, uniform on the sphere. */
static void random_unit(ht_rng *r, float v[3]) {
    double z = ht_rng_range(r, -1.0, 1.0), phi = ht_rng_range(r, 0.0, 6.283185307179586);
    double s = sqrt(1.0 - z * z);
    v[0] = (float)(s * cos(phi));
    v[1] = (float)(s * sin(phi));
    v[2] = (float)z;
}

static void random_color(ht_rng *r, double c[3]) {
    for (int i = 0; i < 3; i++) c[i] = ht_rng_unit(r);
}

/* ---- the LUT ---- */

static void test_lut_mapping_puts_first_and_last_texel_centres_on_plus_minus_one(void **state) {
    (void)state;
    const int sizes[] = { 2, 16, 32, 128, 256 };
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        int n = sizes[k];
        assert_true(fabs(ht_combiner_lut_centre(0, n) + 1.0) < 1e-15);
        assert_true(fabs(ht_combiner_lut_centre(n - 1, n) - 1.0) < 1e-15);
        /* GL samples texel x alone at texture coordinate (x + 0.5) / n */
        for (int x = 0; x < n; x++)
            assert_true(fabsf(ht_combiner_lut_coord(ht_combiner_lut_centre(x, n), n) -
                              (float)((x + 0.5) / n)) < 1e-6f);
    }
    assert_true(ht_combiner_lut_coord(0.3, 1) == 0.5f);
    /* outside [-1,1] (and NaN) clamps to the end texels */
    assert_true(ht_combiner_lut_coord(7.0, 16) == ht_combiner_lut_coord(1.0, 16));
    assert_true(ht_combiner_lut_coord(NAN, 16) == ht_combiner_lut_coord(-1.0, 16));
}

static void test_lut_texels_are_the_rounded_dot_terms_at_texel_centres(void **state) {
    (void)state;
    const char *materials[] = { "materials/dark-brown.json", "materials/kajiya-kay.json",
                                "materials/blond.json", "materials/high-contrast.json" };
    for (size_t k = 0; k < sizeof materials / sizeof materials[0]; k++) {
        ht_plan plan;
        plan_for_material(materials[k], &plan);
        /* the first under a light of colour 2 (its LUT carries it) */
        if (k == 0)
            for (int c = 0; c < 3; c++) plan.light_colors[0][c] = c == 0 ? 2.0 : 1.5;
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plan, &out, &p);
        const ht_out_image *lut = lut_of(&out);
        const int *n = p.lut_size;
        assert_int_equal(lut->image.width, n[0]);
        assert_int_equal(lut->image.height, n[1] * n[2]);
        assert_int_equal(lut->depth, n[2]);
        assert_int_equal(lut->image.channels, 3);
        const double tol = 0.5 / 255.0 * p.lut_scale / p.light_scale + 1e-9;
        double worst = 0.0;
        long changed = 0;
        for (int z = 0; z < n[2]; z++)
            for (int y = 0; y < n[1]; y++)
                for (int x = 0; x < n[0]; x++) {
                    double want[3];
                    ht_model_dot_terms_d(&plan.shading, ht_combiner_lut_centre(x, n[0]),
                                         ht_combiner_lut_centre(y, n[1]),
                                         ht_combiner_lut_centre(z, n[2]), want);
                    const uint8_t *px = lut->image.pixels + 3 * ((size_t)(z * n[1] + y) * n[0] + x);
                    for (int i = 0; i < 3; i++) {
                        double got = px[i] / 255.0 * p.lut_scale / p.light_scale;
                        double e = fabs(got - want[i]);
                        if (e > worst) worst = e;
                        /* the byte the per-texel bake wrote (before the
                           per-axis sums): the bake's speed-ups keep it */
                        double v = want[i] * p.light_scale / p.lut_scale;
                        v = v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
                        if (px[i] != (uint8_t)lround(v * 255.0)) changed++;
                    }
                }
        if (worst > tol) fail_msg("%s: LUT off by %g > %g", materials[k], worst, tol);
        if (changed)
            fail_msg("%s: %ld LUT bytes differ from lround(dot_terms x light_scale / scale * 255)", materials[k],
                     changed);
        /* the light scale is the scene's brightest channel (at least 1), and
           the scale the smallest of 1, 2, 4 that holds the brightest term
           under it */
        assert_true(p.light_scale == (k == 0 ? 2.0 : 1.0));
        double most = ht_model_dot_terms_max(&plan.shading) * p.light_scale;
        assert_true(most <= p.lut_scale);
        assert_true(p.lut_scale == 1 || most > p.lut_scale / 2);
        long texels = (long)n[0] * n[1] * n[2];
        assert_true(texels <= (1L << 20));
        print_message("%-28s LUT %dx%dx%d = %ld texels, scale %d, worst texel error %.5f\n",
                      materials[k], n[0], n[1], n[2], texels, p.lut_scale, worst);
        ht_tier_output_free(&out);
    }
}

static ht_combiner_program program_for_exponents(double e1, double e2) {
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    plan.shading.primary.exponent = e1;
    plan.shading.secondary.exponent = e2;
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    ht_tier_output_free(&out);
    return p;
}

static bool dropped_names(const ht_tier_output *out, const char *what) {
    for (int i = 0; i < out->dropped_count; i++)
        if (strstr(out->dropped[i], what)) return true;
    return false;
}

/* What an axis wants: at least 4 texels across a lobe width 1/sqrt(e),
   a power of two, up to the 256 cap; 0 < e < 2 the largest axis. A 2D LUT
   (Kajiya-Kay) gets it. */
static void test_highlight_axis_grows_with_exponent_and_resolves_the_lobe(void **state) {
    (void)state;
    const double exponents[] = { 0, 2, 10, 80, 300, 1000, 10000 };
    int previous = 0;
    for (size_t k = 0; k < sizeof exponents / sizeof exponents[0]; k++) {
        double e = exponents[k];
        int n = ht_lut_highlight_texels(e);
        assert_true(n >= previous);
        assert_true((n & (n - 1)) == 0);
        previous = n;
        if (n > 1 && n <= 256) assert_true(2.0 / (n - 1) <= 0.25 / sqrt(e > 1 ? e : 1));
        ht_plan plan = simple_plan(HT_MODEL_KAJIYA_KAY, true);
        plan.shading.primary.exponent = e;
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plan, &out, &p);
        assert_int_equal(p.lut_size[1], n < 16 ? 16 : (n > 256 ? 256 : n));
        ht_tier_output_free(&out);
    }
    assert_int_equal(ht_lut_highlight_texels(1), 256);
    assert_int_equal(ht_lut_highlight_texels(1000), 256);
}

/* A 3D LUT (Scheuermann) keeps within 16 depth slices and 16384 texels
   (emit_fixed.c says why), never above what its axes want, and lists
   every axis it shrank. */
static void test_3d_lut_keeps_its_budget(void **state) {
    (void)state;
    const double exponents[][2] = { { 2, 2 }, { 4, 24 }, { 80, 24 }, { 900, 300 }, { 10000, 10000 }, { 1, 1 } };
    for (size_t k = 0; k < sizeof exponents / sizeof exponents[0]; k++) {
        ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
        plan.shading.primary.exponent = exponents[k][0];
        plan.shading.secondary.exponent = exponents[k][1];
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plan, &out, &p);
        const int *n = p.lut_size;
        const int want[3] = { 32, ht_lut_highlight_texels(exponents[k][0]), ht_lut_highlight_texels(exponents[k][1]) };
        print_message("e %g / %g: LUT %dx%dx%d\n", exponents[k][0], exponents[k][1], n[0], n[1], n[2]);
        assert_true(n[2] > 1 && n[2] <= 16);
        assert_true((long)n[0] * n[1] * n[2] <= 16384);
        for (int i = 0; i < 3; i++) {
            int cap = want[i] < 16 ? 16 : (want[i] > 256 ? 256 : want[i]);
            assert_true(n[i] <= cap);
            const char *names[3] = { "LUT axis N.L:", "LUT axis t1.H:", "LUT axis t2.H:" };
            assert_true(dropped_names(&out, names[i]) == (n[i] < cap || cap < want[i]));
        }
        ht_tier_output_free(&out);
    }
    /* what fits keeps its axes: 32 x 16 x 16 */
    ht_combiner_program small = program_for_exponents(2, 2);
    assert_int_equal(small.lut_size[1], 16);
    assert_int_equal(small.lut_size[2], 16);
}

static void test_dark_brown_and_narrow_highlight_sizes(void **state) {
    (void)state;
    ht_plan plan;
    plan_for_material("materials/dark-brown.json", &plan);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    print_message("dark-brown LUT %dx%dx%d scale %d\n", p.lut_size[0], p.lut_size[1], p.lut_size[2],
                  p.lut_scale);
    /* wants 32 x 128 x 64 (8 sqrt(80) = 71.6 -> 128, 8 sqrt(24) = 39.2 ->
       64): the depth drops to 16, then t1.H halves twice */
    assert_int_equal(p.lut_size[0], 32);
    assert_int_equal(p.lut_size[1], 32);
    assert_int_equal(p.lut_size[2], 16);
    assert_true(dropped_names(&out, "LUT axis t1.H: 32 texels, not 128"));
    assert_true(dropped_names(&out, "LUT axis t2.H: 16 texels, not 64"));
    ht_tier_output_free(&out);
}

static void test_clamped_axis_is_listed_as_dropped(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    plan.shading.primary.exponent = 10000;
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    bool listed = false;
    for (int i = 0; i < out.dropped_count; i++) listed = listed || strstr(out.dropped[i], "t1.H") != NULL;
    assert_true(listed);
    ht_tier_output_free(&out);
}

/* Evaluates unit 0 alone at LUT coordinate d along the primary axis. */
static double emulate_primary_axis(const ht_combiner_program *p, const ht_out_image *lut, double d) {
    ht_combiner_texture tex = { "fixed-lut", &lut->image, lut->depth };
    ht_combiner_fragment f = { .primary = { 1, 1, 1, 1 } };
    f.lut_coord[0] = ht_combiner_lut_coord(0.0, p->lut_size[0]);
    f.lut_coord[1] = ht_combiner_lut_coord(d, p->lut_size[1]);
    f.lut_coord[2] = ht_combiner_lut_coord(0.0, p->lut_size[2]);
    float rgba[4];
    char err[256];
    if (ht_combiner_eval(p, &tex, 1, &f, rgba, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return rgba[0];
}

static void test_narrow_highlight_keeps_its_peak_at_zero(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, false);
    for (int i = 0; i < 3; i++) {
        plan.shading.diffuse_color[i] = 0.0;
        plan.shading.secondary.color[i] = 0.0;
        plan.shading.primary.color[i] = 1.0;
    }
    plan.shading.primary.exponent = 1000;
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    assert_int_equal(p.lut_size[1], 256);
    assert_int_equal(p.lut_scale, 1);
    const ht_out_image *lut = lut_of(&out);
    /* No texel centre sits on d = 0 on a power-of-two axis: the peak is read
       between d = +-1/255, S(1/255) = 0.9923, plus 8-bit rounding. */
    const double tol = 0.0100;
    double peak = emulate_primary_axis(&p, lut, 0.0);
    print_message("e=1000: peak read %.4f (model 1.0)\n", peak);
    assert_true(fabs(peak - 1.0) <= tol);
    /* the lobe keeps its width: one lobe width out, S = (1 - 1/e)^(e/2) */
    double w = 1.0 / sqrt(1000.0);
    for (int s = -1; s <= 1; s += 2) {
        double got = emulate_primary_axis(&p, lut, s * w);
        double want = ht_model_highlight_of_cos_d(s * w, 1000);
        assert_true(fabs(got - want) <= 0.02);
    }
    ht_tier_output_free(&out);
}

/* ---- the program ---- */

static void test_program_round_trips_through_json(void **state) {
    (void)state;
    ht_plan plans[3] = { simple_plan(HT_MODEL_SCHEUERMANN, true), simple_plan(HT_MODEL_KAJIYA_KAY, true),
                         simple_plan(HT_MODEL_SCHEUERMANN, false) };
    const ht_combiner_coords rules[3] = { HT_COORDS_CPU_DOTS, HT_COORDS_TEXTURE_MATRIX, HT_COORDS_CPU_DOTS };
    const char *rule_text[3] = { "\"cpu-dots\"", "\"texture-matrix\"",
                                 "\"cpu-dots\"" };
    for (int k = 0; k < 3; k++) {
        ht_tier_output out;
        ht_combiner_program p, again;
        emit(&plans[k], &out, &p);
        assert_int_equal(ht_combiner_lut_coords(&p), rules[k]);
        assert_non_null(strstr(out.texts[0].text, rule_text[k]));
        char *text = NULL, err[256];
        assert_int_equal(ht_combiner_write(&p, &text, err, sizeof err), HT_OK);
        assert_string_equal(text, out.texts[0].text);
        assert_int_equal(ht_combiner_parse(text, "fixed.json", &again, err, sizeof err), HT_OK);
        assert_memory_equal(&p, &again, sizeof p);
        free(text);
        ht_tier_output_free(&out);
    }

    /* every function, source and operand the format names */
    ht_combiner_program p;
    memset(&p, 0, sizeof p);
    p.model = HT_MODEL_SCHEUERMANN;
    p.light = 2;
    p.ao = false;
    p.shift[0] = 0.1;
    p.shift[1] = -1.0 / 3.0;
    snprintf(p.lut_texture, sizeof p.lut_texture, "fixed-lut");
    p.lut_size[0] = 16, p.lut_size[1] = 64, p.lut_size[2] = 32;
    p.lut_scale = 4;
    p.light_scale = 1.0 / 0.7; /* any number in [1, 4] */
    p.add_lights[0] = 0;
    p.add_lights[1] = 3;
    p.add_light_count = 2;
    p.stage_count = 4;
    for (int i = 0; i < 4; i++) ht_combiner_stage_defaults(&p.stages[i], i);
    snprintf(p.stages[0].texture, sizeof p.stages[0].texture, "fixed-lut");
    p.stages[0].target = GL_TEXTURE_3D;
    p.stages[0].coords = HT_COORDS_CPU_DOTS;
    p.stages[0].wrap = GL_CLAMP_TO_EDGE;
    p.stages[0].filter = GL_NEAREST;
    p.stages[0].combine_rgb = GL_INTERPOLATE;
    p.stages[0].source_rgb[0] = GL_CONSTANT;
    p.stages[0].source_rgb[1] = GL_PRIMARY_COLOR;
    p.stages[0].source_rgb[2] = GL_TEXTURE;
    p.stages[0].operand_rgb[0] = GL_ONE_MINUS_SRC_COLOR;
    p.stages[0].operand_rgb[2] = GL_ONE_MINUS_SRC_ALPHA;
    p.stages[0].combine_alpha = GL_SUBTRACT;
    p.stages[0].operand_alpha[1] = GL_ONE_MINUS_SRC_ALPHA;
    p.stages[0].constant[0] = 0.1f, p.stages[0].constant[3] = 1.0f / 3.0f;
    p.stages[0].alpha_scale = 2;
    const char *names[] = { "albedo", "detail", "albedo" };
    const GLenum fns[] = { GL_ADD, GL_ADD_SIGNED, GL_REPLACE };
    for (int i = 1; i < 4; i++) {
        snprintf(p.stages[i].texture, sizeof p.stages[i].texture, "%s", names[i - 1]);
        p.stages[i].combine_rgb = fns[i - 1];
        p.stages[i].rgb_scale = 1 << (i - 1);
    }
    p.stages[3].source_rgb[1] = GL_PREVIOUS; /* REPLACE reads one argument; 1 keeps the default */
    char *text = NULL, err[256] = "";
    if (ht_combiner_write(&p, &text, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_combiner_program again;
    if (ht_combiner_parse(text, "x.json", &again, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_memory_equal(&p, &again, sizeof p);
    free(text);
}

typedef struct mutation {
    const char *path;     /* where to change the emitted program: "lut.scale" */
    const char *json;     /* the new value (JSON), NULL removes the field */
    const char *field;    /* what the error must start with */
} mutation;

/* Finds "a.b[2].c" in root; returns the parent and the last key / index. */
static cJSON *parent_of(cJSON *root, const char *path, char *key, int *index) {
    cJSON *node = root, *parent = NULL;
    char buf[128];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *tok = strtok(buf, "."); tok; tok = strtok(NULL, ".")) {
        char *br = strchr(tok, '[');
        *index = -1;
        if (br) {
            *br = '\0';
            *index = atoi(br + 1);
        }
        parent = node;
        strcpy(key, tok);
        node = cJSON_GetObjectItemCaseSensitive(node, tok);
        if (*index >= 0) {
            parent = node;
            node = cJSON_GetArrayItem(node, *index);
        }
        assert_non_null(node);
    }
    return parent;
}

/* Parses `program` changed by m (or with m's field added) and checks the
   error starts with m->field. */
static void expect_mutation(const char *program, const mutation *m, bool add) {
    cJSON *root = cJSON_Parse(program);
    char key[64];
    int index = -1;
    cJSON *parent;
    if (add) { /* "a.b[1].new": parent a.b[1], key "new" */
        char where[64];
        snprintf(where, sizeof where, "%s", m->path);
        char *dot = strrchr(where, '.');
        parent = root;
        if (dot) {
            *dot = '\0';
            cJSON *up = parent_of(root, where, key, &index);
            parent = index >= 0 ? cJSON_GetArrayItem(up, index) : cJSON_GetObjectItem(up, key);
        }
        snprintf(key, sizeof key, "%s", dot ? dot + 1 : where);
        index = -1;
    } else {
        parent = parent_of(root, m->path, key, &index);
    }
    cJSON *value = m->json ? cJSON_Parse(m->json) : NULL;
    if (add) cJSON_AddItemToObject(parent, key, value);
    else if (!value) cJSON_DeleteItemFromObjectCaseSensitive(parent, key);
    else if (index >= 0) cJSON_ReplaceItemInArray(parent, index, value);
    else cJSON_ReplaceItemInObjectCaseSensitive(parent, key, value);
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    ht_combiner_program q;
    char err[512] = "";
    ht_result r = ht_combiner_parse(text, "fixed.json", &q, err, sizeof err);
    cJSON_free(text);
    if (r != HT_ERR_PARSE || strncmp(err, m->field, strlen(m->field)) != 0)
        fail_msg("%s %s %s: got %d \"%s\", want \"%s...\"", m->path, add ? "+=" : "=",
                 m->json ? m->json : "(removed)", r, err, m->field);
}

static void test_malformed_program_errors_name_the_field(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    const mutation cases[] = {
        { "format", "\"hairtier-combiner/2\"",
          "fixed.json: format: expected \"hairtier-combiner/1\" (a combiner program), got \"hairtier-combiner/2\"" },
        { "model", "\"marschner\"", "fixed.json: model: unknown value \"marschner\" (expected one of" },
        { "primary_color", "\"light0.colour\"", "fixed.json: primary_color:" },
        { "dots", "[\"T.L\", \"T.H\"]", "fixed.json: dots:" },
        { "shifts[1]", "1e300", "fixed.json: shifts[1]: must be in [-100, 100]" },
        { "lut.scale", NULL, "fixed.json: lut.scale: missing required integer" },
        { "lut.scale", "3", "fixed.json: lut.scale:" },
        { "lut.size[1]", "100", "fixed.json: lut.size[1]:" },
        { "lut.size[2]", "64.5", "fixed.json: lut.size[2]: must be an integer, got 64.5" },
        { "lut.centres", "\"half-texel\"", "fixed.json: lut.centres:" },
        { "lut.light_scale", "0.5", "fixed.json: lut.light_scale: must be in [1, 4], got 0.5" },
        { "lut.light_scale", "\"2\"", "fixed.json: lut.light_scale:" },
        { "add_lights", "[0]", "fixed.json: add_lights[0]: light 0 is the key light (primary_color)" },
        { "add_lights", "[1, 1]", "fixed.json: add_lights[1]: light 1 is listed twice" },
        { "add_lights", "[4]", "fixed.json: add_lights[0]:" },
        { "add_lights", "[1, 2, 3, 1]", "fixed.json: add_lights: expected 0 to 3 elements, got 4" },
        { "add_lights", "1", "fixed.json: add_lights:" },
        { "stages", "[]", "fixed.json: stages: expected 1 to 4 elements, got 0" },
        { "stages[1]", "5", "fixed.json: stages[1]: expected an object, got number 5" },
        { "stages[0].unit", "1", "fixed.json: stages[0].unit:" },
        { "stages[0].coords", "\"uv\"", "fixed.json: stages[0].coords:" },
        { "stages[0].target", "\"2d\"", "fixed.json: stages[0].target:" },
        { "stages[0].wrap", "\"GL_CLAMP\"",
          "fixed.json: stages[0].wrap: unknown value \"GL_CLAMP\" (did you mean \"GL_CLAMP_TO_EDGE\"?)" },
        { "stages[1].combine_rgb", "\"GL_DOT3_RGB\"",
          "fixed.json: stages[1].combine_rgb: unknown value \"GL_DOT3_RGB\" (expected one of \"GL_REPLACE\"," },
        { "stages[1].source_rgb[0]", "\"GL_TEXTURE0\"",
          "fixed.json: stages[1].source_rgb[0]: unknown value \"GL_TEXTURE0\" (did you mean \"GL_TEXTURE\"?)" },
        { "stages[1].source_rgb[1]", "7", "fixed.json: stages[1].source_rgb[1]: expected one of \"GL_TEXTURE\"," },
        { "stages[1].operand_rgb", "[\"GL_SRC_COLOR\"]",
          "fixed.json: stages[1].operand_rgb: 1 entries, GL_MODULATE reads 2" },
        { "stages[1].operand_alpha[0]", "\"GL_SRC_COLOR\"", "fixed.json: stages[1].operand_alpha[0]: unknown value" },
        { "stages[1].rgb_scale", "3", "fixed.json: stages[1].rgb_scale:" },
        { "stages[1].constant[2]", "-0.5", "fixed.json: stages[1].constant[2]: must be in [0, 1], got -0.5" },
        { "stages[1].texture", NULL, "fixed.json: stages[1].texture: missing required string" },
        { "stages[1].coords", "\"cpu-dots\"", "fixed.json: stages[1].coords:" },
        /* Scheuermann's shifted tangents: no texture matrix */
        { "stages[0].coords", "\"texture-matrix\"", "fixed.json: stages[0].coords: texture-matrix needs kajiya-kay" },
        { "stages[1].coords", "\"texture-matrix\"", "fixed.json: stages[1].coords:" },
        { "stages[0].coords", "\"texture matrix\"",
          "fixed.json: stages[0].coords: unknown value \"texture matrix\" (did you mean \"texture-matrix\"?)" },
    };
    /* fields added: "a.b[1].new" adds "new" to a.b[1] */
    const mutation added[] = {
        { "stages[1].colour", "1", "fixed.json: stages[1].colour: unknown key \"colour\" (known keys: \"unit\"," },
        { "stages[1].textur", "1", "fixed.json: stages[1].textur: unknown key \"textur\" (did you mean \"texture\"?)" },
        { "stages[1].unit", "1", "fixed.json: stages[1].unit: duplicate key \"unit\"" },
        { "modle", "1", "fixed.json: modle: unknown key \"modle\" (did you mean \"model\"?)" },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) expect_mutation(out.texts[0].text, &cases[k], false);
    for (size_t k = 0; k < sizeof added / sizeof added[0]; k++) expect_mutation(out.texts[0].text, &added[k], true);
    /* broken JSON names its line (and column), like every other format */
    char err[256] = "";
    ht_combiner_program q;
    assert_int_equal(ht_combiner_parse("{\n\"format\": \n", "fixed.json", &q, err, sizeof err), HT_ERR_PARSE);
    assert_string_equal(err, "fixed.json: line 3: malformed JSON: unexpected end of file (truncated?)");
    assert_int_equal(ht_combiner_parse("{\n  \"format\": x\n}", "fixed.json", &q, err, sizeof err), HT_ERR_PARSE);
    assert_string_equal(err, "fixed.json: line 2: malformed JSON at column 13 near 'x'");
    assert_int_equal(ht_combiner_parse("[1]", "fixed.json", &q, err, sizeof err), HT_ERR_PARSE);
    assert_string_equal(err, "fixed.json: (root): expected a JSON object, got an array");
    assert_int_equal(ht_combiner_parse(NULL, "fixed.json", &q, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_string_equal(err, "fixed.json: (call): no text or no output");
    ht_tier_output_free(&out);
}

static void test_write_refuses_an_invalid_program(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    char *text = NULL, err[256] = "";
    ht_combiner_program bad = p;
    bad.stages[1].source_rgb[2] = GL_TEXTURE; /* unused by MODULATE, must stay GL's default */
    assert_int_equal(ht_combiner_write(&bad, &text, err, sizeof err), HT_ERR_PARSE);
    assert_null(text);
    assert_non_null(strstr(err, "stages[1].source_rgb[2]"));
    bad = p;
    bad.stages[0].combine_rgb = GL_DOT3_RGB;
    assert_int_equal(ht_combiner_validate(&bad, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "stages[0].combine_rgb"));
    bad = p;
    bad.stages[0].coords = (ht_combiner_coords)7;
    assert_int_equal(ht_combiner_write(&bad, &text, err, sizeof err), HT_ERR_PARSE);
    assert_null(text);
    assert_non_null(strstr(err, "stages[0].coords"));
    ht_tier_output_free(&out);

    /* Kajiya-Kay: the matrix indexes the LUT, never the albedo */
    plan = simple_plan(HT_MODEL_KAJIYA_KAY, true);
    emit(&plan, &out, &p);
    assert_int_equal(p.stages[0].coords, HT_COORDS_TEXTURE_MATRIX);
    bad = p;
    bad.stages[1].coords = HT_COORDS_TEXTURE_MATRIX;
    assert_int_equal(ht_combiner_validate(&bad, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "stages[1].coords"));
    ht_tier_output_free(&out);
}

static void test_emitter_is_deterministic(void **state) {
    (void)state;
    /* cpu-dots and texture-matrix programs alike */
    const char *materials[] = { "materials/dark-brown.json", "materials/kajiya-kay.json" };
    for (size_t k = 0; k < sizeof materials / sizeof materials[0]; k++) {
        ht_plan plan;
        plan_for_material(materials[k], &plan);
        ht_tier_output a, b;
        ht_combiner_program pa, pb;
        emit(&plan, &a, &pa);
        emit(&plan, &b, &pb);
        assert_int_equal(ht_combiner_lut_coords(&pa), k == 0 ? HT_COORDS_CPU_DOTS : HT_COORDS_TEXTURE_MATRIX);
        assert_string_equal(a.texts[0].text, b.texts[0].text);
        const ht_image *ia = &lut_of(&a)->image, *ib = &lut_of(&b)->image;
        assert_int_equal(ia->width, ib->width);
        assert_int_equal(ia->height, ib->height);
        assert_memory_equal(ia->pixels, ib->pixels, (size_t)ia->width * ia->height * ia->channels);
        assert_int_equal(a.dropped_count, b.dropped_count);
        for (int i = 0; i < a.dropped_count; i++) assert_string_equal(a.dropped[i], b.dropped[i]);
        ht_tier_output_free(&a);
        ht_tier_output_free(&b);
    }
    /* the frame's texture matrix is a pure function of program, light, view */
    ht_plan plan = simple_plan(HT_MODEL_KAJIYA_KAY, true);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    const ht_light light = { HT_LIGHT_DIRECTIONAL, { 0.3f, -0.5f, 0.8f }, { 1, 1, 1 } };
    const float view[3] = { 0.1f, 0.2f, 0.9f };
    float m1[16], m2[16];
    char err[256];
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &light, 1, view, m1, err, sizeof err), HT_OK);
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &light, 1, view, m2, err, sizeof err), HT_OK);
    assert_memory_equal(m1, m2, sizeof m1);
    ht_tier_output_free(&out);
}

static bool listed(const char list[][160], int count, const char *start) {
    for (int i = 0; i < count; i++)
        if (strncmp(list[i], start, strlen(start)) == 0) return true;
    return false;
}

static bool has_feature(const ht_tier_output *out, const char *name) {
    for (int i = 0; i < out->feature_count; i++)
        if (strcmp(out->features[i], name) == 0) return true;
    return false;
}

static void test_texture_matrix_rule_only_for_kajiya_kay_under_a_directional_key_light(void **state) {
    (void)state;
    const struct {
        ht_model_kind model;
        ht_light_type key;
        ht_combiner_coords want;
    } cases[] = {
        { HT_MODEL_KAJIYA_KAY, HT_LIGHT_DIRECTIONAL, HT_COORDS_TEXTURE_MATRIX },
        { HT_MODEL_KAJIYA_KAY, HT_LIGHT_POINT, HT_COORDS_CPU_DOTS },        /* L per vertex */
        { HT_MODEL_SCHEUERMANN, HT_LIGHT_DIRECTIONAL, HT_COORDS_CPU_DOTS }, /* two shifted tangents */
        { HT_MODEL_SCHEUERMANN, HT_LIGHT_POINT, HT_COORDS_CPU_DOTS },
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ht_plan plan = simple_plan(cases[k].model, true);
        plan.light_types[0] = cases[k].key;
        /* a point fill light after a directional key does not matter */
        plan.light_count = 2;
        plan.light_types[1] = HT_LIGHT_POINT;
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plan, &out, &p);
        assert_int_equal(ht_combiner_lut_coords(&p), cases[k].want);
        assert_int_equal(p.stages[0].coords, cases[k].want);
        assert_int_equal(p.stages[1].coords, HT_COORDS_UV);
        const bool matrix = cases[k].want == HT_COORDS_TEXTURE_MATRIX;
        /* the manifest says which rule, and the matrix's approximation */
        assert_int_equal(listed(out.dropped, out.dropped_count, "infinite viewer for H"), matrix);
        assert_true(has_feature(&out, matrix ? "coords texture-matrix" : "coords cpu-dots"));
        ht_tier_output_free(&out);
    }
}

static void test_no_albedo_gives_a_single_stage_that_restores_the_scale(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, false);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    assert_int_equal(p.stage_count, 1);
    assert_int_equal(out.requires.texture_units, 1);
    assert_int_equal(out.sampler_count, 0);
    assert_int_equal(p.stages[0].rgb_scale, p.lut_scale);
    for (int i = 0; i < out.requires.extension_count; i++)
        assert_string_not_equal(out.requires.extensions[i], "GL_ARB_multitexture");
    ht_tier_output_free(&out);

    plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    emit(&plan, &out, &p);
    assert_int_equal(p.stage_count, 2);
    assert_int_equal(out.requires.texture_units, 2);
    assert_string_equal(p.stages[1].texture, "albedo");
    assert_int_equal(out.samplers[0].unit, 1);
    assert_int_equal(p.stages[0].rgb_scale, 1);
    assert_int_equal(p.stages[1].rgb_scale, p.lut_scale);
    ht_tier_output_free(&out);
}

static void test_kajiya_kay_lut_is_two_dimensional(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_KAJIYA_KAY, true);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    assert_int_equal(p.lut_size[2], 1);
    assert_int_equal(p.stages[0].target, GL_TEXTURE_2D);
    assert_int_equal(lut_of(&out)->depth, 1);
    ht_tier_output_free(&out);
}

static void test_program_contains_no_glsl(void **state) {
    (void)state;
    ht_plan plan;
    plan_for_material("materials/dark-brown.json", &plan);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    assert_string_equal(out.requires.glsl, "");
    assert_int_equal(out.tier, HT_TIER_FIXED);
    for (int i = 0; i < out.text_count; i++) {
        const ht_out_text *t = &out.texts[i];
        assert_int_equal(t->stage, HT_STAGE_NONE);
        assert_int_equal(t->glsl_version, 0);
        const char *glsl_marks[] = { "#version", "void main", "gl_", "uniform", "sampler", "vec3" };
        for (size_t k = 0; k < sizeof glsl_marks / sizeof glsl_marks[0]; k++)
            assert_null(strstr(t->text, glsl_marks[k]));
        assert_string_equal(t->role, "program");
        assert_string_equal(t->file, "fixed.json");
    }
    /* the dropped features are listed with a reason */
    const char *dropped[] = { "shift", "sparkle", "light colour" };
    for (size_t k = 0; k < sizeof dropped / sizeof dropped[0]; k++) {
        bool found = false;
        for (int i = 0; i < out.dropped_count; i++)
            found = found || strncmp(out.dropped[i], dropped[k], strlen(dropped[k])) == 0;
        if (!found) fail_msg("dropped list lacks %s", dropped[k]);
    }
    ht_tier_output_free(&out);
}

/* Programs written before the light scale and the sub-passes read as one
   light of colour up to 1. */
static void test_program_without_light_scale_or_sub_passes_reads_as_before(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    ht_tier_output out;
    ht_combiner_program p, old;
    emit(&plan, &out, &p);
    cJSON *root = cJSON_Parse(out.texts[0].text);
    cJSON_DeleteItemFromObjectCaseSensitive(root, "add_lights");
    cJSON_DeleteItemFromObjectCaseSensitive(cJSON_GetObjectItem(root, "lut"), "light_scale");
    char *text = cJSON_Print(root), err[256] = "";
    cJSON_Delete(root);
    if (ht_combiner_parse(text, "fixed.json", &old, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_true(old.light_scale == 1.0);
    assert_int_equal(old.add_light_count, 0);
    assert_int_equal(ht_combiner_sub_passes(&old), 1);
    assert_memory_equal(&p, &old, sizeof p);
    cJSON_free(text);
    ht_tier_output_free(&out);
}

/* The scene's lights after the key get additive sub-passes when their
   diffuse term (light x diffuse colour 0.3) reaches 32/255 and the
   coordinates are the CPU's (under the texture matrix: every fill, only
   when the key shines from behind); the LUT carries the brightest colour drawn,
   and the primary colours divide by it. */
static void test_second_light_gets_an_additive_sub_pass_and_bright_lights_a_light_scale(void **state) {
    (void)state;
    const struct {
        ht_model_kind model;
        int lights;
        double fill;          /* the second light's grey level */
        double key;           /* the key light's grey level */
        int want_add;         /* sub-passes after the key's */
        double light_scale;
    } cases[] = {
        { HT_MODEL_SCHEUERMANN, 2, 0.5, 2.0, 1, 2.0 },  /* diffuse 0.15 */
        { HT_MODEL_SCHEUERMANN, 2, 3.0, 1.0, 1, 3.0 },  /* a fill brighter than the key sets the scale */
        { HT_MODEL_SCHEUERMANN, 1, 0.0, 1.0, 0, 1.0 },
        { HT_MODEL_SCHEUERMANN, 2, 0.4, 1.0, 0, 1.0 },  /* diffuse 0.12: highlights only, dropped */
        { HT_MODEL_SCHEUERMANN, 2, 0.42, 1.0, 1, 1.0 }, /* diffuse 0.126: drawn */
        { HT_MODEL_SCHEUERMANN, 2, 1.0 / 1024, 1.0, 0, 1.0 },
        { HT_MODEL_SCHEUERMANN, 3, 0.5, 0.5, 2, 1.0 },
        { HT_MODEL_KAJIYA_KAY, 2, 0.5, 1.0, 0, 1.0 }, /* texture matrix: the key light alone */
        { HT_MODEL_KAJIYA_KAY, -2, 0.1, 1.0, 1, 1.0 }, /* ... unless the key shines from behind: any fill */
        { HT_MODEL_SCHEUERMANN, -2, 0.4, 1.0, 0, 1.0 }, /* CPU coordinates: the 32/255 rule still */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ht_plan plan = simple_plan(cases[k].model, true);
        plan.light_count = abs(cases[k].lights); /* negative: the key light from behind */
        plan.key_behind = cases[k].lights < 0;
        for (int l = 0; l < plan.light_count; l++) {
            plan.light_types[l] = HT_LIGHT_DIRECTIONAL;
            for (int c = 0; c < 3; c++) plan.light_colors[l][c] = l == 0 ? cases[k].key : cases[k].fill;
        }
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plan, &out, &p);
        assert_int_equal(p.add_light_count, cases[k].want_add);
        assert_int_equal(ht_combiner_sub_passes(&p), 1 + cases[k].want_add);
        for (int i = 0; i < p.add_light_count; i++) assert_int_equal(ht_combiner_sub_pass_light(&p, 1 + i), 1 + i);
        assert_int_equal(ht_combiner_sub_pass_light(&p, 0), 0);
        assert_int_equal(ht_combiner_sub_pass_light(&p, 1 + p.add_light_count), -1);
        assert_true(p.light_scale == cases[k].light_scale);
        /* lighting above 4 clamps (GL_RGB_SCALE stops there), and says so */
        const double most = ht_model_dot_terms_max(&plan.shading) * p.light_scale;
        assert_true(most <= p.lut_scale || p.lut_scale == 4);
        assert_int_equal(listed(out.dropped, out.dropped_count, "LUT: lighting up to"), most > 4.0);
        assert_true(has_feature(&out, cases[k].want_add ? "light 2 directional, additive sub-pass"
                                                        : "light 1 directional"));
        assert_int_equal(listed(out.dropped, out.dropped_count, "lights after the key: additive sub-passes"),
                         cases[k].want_add > 0);
        assert_int_equal(listed(out.dropped, out.dropped_count, "light 2: dropped"),
                         abs(cases[k].lights) > 1 && cases[k].want_add == 0);
        char want[96];
        snprintf(want, sizeof want, "light colour: channels above %g clamp", cases[k].light_scale);
        assert_true(listed(out.dropped, out.dropped_count, want));
        ht_tier_output_free(&out);
    }
}

/* The primary colour is light colour x ao / light_scale, so a light of
   colour 2 is not clamped at 1: LUT x primary x scale is the model's. */
static void test_primary_colours_divide_by_the_light_scale(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    plan.light_count = 2;
    plan.light_types[1] = HT_LIGHT_DIRECTIONAL;
    for (int c = 0; c < 3; c++) {
        plan.light_colors[0][c] = 2.0;
        plan.light_colors[1][c] = 0.5;
    }
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    assert_true(p.light_scale == 2.0);
    ht_vertex v[2];
    memset(v, 0, sizeof v);
    for (int i = 0; i < 2; i++) {
        v[i].tangent[1] = 1.0f;
        v[i].normal[2] = 1.0f;
        v[i].ao = i == 0 ? 1.0f : 0.5f;
    }
    const ht_light lights[2] = { { HT_LIGHT_DIRECTIONAL, { 0, 0, 1 }, { 2.0f, 1.0f, 0.5f } },
                                 { HT_LIGHT_DIRECTIONAL, { 1, 0, 0 }, { 0.5f, 0.25f, 3.0f } } };
    float colors[8];
    char err[256];
    assert_int_equal(ht_fixed_coords_colors(&p, v, 2, lights, 2, colors, err, sizeof err), HT_OK);
    const float key[8] = { 1.0f, 0.5f, 0.25f, 1.0f, 0.5f, 0.25f, 0.125f, 1.0f };
    for (int i = 0; i < 8; i++) assert_true(fabsf(colors[i] - key[i]) < 1e-6f);
    /* the sub-pass's light, by the same rule; above the light scale it clamps */
    assert_int_equal(ht_fixed_coords_colors_of(&p, 1, v, 2, lights, 2, colors, err, sizeof err), HT_OK);
    const float fill[8] = { 0.25f, 0.125f, 1.0f, 1.0f, 0.125f, 0.0625f, 0.75f, 1.0f };
    for (int i = 0; i < 8; i++) assert_true(fabsf(colors[i] - fill[i]) < 1e-6f);
    /* a light the frame does not have is black */
    assert_int_equal(ht_fixed_coords_colors_of(&p, 1, v, 2, lights, 1, colors, err, sizeof err), HT_OK);
    for (int i = 0; i < 8; i++) assert_true(colors[i] == (i % 4 == 3 ? 1.0f : 0.0f));
    ht_tier_output_free(&out);
}

/* ---- the emulator ---- */

static void test_emulator_follows_gl_combine_semantics(void **state) {
    (void)state;
    /* a 2x1 RGBA texture: texel 0 = (200, 0, 40, 255), texel 1 = (0, 100, 255, 0) */
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, 2, 1, 4), HT_OK);
    const uint8_t px[8] = { 200, 0, 40, 255, 0, 100, 255, 0 };
    memcpy(img.pixels, px, sizeof px);
    ht_image lut;
    assert_int_equal(ht_image_alloc(&lut, 1, 1, 3), HT_OK);
    memset(lut.pixels, 255, 3);

    ht_combiner_program p;
    memset(&p, 0, sizeof p);
    snprintf(p.lut_texture, sizeof p.lut_texture, "fixed-lut");
    p.lut_size[0] = p.lut_size[1] = p.lut_size[2] = 1;
    p.lut_scale = 1;
    p.stage_count = 2;
    ht_combiner_stage_defaults(&p.stages[0], 0);
    snprintf(p.stages[0].texture, sizeof p.stages[0].texture, "fixed-lut");
    p.stages[0].coords = HT_COORDS_CPU_DOTS;
    p.stages[0].wrap = GL_CLAMP_TO_EDGE;
    p.stages[0].source_rgb[1] = GL_PRIMARY_COLOR; /* white LUT x primary */
    ht_combiner_stage_defaults(&p.stages[1], 1);
    snprintf(p.stages[1].texture, sizeof p.stages[1].texture, "tex");
    ht_combiner_texture textures[2] = { { "fixed-lut", &lut, 1 }, { "tex", &img, 1 } };
    char err[256];
    float out[4];
    const float primary[4] = { 0.8f, 0.5f, 0.25f, 0.6f };
    ht_combiner_fragment f = { .primary = { 0.8f, 0.5f, 0.25f, 0.6f } };
    const float t0[4] = { 200 / 255.0f, 0, 40 / 255.0f, 1 }, t1[4] = { 0, 100 / 255.0f, 1, 0 };

    /* MODULATE x 4 clamps after scaling: 0.8 * 200/255 * 4 > 1 */
    p.stages[1].rgb_scale = 4;
    p.stages[1].wrap = GL_CLAMP_TO_EDGE;
    f.uv[0] = 0.0f; /* clamp to edge: texel 0 alone */
    assert_int_equal(ht_combiner_eval(&p, textures, 2, &f, out, err, sizeof err), HT_OK);
    assert_float_equal(out[0], 1.0f, 1e-6);
    assert_float_equal(out[1], 0.0f, 1e-6);
    assert_float_equal(out[2], fminf(1.0f, 4 * primary[2] * t0[2]), 1e-6);
    assert_float_equal(out[3], primary[3] * t0[3], 1e-6);

    /* GL_REPEAT at s = 0 blends the last and the first texel half and half */
    p.stages[1].rgb_scale = 1;
    p.stages[1].wrap = GL_REPEAT;
    assert_int_equal(ht_combiner_eval(&p, textures, 2, &f, out, err, sizeof err), HT_OK);
    for (int i = 0; i < 3; i++) assert_float_equal(out[i], primary[i] * 0.5f * (t0[i] + t1[i]), 1e-6);

    /* SUBTRACT clamps below 0; ADD_SIGNED subtracts 0.5 */
    p.stages[1].combine_rgb = GL_SUBTRACT;
    f.uv[0] = 0.75f; /* texel 1 alone */
    assert_int_equal(ht_combiner_eval(&p, textures, 2, &f, out, err, sizeof err), HT_OK);
    for (int i = 0; i < 3; i++) assert_float_equal(out[i], fmaxf(0.0f, t1[i] - primary[i]), 1e-6);
    p.stages[1].combine_rgb = GL_ADD_SIGNED;
    assert_int_equal(ht_combiner_eval(&p, textures, 2, &f, out, err, sizeof err), HT_OK);
    for (int i = 0; i < 3; i++)
        assert_float_equal(out[i], fminf(1.0f, fmaxf(0.0f, t1[i] + primary[i] - 0.5f)), 1e-6);

    /* INTERPOLATE(CONSTANT, PREVIOUS, TEXTURE alpha), alpha REPLACE(1 - texture alpha) */
    p.stages[1].combine_rgb = GL_INTERPOLATE;
    p.stages[1].source_rgb[0] = GL_CONSTANT;
    p.stages[1].source_rgb[2] = GL_TEXTURE;
    p.stages[1].operand_rgb[2] = GL_SRC_ALPHA;
    p.stages[1].constant[0] = 0.25f;
    p.stages[1].combine_alpha = GL_REPLACE;
    p.stages[1].operand_alpha[0] = GL_ONE_MINUS_SRC_ALPHA;
    p.stages[1].source_alpha[1] = GL_PREVIOUS;
    f.uv[0] = 0.25f; /* texel 0 alone, alpha 1: all constant */
    assert_int_equal(ht_combiner_eval(&p, textures, 2, &f, out, err, sizeof err), HT_OK);
    assert_float_equal(out[0], 0.25f, 1e-6);
    assert_float_equal(out[1], 0.0f, 1e-6);
    assert_float_equal(out[3], 0.0f, 1e-6);

    /* a missing or mis-sized texture is an error, not a guess */
    assert_int_equal(ht_combiner_eval(&p, textures, 1, &f, out, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "stages[1].texture"));
    p.lut_size[0] = 2;
    assert_int_equal(ht_combiner_eval(&p, textures, 2, &f, out, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "LUT image"));
    ht_image_free(&img);
    ht_image_free(&lut);
}

/* ---- the texture-matrix rule ---- */

/* What GL does with a texture coordinate (T, 1): M (T,1), divided by q. */
static void gl_transform(const float m[16], const float T[3], double out[3]) {
    double v[4];
    for (int row = 0; row < 4; row++)
        v[row] = (double)m[row] * T[0] + (double)m[4 + row] * T[1] + (double)m[8 + row] * T[2] + m[12 + row];
    for (int i = 0; i < 3; i++) out[i] = v[i] / v[3];
}

static void test_texture_matrix_maps_the_tangent_to_the_lut_coordinates_of_t_dot_l_and_t_dot_h(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_KAJIYA_KAY, true);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    assert_int_equal(ht_combiner_lut_coords(&p), HT_COORDS_TEXTURE_MATRIX);
    assert_true(p.lut_size[0] != p.lut_size[1]); /* each row has its own axis' mapping */
    ht_rng rng = ht_rng_seed(777);
    char err[256];
    double worst = 0.0;
    for (int k = 0; k < 2000; k++) {
        ht_light light = { HT_LIGHT_DIRECTIONAL, { 0, 0, 0 }, { 1, 1, 1 } };
        float T[3], view[3];
        random_unit(&rng, light.vector);
        random_unit(&rng, T);
        random_unit(&rng, view);
        /* lengths do not matter, only directions */
        for (int i = 0; i < 3; i++) light.vector[i] *= 3.0f, view[i] *= 0.25f;
        float m[16];
        assert_int_equal(ht_fixed_coords_texture_matrix(&p, &light, 1, view, m, err, sizeof err), HT_OK);
        double L[3], H[3], len = 0.0;
        for (int i = 0; i < 3; i++) L[i] = light.vector[i] / 3.0, H[i] = L[i] + view[i] / 0.25;
        for (int i = 0; i < 3; i++) len += H[i] * H[i];
        if (len < 1e-6) continue;
        double tl = 0.0, th = 0.0;
        for (int i = 0; i < 3; i++) tl += T[i] * L[i], th += T[i] * H[i] / sqrt(len);
        double got[3];
        gl_transform(m, T, got);
        const double want[3] = { ht_combiner_lut_coord(tl, p.lut_size[0]), ht_combiner_lut_coord(th, p.lut_size[1]),
                                 0.5 };
        for (int i = 0; i < 3; i++) worst = fmax(worst, fabs(got[i] - want[i]));
    }
    print_message("texture matrix vs lut_coord(T.L), lut_coord(T.H): worst %.2e\n", worst);
    /* float matrix entries: a few ulps of 0.5 */
    assert_true(worst < 1e-6);

    /* without a direction, the rows are the CPU rule's constants */
    const float T[3] = { 0.6f, 0.0f, 0.8f };
    const float view[3] = { 0, 0, 1 };
    float m[16];
    double got[3];
    ht_light behind = { HT_LIGHT_DIRECTIONAL, { 0, 0, -2 }, { 1, 1, 1 } }; /* L = -V: no H */
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &behind, 1, view, m, err, sizeof err), HT_OK);
    gl_transform(m, T, got);
    assert_float_equal(got[1], ht_combiner_lut_coord(-1.0, p.lut_size[1]), 1e-7);   /* S = 0 */
    assert_float_equal(got[0], ht_combiner_lut_coord(-0.8, p.lut_size[0]), 1e-6);
    ht_light none = { HT_LIGHT_DIRECTIONAL, { 0, 0, 0 }, { 1, 1, 1 } };           /* no L: sin = 0 */
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &none, 1, view, m, err, sizeof err), HT_OK);
    gl_transform(m, T, got);
    assert_float_equal(got[0], ht_combiner_lut_coord(1.0, p.lut_size[0]), 1e-7);
    assert_float_equal(got[1], ht_combiner_lut_coord(0.8, p.lut_size[1]), 1e-6);   /* H = V */
    /* no light at all: a finite matrix (the colour is what makes it unlit) */
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, NULL, 0, view, m, err, sizeof err), HT_OK);
    for (int i = 0; i < 16; i++) assert_true(isfinite(m[i]));

    /* what the matrix cannot do is refused, leaving the identity */
    static const float identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    ht_light point = { HT_LIGHT_POINT, { 0, 1, 2 }, { 1, 1, 1 } };
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &point, 1, view, m, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "point light"));
    assert_memory_equal(m, identity, sizeof m);
    ht_tier_output_free(&out);
    plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    emit(&plan, &out, &p);
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &behind, 1, view, m, err, sizeof err),
                     HT_ERR_INVALID_ARGUMENT);
    assert_memory_equal(m, identity, sizeof m);
    assert_int_equal(ht_fixed_coords_texture_matrix(&p, &behind, 1, NULL, m, err, sizeof err),
                     HT_ERR_INVALID_ARGUMENT);
    ht_tier_output_free(&out);
}

static void test_emulator_applies_the_texture_matrix_like_gl(void **state) {
    (void)state;
    ht_plan plan = simple_plan(HT_MODEL_KAJIYA_KAY, true);
    ht_tier_output out;
    ht_combiner_program p;
    emit(&plan, &out, &p);
    const ht_out_image *lut = lut_of(&out);
    const uint8_t base[4] = { 200, 150, 90, 255 };
    ht_image albedo = { 1, 1, 4, (uint8_t *)base };
    ht_combiner_texture tex[2] = { { "fixed-lut", &lut->image, lut->depth }, { "albedo", &albedo, 1 } };
    /* the same program read through cpu-dots coordinates: the reference */
    ht_combiner_program cpu = p;
    cpu.stages[0].coords = HT_COORDS_CPU_DOTS;
    char err[256];
    ht_rng rng = ht_rng_seed(31337);
    for (int k = 0; k < 500; k++) {
        ht_light light = { HT_LIGHT_DIRECTIONAL, { 0, 0, 0 }, { 1, 1, 1 } };
        float view[3];
        ht_combiner_fragment f;
        memset(&f, 0, sizeof f);
        random_unit(&rng, light.vector);
        random_unit(&rng, view);
        random_unit(&rng, f.tangent);
        f.uv[0] = f.uv[1] = 0.5f;
        for (int i = 0; i < 4; i++) f.primary[i] = 1.0f;
        assert_int_equal(ht_fixed_coords_texture_matrix(&p, &light, 1, view, f.texture_matrix, err, sizeof err),
                         HT_OK);
        ht_combiner_fragment g = f;
        double c[3];
        gl_transform(f.texture_matrix, f.tangent, c);
        for (int i = 0; i < 3; i++) g.lut_coord[i] = (float)c[i];
        float a[4], b[4];
        assert_int_equal(ht_combiner_eval(&p, tex, 2, &f, a, err, sizeof err), HT_OK);
        assert_int_equal(ht_combiner_eval(&cpu, tex, 2, &g, b, err, sizeof err), HT_OK);
        for (int i = 0; i < 4; i++) assert_float_equal(a[i], b[i], 1e-6);
        /* GL divides by q: the matrix times 2 is the same coordinate */
        for (int i = 0; i < 16; i++) g.texture_matrix[i] = 2.0f * f.texture_matrix[i];
        memcpy(g.tangent, f.tangent, sizeof g.tangent);
        assert_int_equal(ht_combiner_eval(&p, tex, 2, &g, b, err, sizeof err), HT_OK);
        for (int i = 0; i < 4; i++) assert_float_equal(a[i], b[i], 1e-6);
    }
    /* q = 0 (an all-zero matrix: a fragment that was never given one) is an
       error naming the stage, not a guess */
    ht_combiner_fragment f;
    memset(&f, 0, sizeof f);
    float rgba[4];
    assert_int_equal(ht_combiner_eval(&p, tex, 2, &f, rgba, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "stages[0].coords"));
    ht_tier_output_free(&out);
}

static void test_texture_matrix_colours_make_a_vertex_without_tangent_black(void **state) {
    (void)state;
    ht_plan plans[2] = { simple_plan(HT_MODEL_KAJIYA_KAY, true), simple_plan(HT_MODEL_SCHEUERMANN, true) };
    ht_vertex v[2] = { { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0 }, 0.5f },
                       { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 0, 0 }, { 0, 0 }, 0.5f } };
    ht_light light = { HT_LIGHT_DIRECTIONAL, { 0, 1, 0 }, { 0.8f, 0.6f, 4.0f } };
    char err[256];
    for (int k = 0; k < 2; k++) {
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plans[k], &out, &p);
        float colors[8];
        assert_int_equal(ht_fixed_coords_colors(&p, v, 2, &light, 1, colors, err, sizeof err), HT_OK);
        /* light colour x ao, clamped */
        assert_float_equal(colors[0], 0.4f, 1e-6);
        assert_float_equal(colors[1], 0.3f, 1e-6);
        assert_float_equal(colors[2], 1.0f, 0);
        assert_float_equal(colors[3], 1.0f, 0);
        /* the matrix reads T = 0 as d = 0 (a bright highlight): black there
           is the model's answer; CPU coordinates read it right themselves */
        const bool matrix = ht_combiner_lut_coords(&p) == HT_COORDS_TEXTURE_MATRIX;
        for (int i = 0; i < 3; i++) assert_float_equal(colors[4 + i], matrix ? 0.0f : colors[i], 0);
        assert_float_equal(colors[7], 1.0f, 0);
        assert_int_equal(ht_fixed_coords_colors(&p, v, 2, &light, 1, NULL, err, sizeof err),
                         HT_ERR_INVALID_ARGUMENT);
        ht_tier_output_free(&out);
    }
}

/* ---- the whole tier against the oracle ---- */

typedef struct tier_error { double sum, max; long count; } tier_error;

/* One point: the program's coordinate rule (CPU coordinates, or the
   tangent through the texture matrix with the camera looking at the origin
   from eye) -> emulated combiners, against ht_model_shade_d with the tier's
   rules (shift texture 0.5, sparkle 1, light 0 only; for the texture
   matrix V = the view direction, an infinite viewer), both clamped to
   [0,1] as the framebuffer would. */
static double point_error(const ht_combiner_program *p, const ht_shading *shading,
                          const ht_out_image *lut, const ht_vertex *v, const ht_light *light,
                          const float eye[3], const uint8_t base[4]) {
    /* a point light falls back to CPU coordinates, as the backend does */
    const bool matrix = ht_combiner_lut_coords(p) == HT_COORDS_TEXTURE_MATRIX && light->type != HT_LIGHT_POINT;
    ht_combiner_fragment f;
    memset(&f, 0, sizeof f);
    char err[256];
    if (matrix) {
        if (ht_fixed_coords_texture_matrix(p, light, 1, eye, f.texture_matrix, err, sizeof err) != HT_OK ||
            ht_fixed_coords_colors(p, v, 1, light, 1, f.primary, err, sizeof err) != HT_OK)
            fail_msg("%s", err);
        memcpy(f.tangent, v->tangent, sizeof f.tangent);
    } else {
        if (ht_fixed_coords_compute(p, v, 1, light, 1, eye, f.lut_coord, f.primary, err, sizeof err) != HT_OK)
            fail_msg("%s", err);
        for (int i = 0; i < 3; i++)
            assert_true(isfinite(f.lut_coord[i]) && f.lut_coord[i] >= 0.0f && f.lut_coord[i] <= 1.0f);
        /* a texture-matrix stage fed CPU coordinates through GL's initial
           identity matrix (the backend's point-light frames) */
        memcpy(f.tangent, f.lut_coord, sizeof f.tangent);
        for (int i = 0; i < 4; i++) f.texture_matrix[5 * i] = 1.0f;
    }
    ht_image albedo = { 1, 1, 4, (uint8_t *)base };
    ht_combiner_texture tex[2] = { { "fixed-lut", &lut->image, lut->depth }, { "albedo", &albedo, 1 } };
    f.uv[0] = f.uv[1] = 0.5f;
    float got[4];
    if (ht_combiner_eval(p, tex, 2, &f, got, err, sizeof err) != HT_OK) fail_msg("%s", err);

    ht_surface s;
    ht_light_ray ray;
    for (int i = 0; i < 3; i++) {
        s.T[i] = v->tangent[i];
        s.N[i] = v->normal[i];
        s.V[i] = matrix ? (double)eye[i] : (double)eye[i] - v->position[i];
        s.base[i] = base[i] / 255.0;
        ray.L[i] = light->type == HT_LIGHT_POINT ? (double)light->vector[i] - v->position[i] : light->vector[i];
        ray.color[i] = light->color[i];
    }
    s.shift_tex = 0.5;
    s.sparkle = 1.0;
    s.ao = v->ao;
    double want[3];
    ht_model_shade_d(shading, &s, &ray, 1, want);
    double worst = 0.0;
    for (int i = 0; i < 3; i++) {
        double w = fmin(1.0, fmax(0.0, want[i]));
        double e = fabs(got[i] - w);
        if (e > worst) worst = e;
    }
    assert_float_equal(got[3], base[3] / 255.0f, 1e-6);
    return worst;
}

static void test_whole_tier_emulated_on_cpu_tracks_the_oracle(void **state) {
    (void)state;
    ht_rng rng = ht_rng_seed(20240611);
    tier_error all = { 0, 0, 0 }, matrix = { 0, 0, 0 };
    for (int mi = 0; mi < 24; mi++) {
        const bool kk = mi % 4 == 3;
        ht_plan plan = simple_plan(kk ? HT_MODEL_KAJIYA_KAY : HT_MODEL_SCHEUERMANN, true);
        ht_shading *m = &plan.shading;
        random_color(&rng, m->diffuse_color);
        random_color(&rng, m->primary.color);
        if (!kk) random_color(&rng, m->secondary.color);
        m->wrap = ht_rng_unit(&rng);
        m->primary.exponent = ht_rng_range(&rng, 0.0, 100.0);
        m->secondary.exponent = ht_rng_range(&rng, 0.0, 100.0);
        m->primary.shift = kk ? 0.0 : ht_rng_range(&rng, -0.3, 0.3);
        m->secondary.shift = kk ? 0.0 : ht_rng_range(&rng, -0.3, 0.3);
        plan.light_types[0] = mi % 3 == 1 ? HT_LIGHT_POINT : HT_LIGHT_DIRECTIONAL;
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plan, &out, &p);
        const ht_out_image *lut = lut_of(&out);
        for (int si = 0; si < 200; si++) {
            ht_vertex v;
            memset(&v, 0, sizeof v);
            for (int i = 0; i < 3; i++) v.position[i] = (float)ht_rng_range(&rng, -1.0, 1.0);
            random_unit(&rng, v.tangent);
            random_unit(&rng, v.normal);
            v.ao = (float)ht_rng_unit(&rng);
            ht_light light = { .type = plan.light_types[0] };
            if (light.type == HT_LIGHT_POINT) {
                random_unit(&rng, light.vector);
                for (int i = 0; i < 3; i++) light.vector[i] *= 3.0f;
            } else {
                random_unit(&rng, light.vector);
            }
            for (int i = 0; i < 3; i++) light.color[i] = (float)ht_rng_unit(&rng);
            float eye[3];
            random_unit(&rng, eye);
            for (int i = 0; i < 3; i++) eye[i] *= 4.0f;
            uint8_t base[4];
            for (int i = 0; i < 4; i++) base[i] = (uint8_t)(ht_rng_next(&rng) & 0xFF);
            double e = point_error(&p, m, lut, &v, &light, eye, base);
            tier_error *rules[2] = { &all, ht_combiner_lut_coords(&p) == HT_COORDS_TEXTURE_MATRIX ? &matrix : NULL };
            for (int k = 0; k < 2; k++) {
                if (!rules[k]) continue;
                rules[k]->sum += e;
                rules[k]->count++;
                if (e > rules[k]->max) rules[k]->max = e;
            }
        }
        ht_tier_output_free(&out);
    }
    double mean = all.sum / all.count;
    print_message("fixed tier vs oracle over %ld points: mean %.5f, max %.5f\n", all.count, mean, all.max);
    /* Kajiya-Kay under directional lights, through the texture matrix, vs
       the oracle with the same infinite viewer */
    assert_true(matrix.count >= 600);
    print_message("  of which texture-matrix: %ld points, mean %.5f, max %.5f\n", matrix.count,
                  matrix.sum / matrix.count, matrix.max);
    /* Measured (this seed, 4800 points): see TIER_MAX / TIER_MEAN. */
    assert_true(all.max <= TIER_MAX);
    assert_true(matrix.max <= TIER_MAX_2D);
    assert_true(mean <= TIER_MEAN);
}

static void test_degenerate_vertices_give_the_models_answer(void **state) {
    (void)state;
    ht_plan plans[2] = { simple_plan(HT_MODEL_SCHEUERMANN, true), simple_plan(HT_MODEL_KAJIYA_KAY, true) };
    const uint8_t base[4] = { 255, 200, 100, 255 };
    for (int k = 0; k < 2; k++) {
        ht_tier_output out;
        ht_combiner_program p;
        emit(&plans[k], &out, &p);
        const ht_out_image *lut = lut_of(&out);
        const float eye[3] = { 0, 0, 4 };
        ht_light dir = { HT_LIGHT_DIRECTIONAL, { 0, 0, -1 }, { 1, 1, 1 } }; /* L = -V: H has no direction */
        ht_vertex v = { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0 }, 1 };
        assert_true(point_error(&p, &plans[k].shading, lut, &v, &dir, eye, base) <= TIER_MAX);
        ht_vertex zero_t = { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 0, 0 }, { 0, 0 }, 1 };
        ht_light up = { HT_LIGHT_DIRECTIONAL, { 0, 1, 0 }, { 1, 1, 1 } };
        assert_true(point_error(&p, &plans[k].shading, lut, &zero_t, &up, eye, base) <= TIER_MAX);
        ht_vertex zero_n = { { 0, 0, 0 }, { 0, 0, 0 }, { 1, 0, 0 }, { 0, 0 }, 0.5f };
        assert_true(point_error(&p, &plans[k].shading, lut, &zero_n, &up, eye, base) <= TIER_MAX);
        ht_light at_vertex = { HT_LIGHT_POINT, { 0, 0, 0 }, { 1, 1, 1 } };
        assert_true(point_error(&p, &plans[k].shading, lut, &v, &at_vertex, eye, base) <= TIER_MAX);
        ht_vertex parallel = { { 0, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 0, 0 }, 1 }; /* T = L */
        ht_light along = { HT_LIGHT_DIRECTIONAL, { 0, 0, 1 }, { 1, 1, 1 } };
        assert_true(point_error(&p, &plans[k].shading, lut, &parallel, &along, eye, base) <= TIER_MAX);
        ht_tier_output_free(&out);
    }
    /* no light: unlit, alpha 1 */
    ht_combiner_program p;
    ht_tier_output out;
    ht_plan plan = simple_plan(HT_MODEL_SCHEUERMANN, true);
    emit(&plan, &out, &p);
    ht_vertex v = { { 0, 0, 0 }, { 0, 1, 0 }, { 1, 0, 0 }, { 0, 0 }, 1 };
    float coord[3], color[4];
    const float eye[3] = { 0, 0, 4 };
    char err[128];
    assert_int_equal(ht_fixed_coords_compute(&p, &v, 1, NULL, 0, eye, coord, color, err, sizeof err), HT_OK);
    assert_true(color[0] == 0.0f && color[1] == 0.0f && color[2] == 0.0f && color[3] == 1.0f);
    assert_int_equal(ht_fixed_coords_compute(&p, &v, 1, NULL, 0, eye, NULL, color, err, sizeof err),
                     HT_ERR_INVALID_ARGUMENT);
    /* a bright light clamps to 1 in the primary colour */
    ht_light bright = { HT_LIGHT_DIRECTIONAL, { 0, 1, 0 }, { 4, 0.5f, 2 } };
    assert_int_equal(ht_fixed_coords_compute(&p, &v, 1, &bright, 1, eye, coord, color, err, sizeof err), HT_OK);
    assert_float_equal(color[0], 1.0f, 0);
    assert_float_equal(color[1], 0.5f, 0);
    ht_tier_output_free(&out);
}

/* The float structure-of-arrays path the tier draws with gives the double
   reference's coordinates: within float rounding of the dot products, and
   the same constants where a direction is missing (zero tangent, zero
   normal, a point light on the vertex, the eye on the vertex). */
static void test_float_soa_coordinates_match_the_double_reference(void **state) {
    (void)state;
    enum { N = 400 };
    ht_rng rng = ht_rng_seed(5);
    ht_vertex v[N];
    for (int i = 0; i < N; i++) {
        for (int k = 0; k < 3; k++) {
            v[i].position[k] = (float)ht_rng_range(&rng, -1, 1);
            v[i].tangent[k] = (float)ht_rng_range(&rng, -1, 1);
            v[i].normal[k] = (float)ht_rng_range(&rng, -1, 1);
        }
        v[i].ao = (float)ht_rng_unit(&rng);
    }
    memset(v[1].tangent, 0, sizeof v[1].tangent);
    memset(v[2].normal, 0, sizeof v[2].normal);
    const float eye[3] = { 0.3f, 0.5f, 3.0f };
    memcpy(v[3].position, eye, sizeof eye);
    ht_light lights[2] = { { HT_LIGHT_DIRECTIONAL, { 0.6f, 0.8f, 0.7f }, { 1, 1, 1 } },
                           { HT_LIGHT_POINT, { 0.2f, 1.5f, 0.4f }, { 1, 1, 1 } } };
    memcpy(v[4].position, lights[1].vector, sizeof eye);
    const ht_model_kind models[2] = { HT_MODEL_SCHEUERMANN, HT_MODEL_KAJIYA_KAY };
    for (int m = 0; m < 2; m++)
        for (int l = 0; l < 2; l++) {
            ht_plan plan = simple_plan(models[m], true);
            ht_tier_output out;
            ht_combiner_program p;
            emit(&plan, &out, &p);
            ht_tier_output_free(&out);
            ht_fixed_soa soa;
            assert_int_equal(ht_fixed_soa_make(&p, v, N, &soa), HT_OK);
            static float want[3 * N], got[3 * N], colors[4 * N];
            char err[128];
            assert_int_equal(ht_fixed_coords_compute(&p, v, N, &lights[l], 1, eye, want, colors, err, sizeof err), HT_OK);
            ht_fixed_soa_coords(&p, &soa, &lights[l], eye, got);
            for (int i = 0; i < 3 * N; i++) {
                if (fabsf(got[i] - want[i]) > 2e-5f)
                    fail_msg("model %d light %d vertex %d axis %d: float %.6f, double %.6f", m, l, i / 3, i % 3,
                             got[i], want[i]);
            }
            ht_fixed_soa_free(&soa);
        }
}


/* No 3D textures (GL ES 1.1): an additive LUT comes back exactly from its
   two 2D halves (a slice clipped at 255 stays clipped), and the LUT stage
   becomes C, A + C and the original stage reading the sum; a LUT stage that
   reads the previous colour, or a fourth stage, is refused with a line. */
static void test_split_lut_is_exact_for_an_additive_lut(void **state) {
    (void)state;
    const int n[3] = { 4, 4, 4 };
    ht_image lut = { 0 }, a, c;
    assert_int_equal(ht_image_alloc(&lut, 4, 16, 3), HT_OK);
    for (int z = 0; z < 4; z++)
        for (int y = 0; y < 4; y++)
            for (int x = 0; x < 4; x++)
                for (int k = 0; k < 3; k++) {
                    int v = 10 * x + 5 * y + 7 * z * (k + 1) + (x == 3 && y == 3 ? 240 : 0);
                    lut.pixels[((size_t)(z * 4 + y) * 4 + (size_t)x) * 3 + (size_t)k] = (uint8_t)(v > 255 ? 255 : v);
                }
    int worst = -1;
    assert_int_equal(ht_fixed_split_lut(n, &lut, &a, &c, &worst), HT_OK);
    assert_int_equal(worst, 0);
    assert_int_equal(a.width * 10 + a.height, 44);
    assert_int_equal(c.width * 10 + c.height, 41);
    assert_int_equal(c.pixels[3 * 3 + 2], 63); /* 7 z (k + 1) at z = 3, blue */
    ht_image_free(&a);
    ht_image_free(&c);
    ht_image_free(&lut);

    ht_combiner_program p = { .model = HT_MODEL_SCHEUERMANN, .stage_count = 2, .lut_size = { 4, 4, 4 } };
    snprintf(p.lut_texture, sizeof p.lut_texture, "fixed-lut");
    ht_combiner_stage_defaults(&p.stages[0], 0);
    ht_combiner_stage_defaults(&p.stages[1], 1);
    snprintf(p.stages[0].texture, sizeof p.stages[0].texture, "fixed-lut");
    p.stages[0].target = GL_TEXTURE_3D;
    p.stages[0].coords = HT_COORDS_CPU_DOTS;
    p.stages[0].source_rgb[1] = GL_PRIMARY_COLOR;
    snprintf(p.stages[1].texture, sizeof p.stages[1].texture, "albedo");
    assert_int_equal(ht_fixed_split_lut_stage(&p), 0);
    char err[256];
    ht_combiner_program bad = p;
    bad.stages[0].source_rgb[1] = GL_PREVIOUS;
    assert_int_equal(ht_fixed_split_program(&bad, 0, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "LUT stage 0 reads the previous stage's colour"));
    bad = p;
    bad.stage_count = 3;
    bad.stages[2] = p.stages[1];
    bad.stages[2].unit = 2;
    assert_int_equal(ht_fixed_split_program(&bad, 0, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "3 stages and 2 more"));
    assert_int_equal(ht_fixed_split_program(&p, 0, err, sizeof err), HT_OK);
    assert_int_equal(p.stage_count, 4);
    assert_int_equal(ht_fixed_split_lut_stage(&p), -1);
    assert_int_equal(p.stages[0].combine_rgb, GL_REPLACE);
    assert_int_equal(p.stages[1].combine_rgb, GL_ADD);
    assert_int_equal(p.stages[1].source_rgb[1], GL_PREVIOUS);
    assert_int_equal(p.stages[2].combine_rgb, GL_MODULATE);
    assert_int_equal(p.stages[2].source_rgb[0], GL_PREVIOUS);
    assert_int_equal(p.stages[2].source_rgb[1], GL_PRIMARY_COLOR);
    assert_string_equal(p.stages[3].texture, "albedo");
    assert_int_equal(p.stages[3].unit, 3);
    float m[16];
    ht_fixed_split_matrix(m);
    const float r = 0.75f; /* (s, t, r, 1) -> (r, 1/2) */
    assert_true(m[0] * 0.1f + m[4] * 0.2f + m[8] * r + m[12] == r);
    assert_true(m[1] * 0.1f + m[5] * 0.2f + m[9] * r + m[13] == 0.5f);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_float_soa_coordinates_match_the_double_reference),
        cmocka_unit_test(test_lut_mapping_puts_first_and_last_texel_centres_on_plus_minus_one),
        cmocka_unit_test(test_lut_texels_are_the_rounded_dot_terms_at_texel_centres),
        cmocka_unit_test(test_highlight_axis_grows_with_exponent_and_resolves_the_lobe),
        cmocka_unit_test(test_3d_lut_keeps_its_budget),
    cmocka_unit_test(test_dark_brown_and_narrow_highlight_sizes),
        cmocka_unit_test(test_clamped_axis_is_listed_as_dropped),
        cmocka_unit_test(test_narrow_highlight_keeps_its_peak_at_zero),
        cmocka_unit_test(test_program_round_trips_through_json),
        cmocka_unit_test(test_program_without_light_scale_or_sub_passes_reads_as_before),
        cmocka_unit_test(test_second_light_gets_an_additive_sub_pass_and_bright_lights_a_light_scale),
        cmocka_unit_test(test_primary_colours_divide_by_the_light_scale),
        cmocka_unit_test(test_malformed_program_errors_name_the_field),
        cmocka_unit_test(test_write_refuses_an_invalid_program),
        cmocka_unit_test(test_emitter_is_deterministic),
        cmocka_unit_test(test_no_albedo_gives_a_single_stage_that_restores_the_scale),
        cmocka_unit_test(test_kajiya_kay_lut_is_two_dimensional),
        cmocka_unit_test(test_program_contains_no_glsl),
        cmocka_unit_test(test_emulator_follows_gl_combine_semantics),
        cmocka_unit_test(test_texture_matrix_rule_only_for_kajiya_kay_under_a_directional_key_light),
        cmocka_unit_test(test_texture_matrix_maps_the_tangent_to_the_lut_coordinates_of_t_dot_l_and_t_dot_h),
        cmocka_unit_test(test_emulator_applies_the_texture_matrix_like_gl),
        cmocka_unit_test(test_texture_matrix_colours_make_a_vertex_without_tangent_black),
        cmocka_unit_test(test_whole_tier_emulated_on_cpu_tracks_the_oracle),
        cmocka_unit_test(test_degenerate_vertices_give_the_models_answer),
        cmocka_unit_test(test_split_lut_is_exact_for_an_additive_lut),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

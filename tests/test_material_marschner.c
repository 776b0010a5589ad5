/* test_material_marschner.c — `model: "marschner"` material files
   (docs/materials.md): the shipped one parses with the documented values,
   absent fields take their defaults, every bad field fails with one line
   naming the file and the field, ht_material_check rejects NaN and
   out-of-range values of a material built in memory, and ht_generate
   writes the marschner tier for it, first. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairgen.h>

#define DEG (HT_PI / 180)

static const char *const good =
    "{\"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"marschner\","
    " \"diffuse\": {\"color\": [0.1, 0.2, 0.3]},"
    " \"marschner\": {\"absorption\": [0.4, 0.7, 1.2]%s}%s}";

static ht_result parse(const char *extra_marschner, const char *extra_root, ht_material *m, char *err,
                       size_t err_size) {
    char text[2048];
    snprintf(text, sizeof text, good, extra_marschner, extra_root);
    return ht_material_parse(text, "x.json", m, err, err_size);
}

static void shipped_material_has_its_values(void **state) {
    (void)state;
    ht_material m;
    char err[512];
    assert_int_equal(ht_material_load("materials/brown-marschner.json", &m, err, sizeof err), HT_OK);
    assert_int_equal(m.shading.model, HT_MODEL_MARSCHNER);
    assert_true(fabs(m.shading.marschner.absorption[2] - 1.25) < 1e-12);
    assert_true(fabs(m.shading.marschner.shift_r + 7 * DEG) < 1e-12);
    assert_true(fabs(m.shading.marschner.width_r - 7 * DEG) < 1e-12);
    assert_true(fabs(m.shading.marschner.eta - 1.55) < 1e-12);
    assert_int_equal(m.textures[HT_TEX_BASE].origin, HT_TEXTURE_PROCEDURAL);
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_OK);
}

static void absent_fields_take_the_defaults(void **state) {
    (void)state;
    ht_material m;
    char err[512];
    assert_int_equal(parse("", "", &m, err, sizeof err), HT_OK);
    assert_true(fabs(m.shading.marschner.shift_r + 7 * DEG) < 1e-12);
    assert_true(fabs(m.shading.marschner.width_r - 7 * DEG) < 1e-12);
    assert_true(fabs(m.shading.marschner.eta - 1.55) < 1e-12);
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_OK);
    /* the range edges are accepted */
    assert_int_equal(parse(", \"shift\": 20, \"width\": 60, \"eta\": 3", "", &m, err, sizeof err), HT_OK);
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_OK);
    assert_int_equal(parse(", \"shift\": -20, \"width\": 1, \"eta\": 1.1", "", &m, err, sizeof err), HT_OK);
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_OK);
}

typedef struct bad_field {
    const char *marschner, *root; /* appended inside "marschner" / the root */
    const char *line;             /* the start of the one-line error */
} bad_field;

static void every_bad_field_is_named(void **state) {
    (void)state;
    static const bad_field cases[] = {
        { ", \"shift\": 21", "", "x.json: marschner.shift: " },
        { ", \"shift\": -20.5", "", "x.json: marschner.shift: " },
        { ", \"width\": 0.5", "", "x.json: marschner.width: " },
        { ", \"width\": 61", "", "x.json: marschner.width: " },
        { ", \"eta\": 1", "", "x.json: marschner.eta: " },
        { ", \"eta\": 1e400", "", "x.json: marschner.eta: " },
        { ", \"eta\": \"1.5\"", "", "x.json: marschner.eta: " },
        { ", \"absorption\": [1, 2]", "", "x.json: marschner.absorption" },
        { ", \"sigma\": 1", "", "x.json: marschner.sigma: unknown key" },
        { "", ", \"primary\": {\"color\": [1,1,1], \"exponent\": 8}", "x.json: primary: " },
        { "", ", \"secondary\": {\"color\": [1,1,1], \"exponent\": 8}", "x.json: secondary: " },
        { "", ", \"textures\": {\"shift\": {\"procedural\": \"noise\"}}", "x.json: textures.shift: " },
        { "", ", \"textures\": {\"sparkle\": {\"procedural\": \"sparkle\"}}", "x.json: textures.sparkle: " },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        ht_material m;
        char err[512];
        ht_result r = parse(cases[i].marschner, cases[i].root, &m, err, sizeof err);
        if (r == HT_OK || strncmp(err, cases[i].line, strlen(cases[i].line)) != 0 || strchr(err, '\n'))
            fail_msg("case %zu: result %d, error \"%s\", want \"%s...\"", i, (int)r, err, cases[i].line);
    }
    /* absorption out of range, wrap, and a missing "marschner" */
    const char *texts[][2] = {
        { "{\"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"marschner\", \"diffuse\": "
          "{\"color\": [0.1, 0.2, 0.3]}, \"marschner\": {\"absorption\": [0.4, 51, 1]}}",
          "x.json: marschner.absorption[1]: " },
        { "{\"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"marschner\", \"diffuse\": "
          "{\"color\": [0.1, 0.2, 0.3], \"wrap\": 0.2}, \"marschner\": {\"absorption\": [0.4, 1, 1]}}",
          "x.json: diffuse.wrap: " },
        { "{\"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"marschner\", \"diffuse\": "
          "{\"color\": [0.1, 0.2, 0.3]}}",
          "x.json: marschner: " },
        { "{\"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"kajiya-kay\", \"diffuse\": "
          "{\"color\": [0.1, 0.2, 0.3]}, \"primary\": {\"color\": [1,1,1], \"exponent\": 8}, "
          "\"marschner\": {\"absorption\": [0.4, 1, 1]}}",
          "x.json: marschner: " },
    };
    for (size_t i = 0; i < sizeof texts / sizeof *texts; i++) {
        ht_material m;
        char err[512];
        ht_result r = ht_material_parse(texts[i][0], "x.json", &m, err, sizeof err);
        if (r == HT_OK || strncmp(err, texts[i][1], strlen(texts[i][1])) != 0)
            fail_msg("text %zu: result %d, error \"%s\", want \"%s...\"", i, (int)r, err, texts[i][1]);
    }
}

static void check_rejects_nan_and_ranges_in_memory(void **state) {
    (void)state;
    ht_material good_m;
    char err[512];
    assert_int_equal(parse("", "", &good_m, err, sizeof err), HT_OK);
    struct {
        double value;
        const char *line;
    } cases[] = {
        { NAN, "x.json: marschner.absorption[1]: must be a finite number" },
        { -0.001, "x.json: marschner.absorption[1]: must be in [0, 50]" },
    };
    for (size_t i = 0; i < 2; i++) {
        ht_material m = good_m;
        m.shading.marschner.absorption[1] = cases[i].value;
        assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        if (strncmp(err, cases[i].line, strlen(cases[i].line)) != 0) fail_msg("got \"%s\"", err);
    }
    ht_material m = good_m;
    m.shading.marschner.shift_r = NAN;
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "marschner.shift: must be a finite number"));
    m = good_m;
    m.shading.marschner.width_r = 0.5 * DEG;
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "marschner.width: must be in [1, 60]"));
    m = good_m;
    m.shading.marschner.eta = INFINITY;
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "marschner.eta: must be a finite number"));
    m = good_m;
    m.shading.marschner.eta = 1.0;
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "marschner.eta: must be in [1.1, 3]"));
    m = good_m;
    m.shading.diffuse_color[0] = NAN;
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "diffuse.color[0]"));
    m = good_m;
    m.textures[HT_TEX_SHIFT] = (ht_texture_source){ .origin = HT_TEXTURE_PROCEDURAL, .procedural = "noise", .size = 64 };
    assert_int_equal(ht_material_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "textures.shift: model \"marschner\" has no shift texture"));
}

/* The bundle holds the marschner tier first: its shaders (validated by
   glslang as ht_generate writes them) and its two lookup atlases. */
static void generate_writes_the_marschner_tier_first(void **state) {
    (void)state;
    ht_material m;
    char err[512];
    assert_int_equal(parse("", "", &m, err, sizeof err), HT_OK);
    ht_generated g;
    assert_int_equal(ht_generate(&(ht_generate_desc){ .material = &m }, &g, err, sizeof err), HT_OK);
    const char *want[] = { "marschner.vert", "marschner.frag", "marschner-es2.vert", "marschner-es2.frag",
                           "marschner-es3.vert", "marschner-es3.frag",
                           "marschner-prime.vert", "marschner-prime.frag", "marschner-m.png", "marschner-n.png" };
    for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
        const ht_generated_file *f = ht_generated_find(&g, want[i]);
        if (!f) fail_msg("no %s", want[i]);
        assert_int_equal(f->tier, HT_TIER_MARSCHNER);
    }
    const ht_generated_file *lut = ht_generated_find(&g, "marschner-m.png");
    /* two lobes side by side, each value's high byte in the top half of
       the rows and its low byte in the bottom half: 2n x 2n */
    assert_int_equal(lut->image.width, lut->image.height);
    assert_int_equal(lut->image.height % 2, 0);
    /* the lower tiers draw fitted Scheuermann constants (test_marschner_fit) */
    assert_non_null(ht_generated_find(&g, "full.frag"));
    assert_non_null(strstr(g.manifest, "\"model\":\t\"marschner\""));
    assert_non_null(strstr(g.manifest, "\"u_marschner_m\""));
    ht_generated_free(&g);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shipped_material_has_its_values),
        cmocka_unit_test(absent_fields_take_the_defaults),
        cmocka_unit_test(every_bad_field_is_named),
        cmocka_unit_test(check_rejects_nan_and_ranges_in_memory),
        cmocka_unit_test(generate_writes_the_marschner_tier_first),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

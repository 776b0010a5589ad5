/* test_generate.c — the generator as a library (include/hairtier/hairgen.h): the
   in-memory call ht_generate gives exactly the files ht_generate_bundle
   writes, gives the same bytes every time, and refuses a bad material struct
   with one line naming the field. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emit.h"
#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_scratch.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "generate") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* The whole file; *size its length. */
static unsigned char *read_all(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot read %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buf = malloc((size_t)n + 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *size = (size_t)n;
    return buf;
}

static int count_entries(const char *dir) {
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) n++;
    closedir(d);
    return n;
}

static void generate_in_memory(const char *material_path, const char *scene_path, ht_generated *g) {
    char err[1024];
    ht_material m;
    ht_scene scene;
    assert_int_equal(ht_material_load(material_path, &m, err, sizeof err), HT_OK);
    assert_int_equal(ht_scene_load(scene_path, &scene, err, sizeof err), HT_OK);
    ht_result r = ht_generate(&(ht_generate_desc){ .material = &m, .scene = &scene }, g, err, sizeof err);
    if (r != HT_OK) fail_msg("%s", err);
}

/* Every file of the bundle directory equals the in-memory file of that
   name, byte for byte (images: the PNG the build made, which decodes to the
   image's texels), and the
   directory holds nothing else. The input hash differs by design (files'
   bytes vs values), so the manifest is compared with it masked. */
static void check_same_as_bundle(const char *material_path, const char *scene_path) {
    char err[1024], dir[256];
    snprintf(dir, sizeof dir, "%s/bundle", work);
    assert_int_equal(ht_generate_bundle(material_path, scene_path, dir, NULL, err, sizeof err), HT_OK);

    ht_generated g;
    generate_in_memory(material_path, scene_path, &g);
    assert_true(g.file_count > 3);
    assert_int_equal(count_entries(dir), g.file_count);
    assert_string_equal(g.files[g.file_count - 1].name, "manifest.json");
    assert_ptr_equal(g.manifest, g.files[g.file_count - 1].text);

    for (int i = 0; i < g.file_count; i++) {
        const ht_generated_file *f = &g.files[i];
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, f->name);
        size_t size;
        unsigned char *bytes = read_all(path, &size);
        if (f->text) {
            assert_null(f->image.pixels);
            char *expect = strdup(f->text);
            if (f == &g.files[g.file_count - 1]) {
                /* "input_hash": "fnv1a64:<16 hex>" differs; the rest is identical. */
                char *a = strstr(expect, "fnv1a64:"), *b = strstr((char *)bytes, "fnv1a64:");
                assert_non_null(a);
                assert_non_null(b);
                memset(a, 'x', 24);
                memset(b, 'x', 24);
            }
            assert_int_equal(size, strlen(expect));
            assert_memory_equal(bytes, expect, size);
            free(expect);
        } else {
            /* The file is the PNG made with the tiers, and it decodes to
               exactly the image's texels. */
            assert_non_null(f->image.pixels);
            assert_true(f->depth >= 1);
            assert_non_null(f->png);
            assert_int_equal(size, f->png_size);
            assert_memory_equal(bytes, f->png, size);
            ht_image decoded;
            assert_int_equal(ht_image_decode_png(f->name, f->png, f->png_size, &decoded, err, sizeof err), HT_OK);
            assert_int_equal(decoded.width, f->image.width);
            assert_int_equal(decoded.height, f->image.height);
            assert_int_equal(decoded.channels, f->image.channels);
            assert_memory_equal(decoded.pixels, f->image.pixels,
                                (size_t)f->image.width * (size_t)f->image.height * (size_t)f->image.channels);
            ht_image_free(&decoded);
        }
        free(bytes);
    }
    ht_generated_free(&g);
}

static void test_in_memory_output_equals_the_bundle_files_furball(void **state) {
    (void)state;
    check_same_as_bundle("materials/dark-brown.json", "scenes/furball.json");
}

static void test_in_memory_output_equals_the_bundle_files_kajiya_kay_patches(void **state) {
    (void)state;
    check_same_as_bundle("materials/kajiya-kay.json", "scenes/patches.json");
}

static void test_bundle_input_hash_is_the_one_passed(void **state) {
    (void)state;
    char err[1024];
    ht_material m;
    assert_int_equal(ht_material_load("materials/blond.json", &m, err, sizeof err), HT_OK);
    ht_generated g;
    assert_int_equal(ht_generate(&(ht_generate_desc){ .material = &m, .input_hash = 0x0123456789abcdefull },
                                 &g, err, sizeof err), HT_OK);
    assert_true(g.input_hash == 0x0123456789abcdefull);
    assert_non_null(strstr(g.manifest, "\"fnv1a64:0123456789abcdef\""));
    ht_generated_free(&g);
}

static void test_two_calls_give_identical_output(void **state) {
    (void)state;
    ht_generated a, b;
    generate_in_memory("materials/blond.json", "scenes/patches.json", &a);
    generate_in_memory("materials/blond.json", "scenes/patches.json", &b);
    assert_int_equal(a.file_count, b.file_count);
    assert_true(a.input_hash == b.input_hash);
    assert_string_equal(a.summary, b.summary);
    for (int i = 0; i < a.file_count; i++) {
        const ht_generated_file *x = &a.files[i], *y = &b.files[i];
        assert_string_equal(x->name, y->name);
        assert_string_equal(x->role, y->role);
        assert_int_equal(x->tier, y->tier);
        assert_int_equal(x->depth, y->depth);
        if (x->text) {
            assert_non_null(y->text);
            assert_string_equal(x->text, y->text);
        } else {
            assert_int_equal(x->image.width, y->image.width);
            assert_int_equal(x->image.height, y->image.height);
            assert_int_equal(x->image.channels, y->image.channels);
            assert_memory_equal(x->image.pixels, y->image.pixels,
                                (size_t)x->image.width * x->image.height * x->image.channels);
            assert_int_equal(x->png_size, y->png_size);
            assert_memory_equal(x->png, y->png, x->png_size);
        }
    }
    ht_generated_free(&a);
    ht_generated_free(&b);
}

/* The tier's whole output for plan (texts, requirements, lists). */
static void assert_same_output(const ht_tier_output *a, const ht_tier_output *b) {
    assert_int_equal(a->text_count, b->text_count);
    for (int i = 0; i < a->text_count; i++) {
        assert_string_equal(a->texts[i].file, b->texts[i].file);
        assert_string_equal(a->texts[i].text, b->texts[i].text);
    }
    assert_int_equal(a->image_count, b->image_count);
    assert_memory_equal(&a->requires, &b->requires, sizeof a->requires);
    assert_int_equal(a->feature_count, b->feature_count);
    assert_memory_equal(a->features, b->features, sizeof a->features);
    assert_int_equal(a->dropped_count, b->dropped_count);
    assert_memory_equal(a->dropped, b->dropped, sizeof a->dropped);
    assert_int_equal(a->sampler_count, b->sampler_count);
    assert_memory_equal(a->samplers, b->samplers, sizeof a->samplers);
}

/* build.c starts the full and Marschner tiers before the textures exist,
   with the plan's default measurements: so those emitters must not read
   the texture measurements (sparkle mean, albedo maximum). */
static void test_glsl_tiers_do_not_read_texture_measurements(void **state) {
    (void)state;
    static const struct { const char *material; ht_result (*emit)(const ht_plan *, ht_tier_output *, char *, size_t); }
        cases[] = { { "materials/dark-brown.json", ht_emit_full }, { "materials/brown-marschner.json", ht_emit_marschner } };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char err[1024];
        ht_material m;
        ht_scene scene;
        assert_int_equal(ht_material_load(cases[c].material, &m, err, sizeof err), HT_OK);
        assert_int_equal(ht_scene_load("scenes/furball.json", &scene, err, sizeof err), HT_OK);
        ht_plan plan, measured;
        ht_plan_make(&m, &scene, &plan);
        /* A wider fibre lobe than brown-marschner's 7 degrees: a 128² M
           table, not 512², baked twice here (what is checked is which plan
           fields the emitter reads, not the fibre). */
        plan.shading.marschner.width_r = 30 * HT_PI / 180;
        measured = plan;
        measured.sparkle_mean = 0.37;
        measured.albedo_max = 0.42;
        ht_tier_output a, b;
        assert_int_equal(cases[c].emit(&plan, &a, err, sizeof err), HT_OK);
        assert_int_equal(cases[c].emit(&measured, &b, err, sizeof err), HT_OK);
        assert_same_output(&a, &b);
        ht_tier_output_free(&a);
        ht_tier_output_free(&b);
    }
}

static void test_every_tier_has_its_texts_in_memory(void **state) {
    (void)state;
    ht_generated g;
    generate_in_memory("materials/dark-brown.json", "scenes/furball.json", &g);
    bool full_fragment = false, vertex_vertex = false, fixed_program = false, fixed_lut = false;
    for (int i = 0; i < g.file_count; i++) {
        const ht_generated_file *f = &g.files[i];
        full_fragment |= f->tier == HT_TIER_FULL && strcmp(f->role, "fragment") == 0 && f->text;
        vertex_vertex |= f->tier == HT_TIER_VERTEX && strcmp(f->role, "vertex") == 0 && f->text;
        fixed_program |= f->tier == HT_TIER_FIXED && strcmp(f->role, "program") == 0 && f->text;
        fixed_lut |= f->tier == HT_TIER_FIXED && f->image.pixels != NULL;
    }
    assert_true(full_fragment && vertex_vertex && fixed_program && fixed_lut);
    assert_non_null(ht_generated_find(&g, "manifest.json"));
    assert_null(ht_generated_find(&g, "no-such-file"));
    ht_generated_free(&g);
    ht_generated_free(&g); /* zeroed: fine twice */
}

/* err of a refused material; asserts one line and nothing generated. */
static void expect_refused(const ht_material *m, const char *expect) {
    char err[1024] = "";
    ht_generated g;
    assert_int_not_equal(ht_generate(&(ht_generate_desc){ .material = m }, &g, err, sizeof err), HT_OK);
    assert_int_equal(g.file_count, 0);
    assert_null(g.manifest);
    assert_null(strchr(err, '\n'));
    if (strstr(err, expect) == NULL) fail_msg("expected \"%s\" in \"%s\"", expect, err);
}

static void test_bad_material_struct_is_refused_naming_the_field(void **state) {
    (void)state;
    char err[1024];
    ht_material good;
    assert_int_equal(ht_material_load("materials/dark-brown.json", &good, err, sizeof err), HT_OK);
    assert_int_equal(ht_material_check(&good, err, sizeof err), HT_OK);

    ht_material m = good;
    m.shading.primary.exponent = NAN;
    expect_refused(&m, "materials/dark-brown.json: primary.exponent: must be a finite number");

    m = good;
    m.shading.secondary.exponent = 20000;
    expect_refused(&m, "materials/dark-brown.json: secondary.exponent: must be in [0, 10000], got 20000");

    m = good;
    m.file[0] = '\0';
    m.shading.diffuse_color[1] = -0.5;
    expect_refused(&m, "<material>: diffuse.color[1]: must be in [0, 1], got -0.5");

    m = good;
    m.shading.wrap = INFINITY;
    expect_refused(&m, "diffuse.wrap: must be a finite number");

    /* the range every tier program holds (ht_limits.h), not any finite shift */
    m = good;
    m.shading.secondary.shift = 150;
    expect_refused(&m, "materials/dark-brown.json: secondary.shift: must be in [-100, 100], got 150");

    m = good;
    m.opaque_cutoff = 1.5;
    expect_refused(&m, "alpha.opaque_cutoff: must be 0 (default) or in (0, 1], got 1.5");

    m = good;
    m.textures[HT_TEX_BASE].origin = HT_TEXTURE_PROCEDURAL;
    snprintf(m.textures[HT_TEX_BASE].procedural, sizeof m.textures[0].procedural, "stretched-noise");
    m.textures[HT_TEX_BASE].size = 100;
    expect_refused(&m, "textures.base: size must be a power of two");

    m = good;
    m.name[0] = '\0';
    expect_refused(&m, "name: empty");

    char text[64] = "";
    ht_generated g;
    assert_int_equal(ht_generate(&(ht_generate_desc){ 0 }, &g, text, sizeof text), HT_ERR_INVALID_ARGUMENT);
    assert_string_equal(text, "ht_generate: material: required");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_in_memory_output_equals_the_bundle_files_furball),
        cmocka_unit_test(test_in_memory_output_equals_the_bundle_files_kajiya_kay_patches),
        cmocka_unit_test(test_bundle_input_hash_is_the_one_passed),
        cmocka_unit_test(test_two_calls_give_identical_output),
        cmocka_unit_test(test_glsl_tiers_do_not_read_texture_measurements),
        cmocka_unit_test(test_every_tier_has_its_texts_in_memory),
        cmocka_unit_test(test_bad_material_struct_is_refused_naming_the_field),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_texture.c — procedural textures (determinism, value ranges, the
   statistics the renderer relies on), file textures reduced to their slot,
   and packing into the albedo and detail images. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "emit.h"
#include "hairgen_internal.h"
#include "rng.h"
#include "support_scratch.h"

static char dir[64];

static int make_dir(void **state) {
    (void)state;
    return ht_test_scratch_create(dir, sizeof dir, "texture") ? 0 : -1;
}

static int remove_dir(void **state) {
    (void)state;
    return ht_test_scratch_remove(dir);
}

static ht_texture_source procedural(const char *name, int size, uint32_t seed) {
    ht_texture_source src = { .origin = HT_TEXTURE_PROCEDURAL, .size = size, .seed = seed };
    snprintf(src.procedural, sizeof src.procedural, "%s", name);
    return src;
}

static ht_texture_source file_source(const char *name) {
    ht_texture_source src = { .origin = HT_TEXTURE_FILE };
    snprintf(src.path, sizeof src.path, "%s/%s", dir, name);
    return src;
}

static ht_image make(const ht_texture_source *src, ht_texture_slot slot) {
    ht_image img;
    char err[256] = "";
    ht_result r = ht_texture_make(src, slot, &img, err, sizeof err);
    if (r != HT_OK) fail_msg("ht_texture_make: %s", err);
    return img;
}

static ht_image make_procedural(const char *name, ht_texture_slot slot, int size, uint32_t seed) {
    ht_texture_source src = procedural(name, size, seed);
    return make(&src, slot);
}

static size_t texel_count(const ht_image *img) { return (size_t)img->width * img->height; }

static int texel(const ht_image *img, int x, int y, int c) {
    return img->pixels[((size_t)y * img->width + x) * img->channels + c];
}

/* Mean |difference| between texels one step apart along u (x) or v (y),
   wrapping around: the textures tile. */
static double mean_step(const ht_image *img, int dx, int dy) {
    double sum = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            sum += abs(texel(img, x, y, 0) -
                       texel(img, (x + dx) % img->width, (y + dy) % img->height, 0));
    return sum / (double)texel_count(img);
}

static void write_png(const char *name, int width, int height, int channels,
                      const uint8_t *pixels) {
    char path[256], err[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    ht_image img = { width, height, channels, (uint8_t *)pixels };
    assert_int_equal(ht_image_write_png(path, &img, err, sizeof err), HT_OK);
}

/* ---- procedural ---- */

static const char *const generator_names[] = { "stretched-noise", "strand-alpha", "noise", "sparkle" };
static const ht_texture_slot generator_slots[] = { HT_TEX_BASE, HT_TEX_ALPHA, HT_TEX_SHIFT, HT_TEX_SPARKLE };

static void test_procedural_is_a_function_of_size_and_seed(void **state) {
    (void)state;
    for (int g = 0; g < 4; g++) {
        ht_image a = make_procedural(generator_names[g], generator_slots[g], 64, 42);
        ht_image b = make_procedural(generator_names[g], generator_slots[g], 64, 42);
        ht_image c = make_procedural(generator_names[g], generator_slots[g], 64, 43);
        assert_int_equal(a.width, 64);
        assert_int_equal(a.height, 64);
        assert_int_equal(a.channels, generator_slots[g] == HT_TEX_BASE ? 3 : 1);
        size_t bytes = texel_count(&a) * a.channels;
        assert_memory_equal(a.pixels, b.pixels, bytes);
        assert_memory_not_equal(a.pixels, c.pixels, bytes);
        ht_image_free(&a);
        ht_image_free(&b);
        ht_image_free(&c);
    }
}

static void test_stretched_noise_is_grey_within_its_range(void **state) {
    (void)state;
    ht_image img = make_procedural("stretched-noise", HT_TEX_BASE, 256, 1);
    int lo = 255, hi = 0;
    for (size_t i = 0; i < texel_count(&img); i++) {
        const uint8_t *px = img.pixels + 3 * i;
        assert_int_equal(px[0], px[1]);
        assert_int_equal(px[0], px[2]);
        if (px[0] < lo) lo = px[0];
        if (px[0] > hi) hi = px[0];
    }
    assert_true(lo >= 140);          /* 0.55 */
    assert_true(hi - lo >= 60);      /* a visible variation, not a flat grey */
    ht_image_free(&img);
}

static void test_stretched_noise_varies_across_strands_not_along_them(void **state) {
    (void)state;
    for (int size = 16; size <= 1024; size *= 4) {
        ht_image img = make_procedural("stretched-noise", HT_TEX_BASE, size, 5);
        double across = mean_step(&img, 1, 0), along = mean_step(&img, 0, 1);
        assert_true(across > 2.0);
        assert_true(along * 5 < across);
        ht_image_free(&img);
    }
}

static void test_strand_alpha_has_opaque_translucent_and_empty_texels(void **state) {
    (void)state;
    const int sizes[] = { 64, 256, 2048 };
    for (int s = 0; s < 3; s++) {
        ht_image img = make_procedural("strand-alpha", HT_TEX_ALPHA, sizes[s], 3);
        size_t opaque = 0, empty = 0, n = texel_count(&img);
        for (size_t i = 0; i < n; i++) {
            if (img.pixels[i] >= 250) opaque++; /* alpha >= 0.98 */
            if (img.pixels[i] == 0) empty++;
        }
        size_t translucent = n - opaque - empty;
        assert_true(opaque * 10 >= n);
        assert_true(translucent * 10 >= n);
        assert_true(empty * 10 >= n);
        ht_image_free(&img);
    }
}

static void test_strand_alpha_is_opaque_at_the_root_and_fades_to_the_tip(void **state) {
    (void)state;
    ht_image img = make_procedural("strand-alpha", HT_TEX_ALPHA, 256, 8);
    int root_opaque = 0, tip_opaque = 0, tip_empty = 0;
    for (int x = 0; x < img.width; x++) {
        root_opaque += texel(&img, x, 0, 0) >= 250;
        tip_opaque += texel(&img, x, img.height - 1, 0) >= 250;
        tip_empty += texel(&img, x, img.height - 1, 0) == 0;
        /* never more coverage further from the root */
        for (int y = 1; y < img.height; y++)
            assert_true(texel(&img, x, y, 0) <= texel(&img, x, y - 1, 0));
    }
    assert_true(root_opaque * 4 >= img.width);
    assert_int_equal(tip_opaque, 0);
    assert_true(tip_empty * 2 >= img.width);
    ht_image_free(&img);
}

static void test_shift_noise_centres_on_half(void **state) {
    (void)state;
    ht_image img = make_procedural("noise", HT_TEX_SHIFT, 256, 11);
    double sum = 0;
    int lo = 255, hi = 0;
    for (size_t i = 0; i < texel_count(&img); i++) {
        int v = img.pixels[i];
        sum += v;
        if (v < lo) lo = v;
        if (v > hi) hi = v;
    }
    double mean = sum / (double)texel_count(&img) / 255.0;
    assert_true(mean > 0.47 && mean < 0.53);
    assert_true(lo >= 96 && hi <= 159);  /* within [0.38, 0.62] */
    assert_true(lo <= 107 && hi >= 148); /* and reaching out to 0.42 and 0.58 */
    assert_true(mean_step(&img, 0, 1) * 5 < mean_step(&img, 1, 0));
    ht_image_free(&img);
}

static void test_sparkle_is_a_mask_of_glints_along_v_at_every_size(void **state) {
    (void)state;
    const int sizes[] = { 64, 256, 2048 };
    for (int k = 0; k < 3; k++) {
        ht_image img = make_procedural("sparkle", HT_TEX_SPARKLE, sizes[k], 2);
        size_t lit = 0, lit_below = 0, lit_beside = 0, bright = 0, n = texel_count(&img);
        for (int y = 0; y < img.height; y++)
            for (int x = 0; x < img.width; x++) {
                if (!texel(&img, x, y, 0)) continue;
                lit++;
                bright += texel(&img, x, y, 0) >= 200;
                lit_below += texel(&img, x, (y + 1) % img.height, 0) != 0;
                lit_beside += texel(&img, (x + 1) % img.width, y, 0) != 0;
            }
        assert_true(lit * 4 <= n);        /* mostly 0 */
        assert_true(lit * 10 >= n);       /* but enough glints to show a band */
        assert_true(bright * 20 >= lit);  /* some of them bright */
        /* Along v a glint goes on; across, a neighbour is lit about as often
           as any texel is (glints are 1 texel wide, columns independent). */
        assert_true(lit_below * 10 >= lit * 8);
        assert_true((double)lit_beside / (double)lit < 2.0 * (double)lit / (double)n);
        ht_image_free(&img);
    }
}

static void test_any_generator_fills_any_slot(void **state) {
    (void)state;
    ht_image base = make_procedural("noise", HT_TEX_BASE, 16, 1);
    ht_image alpha = make_procedural("stretched-noise", HT_TEX_ALPHA, 16, 1);
    assert_int_equal(base.channels, 3);
    assert_int_equal(alpha.channels, 1);
    for (size_t i = 0; i < texel_count(&base); i++) {
        assert_int_equal(base.pixels[3 * i], base.pixels[3 * i + 1]);
        assert_int_equal(base.pixels[3 * i], base.pixels[3 * i + 2]);
    }
    ht_image_free(&base);
    ht_image_free(&alpha);
}

static void assert_make_fails(const ht_texture_source *src, ht_texture_slot slot,
                              ht_result expected, const char *mentioned) {
    ht_image img = { .width = 3 };
    char err[256] = "";
    assert_int_equal(ht_texture_make(src, slot, &img, err, sizeof err), expected);
    assert_null(img.pixels);
    assert_non_null(strstr(err, mentioned));
}

static void test_procedural_rejects_unknown_names_and_bad_sizes(void **state) {
    (void)state;
    ht_texture_source src = procedural("perlin", 64, 1);
    assert_make_fails(&src, HT_TEX_BASE, HT_ERR_PARSE, "perlin");
    const int bad_sizes[] = { 0, 8, 100, 4096, -16 };
    for (int i = 0; i < 5; i++) {
        src = procedural("noise", bad_sizes[i], 1);
        assert_make_fails(&src, HT_TEX_SHIFT, HT_ERR_PARSE, "size");
    }
    src = (ht_texture_source){ .origin = HT_TEXTURE_ABSENT };
    assert_make_fails(&src, HT_TEX_SPARKLE, HT_ERR_INVALID_ARGUMENT, "sparkle");
}

/* ---- file textures ---- */

static void test_file_rgba_reduces_to_each_slot(void **state) {
    (void)state;
    /* 3 x 2 RGBA, not square, not a power of two */
    const uint8_t px[6 * 4] = { 255, 0, 0, 10,    0, 255, 0, 20,   0, 0, 255, 30,
                                255, 255, 255, 40, 0, 0, 0, 50,    90, 60, 30, 60 };
    write_png("rgba.png", 3, 2, 4, px);
    ht_texture_source src = file_source("rgba.png");
    ht_image base = make(&src, HT_TEX_BASE), alpha = make(&src, HT_TEX_ALPHA);
    ht_image shift = make(&src, HT_TEX_SHIFT);
    assert_int_equal(base.width, 3);
    assert_int_equal(base.height, 2);
    for (int i = 0; i < 6; i++) {
        assert_memory_equal(base.pixels + 3 * i, px + 4 * i, 3);
        assert_int_equal(alpha.pixels[i], px[4 * i + 3]);
    }
    /* luminance: white stays white, black black, red darker than green */
    assert_int_equal(shift.pixels[3], 255);
    assert_int_equal(shift.pixels[4], 0);
    assert_true(shift.pixels[0] < shift.pixels[1]);
    assert_true(shift.pixels[2] < shift.pixels[0]);
    ht_image_free(&base);
    ht_image_free(&alpha);
    ht_image_free(&shift);
}

static void test_file_grey_expands_for_base_and_is_alpha_without_alpha(void **state) {
    (void)state;
    const uint8_t grey[4] = { 0, 70, 140, 255 };
    write_png("grey.png", 4, 1, 1, grey);
    ht_texture_source src = file_source("grey.png");
    ht_image base = make(&src, HT_TEX_BASE), alpha = make(&src, HT_TEX_ALPHA);
    ht_image sparkle = make(&src, HT_TEX_SPARKLE);
    for (int i = 0; i < 4; i++) {
        for (int c = 0; c < 3; c++) assert_int_equal(base.pixels[3 * i + c], grey[i]);
        assert_int_equal(alpha.pixels[i], grey[i]);
        assert_int_equal(sparkle.pixels[i], grey[i]);
    }
    ht_image_free(&base);
    ht_image_free(&alpha);
    ht_image_free(&sparkle);

    const uint8_t grey_alpha[4] = { 100, 7, 200, 9 };
    write_png("grey-alpha.png", 2, 1, 2, grey_alpha);
    src = file_source("grey-alpha.png");
    alpha = make(&src, HT_TEX_ALPHA);
    ht_image shift = make(&src, HT_TEX_SHIFT);
    assert_int_equal(alpha.pixels[0], 7);
    assert_int_equal(alpha.pixels[1], 9);
    assert_int_equal(shift.pixels[0], 100);
    assert_int_equal(shift.pixels[1], 200);
    ht_image_free(&alpha);
    ht_image_free(&shift);
}

static void test_file_missing_or_corrupt_names_the_file(void **state) {
    (void)state;
    ht_texture_source src = file_source("absent.png");
    assert_make_fails(&src, HT_TEX_BASE, HT_ERR_IO, src.path);
    char path[256];
    snprintf(path, sizeof path, "%s/corrupt.png", dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("\x89PNG\r\n\x1a\n garbage after a good signature", f);
    fclose(f);
    src = file_source("corrupt.png");
    assert_make_fails(&src, HT_TEX_ALPHA, HT_ERR_IO, src.path);
}

/* ---- packing ---- */

typedef struct packed { ht_image albedo, detail; } packed;

static packed pack(const ht_material *m, const ht_plan *plan) {
    packed p;
    char err[256] = "";
    ht_result r = ht_textures_pack(m, plan, &p.albedo, &p.detail, err, sizeof err);
    if (r != HT_OK) fail_msg("ht_textures_pack: %s", err);
    return p;
}

static void free_packed(packed *p) {
    ht_image_free(&p->albedo);
    ht_image_free(&p->detail);
}

static ht_material procedural_material(int size) {
    ht_material m = { 0 };
    for (int s = 0; s < HT_TEX_COUNT; s++)
        m.textures[s] = procedural(generator_names[s], size, 100 + (uint32_t)s);
    return m;
}

static void test_pack_copies_every_texel_when_sizes_agree(void **state) {
    (void)state;
    ht_material m = procedural_material(64);
    ht_plan plan = { .base = true, .alpha = true, .shift = true, .sparkle = true };
    packed p = pack(&m, &plan);
    ht_image base = make(&m.textures[HT_TEX_BASE], HT_TEX_BASE);
    ht_image alpha = make(&m.textures[HT_TEX_ALPHA], HT_TEX_ALPHA);
    ht_image shift = make(&m.textures[HT_TEX_SHIFT], HT_TEX_SHIFT);
    ht_image sparkle = make(&m.textures[HT_TEX_SPARKLE], HT_TEX_SPARKLE);
    assert_int_equal(p.albedo.width, 64);
    assert_int_equal(p.albedo.channels, 4);
    assert_int_equal(p.detail.height, 64);
    assert_int_equal(p.detail.channels, 4);
    for (size_t i = 0; i < texel_count(&base); i++) {
        assert_memory_equal(p.albedo.pixels + 4 * i, base.pixels + 3 * i, 3);
        assert_int_equal(p.albedo.pixels[4 * i + 3], alpha.pixels[i]);
        assert_int_equal(p.detail.pixels[4 * i + 0], shift.pixels[i]);
        assert_int_equal(p.detail.pixels[4 * i + 1], sparkle.pixels[i]);
        assert_int_equal(p.detail.pixels[4 * i + 2], 0);
        assert_int_equal(p.detail.pixels[4 * i + 3], 255);
    }
    free_packed(&p);
    ht_image_free(&base);
    ht_image_free(&alpha);
    ht_image_free(&shift);
    ht_image_free(&sparkle);
}

static void test_pack_fills_what_the_plan_leaves_out(void **state) {
    (void)state;
    ht_material m = procedural_material(16);

    packed p = pack(&m, &(ht_plan){ .base = true, .sparkle = true });
    for (size_t i = 0; i < texel_count(&p.albedo); i++) {
        assert_int_equal(p.albedo.pixels[4 * i + 3], 255);  /* no alpha: opaque */
        assert_int_equal(p.detail.pixels[4 * i + 0], 128);  /* no shift: 0.5 */
    }
    free_packed(&p);

    p = pack(&m, &(ht_plan){ .alpha = true, .shift = true });
    for (size_t i = 0; i < texel_count(&p.albedo); i++) {
        for (int c = 0; c < 3; c++) assert_int_equal(p.albedo.pixels[4 * i + c], 255);
        assert_int_equal(p.detail.pixels[4 * i + 1], 255);  /* no sparkle mask: 1 */
    }
    free_packed(&p);

    p = pack(&m, &(ht_plan){ .base = true });
    assert_non_null(p.albedo.pixels);
    assert_null(p.detail.pixels);
    assert_int_equal(p.detail.width, 0);
    free_packed(&p);

    p = pack(&m, &(ht_plan){ .ao = true, .secondary = true });
    assert_null(p.albedo.pixels);
    assert_null(p.detail.pixels);
}

static void test_pack_resamples_the_smaller_source_to_the_larger_size(void **state) {
    (void)state;
    /* base 8 x 2, alpha 2 x 8: the albedo is 8 x 8, each source stretched 4 x */
    uint8_t base_px[8 * 2 * 3], alpha_px[2 * 8];
    for (int i = 0; i < 8 * 2 * 3; i++) base_px[i] = (uint8_t)(i * 5);
    for (int i = 0; i < 2 * 8; i++) alpha_px[i] = (uint8_t)(250 - i * 9);
    write_png("base-wide.png", 8, 2, 3, base_px);
    write_png("alpha-tall.png", 2, 8, 1, alpha_px);
    ht_material m = { 0 };
    m.textures[HT_TEX_BASE] = file_source("base-wide.png");
    m.textures[HT_TEX_ALPHA] = file_source("alpha-tall.png");
    packed p = pack(&m, &(ht_plan){ .base = true, .alpha = true });
    assert_int_equal(p.albedo.width, 8);
    assert_int_equal(p.albedo.height, 8);
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++) {
            const uint8_t *px = p.albedo.pixels + 4 * (y * 8 + x);
            assert_memory_equal(px, base_px + 3 * ((y / 4) * 8 + x), 3);
            assert_int_equal(px[3], alpha_px[y * 2 + x / 4]);
        }
    free_packed(&p);
}

static void test_pack_fails_whole_when_one_texture_fails(void **state) {
    (void)state;
    ht_material m = procedural_material(16);
    m.textures[HT_TEX_SPARKLE] = file_source("no-sparkle-here.png");
    ht_image albedo, detail;
    char err[256] = "";
    ht_plan plan = { .base = true, .alpha = true, .shift = true, .sparkle = true };
    assert_int_equal(ht_textures_pack(&m, &plan, &albedo, &detail, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "no-sparkle-here.png"));
    assert_null(albedo.pixels);
    assert_null(detail.pixels);

    /* the plan models a texture the material does not have */
    m = procedural_material(16);
    m.textures[HT_TEX_ALPHA] = (ht_texture_source){ .origin = HT_TEXTURE_ABSENT };
    assert_int_equal(ht_textures_pack(&m, &plan, &albedo, &detail, err, sizeof err),
                     HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "alpha"));
    assert_null(albedo.pixels);
    assert_null(detail.pixels);
}

/* The bytes of every generator at the smallest, a middle and the largest
   size are those the first generator wrote (FNV-1a 64 of the texels,
   recorded from commit cad3a2f, before the row-at-a-time noise): a change
   to how a texture is computed must not change a texel. */
static void test_procedural_bytes_are_unchanged_since_the_first_generator(void **state) {
    (void)state;
    static const struct { const char *name; int size; uint64_t hash; } golden[] = {
        { "stretched-noise", 16, 0x5ed1f7fe8cee6525ull }, { "stretched-noise", 256, 0x58d9c90ace887ae3ull },
        { "stretched-noise", 2048, 0x3c5d203a579a1627ull }, { "strand-alpha", 16, 0x18fe283df642a471ull },
        { "strand-alpha", 256, 0x43d7d7cc6cef82ebull },     { "strand-alpha", 2048, 0xdb6233b435d9d2f5ull },
        { "noise", 16, 0x6fc4d27302629fb9ull },             { "noise", 256, 0x072c68d717390c63ull },
        { "noise", 2048, 0x7b722f92d6def35bull },           { "sparkle", 16, 0xfe2b4efb839477d1ull },
        { "sparkle", 256, 0x0805bfe4664191b9ull },          { "sparkle", 2048, 0xd348efc9b3169ad5ull },
    };
    for (size_t k = 0; k < sizeof golden / sizeof golden[0]; k++) {
        ht_texture_source src = { .origin = HT_TEXTURE_PROCEDURAL, .size = golden[k].size, .seed = 1 };
        snprintf(src.procedural, sizeof src.procedural, "%s", golden[k].name);
        bool base = strcmp(golden[k].name, "stretched-noise") == 0;
        ht_image img;
        char err[256];
        assert_int_equal(ht_texture_make(&src, base ? HT_TEX_BASE : HT_TEX_ALPHA, &img, err, sizeof err), HT_OK);
        uint64_t h = 0xcbf29ce484222325ull;
        size_t n = (size_t)img.width * img.height * img.channels;
        for (size_t i = 0; i < n; i++) h = (h ^ img.pixels[i]) * 0x100000001b3ull;
        ht_image_free(&img);
        if (h != golden[k].hash)
            fail_msg("%s at %d: texel hash %016llx, was %016llx", golden[k].name, golden[k].size,
                     (unsigned long long)h, (unsigned long long)golden[k].hash);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_procedural_is_a_function_of_size_and_seed),
        cmocka_unit_test(test_procedural_bytes_are_unchanged_since_the_first_generator),
        cmocka_unit_test(test_stretched_noise_is_grey_within_its_range),
        cmocka_unit_test(test_stretched_noise_varies_across_strands_not_along_them),
        cmocka_unit_test(test_strand_alpha_has_opaque_translucent_and_empty_texels),
        cmocka_unit_test(test_strand_alpha_is_opaque_at_the_root_and_fades_to_the_tip),
        cmocka_unit_test(test_shift_noise_centres_on_half),
        cmocka_unit_test(test_sparkle_is_a_mask_of_glints_along_v_at_every_size),
        cmocka_unit_test(test_any_generator_fills_any_slot),
        cmocka_unit_test(test_procedural_rejects_unknown_names_and_bad_sizes),
        cmocka_unit_test(test_file_rgba_reduces_to_each_slot),
        cmocka_unit_test(test_file_grey_expands_for_base_and_is_alpha_without_alpha),
        cmocka_unit_test(test_file_missing_or_corrupt_names_the_file),
        cmocka_unit_test(test_pack_copies_every_texel_when_sizes_agree),
        cmocka_unit_test(test_pack_fills_what_the_plan_leaves_out),
        cmocka_unit_test(test_pack_resamples_the_smaller_source_to_the_larger_size),
        cmocka_unit_test(test_pack_fails_whole_when_one_texture_fails),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}

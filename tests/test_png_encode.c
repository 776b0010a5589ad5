/* test_png_encode.c — the generator's PNG encoder (shadergen/png_encode.c):
   what it writes decodes, through the runtime's libpng reader, to exactly
   the texels it was given and to the texels libpng's own writer keeps
   (ht_image_encode_png), for every channel count, for thin, odd and large
   images and for noise that does not compress; the same image gives the
   same bytes; an image no PNG can hold is refused before anything is read. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "hairgen_internal.h"
#include <hairtier/image.h>
#include "rng.h"

static size_t texel_bytes(const ht_image *img) {
    return (size_t)img->width * (size_t)img->height * (size_t)img->channels;
}

/* A w x h image of c channels: smooth ramps (what LUTs and packed
   textures look like), or random bytes. */
static ht_image make_image(int w, int h, int c, bool noise, uint64_t seed) {
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, w, h, c), HT_OK);
    ht_rng r = ht_rng_seed(seed);
    for (size_t i = 0; i < texel_bytes(&img); i++) {
        size_t x = i / (size_t)c % (size_t)w, y = i / ((size_t)c * (size_t)w);
        img.pixels[i] = noise ? (uint8_t)(ht_rng_next(&r) >> 56) : (uint8_t)(x * 7 + y * 3 + i % (size_t)c * 50);
    }
    return img;
}

static void decode(const unsigned char *png, size_t size, ht_image *out) {
    char err[256];
    ht_result r = ht_image_decode_png("test.png", png, size, out, err, sizeof err);
    if (r != HT_OK) fail_msg("%s", err);
}

/* Encodes img, decodes it back, and checks the texels against img and
   against what libpng's writer's file decodes to. */
static void check_round_trip(const ht_image *img) {
    unsigned char *png = NULL, *png_again = NULL, *reference = NULL;
    size_t size = 0, size_again = 0, reference_size = 0;
    assert_int_equal(ht_png_encode(img, &png, &size), HT_OK);
    assert_int_equal(ht_png_encode(img, &png_again, &size_again), HT_OK);
    assert_int_equal(size, size_again);
    assert_memory_equal(png, png_again, size);

    ht_image back, via_libpng;
    decode(png, size, &back);
    assert_int_equal(back.width, img->width);
    assert_int_equal(back.height, img->height);
    assert_int_equal(back.channels, img->channels);
    assert_memory_equal(back.pixels, img->pixels, texel_bytes(img));

    char err[256];
    assert_int_equal(ht_image_encode_png(img, &reference, &reference_size, err, sizeof err), HT_OK);
    decode(reference, reference_size, &via_libpng);
    assert_int_equal(via_libpng.channels, back.channels);
    assert_memory_equal(via_libpng.pixels, back.pixels, texel_bytes(img));

    ht_image_free(&back);
    ht_image_free(&via_libpng);
    free(png);
    free(png_again);
    free(reference);
}

static void test_every_channel_count_and_shape_decodes_to_the_same_texels(void **state) {
    (void)state;
    static const int sizes[][2] = { { 1, 1 }, { 3, 5 }, { 17, 1 }, { 1, 17 }, { 256, 256 }, { 255, 3 } };
    for (int c = 1; c <= 4; c++)
        for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
            for (int noise = 0; noise < 2; noise++) {
                ht_image img = make_image(sizes[s][0], sizes[s][1], c, noise, (uint64_t)(c * 100 + (int)s));
                check_round_trip(&img);
                ht_image_free(&img);
            }
}

/* A 3D LUT as the fixed tier stores it (slices stacked: 32 x 8192 RGB),
   and a noisy 1024 x 1024 RGBA image that compresses to nothing (its
   zlib stream is larger than the texels). */
static void test_large_images_decode_to_the_same_texels(void **state) {
    (void)state;
    ht_image lut = make_image(32, 8192, 3, false, 1);
    check_round_trip(&lut);
    ht_image_free(&lut);
    ht_image noise = make_image(1024, 1024, 4, true, 2);
    check_round_trip(&noise);
    ht_image_free(&noise);
}

static void test_an_image_no_png_can_hold_is_refused(void **state) {
    (void)state;
    uint8_t byte = 0;
    const ht_image bad[] = {
        { 0, 1, 3, &byte },            /* no width */
        { 1, 0, 3, &byte },            /* no height */
        { 1, 1, 0, &byte },            /* no channel */
        { 1, 1, 5, &byte },            /* five channels */
        { 1, 1, 3, NULL },             /* no pixels */
        { 65536, 65536, 1, &byte },    /* past HT_IMAGE_MAX_PIXELS: refused before a texel is read */
        { -4, 4, 1, &byte },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        unsigned char *png = (unsigned char *)&byte;
        size_t size = 7;
        assert_int_equal(ht_png_encode(&bad[i], &png, &size), HT_ERR_INVALID_ARGUMENT);
        assert_null(png);
        assert_int_equal(size, 0);
    }
    unsigned char *png;
    size_t size;
    assert_int_equal(ht_png_encode(NULL, &png, &size), HT_ERR_INVALID_ARGUMENT);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_channel_count_and_shape_decodes_to_the_same_texels),
        cmocka_unit_test(test_large_images_decode_to_the_same_texels),
        cmocka_unit_test(test_an_image_no_png_can_hold_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

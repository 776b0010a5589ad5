/* test_metrics — PSNR, SSIM and CIEDE2000 (shadergen/metrics.h) against
   published and independently computed values; no GL. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "metrics.h"

/* Sharma, Wu, Dalal, "The CIEDE2000 Color-Difference Formula:
   Implementation Notes, Supplementary Test Data, and Mathematical
   Observations", Color Res. Appl. 30(1), 2005, Table 1: all 34 pairs
   (L1 a1 b1, L2 a2 b2, ΔE00). Written from memory, then checked row by row
   against a public copy of the table (ArgyllCMS's CIEDE2000 test data):
   identical. */
static const double sharma[34][7] = {
    { 50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425 },
    { 50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615 },
    { 50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412 },
    { 50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000 },
    { 50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000 },
    { 50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000 },
    { 50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669 },
    { 50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669 },
    { 50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792 },
    { 50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792 },
    { 50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195 },
    { 50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195 },
    { 50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045 },
    { 50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045 },
    { 50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461 },
    { 50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065 },
    { 50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492 },
    { 50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977 },
    { 50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030 },
    { 50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535 },
    { 50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000 },
    { 50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000 },
    { 50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000 },
    { 50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000 },
    { 60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644 },
    { 63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630 },
    { 61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731 },
    { 35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645 },
    { 22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373 },
    { 36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146 },
    { 90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441 },
    { 90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381 },
    { 6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377 },
    { 2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082 },
};

static void test_ciede2000_matches_the_34_sharma_wu_dalal_pairs_both_ways(void **state) {
    (void)state;
    for (int i = 0; i < 34; i++) {
        const double *p = sharma[i];
        double forward = ht_metrics_ciede2000(p, p + 3), backward = ht_metrics_ciede2000(p + 3, p);
        if (fabs(forward - p[6]) > 1e-4 || fabs(backward - p[6]) > 1e-4)
            fail_msg("pair %d: %.6f / %.6f, published %.4f", i + 1, forward, backward, p[6]);
    }
}

static void test_ciede2000_of_a_colour_with_itself_is_zero(void **state) {
    (void)state;
    for (int i = 0; i < 34; i++) assert_true(ht_metrics_ciede2000(sharma[i], sharma[i]) == 0.0);
}

static void test_srgb_to_lab_of_white_black_and_red(void **state) {
    (void)state;
    double lab[3];
    ht_metrics_srgb_to_lab((const uint8_t[3]){ 255, 255, 255 }, lab);
    assert_true(fabs(lab[0] - 100.0) < 1e-9 && fabs(lab[1]) < 1e-9 && fabs(lab[2]) < 1e-9);
    ht_metrics_srgb_to_lab((const uint8_t[3]){ 0, 0, 0 }, lab);
    assert_true(fabs(lab[0]) < 1e-9 && fabs(lab[1]) < 1e-9 && fabs(lab[2]) < 1e-9);
    /* sRGB red, D65: L 53.24, a 80.09, b 67.20 (the usual published value). */
    ht_metrics_srgb_to_lab((const uint8_t[3]){ 255, 0, 0 }, lab);
    assert_true(fabs(lab[0] - 53.24) < 0.01 && fabs(lab[1] - 80.09) < 0.02 && fabs(lab[2] - 67.20) < 0.02);
}

/* The fixed noise pattern tests/data/ssim_reference.py builds the same way. */
enum { W = 32, H = 24 };
static uint32_t lcg(uint32_t s) { return s * 1664525u + 1013904223u; }

static void noise_pair(uint8_t ref[W * H * 4], uint8_t test[W * H * 4]) {
    uint32_t s = 12345;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint8_t *a = ref + 4 * (y * W + x), *b = test + 4 * (y * W + x);
            for (int c = 0; c < 3; c++) {
                int v = (x * 6 + y * 4 + c * 50) % 256;
                s = lcg(s);
                int n = (int)((s >> 24) % 41) - 20;
                int t = v + n;
                a[c] = (uint8_t)v;
                b[c] = (uint8_t)(t < 0 ? 0 : t > 255 ? 255 : t);
            }
            a[3] = b[3] = 255;
        }
}

static void test_ssim_of_an_image_with_itself_is_one(void **state) {
    (void)state;
    static uint8_t ref[W * H * 4], test[W * H * 4];
    noise_pair(ref, test);
    ht_metrics whole, hair;
    char err[128];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = test, .test = test, .width = W, .height = H },
                                        &whole, &hair, err, sizeof err), HT_OK);
    assert_true(whole.ssim == 1.0);
    assert_true(isinf(whole.psnr_db) && whole.psnr_db > 0);
    assert_true(whole.delta_e00_mean == 0.0 && whole.delta_e00_p95 == 0.0);
    assert_int_equal(whole.pixels, W * H);
}

/* Reference 0.8403119227: tests/data/ssim_reference.py, an independent pure
   Python SSIM (no numpy or scikit-image here: a direct 2-D weighted sum per
   11x11 window, not this module's separable filter), run once with
   python3 3.11. */
static void test_ssim_of_a_fixed_noise_pattern_matches_an_independent_computation(void **state) {
    (void)state;
    static uint8_t ref[W * H * 4], test[W * H * 4];
    noise_pair(ref, test);
    ht_metrics whole;
    char err[128];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = ref, .test = test, .width = W, .height = H },
                                        &whole, NULL, err, sizeof err), HT_OK);
    if (fabs(whole.ssim - 0.8403119227) > 1e-9) fail_msg("ssim %.10f, reference 0.8403119227", whole.ssim);
}

static void test_psnr_of_a_one_level_difference_is_48_13_db(void **state) {
    (void)state;
    enum { N = 16 };
    static uint8_t a[N * N * 4], b[N * N * 4];
    memset(a, 100, sizeof a);
    memset(b, 101, sizeof b);
    ht_metrics whole;
    char err[128];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = a, .test = b, .width = N, .height = N },
                                        &whole, NULL, err, sizeof err), HT_OK);
    assert_true(fabs(whole.psnr_db - 20.0 * log10(255.0)) < 1e-9); /* MSE 1 */
    assert_true(whole.ssim < 1.0 && whole.ssim > 0.99);
}

/* Hair pixels: where either image differs from the background. A 20 x 1
   frame (no SSIM window): black background, pixels 0-1 differ between the
   images, pixels 2-3 are hair drawn identically in both. */
static void test_hair_pixels_and_the_95th_percentile(void **state) {
    (void)state;
    static uint8_t a[20 * 4], b[20 * 4];
    for (int i = 0; i < 4; i++) a[4 * i] = b[4 * i] = 200;
    b[0] = b[4] = 180;
    double la[3], lb[3];
    ht_metrics_srgb_to_lab((const uint8_t[3]){ 200, 0, 0 }, la);
    ht_metrics_srgb_to_lab((const uint8_t[3]){ 180, 0, 0 }, lb);
    double de = ht_metrics_ciede2000(la, lb);
    ht_metrics whole, hair;
    char err[128];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = a, .test = b, .width = 20, .height = 1,
                                                            .background = (const uint8_t[3]){ 0, 0, 0 } },
                                        &whole, &hair, err, sizeof err), HT_OK);
    assert_int_equal(whole.pixels, 20);
    assert_int_equal(hair.pixels, 4);
    assert_true(fabs(whole.delta_e00_mean - 2 * de / 20) < 1e-12);
    assert_true(fabs(hair.delta_e00_mean - de / 2) < 1e-12);
    /* nearest rank: the 19th of 20 sorted values is the first nonzero one */
    assert_true(whole.delta_e00_p95 == de);
    assert_true(hair.delta_e00_p95 == de);
    double mse_whole = 2.0 * 400.0 / 60.0, mse_hair = 2.0 * 400.0 / 12.0;
    assert_true(fabs(whole.psnr_db - 10.0 * log10(255.0 * 255.0 / mse_whole)) < 1e-9);
    assert_true(fabs(hair.psnr_db - 10.0 * log10(255.0 * 255.0 / mse_hair)) < 1e-9);
    assert_true(isnan(whole.ssim)); /* no 11 x 11 window, images differ */
    /* 1 of 20 differing: the 19th value is 0. */
    b[4] = 200;
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = a, .test = b, .width = 20, .height = 1 },
                                        &whole, NULL, err, sizeof err), HT_OK);
    assert_true(whole.delta_e00_p95 == 0.0);
}

static void test_hair_ssim_counts_only_windows_centred_on_hair(void **state) {
    (void)state;
    static uint8_t ref[W * H * 4], test[W * H * 4];
    noise_pair(ref, test);
    /* Background everywhere but a 4 x 4 block around (16, 12) in both. */
    static uint8_t a[W * H * 4], b[W * H * 4];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool in = x >= 14 && x < 18 && y >= 10 && y < 14;
            memcpy(a + 4 * (y * W + x), in ? ref + 4 * (y * W + x) : (const uint8_t[4]){ 7, 7, 7, 255 }, 4);
            memcpy(b + 4 * (y * W + x), in ? test + 4 * (y * W + x) : (const uint8_t[4]){ 7, 7, 7, 255 }, 4);
        }
    ht_metrics whole, hair;
    char err[128];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = a, .test = b, .width = W, .height = H },
                                        &whole, &hair, err, sizeof err), HT_OK);
    assert_int_equal(hair.pixels, 16);
    assert_true(hair.ssim < whole.ssim);            /* the background windows are perfect */
    assert_true(hair.psnr_db < whole.psnr_db);
}

static void test_compare_refuses_missing_images_and_bad_sizes(void **state) {
    (void)state;
    uint8_t px[4] = { 0 };
    char err[160];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = px, .width = 1, .height = 1 }, NULL, NULL,
                                        err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "required"));
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = px, .test = px, .width = 0, .height = 1 },
                                        NULL, NULL, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "0 x 1"));
}

/* The heatmap's values are the pixels the summary is made of: each one the
   formula on that pixel's Lab pair, their mean and nearest-rank p95 those
   ht_metrics_compare reports, in the images' own order. */
static int compare_doubles(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void test_delta_e00_map_is_the_per_pixel_formula_behind_the_mean_and_p95(void **state) {
    (void)state;
    static uint8_t ref[W * H * 4], test[W * H * 4];
    static double map[W * H], sorted[W * H];
    noise_pair(ref, test);
    char err[128];
    const ht_metrics_desc d = { .reference = ref, .test = test, .width = W, .height = H };
    assert_int_equal(ht_metrics_delta_e00_map(&d, map, err, sizeof err), HT_OK);
    double sum = 0.0;
    int zero = 0;
    for (int i = 0; i < W * H; i++) {
        double la[3], lb[3];
        ht_metrics_srgb_to_lab(ref + 4 * i, la);
        ht_metrics_srgb_to_lab(test + 4 * i, lb);
        double want = memcmp(ref + 4 * i, test + 4 * i, 3) == 0 ? 0.0 : ht_metrics_ciede2000(la, lb);
        if (map[i] != want) fail_msg("pixel %d: map %.12f, formula %.12f", i, map[i], want);
        assert_true(map[i] == ht_metrics_delta_e00_pixel(test + 4 * i, ref + 4 * i)); /* symmetric */
        zero += map[i] == 0.0;
        sum += map[i];
    }
    assert_true(zero < W * H / 4); /* the noise moves most pixels */
    ht_metrics whole;
    assert_int_equal(ht_metrics_compare(&d, &whole, NULL, err, sizeof err), HT_OK);
    assert_true(fabs(sum / (W * H) - whole.delta_e00_mean) < 1e-12);
    memcpy(sorted, map, sizeof map);
    qsort(sorted, W * H, sizeof sorted[0], compare_doubles);
    assert_true(sorted[(int)ceil(0.95 * W * H) - 1] == whole.delta_e00_p95);
    /* a pixel changed in the test image shows at that pixel only */
    memcpy(test, ref, sizeof ref);
    test[4 * (3 * W + 5) + 1] ^= 0x40;
    assert_int_equal(ht_metrics_delta_e00_map(&d, map, err, sizeof err), HT_OK);
    for (int i = 0; i < W * H; i++)
        if ((map[i] > 0.0) != (i == 3 * W + 5)) fail_msg("pixel %d: %.6f", i, map[i]);
}

static void test_delta_e00_map_refuses_missing_images_output_and_bad_sizes(void **state) {
    (void)state;
    uint8_t px[4] = { 0 };
    double map[1];
    char err[160];
    assert_int_equal(ht_metrics_delta_e00_map(&(ht_metrics_desc){ .test = px, .width = 1, .height = 1 }, map, err,
                                              sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "ht_metrics_delta_e00_map: reference and test images are required"));
    assert_int_equal(ht_metrics_delta_e00_map(&(ht_metrics_desc){ .reference = px, .test = px, .width = 1, .height = 1 },
                                              NULL, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "no output map"));
    assert_int_equal(ht_metrics_delta_e00_map(&(ht_metrics_desc){ .reference = px, .test = px, .width = 1, .height = -2 },
                                              map, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "1 x -2"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ciede2000_matches_the_34_sharma_wu_dalal_pairs_both_ways),
        cmocka_unit_test(test_ciede2000_of_a_colour_with_itself_is_zero),
        cmocka_unit_test(test_srgb_to_lab_of_white_black_and_red),
        cmocka_unit_test(test_ssim_of_an_image_with_itself_is_one),
        cmocka_unit_test(test_ssim_of_a_fixed_noise_pattern_matches_an_independent_computation),
        cmocka_unit_test(test_psnr_of_a_one_level_difference_is_48_13_db),
        cmocka_unit_test(test_hair_pixels_and_the_95th_percentile),
        cmocka_unit_test(test_hair_ssim_counts_only_windows_centred_on_hair),
        cmocka_unit_test(test_compare_refuses_missing_images_and_bad_sizes),
        cmocka_unit_test(test_delta_e00_map_is_the_per_pixel_formula_behind_the_mean_and_p95),
        cmocka_unit_test(test_delta_e00_map_refuses_missing_images_output_and_bad_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_flip — LDR-FLIP (shadergen/flip.h) against a published value, and
   the properties the paper states: 0 for identical images, symmetric, in
   [0, 1], green against blue the largest colour error, blur and fine noise
   ranked as the eye ranks them; no GL. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/image.h>
#include "flip.h"

#define DATA "tests/data/flip/"

/* RGBA8 from a PNG of 1 to 4 channels; NULL when the file is absent. */
static uint8_t *read_rgba(const char *path, int *w, int *h) {
    ht_image img = { 0 };
    char err[256];
    if (ht_image_read_png(path, &img, err, sizeof err) != HT_OK) return NULL;
    size_t n = (size_t)img.width * (size_t)img.height;
    uint8_t *out = malloc(4 * n);
    assert_non_null(out);
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = img.pixels + i * (size_t)img.channels;
        for (int c = 0; c < 3; c++) out[4 * i + c] = p[img.channels < 3 ? 0 : c];
        out[4 * i + 3] = 255;
    }
    *w = img.width, *h = img.height;
    ht_image_free(&img);
    return out;
}

static ht_flip_result flip(const uint8_t *ref, const uint8_t *test, int w, int h, double ppd, double *map) {
    ht_flip_result r;
    char err[256];
    if (ht_flip_compare(&(ht_flip_desc){ .reference = ref, .test = test, .width = w, .height = h,
                                         .pixels_per_degree = ppd }, map, &r, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    return r;
}

/* The tree pair of gfx-rs/nv-flip-rs (tests/data/flip/README.md): mean
   0.133285 and largest error 0.983044 from NVlabs' FLIP tool at 67 ppd,
   each held there to 1e-4. */
static void test_mean_of_the_published_pair_matches_within_its_tolerance(void **state) {
    (void)state;
    int w, h, tw, th;
    uint8_t *ref = read_rgba(DATA "tree-ref.png", &w, &h), *test = read_rgba(DATA "tree-test.png", &tw, &th);
    if (!ref || !test) {
        free(ref), free(test);
        print_message("tests/data/flip/tree-*.png absent: published-value check skipped\n");
        skip();
    }
    assert_true(w == 640 && h == 960 && tw == w && th == h);
    double *map = malloc(sizeof *map * 640 * 960), max = 0.0;
    assert_non_null(map);
    ht_flip_result r = flip(ref, test, w, h, HT_FLIP_DEFAULT_PPD, map);
    for (int i = 0; i < w * h; i++) max = fmax(max, map[i]);
    if (fabs(r.mean - 0.133285) > 1e-4) fail_msg("mean %.6f, published 0.133285 +- 1e-4", r.mean);
    if (fabs(max - 0.983044) > 1e-4) fail_msg("max %.6f, published 0.983044 +- 1e-4", max);
    assert_int_equal(r.pixels, 640 * 960);
    free(map), free(ref), free(test);
}

enum { W = 64, H = 48 };
static uint32_t lcg(uint32_t s) { return s * 1664525u + 1013904223u; }

/* A textured image: gradients, a hard edge, and noise. */
static void scene(uint8_t img[W * H * 4]) {
    uint32_t s = 777;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint8_t *p = img + 4 * (y * W + x);
            s = lcg(s);
            int n = (int)((s >> 24) % 61) - 30;
            for (int c = 0; c < 3; c++) {
                int v = (x * 3 + y * 2 + c * 60) % 200 + (x > W / 2 ? 40 : 0) + n;
                p[c] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
            }
            p[3] = 255;
        }
}

/* A (2r+1)² box blur, clamped at the border. */
static void blur(const uint8_t *in, uint8_t *out, int r) {
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 4; c++) {
                int sum = 0, count = 0;
                for (int j = -r; j <= r; j++)
                    for (int i = -r; i <= r; i++) {
                        int xx = x + i < 0 ? 0 : x + i >= W ? W - 1 : x + i;
                        int yy = y + j < 0 ? 0 : y + j >= H ? H - 1 : y + j;
                        sum += in[4 * (yy * W + xx) + c];
                        count++;
                    }
                out[4 * (y * W + x) + c] = (uint8_t)((sum + count / 2) / count);
            }
}

static void test_identical_images_score_zero_everywhere(void **state) {
    (void)state;
    static uint8_t img[W * H * 4];
    static double map[W * H];
    scene(img);
    ht_flip_result r = flip(img, img, W, H, 0.0, map);
    assert_true(r.mean == 0.0 && r.p95 == 0.0);
    for (int i = 0; i < W * H; i++) assert_true(map[i] == 0.0);
}

static void test_swapping_the_images_gives_the_same_map(void **state) {
    (void)state;
    static uint8_t a[W * H * 4], b[W * H * 4];
    static double ab[W * H], ba[W * H];
    scene(a);
    blur(a, b, 1);
    ht_flip_result r1 = flip(a, b, W, H, 0.0, ab), r2 = flip(b, a, W, H, 0.0, ba);
    assert_memory_equal(ab, ba, sizeof ab);
    assert_true(r1.mean == r2.mean && r1.p95 == r2.p95);
}

static int compare_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void test_map_is_in_0_1_and_gives_the_mean_and_nearest_rank_p95(void **state) {
    (void)state;
    static uint8_t a[W * H * 4], b[W * H * 4];
    static double map[W * H];
    scene(a);
    blur(a, b, 2);
    ht_flip_result r = flip(a, b, W, H, 0.0, map);
    double sum = 0.0;
    for (int i = 0; i < W * H; i++) {
        assert_true(map[i] >= 0.0 && map[i] <= 1.0);
        sum += map[i];
    }
    assert_true(fabs(sum / (W * H) - r.mean) < 1e-12);
    qsort(map, W * H, sizeof *map, compare_double);
    assert_true(map[(int)ceil(0.95 * W * H) - 1] == r.p95);
    assert_true(r.p95 >= r.mean && r.pixels == W * H);
}

/* The colour error's normalisation: Hunt-adjusted green to blue is the
   largest distance, mapped to 1; flat frames have no features. */
static void test_flat_green_against_flat_blue_is_the_largest_error(void **state) {
    (void)state;
    static uint8_t g[W * H * 4], b[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        memcpy(g + 4 * i, (const uint8_t[4]){ 0, 255, 0, 255 }, 4);
        memcpy(b + 4 * i, (const uint8_t[4]){ 0, 0, 255, 255 }, 4);
    }
    ht_flip_result r = flip(g, b, W, H, 0.0, NULL);
    assert_true(fabs(r.mean - 1.0) < 1e-9 && fabs(r.p95 - 1.0) < 1e-9);
    /* Equal colours with a one-level change score far below it. */
    for (int i = 0; i < W * H; i++) b[4 * i + 1] = 254, b[4 * i + 2] = 0;
    r = flip(g, b, W, H, 0.0, NULL);
    if (!(r.mean > 0.0 && r.mean < 0.1)) fail_msg("one level of green: %g", r.mean);
}

static void test_more_blur_scores_worse(void **state) {
    (void)state;
    static uint8_t a[W * H * 4], b1[W * H * 4], b2[W * H * 4];
    scene(a);
    blur(a, b1, 1);
    blur(a, b2, 3);
    double self = flip(a, a, W, H, 0.0, NULL).mean, m1 = flip(a, b1, W, H, 0.0, NULL).mean,
           m2 = flip(a, b2, W, H, 0.0, NULL).mean;
    if (!(self < m1 && m1 < m2)) fail_msg("itself %g, 3x3 blur %g, 7x7 blur %g: not increasing", self, m1, m2);
}

/* Pixel-sized noise is harder to see from farther away (more pixels per
   degree): the CSF filters it out. */
static void test_fine_noise_fades_as_the_pixels_per_degree_grow(void **state) {
    (void)state;
    static uint8_t a[W * H * 4], b[W * H * 4];
    uint32_t s = 99;
    for (int i = 0; i < W * H; i++) {
        s = lcg(s);
        int n = (s >> 24) & 1 ? 24 : -24;
        for (int c = 0; c < 3; c++) a[4 * i + c] = 128, b[4 * i + c] = (uint8_t)(128 + n);
        a[4 * i + 3] = b[4 * i + 3] = 255;
    }
    double near = flip(a, b, W, H, 20.0, NULL).mean, mid = flip(a, b, W, H, 67.0, NULL).mean,
           far = flip(a, b, W, H, 200.0, NULL).mean;
    if (!(near > mid && mid > far)) fail_msg("20 ppd %g, 67 ppd %g, 200 ppd %g: not decreasing", near, mid, far);
    /* The extremes stay numbers in [0, 1]: at 0.01 ppd the kernels are one
       pixel wide, at the largest ppd 136 pixels, wider than the frame. */
    const double extremes[] = { 0.01, 0.5, HT_FLIP_MAX_PPD };
    for (int i = 0; i < 3; i++) {
        ht_flip_result r = flip(a, b, W, H, extremes[i], NULL);
        if (!(r.mean >= 0.0 && r.mean <= 1.0 && r.p95 >= 0.0 && r.p95 <= 1.0))
            fail_msg("%g ppd: mean %g, p95 %g", extremes[i], r.mean, r.p95);
    }
}

static void test_refuses_missing_images_bad_sizes_and_bad_ppd(void **state) {
    (void)state;
    static uint8_t img[W * H * 4];
    ht_flip_result r;
    char err[256];
    struct { ht_flip_desc d; const char *says; } cases[] = {
        { { .reference = NULL, .test = img, .width = W, .height = H }, "required" },
        { { .reference = img, .test = img, .width = 0, .height = H }, "0 x 48" },
        { { .reference = img, .test = img, .width = W, .height = H, .pixels_per_degree = -1 }, "pixels_per_degree: -1" },
        { { .reference = img, .test = img, .width = W, .height = H, .pixels_per_degree = NAN }, "pixels_per_degree: nan" },
        { { .reference = img, .test = img, .width = W, .height = H, .pixels_per_degree = 2000 }, "pixels_per_degree: 2000" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        err[0] = '\0';
        assert_int_equal(ht_flip_compare(&cases[i].d, NULL, &r, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        if (!strstr(err, cases[i].says) || strchr(err, '\n')) fail_msg("case %zu: \"%s\"", i, err);
    }
    assert_int_equal(ht_flip_compare(NULL, NULL, &r, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mean_of_the_published_pair_matches_within_its_tolerance),
        cmocka_unit_test(test_identical_images_score_zero_everywhere),
        cmocka_unit_test(test_swapping_the_images_gives_the_same_map),
        cmocka_unit_test(test_map_is_in_0_1_and_gives_the_mean_and_nearest_rank_p95),
        cmocka_unit_test(test_flat_green_against_flat_blue_is_the_largest_error),
        cmocka_unit_test(test_more_blur_scores_worse),
        cmocka_unit_test(test_fine_noise_fades_as_the_pixels_per_degree_grow),
        cmocka_unit_test(test_refuses_missing_images_bad_sizes_and_bad_ppd),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

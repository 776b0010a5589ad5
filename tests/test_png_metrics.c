/* test_png_metrics — build/png_metrics, the comparison tools/device_nvidia.sh
   runs on a device: identical images print PSNR inf, a difference of one
   level in every channel of every pixel prints 10 log10(255²) = 48.13 dB
   and a FLIP mean above 0; --parts puts that one level all in the mean and
   the low (blurred) part, none in the high part, and identical images
   nowhere;
   and a size mismatch, a missing or broken file or a wrong argument count
   is one line and a non-zero exit. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <hairtier/image.h>
#include "support_scratch.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "png-metrics") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* work/NAME: a w x h RGB gradient on a flat background, every value + add. */
static void write_png(const char *name, int w, int h, int add) {
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, w, h, 3), HT_OK);
    for (int i = 0; i < w * h; i++)
        for (int c = 0; c < 3; c++)
            img.pixels[3 * i + c] = (uint8_t)((i % w > w / 2 ? (i * 7 + c * 50) % 200 + 20 : 10) + add);
    char path[256], err[256];
    snprintf(path, sizeof path, "%s/%s", work, name);
    if (ht_image_write_png(path, &img, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_image_free(&img);
}

/* build/png_metrics ARGS: the exit status, stdout and stderr together in out. */
static int run(const char *args, char *out, size_t size) {
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[2048], root[1024];
    assert_non_null(getcwd(root, sizeof root));   /* tests run from the repository root */
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s/%s/png_metrics' %s 2>&1", work, root, build ? build : "build", args);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, size - 1, p);
    out[n] = '\0';
    int status = pclose(p);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

static void test_png_metrics_prints_inf_for_identical_and_48_db_for_one_level(void **state) {
    (void)state;
    char out[2048];
    write_png("a.png", 40, 30, 0);
    write_png("b.png", 40, 30, 0);
    write_png("c.png", 40, 30, 1);
    assert_int_equal(run("a.png b.png", out, sizeof out), 0);
    assert_non_null(strstr(out, "psnr_db=inf ssim=1.0000 de00_mean=0.000"));
    assert_non_null(strstr(out, " flip_mean=0.00000 flip_p95=0.00000 max_diff=0\n"));
    assert_int_equal(run("a.png c.png", out, sizeof out), 0);
    assert_true(strncmp(out, "psnr_db=48.13 ", 14) == 0);
    assert_non_null(strstr(out, "max_diff=1\n"));
    assert_null(strstr(out, " flip_mean=0.00000 "));

    /* --parts: the one level is all mean and low part, none of it high */
    assert_int_equal(run("--parts a.png b.png", out, sizeof out), 0);
    assert_non_null(strstr(out, "\nparts: mean_diff=+0.0000,+0.0000,+0.0000 ink_ratio=1.000 covered_ratio=1.000 "
                                "gain=1.000 gain_psnr_db=inf r1:low=inf,high=inf,smooth="));
    assert_int_equal(run("a.png c.png --parts", out, sizeof out), 0);
    assert_non_null(strstr(out, "\nparts: mean_diff=+0.0039,+0.0039,+0.0039 "));
    for (int r = 1; r <= 8; r *= 2) {
        char part[32];
        double low = 0, high = 0;
        snprintf(part, sizeof part, " r%d:low=", r);
        const char *at = strstr(out, part);
        assert_non_null(at);
        assert_int_equal(sscanf(at + strlen(part), "%lf,high=%lf", &low, &high), 2);
        assert_true(fabs(low - 48.13) < 0.01 && high > 200); /* high: only rounding left */
    }
}

static void test_png_metrics_refuses_bad_input_in_one_line(void **state) {
    (void)state;
    char out[1024];
    write_png("a.png", 40, 30, 0);
    write_png("small.png", 20, 30, 0);
    ht_test_write_file(work, "broken.png", "\x89PNG\r\n");
    assert_int_equal(run("a.png small.png", out, sizeof out), 1);
    assert_string_equal(out, "png_metrics: small.png: 20x30, but a.png is 40x30\n");
    assert_int_equal(run("a.png missing.png", out, sizeof out), 1);
    assert_true(strncmp(out, "png_metrics: ", 13) == 0 && strstr(out, "missing.png") && !strchr(out, '\n')[1]);
    assert_int_equal(run("broken.png a.png", out, sizeof out), 1);
    assert_true(strncmp(out, "png_metrics: ", 13) == 0 && strstr(out, "broken.png") && !strchr(out, '\n')[1]);
    assert_int_equal(run("a.png", out, sizeof out), 2);
    assert_string_equal(out, "png_metrics: two PNGs required\nusage: png_metrics [--parts] REFERENCE.png TEST.png\n");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png_metrics_prints_inf_for_identical_and_48_db_for_one_level),
        cmocka_unit_test(test_png_metrics_refuses_bad_input_in_one_line),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

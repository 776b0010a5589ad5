/* test_bench_tools — the benchmark's small parts (examples/): the ETA and
   durations of its progress line (support_progress.h), the median
   (timing.h), figures read back from a program's printed lines
   (support_figures.h). No GL, no timing. (Result files are written by
   ht_file_write_atomic: tests/test_file_atomic.c.) */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support_figures.h"
#include "support_progress.h"
#include "support_scratch.h"
#include "timing.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "bench-tools") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static void test_eta_is_the_remaining_weight_at_the_pace_so_far(void **state) {
    (void)state;
    assert_float_equal(bench_eta_seconds(60, 100, 300), 180, 1e-9);
    assert_float_equal(bench_eta_seconds(60, 100, 0), 0, 0);
    assert_true(isnan(bench_eta_seconds(5, 0, 300)));   /* nothing done: no pace yet */
    assert_true(isnan(bench_eta_seconds(NAN, 1, 1)));
    assert_true(isnan(bench_eta_seconds(1, -1, 1)));
    assert_true(isnan(bench_eta_seconds(1, 1, INFINITY)));
}

static void test_durations_read_as_hours_minutes_seconds(void **state) {
    (void)state;
    char t[32];
    assert_string_equal(bench_format_duration(0, t, sizeof t), "0s");
    assert_string_equal(bench_format_duration(59.4, t, sizeof t), "59s");
    assert_string_equal(bench_format_duration(59.6, t, sizeof t), "1m00s");
    assert_string_equal(bench_format_duration(61, t, sizeof t), "1m01s");
    assert_string_equal(bench_format_duration(3725, t, sizeof t), "1h02m05s");
    assert_string_equal(bench_format_duration(NAN, t, sizeof t), "--");
    assert_string_equal(bench_format_duration(-1, t, sizeof t), "--");
    assert_string_equal(bench_format_duration(INFINITY, t, sizeof t), "--");
    assert_string_equal(bench_format_duration(1e12, t, sizeof t), "--");
    char small[4];
    bench_format_duration(3725, small, sizeof small); /* cut, never overflowed */
    assert_int_equal(strlen(small), 3);
}

static void test_median_of_odd_and_even_counts(void **state) {
    (void)state;
    double odd[] = { 9, 1, 5 }, even[] = { 4, 1, 3, 2 }, one[] = { 7 };
    assert_float_equal(median(odd, 3), 5, 0);
    assert_float_equal(median(even, 4), 2.5, 0);
    assert_float_equal(median(one, 1), 7, 0);
}

static void test_figures_are_read_from_bench_hairgen_lines(void **state) {
    (void)state;
    bench_row r;
    assert_true(bench_parse_figure("hairgen, all tiers of dark-brown:               259.9 ms", "generator", &r));
    assert_string_equal(r.series, "generator");
    assert_string_equal(r.figure, "hairgen, all tiers of dark-brown");
    assert_float_equal(r.value, 259.9, 1e-12);
    assert_string_equal(r.unit, "ms");
    assert_true(isnan(r.median_ms));

    assert_true(bench_parse_figure("hairgen, all tiers of 100 materials:  13963.3 ms (139.6 ms each)", "generator", &r));
    assert_string_equal(r.figure, "hairgen, all tiers of 100 materials (139.6 ms each)");
    assert_float_equal(r.value, 13963.3, 1e-9);

    /* The first colon followed by a number splits: a colon inside the label stays. */
    assert_true(bench_parse_figure("glslangValidator, one process per file (800): 127009.8 ms", "generator", &r));
    assert_string_equal(r.figure, "glslangValidator, one process per file (800)");
    assert_true(bench_parse_figure("ratio: shell validation / in-process generation: 9.10", "generator", &r));
    assert_string_equal(r.figure, "ratio: shell validation / in-process generation");
    assert_float_equal(r.value, 9.10, 1e-12);
    assert_string_equal(r.unit, "");
    assert_true(bench_parse_figure("speed-up: -2.5e1 x", "generator", &r));
    assert_float_equal(r.value, -25, 0);
    assert_string_equal(r.unit, "x");
}

static void test_other_lines_are_not_figures(void **state) {
    (void)state;
    bench_row r = bench_row_blank();
    r.value = 42;
    const char *lines[] = {
        "",
        "furball   1000020 triangles  build   622.47 ms",   /* no colon */
        "hairgen: failed",                                  /* no number */
        ": 12 ms",                                          /* no label */
        "ratio: 12abc",                                     /* not a number as a whole */
        "ratio: inf",
        "ratio: nan ms",
        "time: 1e999 ms",                                   /* not finite */
    };
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++)
        if (bench_parse_figure(lines[i], "generator", &r)) fail_msg("'%s' read as a figure", lines[i]);
    assert_float_equal(r.value, 42, 0); /* untouched */
    char long_line[400];
    memset(long_line, 'x', 300);
    snprintf(long_line + 300, sizeof long_line - 300, ": 1 ms");
    assert_false(bench_parse_figure(long_line, "generator", &r));
    assert_false(bench_parse_figure("a: 1 ms", "a-series-name-far-too-long", &r));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_eta_is_the_remaining_weight_at_the_pace_so_far),
        cmocka_unit_test(test_durations_read_as_hours_minutes_seconds),
        cmocka_unit_test(test_median_of_odd_and_even_counts),
        cmocka_unit_test(test_figures_are_read_from_bench_hairgen_lines),
        cmocka_unit_test(test_other_lines_are_not_figures),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

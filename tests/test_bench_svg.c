/* test_bench_svg — the benchmark's plots (examples/bench/support_svg_plot.h,
   support_results_svg.h): round axis ticks, what a plot draws and leaves
   out, text escaped, every tier its colour. No GL, no timing. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support_results_svg.h"
#include "support_svg_plot.h"

typedef bool (*draw_fn)(FILE *f, const void *what);

static char *to_text(draw_fn draw, const void *what) {
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_true(draw(f, what));
    long size = ftell(f);
    rewind(f);
    char *text = malloc((size_t)size + 1);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)size, f), (size_t)size);
    text[size] = '\0';
    fclose(f);
    return text;
}

static size_t count(const char *text, const char *needle) {
    size_t n = 0;
    for (const char *p = strstr(text, needle); p; p = strstr(p + 1, needle)) n++;
    return n;
}

static void test_nice_axis_rounds_out_to_1_2_5_steps(void **state) {
    (void)state;
    const struct {
        double lo, hi;
        int ticks;
        double want_lo, want_hi, want_step;
    } cases[] = {
        { 0, 40000, 7, 0, 40000, 10000 },
        { 0.03, 1.04, 7, 0, 1.2, 0.2 },
        { 13.99, 39.1, 7, 10, 40, 5 },
        { 3, 3, 7, 2.7, 3.3, 0.1 },        /* one value: widened around it (±10%) */
        { 0, 0, 7, -1, 1, 0.5 },
        { NAN, 1, 7, 0, 1, 0.2 },          /* nothing finite: [0, 1] */
        { 5, 1, 7, 0, 1, 0.2 },            /* empty */
        { -7, 93, 3, -100, 100, 100 },     /* the fewest ticks: across zero, three */
        { -7, 93, 2, -100, 100, 100 },     /* two cannot span zero: taken as three */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double lo = cases[i].lo, hi = cases[i].hi;
        double step = bench_nice_axis(&lo, &hi, cases[i].ticks);
        if (fabs(step - cases[i].want_step) > 1e-9 || fabs(lo - cases[i].want_lo) > 1e-9 ||
            fabs(hi - cases[i].want_hi) > 1e-9)
            fail_msg("case %zu: [%g, %g] step %g, want [%g, %g] step %g", i, lo, hi, step, cases[i].want_lo,
                     cases[i].want_hi, cases[i].want_step);
        assert_true(lround((hi - lo) / step) + 1 <= (cases[i].ticks < 3 ? 3 : cases[i].ticks));
    }
}

static bool draw_plot(FILE *f, const void *what) {
    return bench_svg_begin(f, 640, 400) && bench_svg_draw(f, what, 0, 0, 640, 400) && bench_svg_end(f);
}

static void test_a_plot_draws_lines_markers_labels_and_skips_non_finite_points(void **state) {
    (void)state;
    const double x[] = { 1000, 5000, NAN, 20000 }, y[] = { 10, 40, 50, INFINITY };
    const char *labels[] = { "a<b", NULL, NULL, NULL };
    bench_svg_series s[] = { { .name = "full & co", .x = x, .y = y, .labels = labels, .count = 4, .lines = true,
                               .colour = -1 },
                             { .name = "empty", .x = x, .y = y, .count = 0, .colour = 3 } };
    bench_svg_plot p = { .title = "t \"q\"", .x_label = "hairs", .y_label = "ms", .series = s, .series_count = 2,
                         .x_from_zero = true, .y_from_zero = true, .x_ref = 2500, .x_ref_label = "full" };
    char *svg = to_text(draw_plot, &p);
    assert_non_null(strstr(svg, "<svg xmlns=\"http://www.w3.org/2000/svg\""));
    assert_non_null(strstr(svg, "</svg>\n"));
    assert_int_equal(count(svg, "<polyline"), 1);
    assert_int_equal(count(svg, "<circle"), 2);       /* the NaN and infinite points are left out */
    assert_non_null(strstr(svg, ">a&lt;b</text>"));
    assert_non_null(strstr(svg, ">full &amp; co</text>"));
    assert_non_null(strstr(svg, ">t &quot;q&quot;</text>"));
    assert_non_null(strstr(svg, "stroke-dasharray"));  /* the reference line */
    assert_non_null(strstr(svg, bench_svg_colour(3))); /* the empty series still has its legend entry */
    assert_null(strstr(svg, "nan"));
    assert_null(strstr(svg, "inf"));
    free(svg);
}

static void test_a_plot_too_small_for_its_margins_is_refused(void **state) {
    (void)state;
    bench_svg_plot p = { .title = "t", .x_ref = NAN };
    FILE *f = tmpfile();
    assert_false(bench_svg_draw(f, &p, 0, 0, 100, 50));
    fclose(f);
}

static void test_colours_wrap(void **state) {
    (void)state;
    assert_string_equal(bench_svg_colour(0), bench_svg_colour(8));
    assert_string_equal(bench_svg_colour(-1), bench_svg_colour(7));
    assert_string_not_equal(bench_svg_colour(0), bench_svg_colour(1));
}

static void add(bench_rows *rows, const char *series, const char *driver, long hairs, const char *tier, double ms,
                double psnr) {
    bench_row *r = bench_rows_add(rows);
    assert_non_null(r);
    snprintf(r->series, sizeof r->series, "%s", series);
    snprintf(r->scene, sizeof r->scene, "furball");
    snprintf(r->driver, sizeof r->driver, "%s", driver);
    snprintf(r->tier, sizeof r->tier, "%s", tier);
    r->hairs = hairs, r->width = r->height = 512;
    r->ran = ms > 0;
    r->median_ms = ms, r->per_full = ms / 100;
    r->whole.psnr_db = psnr;
}

static bool draw_cost(FILE *f, const void *rows) { return bench_write_cost_svg(f, rows); }
static bool draw_scaling(FILE *f, const void *rows) { return bench_write_scaling_svg(f, rows); }

static void test_cost_plot_has_a_panel_per_run_and_full_as_the_reference_line(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    for (int d = 0; d < 2; d++) {
        const char *driver = d ? "softpipe" : "llvmpipe";
        add(&rows, "matrix", driver, 10000, "floor", 50, 14);
        add(&rows, "matrix", driver, 10000, "full", 100, INFINITY);
        add(&rows, "matrix", driver, 10000, "fixed", 90, 33);
        add(&rows, "matrix", driver, 10000, "gl11", d ? 0 : 80, 31); /* does not run on softpipe */
    }
    char *svg = to_text(draw_cost, &rows);
    assert_non_null(strstr(svg, ">furball × llvmpipe, 512×512</text>"));
    assert_non_null(strstr(svg, ">furball × softpipe, 512×512</text>"));
    assert_int_equal(count(svg, "<circle"), 3 + 2);
    assert_int_equal(count(svg, "stroke-dasharray"), 2);
    /* gl11 keeps its colour (the fourth tier's) though softpipe lacks it. */
    assert_int_equal(count(svg, bench_svg_colour(3)), 1 + 1);
    free(svg);
    bench_rows_free(&rows);
}

static void test_scaling_plot_has_a_line_per_tier_in_hair_order(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    add(&rows, "matrix", "llvmpipe", 10000, "floor", 100, 14);
    add(&rows, "matrix", "llvmpipe", 10000, "full", 200, INFINITY);
    add(&rows, "scaling", "llvmpipe", 40000, "floor", 400, 14);
    add(&rows, "scaling", "llvmpipe", 40000, "full", 800, INFINITY);
    add(&rows, "scaling", "llvmpipe", 1000, "floor", 10, 14);
    add(&rows, "scaling", "llvmpipe", 1000, "full", 20, INFINITY);
    char *svg = to_text(draw_scaling, &rows);
    assert_int_equal(count(svg, "<polyline"), 2);
    assert_int_equal(count(svg, "<circle"), 6);
    assert_non_null(strstr(svg, ">frame cost against hair count: furball × llvmpipe, 512×512</text>"));
    /* x grows along each line: 1k, 10k, 40k. */
    const char *line = strstr(svg, "points=\"");
    double x0, y0, x1, y1, x2, y2;
    assert_int_equal(sscanf(line, "points=\"%lf,%lf %lf,%lf %lf,%lf", &x0, &y0, &x1, &y1, &x2, &y2), 6);
    assert_true(x0 < x1 && x1 < x2);
    assert_true(y0 > y1 && y1 > y2); /* SVG's y grows downwards: more ms is higher */
    free(svg);
    bench_rows_free(&rows);
}

static void test_plots_of_no_rows_are_still_documents(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    char *svg = to_text(draw_cost, &rows);
    assert_non_null(strstr(svg, "</svg>"));
    free(svg);
    svg = to_text(draw_scaling, &rows);
    assert_non_null(strstr(svg, ">no scaling series</text>"));
    free(svg);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nice_axis_rounds_out_to_1_2_5_steps),
        cmocka_unit_test(test_a_plot_draws_lines_markers_labels_and_skips_non_finite_points),
        cmocka_unit_test(test_a_plot_too_small_for_its_margins_is_refused),
        cmocka_unit_test(test_colours_wrap),
        cmocka_unit_test(test_cost_plot_has_a_panel_per_run_and_full_as_the_reference_line),
        cmocka_unit_test(test_scaling_plot_has_a_line_per_tier_in_hair_order),
        cmocka_unit_test(test_plots_of_no_rows_are_still_documents),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

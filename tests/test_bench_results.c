/* test_bench_results — the benchmark's results table (examples/
   support_results.h): its CSV written and read back, bad files refused with
   the file, line and column named, the views the reports share, and the
   markdown report (support_results_md.h). No GL, no timing. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support_results.h"
#include "support_results_md.h"
#include "support_scratch.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "bench-results") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* A frame row of one run. */
static void frame_row(bench_rows *rows, const char *series, const char *scene, const char *driver, long hairs,
                      const char *tier, double ms, double full_ms, double psnr) {
    bench_row *r = bench_rows_add(rows);
    assert_non_null(r);
    snprintf(r->series, sizeof r->series, "%s", series);
    snprintf(r->scene, sizeof r->scene, "%s", scene);
    snprintf(r->driver, sizeof r->driver, "%s", driver);
    snprintf(r->renderer, sizeof r->renderer, "%s (LLVM 15.0.6, 256 bits)", driver);
    snprintf(r->tier, sizeof r->tier, "%s", tier);
    r->hairs = hairs, r->triangles = hairs * 30, r->width = r->height = 512, r->frames = 9;
    r->ran = ms > 0;
    if (!r->ran) return;
    r->median_ms = ms, r->per_full = ms / full_ms, r->per_floor = ms / 100.0;
    /* orbiting: fixed's CPU coordinates double its frame, full's is the same */
    r->orbit_ms = strcmp(tier, "fixed") == 0 ? 2 * ms : ms, r->orbit_per_full = r->orbit_ms / full_ms;
    r->whole = (ht_metrics){ .psnr_db = psnr, .ssim = isinf(psnr) ? 1 : 0.95, .delta_e00_mean = 0.5,
                             .delta_e00_p95 = 2.25 };
    r->hair = r->whole;
    r->flip_mean = isinf(psnr) ? 0 : (50 - psnr) / 1000, r->flip_p95 = 2 * r->flip_mean;
    r->cpu_still = 0, r->cpu_orbit = strcmp(tier, "fixed") == 0 ? 320000 : 0;
}

/* What write writes, as a string (the caller frees it). */
static char *to_text(bool (*write)(FILE *, const bench_rows *), const bench_rows *rows) {
    FILE *f = tmpfile();
    assert_non_null(f);
    assert_true(write(f, rows));
    long size = ftell(f);
    assert_true(size >= 0);
    rewind(f);
    char *text = malloc((size_t)size + 1);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)size, f), (size_t)size);
    text[size] = '\0';
    fclose(f);
    return text;
}

static char *csv_path(const char *name) {
    static char path[128];
    snprintf(path, sizeof path, "%s/%s", work, name);
    return path;
}

static void test_header_is_built_from_the_column_table(void **state) {
    (void)state;
    assert_non_null(bench_csv_header());
    assert_string_equal(bench_csv_header(), BENCH_CSV_HEADER);
}

static void test_csv_round_trip_keeps_every_field(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, "floor", 100, 200, 14.25);
    frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, "full", 200, 200, INFINITY);
    frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, "fixed", 190.5, 200, 33.625);
    frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, "gl11", 0, 200, 0); /* does not run */
    bench_row *g = bench_rows_add(&rows);
    snprintf(g->series, sizeof g->series, "generator");
    snprintf(g->figure, sizeof g->figure, "hairgen, all tiers of \"dark-brown\"");
    g->value = 48.5;
    snprintf(g->unit, sizeof g->unit, "ms");

    char *text = to_text(bench_rows_write_csv, &rows);
    /* A comma or a quote in a text is quoted, quotes doubled. */
    assert_non_null(strstr(text, "\"llvmpipe (LLVM 15.0.6, 256 bits)\""));
    assert_non_null(strstr(text, "\"hairgen, all tiers of \"\"dark-brown\"\"\",48.5,ms\n"));
    assert_non_null(strstr(text, ",full,1,200,2,1,200,1,inf,1,"));
    ht_test_write_file(work, "round.csv", text);
    free(text);

    bench_rows back = { 0 };
    char err[256] = "";
    assert_true(bench_rows_read_csv(csv_path("round.csv"), &back, err, sizeof err));
    assert_int_equal(back.count, rows.count);
    for (size_t i = 0; i < rows.count; i++) {
        const bench_row *a = &rows.row[i], *b = &back.row[i];
        assert_string_equal(a->series, b->series);
        assert_string_equal(a->scene, b->scene);
        assert_string_equal(a->renderer, b->renderer);
        assert_string_equal(a->tier, b->tier);
        assert_string_equal(a->figure, b->figure);
        assert_string_equal(a->unit, b->unit);
        assert_int_equal(a->hairs, b->hairs);
        assert_int_equal(a->ran, b->ran);
        const double pairs[][2] = { { a->median_ms, b->median_ms }, { a->per_full, b->per_full },
                                    { a->whole.psnr_db, b->whole.psnr_db }, { a->hair.delta_e00_p95, b->hair.delta_e00_p95 },
                                    { a->cpu_orbit, b->cpu_orbit }, { a->orbit_ms, b->orbit_ms },
                                    { a->orbit_per_full, b->orbit_per_full }, { a->value, b->value } };
        for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
            if (isnan(pairs[k][0])) assert_true(isnan(pairs[k][1]));
            else if (isinf(pairs[k][0])) assert_true(isinf(pairs[k][1]) && pairs[k][1] > 0);
            else assert_float_equal(pairs[k][0], pairs[k][1], 1e-9 * fabs(pairs[k][0]));
        }
    }
    assert_int_equal(back.row[4].hairs, -1); /* empty count: not applicable */
    assert_true(isnan(back.row[3].median_ms));
    bench_rows_free(&back);
    bench_rows_free(&rows);
}

static void test_reading_appends_to_what_is_there(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, "full", 200, 200, INFINITY);
    char *text = to_text(bench_rows_write_csv, &rows);
    ht_test_write_file(work, "one.csv", text);
    free(text);
    char err[256];
    assert_true(bench_rows_read_csv(csv_path("one.csv"), &rows, err, sizeof err));
    assert_true(bench_rows_read_csv(csv_path("one.csv"), &rows, err, sizeof err));
    assert_int_equal(rows.count, 3);
    bench_rows_free(&rows);
}

/* Each bad file: refused, the message names file (and line and column), and
   the rows already held stay as they were. */
static void test_bad_files_are_refused_with_the_place_named(void **state) {
    (void)state;
    const char *good = "matrix,furball,llvmpipe,x,10,300,512,512,9,full,1,200,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,";
    char text[1024];
    const struct {
        const char *body;   /* after the header; NULL: the header itself is wrong */
        const char *expect;
    } cases[] = {
        { NULL, "header: not the benchmark's columns" },
        { "matrix,furball\n", "line 3: wrong number of fields" },
        { "matrix,\"furball,llvmpipe\n", "line 3: unterminated quote" },
        { "matrix,fur\"ball,llvmpipe,x,10,300,512,512,9,full,1,200,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: quote inside an unquoted field" },
        { "matrix,furball,llvmpipe,x,ten,300,512,512,9,full,1,200,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: hairs: not a count" },
        { "matrix,furball,llvmpipe,x,10,300,512,512,9,full,yes,200,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: ran: not 0 or 1" },
        { "matrix,furball,llvmpipe,x,10,300,512,512,9,full,1,fast,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: median_ms: not a number" },
        { "matrix,furball,llvmpipe,x,10,300,512,512,9,full,1,nan,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: median_ms: not a number" },
        { "a-series-name-too-long,furball,llvmpipe,x,10,300,512,512,9,full,1,1,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: series: text too long for its column" },
        { "matrix,furball,llvmpipe,x,10,300,512,512,9,full,1,1,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,,\n",
          "line 3: wrong number of fields" },
        { "matrix,furball,llvmpipe,x,10,300,512,512,9,full,1,1,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,,,,,\n",
          "line 3: wrong number of fields" },
        { "matrix,\"furball\"x,llvmpipe,x,10,300,512,512,9,full,1,1,2,1,200,1,inf,1,0,0,inf,1,0,0,0,0,0,0,,,\n",
          "line 3: text after a closing quote" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (cases[i].body) snprintf(text, sizeof text, "%s\n%s\n%s", BENCH_CSV_HEADER, good, cases[i].body);
        else snprintf(text, sizeof text, "series,scene\n%s\n", good);
        ht_test_write_file(work, "bad.csv", text);
        bench_rows rows = { 0 };
        frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, "full", 200, 200, INFINITY);
        char err[512] = "";
        assert_false(bench_rows_read_csv(csv_path("bad.csv"), &rows, err, sizeof err));
        assert_non_null(strstr(err, "bad.csv: "));
        if (!strstr(err, cases[i].expect)) fail_msg("case %zu: '%s' lacks '%s'", i, err, cases[i].expect);
        assert_int_equal(rows.count, 1);
        bench_rows_free(&rows);
    }
    bench_rows rows = { 0 };
    char err[512];
    assert_false(bench_rows_read_csv(csv_path("missing.csv"), &rows, err, sizeof err));
    assert_non_null(strstr(err, "missing.csv: cannot open"));
}

/* Two matrix runs, and a scaling series sharing the matrix's 10k point. */
static void sample_rows(bench_rows *rows) {
    const char *tiers[] = { "floor", "full", "fixed" };
    const long scaling[] = { 40000, 1000 };
    for (int t = 0; t < 3; t++) frame_row(rows, "matrix", "furball", "llvmpipe", 10000, tiers[t], 100 + 50 * t, 150, t == 1 ? INFINITY : 20 + 10 * t);
    for (int t = 0; t < 3; t++) frame_row(rows, "matrix", "furball", "softpipe", 2000, tiers[t], t == 2 ? 0 : 400 * (t + 1), 800, t == 1 ? INFINITY : 20);
    for (int s = 0; s < 2; s++)
        for (int t = 0; t < 3; t++)
            frame_row(rows, "scaling", "furball", "llvmpipe", scaling[s], tiers[t], (double)scaling[s] / 100 * (t + 1),
                      (double)scaling[s] / 50, 30);
}

static void test_views_group_runs_and_order_the_scaling_series(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    sample_rows(&rows);
    const char *tiers[8];
    assert_int_equal(bench_rows_tiers(&rows, tiers, 8), 3);
    assert_string_equal(tiers[2], "fixed");
    assert_int_equal(bench_tier_index(tiers, 3, "full"), 1);
    assert_int_equal(bench_tier_index(tiers, 3, "gl11"), -1);
    size_t first[8];
    assert_int_equal(bench_rows_matrix_runs(&rows, first, 8), 2);
    assert_string_equal(rows.row[first[1]].driver, "softpipe");
    assert_int_equal(bench_rows_scaling_runs(&rows, first, 8), 3);
    assert_int_equal(rows.row[first[0]].hairs, 1000);
    assert_int_equal(rows.row[first[1]].hairs, 10000); /* the matrix run: same scene, driver, size */
    assert_string_equal(rows.row[first[1]].series, "matrix");
    assert_int_equal(rows.row[first[2]].hairs, 40000);
    assert_non_null(bench_rows_find(&rows, first[2], "fixed"));
    assert_null(bench_rows_find(&rows, first[2], "gl11"));
    bench_rows_free(&rows);
}

static bool write_md(FILE *f, const bench_rows *rows) {
    return bench_write_markdown(f, rows, &(bench_markdown){ .preamble = "Measured on a test.", .cost_svg = "results.svg",
                                                            .scaling_svg = "scaling.svg" });
}

static void test_markdown_has_a_table_per_run_the_scaling_table_and_figures(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    sample_rows(&rows);
    bench_row *g = bench_rows_add(&rows);
    snprintf(g->series, sizeof g->series, "generator");
    snprintf(g->figure, sizeof g->figure, "hairgen, all tiers of dark-brown");
    g->value = 48;
    snprintf(g->unit, sizeof g->unit, "ms");
    char *md = to_text(write_md, &rows);
    assert_non_null(strstr(md, "Measured on a test.\n"));
    assert_non_null(strstr(md, "### furball × llvmpipe\n"));
    assert_non_null(strstr(md, "### furball × softpipe\n"));
    /* full: infinite PSNR against itself; fixed: ratios from its own run. */
    assert_non_null(strstr(md, "| full | 150.0 | 1.50 | 1.00 | 150.0 | 1.00 | ∞ | 1.0000 | 0.50 | 2.25 | 0.0000 | 0 / 0 |"));
    assert_non_null(strstr(md, "| fixed | 200.0 | 2.00 | 1.33 | 400.0 | 2.67 | 40.0 | 0.9500 | 0.50 | 2.25 | 0.0100 | 0 / 320000 |"));
    assert_non_null(strstr(md, "| fixed | does not run here |"));
    assert_non_null(strstr(md, "## Scaling: furball × llvmpipe, 512×512"));
    const char *r1k = strstr(md, "\n| 1000 | 30000 | 10.0 (0.50×) |");
    const char *r10k = strstr(md, "\n| 10000 | 300000 | 100.0 (0.67×) |");
    const char *r40k = strstr(md, "\n| 40000 | 1200000 | 400.0 (0.50×) |");
    assert_true(r1k && r10k && r40k && r1k < r10k && r10k < r40k);
    assert_non_null(strstr(md, "](results.svg)"));
    assert_non_null(strstr(md, "](scaling.svg)"));
    assert_non_null(strstr(md, "| hairgen, all tiers of dark-brown | 48 | ms |"));
    free(md);
    bench_rows_free(&rows);
}

/* Under each run's table: whether PSNR and FLIP rank its shading tiers
   alike, and the first pair they disagree on. */
static void test_markdown_says_whether_psnr_and_flip_rank_tiers_alike(void **state) {
    (void)state;
    const char *tiers[] = { "floor", "full", "vertex", "fixed", "gl11" };
    const double psnr[] = { 14, INFINITY, 34, 31, 30 };
    for (int disagree = 0; disagree < 2; disagree++) {
        bench_rows rows = { 0 };
        for (int t = 0; t < 5; t++) frame_row(&rows, "matrix", "furball", "llvmpipe", 10000, tiers[t], 150, 150, psnr[t]);
        if (disagree) rows.row[4].flip_mean = 0.005; /* gl11: lower PSNR than fixed, yet closer by FLIP */
        char *md = to_text(write_md, &rows);
        const char *want = disagree ? "PSNR and FLIP disagree on 2 of the 3 pairs both tell apart; first: PSNR ranks "
                                      "vertex closer, FLIP gl11.\n"
                                    : "PSNR and FLIP rank these 3 tiers alike (3 pairs both tell apart).\n";
        if (!strstr(md, want)) fail_msg("no '%s' in:\n%s", want, md);
        free(md);
        bench_rows_free(&rows);
    }
}

/* GL ES runs (bench_frame --api): their own runs and tables beside the
   desktop ones, ratios to the run's desktop full; their tier names stay
   out of the desktop tiers the plots colour. */
static void test_es_runs_get_their_own_tables(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    sample_rows(&rows);
    const char *es_tiers[] = { "floor", "full", "full-gles2", "vertex-gles2" };
    for (int a = 0; a < 2; a++)
        for (int t = 0; t < 4; t++)
            frame_row(&rows, a ? "gles3" : "gles2", "furball", "llvmpipe", 10000, a ? (t < 2 ? es_tiers[t] : "full-gles3")
                                                                                     : es_tiers[t],
                      t == 0 ? 100 : 150 + 30 * t * (t > 1), 150, t == 1 ? INFINITY : 45);
    for (size_t i = 0; i < rows.count; i++) assert_true(bench_row_is_frame(&rows.row[i]));
    assert_true(bench_row_is_es(&rows.row[rows.count - 1]));
    assert_false(bench_row_is_es(&rows.row[0]));
    const char *tiers[8];
    assert_int_equal(bench_rows_tiers(&rows, tiers, 8), 3);
    size_t first[8];
    assert_int_equal(bench_rows_matrix_runs(&rows, first, 8), 2);
    assert_int_equal(bench_rows_series_runs(&rows, "gles2", first, 8), 1);
    assert_non_null(bench_rows_find(&rows, first[0], "vertex-gles2"));
    assert_int_equal(bench_rows_series_runs(&rows, "gles3", first, 8), 1);
    assert_null(bench_rows_find(&rows, first[0], "full-gles2"));
    char *md = to_text(write_md, &rows);
    const char *es = strstr(md, "## GL ES tiers beside desktop GL's full\n");
    assert_non_null(es);
    assert_true(es > strstr(md, "### furball × softpipe\n"));
    assert_non_null(strstr(es, "### furball × llvmpipe, gles2\n"));
    assert_non_null(strstr(es, "### furball × llvmpipe, gles3\n"));
    assert_non_null(strstr(es, "| full-gles2 | 210.0 | 2.10 | 1.40 |"));
    assert_non_null(strstr(es, "`full-gles2` / `full` is what GL ES costs the same tier"));
    assert_non_null(strstr(es, "`full-gles3` / `full` is what GL ES costs the same tier"));
    assert_true(strstr(md, "## Scaling") > es);
    free(md);
    bench_rows_free(&rows);
}

static void test_markdown_of_no_rows_is_only_the_title(void **state) {
    (void)state;
    bench_rows rows = { 0 };
    char *md = to_text(write_md, &rows);
    assert_null(strstr(md, "###"));
    assert_null(strstr(md, "Scaling"));
    assert_null(strstr(md, "Generator"));
    free(md);
}

static void test_md_numbers_show_not_applicable_and_infinity(void **state) {
    (void)state;
    char t[32];
    assert_string_equal(bench_md_number(NAN, "%.1f", t, sizeof t), "—");
    assert_string_equal(bench_md_number(INFINITY, "%.1f", t, sizeof t), "∞");
    assert_string_equal(bench_md_number(-INFINITY, "%.1f", t, sizeof t), "−∞");
    assert_string_equal(bench_md_number(33.25, "%.1f", t, sizeof t), "33.2");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_header_is_built_from_the_column_table),
        cmocka_unit_test(test_csv_round_trip_keeps_every_field),
        cmocka_unit_test(test_reading_appends_to_what_is_there),
        cmocka_unit_test(test_bad_files_are_refused_with_the_place_named),
        cmocka_unit_test(test_views_group_runs_and_order_the_scaling_series),
        cmocka_unit_test(test_markdown_has_a_table_per_run_the_scaling_table_and_figures),
        cmocka_unit_test(test_markdown_says_whether_psnr_and_flip_rank_tiers_alike),
        cmocka_unit_test(test_es_runs_get_their_own_tables),
        cmocka_unit_test(test_markdown_of_no_rows_is_only_the_title),
        cmocka_unit_test(test_md_numbers_show_not_applicable_and_infinity),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_report — haircompare's report pieces without a browser or GL
   (examples/compare/): HTML escaping, the table's contents beside the
   bundle's measured numbers, the level x tier grid (stored levels and
   cards, the manifest's cells beside its own or a sentence saying it has
   none, where its levels came from), the reference every label names, the plot's
   axes, point coordinates and labels, the heatmap colours, the highlight
   crops, the manifest's lists and measured objects, and the report
   directory written whole or not at all. The page in a real browser (it
   fits a 1400 px window) is `make report-check`. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cJSON.h>
#include <cmocka.h>

#include "../examples/compare/crop.h"
#include "../examples/compare/heatmap.h"
#include "../examples/compare/report.h"
#include "../examples/compare/report_dir.h"
#include <hairtier/hairgen.h>
#include "support_scratch.h"

/* What a writer wrote, as a string (free it). */
typedef struct capture {
    char *text;
    size_t size;
    FILE *f;
} capture;

static FILE *capture_open(capture *c) {
    memset(c, 0, sizeof *c);
    c->f = open_memstream(&c->text, &c->size);
    assert_non_null(c->f);
    return c->f;
}

static char *capture_close(capture *c) {
    assert_int_equal(fclose(c->f), 0);
    return c->text;
}

static void expect_in(const char *text, const char *what) {
    if (!strstr(text, what)) fail_msg("\"%s\" not in:\n%.4000s", what, text);
}

static int count_of(const char *text, const char *what) {
    int n = 0;
    for (const char *p = strstr(text, what); p; p = strstr(p + 1, what)) n++;
    return n;
}

/* ---- escaping ---- */

static void test_escape_writes_every_markup_character_as_a_reference(void **state) {
    (void)state;
    capture c;
    report_escape(capture_open(&c), "<img src=\"x\" onerror='a&&b'> ok");
    report_escape(c.f, NULL);
    char *s = capture_close(&c);
    assert_string_equal(s, "&lt;img src=&quot;x&quot; onerror=&#39;a&amp;&amp;b&#39;&gt; ok");
    free(s);
}

/* ---- a report as haircompare fills it ---- */

static void add_dropped(report_tier *t, const char *text) {
    t->dropped[t->dropped_count] = strdup(text);
    assert_non_null(t->dropped[t->dropped_count]);
    t->dropped_count++;
}

/* full (reference), vertex (compared), fixed (not run, a hostile reason),
   gl11 (compared, the slowest). */
static void sample_report(report *r) {
    report_init(r);
    snprintf(r->material, sizeof r->material, "dark<brown>");
    r->bundle = "out/b&b";
    r->scene = "scenes/furball.json";
    snprintf(r->driver, sizeof r->driver, "llvmpipe (LLVM 15.0.6, 256 bits)");
    r->width = r->height = 64;
    r->frames = 5;
    r->tier_count = 4;
    r->reference = 0;
    report_tier *full = &r->tiers[0], *vertex = &r->tiers[1], *fixed = &r->tiers[2], *gl11 = &r->tiers[3];
    *full = (report_tier){ .name = "full", .needs = "GL 2.1, GLSL 1.20", .tier = HT_TIER_FULL, .known = true, .ran = true, .frame_ms = 10.0,
                           .compared = true, .cost_ratio = 1.0, .image = "full.png" };
    full->whole = full->hair = (ht_metrics){ .psnr_db = INFINITY, .ssim = 1.0 };
    *vertex = (report_tier){ .name = "vertex", .needs = "GL 2.0, GLSL 1.10", .tier = HT_TIER_VERTEX, .known = true, .ran = true,
                             .frame_ms = 5.25, .compared = true, .cost_ratio = 0.525, .image = "vertex.png",
                             .heatmap = "vertex-error.png" };
    vertex->whole = (ht_metrics){ .psnr_db = 34.437, .ssim = 0.96891, .delta_e00_mean = 0.5249,
                                  .delta_e00_p95 = 3.2204 };
    vertex->hair = (ht_metrics){ .psnr_db = 25.0, .ssim = 0.8, .delta_e00_mean = 2.611, .delta_e00_p95 = 9.28 };
    vertex->flip = (ht_flip_result){ .mean = 0.04321, .p95 = 0.1875 };
    add_dropped(vertex, "sparkle: approximated by its mean <0.134> & more");
    *fixed = (report_tier){ .name = "fixed", .needs = "GL 1.2, GL_ARB_multitexture", .tier = HT_TIER_FIXED,
                            .known = true,
                            .reason = "fixed: needs <script>alert(1)</script>" };
    add_dropped(fixed, "light 2: dropped");
    *gl11 = (report_tier){ .name = "gl11", .needs = "GL 1.1, 1 texture unit", .tier = HT_TIER_GL11, .known = true, .ran = true,
                           .frame_ms = 13.1, .compared = true, .cost_ratio = 1.31, .image = "gl11.png",
                           .heatmap = "gl11-error.png" };
    gl11->whole = (ht_metrics){ .psnr_db = 34.18, .ssim = 0.9667, .delta_e00_mean = 0.7204, .delta_e00_p95 = 3.53 };
    gl11->flip = (ht_flip_result){ .mean = 0.05, .p95 = 0.2 };
}

/* The text of the table row whose header cell is `name` (in a static buffer). */
static const char *row_of(const char *table, const char *name) {
    static char row[4096];
    char head[64];
    snprintf(head, sizeof head, "<tr><th scope=\"row\">%s</th>", name);
    const char *p = strstr(table, head);
    if (!p) fail_msg("no row for %s", name);
    size_t n = (size_t)(strstr(p, "</tr>") - p);
    snprintf(row, sizeof row, "%.*s", (int)n, p);
    return row;
}

static void test_table_has_a_row_per_tier_with_its_numbers_needs_and_drops(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    capture c;
    report_write_table(capture_open(&c), &r);
    char *t = capture_close(&c);
    assert_int_equal(count_of(t, "<tr><th scope=\"row\">"), 4);
    expect_in(t, "this run, against <b>full</b>");
    const char *full = row_of(t, "full");
    expect_in(full, "<td class=\"num\">10.0</td><td class=\"num\">1.00&times;</td><td class=\"num\">&infin;</td>"
                    "<td class=\"num\">1.0000</td><td class=\"num\">0.00</td><td class=\"num\">0.00</td>");
    const char *vertex = row_of(t, "vertex");
    expect_in(vertex, "<td class=\"num\">5.2</td><td class=\"num\">0.53&times;</td><td class=\"num\">34.4</td>"
                      "<td class=\"num\">0.9689</td><td class=\"num\">0.52</td><td class=\"num\">3.22</td>"
                      "<td class=\"num\">0.0432 / 0.1875</td><td class=\"num\">2.61 / 9.28</td>");
    const char *fixed = row_of(t, "fixed");
    expect_in(fixed, "<td colspan=\"8\" class=\"notrun\">not run: fixed: needs &lt;script&gt;alert(1)&lt;/script&gt;</td>");
    assert_null(strstr(t, "<script"));
    free(t);

    report_write_needs(capture_open(&c), &r);
    t = capture_close(&c);
    assert_int_equal(count_of(t, "<tr><th scope=\"row\">"), 4);
    expect_in(row_of(t, "full"), "<td class=\"dropped\">nothing</td>");
    vertex = row_of(t, "vertex");
    expect_in(vertex, "<td class=\"needs\">GL 2.0, GLSL 1.10</td>");
    expect_in(vertex, "<li>sparkle: approximated by its mean &lt;0.134&gt; &amp; more</li>");
    expect_in(row_of(t, "fixed"), "<li>light 2: dropped</li>");
    free(t);
    report_free(&r);
}

/* Under the table: whether PSNR and FLIP rank the compared tiers (the
   reference aside) alike, naming the first pair they disagree on. */
static void test_table_says_whether_psnr_and_flip_rank_tiers_alike(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    capture c;
    report_write_table(capture_open(&c), &r);
    char *t = capture_close(&c);
    expect_in(t, "<p class=\"note order\">PSNR and FLIP rank the 2 compared tiers alike (1 pair both tell apart).</p>");
    free(t);
    for (int t2 = 0; t2 < r.tier_count; t2++)
        if (!strcmp(r.tiers[t2].name, "gl11")) r.tiers[t2].flip.mean = 0.01; /* lower PSNR, yet closer by FLIP */
    report_write_table(capture_open(&c), &r);
    t = capture_close(&c);
    expect_in(t, "PSNR and FLIP disagree on 1 of the 1 pairs both tell apart; first: PSNR ranks <b>vertex</b> "
                 "closer, FLIP <b>gl11</b>.</p>");
    free(t);
    report_free(&r);
}

/* The manifest's measured numbers sit beside this run's, in the
   manifest's precision, labelled; a tier without them says so, and a
   bundle without any says that instead of showing empty columns. */
static void test_table_shows_the_bundles_measured_numbers_beside_its_own(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    r.tiers[0].measured = (ht_manifest_measured){ .present = true, .psnr_db = INFINITY, .ssim = 1.0,
                                                  .flip_mean = NAN, .flip_p95 = NAN, .cost_ratio = 1.0, .scene = "furball.json",
                                                  .driver = "llvmpipe <LLVM>" };
    r.tiers[1].measured = (ht_manifest_measured){ .present = true, .psnr_db = 41.23, .ssim = 0.9712,
                                                  .delta_e00_mean = 0.431, .delta_e00_p95 = 2.875,
                                                  .flip_mean = 0.0412, .flip_p95 = 0.1799, .cost_ratio = 0.6789, .scene = "furball.json",
                                                  .driver = "llvmpipe <LLVM>" };
    capture c;
    report_write_table(capture_open(&c), &r);
    char *t = capture_close(&c);
    expect_in(t, "the bundle&#8217;s <code>measured</code> (manifest.json, hairgen --measure)");
    expect_in(row_of(t, "vertex"), "<td class=\"num\">2.61 / 9.28</td>"
                                   "<td class=\"num measured\">0.68&times;</td><td class=\"num measured\">41.23</td>"
                                   "<td class=\"num measured\">0.9712</td><td class=\"num measured\">0.431</td>"
                                   "<td class=\"num measured\">2.875</td>"
                                   "<td class=\"num measured\">0.0412 / 0.1799</td>");
    expect_in(row_of(t, "full"), "<td class=\"num measured\">&infin;</td>");
    /* measured before FLIP: the manifest has no flip numbers (NaN) */
    expect_in(row_of(t, "full"), "<td class=\"num measured\">n/a / n/a</td>");
    expect_in(row_of(t, "gl11"), "<td colspan=\"6\" class=\"measured none\">not measured</td>");
    /* a tier that cannot run here still shows what the bundle measured for it */
    expect_in(row_of(t, "fixed"), "not measured");
    expect_in(t, "on scene <code>furball.json</code> and driver <code>llvmpipe &lt;LLVM&gt;</code>");
    assert_null(strstr(t, "has no measured numbers"));
    free(t);

    for (int i = 0; i < r.tier_count; i++) r.tiers[i].measured.present = false;
    report_write_table(capture_open(&c), &r);
    t = capture_close(&c);
    assert_null(strstr(t, "class=\"num measured\""));
    assert_null(strstr(t, "<th class=\"measured\">"));
    expect_in(t, "The bundle has no measured numbers: no tier of its manifest.json carries a <code>measured</code>");
    free(t);
    report_free(&r);
}

/* A Marschner bundle: marschner is the reference, and no label on the
   page says "full" is. */
static void test_every_label_names_the_reference_it_used(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    /* marschner first, then full: the sample's tiers shift down one */
    memmove(&r.tiers[1], &r.tiers[0], sizeof r.tiers[0] * 4);
    r.tier_count = 5;
    r.tiers[0] = (report_tier){ .name = "marschner", .needs = "GL 2.1, GLSL 1.20", .tier = HT_TIER_MARSCHNER,
                                .known = true, .ran = true, .frame_ms = 20.0, .compared = true, .cost_ratio = 1.0,
                                .image = "marschner.png" };
    r.tiers[0].whole = r.tiers[0].hair = (ht_metrics){ .psnr_db = INFINITY, .ssim = 1.0 };
    r.tiers[1].dropped_count = 0; /* full's drops moved with it: none */
    snprintf(r.tiers[1].heatmap, sizeof r.tiers[1].heatmap, "full-error.png");
    r.tiers[1].cost_ratio = 0.5;

    assert_int_equal(report_pick_reference(&r), 0);
    r.reference = report_pick_reference(&r);
    assert_string_equal(report_reference_name(&r), "marschner");
    capture c;
    assert_int_equal(report_write_page(capture_open(&c), &r), 0);
    char *html = capture_close(&c);
    expect_in(html, "reference: <b>marschner</b>");
    expect_in(html, "<h2>Measurements against marschner</h2>");
    expect_in(html, "this run, against <b>marschner</b>");
    expect_in(html, "vs marschner: &#916;E00 mean");
    expect_in(html, "0.50&times; marschner&#8217;s cost");
    expect_in(html, "the reference: marschner<br>no error to show");
    expect_in(html, "per-pixel CIEDE2000 (&#916;E00) against marschner</text>");
    expect_in(html, "cost: frame time / marschner&#8217;s</text>");
    expect_in(html, "&#916;E00 mean against marschner (lower is better)");
    expect_in(html, "median frame time over marschner&#8217;s");
    for (const char *const *w = (const char *const[]){ "against full", "against <b>full", "vs full", "full&#8217;s",
                                                       "reference (full)", "reference: full", "&#215; full", NULL };
         *w; w++)
        if (strstr(html, *w)) fail_msg("\"%s\" on a page whose reference is marschner", *w);
    free(html);

    /* marschner did not run: full is the reference; neither: none */
    r.tiers[0].ran = false;
    assert_int_equal(report_pick_reference(&r), 1);
    r.tiers[1].ran = false;
    assert_int_equal(report_pick_reference(&r), -1);
    r.reference = -1;
    assert_string_equal(report_reference_name(&r), "the reference");
    report_free(&r);
}

static void test_table_shows_dashes_where_full_did_not_run(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    for (int i = 0; i < r.tier_count; i++) r.tiers[i].compared = false;
    r.tiers[0].ran = false;
    capture c;
    report_write_table(capture_open(&c), &r);
    char *t = capture_close(&c);
    const char *vertex = row_of(t, "vertex");
    expect_in(vertex, "<td class=\"num\">5.2</td><td class=\"num\">&ndash;</td><td class=\"num\">&ndash;</td>");
    assert_null(strstr(vertex, "34.4"));
    free(t);
    report_free(&r);
}

/* ---- the plot ---- */

static void test_axis_fits_round_steps_from_zero_to_at_or_above_the_maximum(void **state) {
    (void)state;
    static const struct { double max, hi, step; int ticks; } cases[] = {
        { 0.72 * 1.1, 0.8, 0.1, 9 }, { 1.31 * 1.08, 1.6, 0.2, 9 }, { 1.0, 1.0, 0.1, 11 },
        { 7.0, 7.0, 1.0, 8 },        { 23.0, 25.0, 5.0, 6 },        { 1e-3, 1e-3, 1e-4, 11 },
        { 0.0, 1.0, 0.1, 11 },       { NAN, 1.0, 0.1, 11 },         { 480.0, 500.0, 50.0, 11 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        plot_axis a = plot_axis_fit(cases[i].max);
        if (fabs(a.hi - cases[i].hi) > 1e-9 * cases[i].hi || fabs(a.step - cases[i].step) > 1e-9 * cases[i].step ||
            a.ticks != cases[i].ticks)
            fail_msg("max %g: hi %g step %g ticks %d, expected %g %g %d", cases[i].max, a.hi, a.step, a.ticks,
                     cases[i].hi, cases[i].step, cases[i].ticks);
        if (isfinite(cases[i].max)) assert_true(a.hi >= cases[i].max);
        assert_true(a.ticks >= 5 && a.ticks <= 11);
    }
    plot_axis a = plot_axis_fit(0.8);
    assert_true(plot_map(&a, 0.0, 72, 612) == 72);
    assert_true(fabs(plot_map(&a, 0.4, 72, 612) - 342) < 1e-9);
    assert_true(fabs(plot_map(&a, 0.8, 330, 20) - 20) < 1e-9); /* upward y */
}

/* A circle's centre, from the SVG text after `after`. */
static void circle_after(const char *svg, const char *after, double *cx, double *cy) {
    const char *p = strstr(svg, after);
    assert_non_null(p);
    const char *c = p;
    const char *last = NULL;
    for (const char *q = strstr(svg, "<circle"); q && q < c; q = strstr(q + 1, "<circle")) last = q;
    assert_non_null(last);
    assert_int_equal(sscanf(last, "<circle cx=\"%lf\" cy=\"%lf\"", cx, cy), 2);
}

static void test_plot_puts_each_compared_tier_at_its_cost_and_error(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    capture c;
    report_write_plot(capture_open(&c), &r);
    char *svg = capture_close(&c);
    expect_in(svg, "<svg class=\"plot\" width=\"720\" height=\"400\"");
    assert_int_equal(count_of(svg, "<circle"), 3); /* full, vertex, gl11; fixed did not run */
    /* axes: x to 1.31 x 1.15 -> 1.6, y to 0.7204 x 1.1 -> 0.8; plot area x 72..692, y 330..20 */
    expect_in(svg, ">1.6</text>");
    expect_in(svg, ">0.8</text>");
    expect_in(svg, "cost: frame time / full&#8217;s");
    expect_in(svg, "&#916;E00 mean against full (lower is better)");
    double cx, cy;
    expect_in(svg, "<title>vertex: cost 0.53&#215; full, &#916;E00 mean 0.52</title>");
    circle_after(svg, ">vertex</text>", &cx, &cy);
    assert_true(fabs(cx - (72 + 620 * 0.525 / 1.6)) < 0.06 && fabs(cy - (330 - 310 * 0.5249 / 0.8)) < 0.06);
    circle_after(svg, ">gl11</text>", &cx, &cy);
    assert_true(fabs(cx - (72 + 620 * 1.31 / 1.6)) < 0.06 && fabs(cy - (330 - 310 * 0.7204 / 0.8)) < 0.06);
    circle_after(svg, ">full</text>", &cx, &cy);
    assert_true(fabs(cx - (72 + 620 / 1.6)) < 0.06 && fabs(cy - 330) < 0.06);
    free(svg);

    /* Names from the manifest are escaped in labels too. */
    snprintf(r.tiers[1].name, sizeof r.tiers[1].name, "v<x>");
    report_write_plot(capture_open(&c), &r);
    svg = capture_close(&c);
    expect_in(svg, ">v&lt;x&gt;</text>");
    expect_in(svg, "<title>v&lt;x&gt;: cost");
    free(svg);

    /* Nothing compared: a sentence, no picture. */
    for (int i = 0; i < r.tier_count; i++) r.tiers[i].compared = false;
    report_write_plot(capture_open(&c), &r);
    svg = capture_close(&c);
    assert_null(strstr(svg, "<svg"));
    expect_in(svg, "no reference tier (marschner or full) ran here");
    free(svg);
    report_free(&r);
}

static void test_labels_that_would_overlap_are_stacked_below(void **state) {
    (void)state;
    /* a and b at nearly the same height and overlapping in x; c far away. */
    double px[3] = { 90, 80, 390 }, py[3] = { 200, 205, 203 }, x[3] = { 100, 90, 400 }, w[3] = { 80, 80, 80 }, ly[3];
    plot_place_labels(px, py, x, w, 3, ly);
    assert_true(ly[0] == 204);           /* the higher point keeps its place */
    assert_true(ly[1] == ly[0] + 16);    /* b goes under a */
    assert_true(ly[2] == 207);           /* c overlaps nothing */
    /* a third label on the same spot goes under the second */
    double px2[3] = { 90, 90, 90 }, py2[3] = { 50, 50, 50 }, x2[3] = { 100, 100, 100 }, ly2[3];
    plot_place_labels(px2, py2, x2, w, 3, ly2);
    assert_true(ly2[0] == 54 && ly2[1] == 70 && ly2[2] == 86);
    /* a label drawn left of its point across another point moves below that point */
    double px3[2] = { 300, 200 }, py3[2] = { 100, 102 }, x3[2] = { 190, 210 }, w3[2] = { 100, 60 }, ly3[2];
    plot_place_labels(px3, py3, x3, w3, 2, ly3);
    assert_true(ly3[0] == 102 + 6 + 14); /* from 104: it covered the point at (200, 102) */
    assert_true(ly3[1] == 106);          /* right of its point: clear of the first label, now lower */
}

/* ---- the heatmap ---- */

static void test_heatmap_runs_black_to_white_with_rising_luminance(void **state) {
    (void)state;
    uint8_t c[3], prev[3];
    heatmap_colour(0.0, c);
    assert_true(c[0] == 0 && c[1] == 0 && c[2] == 0);
    heatmap_colour(1.0, c);
    assert_true(c[0] == 255 && c[1] == 255 && c[2] == 255);
    heatmap_colour(7.0, c);
    assert_true(c[0] == 255 && c[1] == 255 && c[2] == 255);
    heatmap_colour(-1.0, c);
    assert_true(c[0] == 0 && c[1] == 0 && c[2] == 0);
    heatmap_colour(NAN, c);
    assert_true(c[0] == 0 && c[1] == 0 && c[2] == 0);
    heatmap_colour(0.0, prev);
    bool coloured = false;
    for (int i = 1; i <= 64; i++) {
        heatmap_colour(i / 64.0, c);
        if (!(heatmap_luma(c) > heatmap_luma(prev))) fail_msg("luma falls at %d/64", i);
        coloured = coloured || c[0] != c[1] || c[1] != c[2];
        memcpy(prev, c, 3);
    }
    assert_true(coloured); /* a colour map, not a grey ramp */
}

static void test_heatmap_image_scales_and_flips_gl_rows(void **state) {
    (void)state;
    const double map[2 * 3] = { 0, 20, /* bottom row (GL first) */ 10, 10, 40, 5 /* top row */ };
    ht_image img = { 0 };
    assert_int_equal(heatmap_image(map, 2, 3, true, 20.0, &img), HT_OK);
    assert_int_equal(img.channels, 3);
    uint8_t mid[3], quarter[3];
    heatmap_colour(0.5, mid);
    heatmap_colour(0.25, quarter);
    static const uint8_t white[3] = { 255, 255, 255 }, black[3] = { 0, 0, 0 };
    assert_memory_equal(img.pixels, white, 3);  /* top-left: 40 / 20, clamped */
    assert_memory_equal(img.pixels + 3, quarter, 3);
    assert_memory_equal(img.pixels + 6, mid, 3);
    assert_memory_equal(img.pixels + 12, black, 3);  /* bottom-left */
    assert_memory_equal(img.pixels + 15, white, 3);
    ht_image_free(&img);
    assert_int_equal(heatmap_image(map, 2, 3, true, 0.0, &img), HT_ERR_INVALID_ARGUMENT);
}

/* ---- the page ---- */

static void test_page_links_every_image_relatively_and_runs_no_script(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    capture c;
    assert_int_equal(report_write_page(capture_open(&c), &r), 0);
    char *html = capture_close(&c);
    expect_in(html, "<!DOCTYPE html>");
    expect_in(html, REPORT_DIR_GENERATOR_MARK);
    expect_in(html, "<title>hairtier tiers: dark&lt;brown&gt;</title>");
    expect_in(html, "bundle <code>out/b&amp;b</code>");
    for (const char *const *f = (const char *const[]){ "full.png", "vertex.png", "vertex-error.png", "gl11.png",
                                                        "gl11-error.png", NULL };
         *f; f++) {
        char tag[64];
        snprintf(tag, sizeof tag, "<img src=\"%s\"", *f);
        assert_int_equal(count_of(html, tag), 1);
    }
    assert_int_equal(count_of(html, "<img "), 5);
    assert_null(strstr(html, "<script"));
    assert_null(strstr(html, "file:"));
    assert_null(strstr(html, "src=\"/"));
    expect_in(html, "this device cannot run this tier:<br>fixed: needs &lt;script&gt;");
    expect_in(html, "<linearGradient id=\"heat\"");
    expect_in(html, ">&#8805; 20</text>");
    /* cards that wrap, images at their pixel size where they fit (the
       screenshot check finds them) and scaled down where they do not */
    expect_in(html, ".tiers{display:flex;flex-wrap:wrap;");
    expect_in(html, ".tier{width:64px;max-width:100%;");
    expect_in(html, "<img src=\"vertex.png\" width=\"64\" height=\"64\"");
    assert_null(strstr(html, "body{margin:0;padding:24px;width:"));
    free(html);
    report_free(&r);
}

/* ---- the highlight crops ---- */

static void test_brightest_window_is_found_over_hair_pixels_only(void **state) {
    (void)state;
    ht_image img = { 0 };
    assert_int_equal(ht_image_alloc(&img, 96, 64, 3), HT_OK);
    const uint8_t bg[3] = { 240, 240, 250 }; /* a bright sky: never the highlight */
    for (size_t i = 0; i < (size_t)96 * 64; i++) memcpy(img.pixels + 3 * i, bg, 3);
    /* dim hair over the left (less in any window than the patch), a bright 6x5 patch at (70, 40) */
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 40; x++) memset(img.pixels + 3 * ((size_t)y * 96 + (size_t)x), 10, 3);
    for (int y = 40; y < 45; y++)
        for (int x = 70; x < 76; x++) memset(img.pixels + 3 * ((size_t)y * 96 + (size_t)x), 250, 3);
    crop_region r;
    assert_int_equal(crop_find_brightest(&img, bg, 16, &r), HT_OK);
    assert_true(r.w == 16 && r.h == 16);
    /* the patch whole inside, and the first such window (top, then left) */
    assert_true(r.x == 76 - 16 && r.y == 45 - 16);
    /* larger than the image: the image */
    assert_int_equal(crop_find_brightest(&img, bg, 100, &r), HT_OK);
    assert_true(r.x == 0 && r.y == 0 && r.w == 96 && r.h == 64);
    assert_int_equal(crop_find_brightest(&img, bg, 0, &r), HT_ERR_INVALID_ARGUMENT);
    ht_image_free(&img);
}

static void test_zoom_repeats_each_pixel_scale_times(void **state) {
    (void)state;
    ht_image src = { 0 }, out = { 0 };
    assert_int_equal(ht_image_alloc(&src, 4, 3, 3), HT_OK);
    for (int i = 0; i < 4 * 3 * 3; i++) src.pixels[i] = (uint8_t)(i * 7);
    const crop_region r = { .x = 1, .y = 1, .w = 2, .h = 2 };
    assert_int_equal(crop_zoom(&src, &r, 4, &out), HT_OK);
    assert_true(out.width == 8 && out.height == 8 && out.channels == 3);
    for (int y = 0; y < 8; y++)
        for (int x = 0; x < 8; x++)
            assert_memory_equal(out.pixels + 3 * (y * 8 + x), src.pixels + 3 * ((1 + y / 4) * 4 + 1 + x / 4), 3);
    ht_image_free(&out);
    const crop_region outside = { .x = 3, .y = 0, .w = 2, .h = 2 };
    assert_int_equal(crop_zoom(&src, &outside, 4, &out), HT_ERR_INVALID_ARGUMENT);
    ht_image_free(&src);
}

static void test_page_shows_each_tiers_crop_over_its_heatmaps(void **state) {
    (void)state;
    report r;
    sample_report(&r);
    r.crop = (crop_region){ .x = 12, .y = 7, .w = 32, .h = 32 };
    for (int t = 0; t < r.tier_count; t++) {
        if (!r.tiers[t].ran) continue;
        char name[sizeof r.tiers[t].name]; /* a copy: -O1's -Wrestrict takes two fields for overlapping */
        memcpy(name, r.tiers[t].name, sizeof name);
        snprintf(r.tiers[t].crop, sizeof r.tiers[t].crop, "%s-crop.png", name);
        if (t != r.reference) snprintf(r.tiers[t].heatmap_crop, sizeof r.tiers[t].heatmap_crop, "%s-error-crop.png", name);
    }
    capture c;
    assert_int_equal(report_write_page(capture_open(&c), &r), 0);
    char *html = capture_close(&c);
    expect_in(html, "<h2>Brightest highlight, 4&times;</h2>");
    expect_in(html, "The 32&times;32 pixels at (12, 7)");
    expect_in(html, "where <b>full</b>&#8217;s hair is brightest");
    expect_in(html, "<img src=\"full-crop.png\" width=\"128\" height=\"128\"");
    expect_in(html, "<img src=\"vertex-error-crop.png\" width=\"128\" height=\"128\"");
    assert_int_equal(count_of(html, "-crop.png\""), 3 + 2); /* full, vertex, gl11; heatmaps but full's */
    free(html);

    /* a frame smaller than the window: the crops are as large as it, 4x */
    r.crop = (crop_region){ .x = 0, .y = 0, .w = 20, .h = 10 };
    report_write_page(capture_open(&c), &r);
    html = capture_close(&c);
    expect_in(html, "<img src=\"vertex-crop.png\" width=\"80\" height=\"40\"");
    expect_in(html, ".crops .tier{width:80px}");
    free(html);

    r.crop.w = 0; /* no reference ran: no crops */
    report_write_page(capture_open(&c), &r);
    html = capture_close(&c);
    assert_null(strstr(html, "Brightest highlight"));
    free(html);
    report_free(&r);
}

/* ---- the manifest's lists ---- */

static char scratch[64];

static int setup_scratch(void **state) {
    (void)state;
    return ht_test_scratch_create(scratch, sizeof scratch, "report") ? 0 : -1;
}

static int teardown_scratch(void **state) {
    (void)state;
    return ht_test_scratch_remove(scratch);
}

static void test_bundle_gives_tiers_in_order_with_needs_and_drops(void **state) {
    (void)state;
    char bundle[128], err[1024];
    snprintf(bundle, sizeof bundle, "%s/bundle", scratch);
    assert_int_equal(ht_generate_bundle("materials/dark-brown.json", "scenes/furball.json", bundle, NULL, err,
                                        sizeof err), HT_OK);
    report r;
    report_init(&r);
    if (report_read_bundle(&r, bundle, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_string_equal(r.material, "dark-brown");
    assert_int_equal(r.tier_count, 5);
    static const char *const names[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int i = 0; i < 5; i++) {
        assert_string_equal(r.tiers[i].name, names[i]);
        assert_true(r.tiers[i].known);
    }
    assert_string_equal(r.tiers[0].needs, "GL 2.1, GLSL 1.20, 2 texture units");
    assert_string_equal(r.tiers[1].needs, "GL 2.0, GLSL 1.10, GL_ARB_texture_env_combine, 4 texture units");
    assert_string_equal(r.tiers[4].needs, "GL 1.1, 1 texture unit");
    assert_int_equal(r.tiers[0].dropped_count, 0);
    assert_true(r.tiers[3].dropped_count >= 3);
    /* dark-brown's fill light shows in highlights only: the fixed tier drops
       it (no sub-pass) and says why */
    bool second_light = false;
    for (int i = 0; i < r.tiers[3].dropped_count; i++)
        second_light |= strncmp(r.tiers[3].dropped[i], "light 2: dropped: diffuse", 25) == 0;
    assert_true(second_light);
    for (int i = 0; i < 5; i++) assert_false(r.tiers[i].measured.present); /* hairgen without --measure */
    report_free(&r);

    /* The manifest's measured objects are read as the runtime reads them. */
    cJSON *root = ht_test_read_json(bundle, "manifest.json");
    cJSON *vertex = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "tiers"), 1);
    cJSON_AddItemToObject(vertex, "measured",
                          cJSON_Parse("{\"psnr_db\": 41.23, \"ssim\": 0.9712, \"delta_e00_mean\": 0.431, "
                                      "\"delta_e00_p95\": 2.875, \"cost_ratio\": 0.6789, \"scene\": \"x.json\"}"));
    char *measured = cJSON_Print(root);
    ht_test_write_file(bundle, "manifest.json", measured);
    free(measured);
    cJSON_Delete(root);
    report_init(&r);
    if (report_read_bundle(&r, bundle, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_false(r.tiers[0].measured.present);
    assert_true(r.tiers[1].measured.present);
    assert_true(r.tiers[1].measured.psnr_db == 41.23 && r.tiers[1].measured.cost_ratio == 0.6789);
    assert_string_equal(r.tiers[1].measured.scene, "x.json");
    assert_int_equal(r.tiers[1].tier, HT_TIER_VERTEX);
    report_free(&r);

    /* A list holding something else than strings is named by its field. */
    char *text = ht_test_read_file(bundle, "manifest.json");
    char *dropped = strstr(strstr(text, "\"name\":\t\"vertex\""), "\"dropped\":\t[");
    assert_non_null(dropped);
    dropped += strlen("\"dropped\":\t[");
    memmove(dropped + 3, dropped, strlen(dropped) + 1);
    memcpy(dropped, "7, ", 3);
    ht_test_write_file(bundle, "manifest.json", text);
    report_init(&r);
    assert_int_equal(report_read_bundle(&r, bundle, err, sizeof err), HT_ERR_PARSE);
    expect_in(err, "bundle/manifest.json: tiers[1].dropped[0]: expected a string");
    report_free(&r);

    snprintf(bundle, sizeof bundle, "%s/no-bundle", scratch);
    report_init(&r);
    assert_int_not_equal(report_read_bundle(&r, bundle, err, sizeof err), HT_OK);
    expect_in(err, "no-bundle/manifest.json: cannot read");
    report_free(&r);
}

/* ---- the report directory ---- */

static bool is_dir(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static void test_report_dir_is_written_whole_and_replaces_only_a_report(void **state) {
    (void)state;
    char dir[128], tmp[4096], err[1024], path[4300];
    snprintf(dir, sizeof dir, "%s/report", scratch);
    /* new: the temporary sibling holds the files until published */
    assert_int_equal(report_dir_begin(dir, tmp, sizeof tmp, err, sizeof err), HT_OK);
    assert_true(strncmp(tmp, dir, strlen(dir)) == 0 && strstr(tmp, ".tmp-"));
    ht_test_write_file(tmp, "index.html", "<head>" REPORT_DIR_GENERATOR_MARK "</head> first");
    assert_false(is_dir(dir));
    assert_int_equal(report_dir_publish(tmp, dir, err, sizeof err), HT_OK);
    assert_false(is_dir(tmp));
    expect_in(ht_test_read_file(dir, "index.html"), "first");

    /* an earlier report is replaced whole: its other files go too */
    ht_test_write_file(dir, "old.png", "x");
    assert_int_equal(report_dir_begin(dir, tmp, sizeof tmp, err, sizeof err), HT_OK);
    ht_test_write_file(tmp, "index.html", "<head>" REPORT_DIR_GENERATOR_MARK "</head> second");
    assert_int_equal(report_dir_publish(tmp, dir, err, sizeof err), HT_OK);
    expect_in(ht_test_read_file(dir, "index.html"), "second");
    snprintf(path, sizeof path, "%s/old.png", dir);
    assert_int_equal(access(path, F_OK), -1);
    assert_false(is_dir(tmp));

    /* a failed run: abandoned, nothing left, the report as it was */
    assert_int_equal(report_dir_begin(dir, tmp, sizeof tmp, err, sizeof err), HT_OK);
    ht_test_write_file(tmp, "half.png", "x");
    report_dir_remove(tmp);
    assert_false(is_dir(tmp));
    expect_in(ht_test_read_file(dir, "index.html"), "second");

    /* someone else's directory is refused and untouched */
    char other[128];
    snprintf(other, sizeof other, "%s/photos", scratch);
    assert_int_equal(mkdir(other, 0755), 0);
    ht_test_write_file(other, "index.html", "<html>my page</html>");
    assert_int_equal(report_dir_begin(other, tmp, sizeof tmp, err, sizeof err), HT_ERR_IO);
    expect_in(err, "photos: exists and is not a haircompare report");
    expect_in(ht_test_read_file(other, "index.html"), "my page");

    /* a file where the directory should be, or below a file */
    ht_test_write_file(scratch, "a-file", "x");
    snprintf(path, sizeof path, "%s/a-file", scratch);
    assert_int_equal(report_dir_begin(path, tmp, sizeof tmp, err, sizeof err), HT_ERR_IO);
    expect_in(err, "a-file: exists and is not a directory");
    snprintf(path, sizeof path, "%s/a-file/report", scratch);
    assert_int_equal(report_dir_begin(path, tmp, sizeof tmp, err, sizeof err), HT_ERR_IO);
    expect_in(err, "a-file/report: cannot create a temporary directory beside it: Not a directory");
    /* an empty directory is fine */
    snprintf(path, sizeof path, "%s/empty", scratch);
    assert_int_equal(mkdir(path, 0755), 0);
    assert_int_equal(report_dir_begin(path, tmp, sizeof tmp, err, sizeof err), HT_OK);
    assert_int_equal(report_dir_publish(tmp, path, err, sizeof err), HT_OK);
}

/* ---- the LOD x tier grid ---- */

/* sample_report's tiers with a grid at a quarter size of two strand levels
   and cards (the bundle's stored levels), and the manifest's cells for
   some of them. */
static void sample_lod_report(report *r) {
    sample_report(r);
    r->measured_lods.cell_count = 5;
    r->measured_lods.cells[0] = (ht_manifest_lod_cell){ .level = 1, .tier = "vertex", .strands = 200, .size = 0.25,
                                                        .psnr_db = 31.25, .cost_ratio = 0.375 };
    r->measured_lods.cells[1] = (ht_manifest_lod_cell){ .level = 1, .tier = "vertex", .strands = 200, .size = 1.0,
                                                        .psnr_db = 20, .cost_ratio = 0.5 };
    r->measured_lods.cells[2] = (ht_manifest_lod_cell){ .level = 0, .tier = "full", .strands = 400, .size = 0.5,
                                                        .psnr_db = INFINITY, .cost_ratio = 1 };
    r->measured_lods.cells[3] = (ht_manifest_lod_cell){ .level = 2, .cards = 1, .tier = "gl11", .strands = 25,
                                                        .size = 0.25, .psnr_db = 24.75, .cost_ratio = 0.0625 };
    /* measured on another ladder: level 1 of 150 strands */
    r->measured_lods.cells[4] = (ht_manifest_lod_cell){ .level = 1, .tier = "full", .strands = 150, .size = 0.25,
                                                        .psnr_db = 29, .cost_ratio = 0.5 };
    r->lods = (report_lod_grid){ .levels = 3, .source = REPORT_LOD_STORED, .size = report_lod_size(&r->measured_lods),
                                 .width = 16, .height = 16, .strands = { 400, 200, 25 },
                                 .cards = { false, false, true }, .strands_per_card = { 0, 0, 16 } };
    const int ran[3] = { 0, 1, 3 }; /* full, vertex, gl11: fixed did not run */
    for (int l = 0; l < 3; l++)
        for (int i = 0; i < 3; i++) {
            report_lod_cell *c = &r->lods.cells[l][ran[i]];
            c->ran = true;
            static const char *const names[3] = { "full", "vertex", "gl11" };
            snprintf(c->image, sizeof c->image, "lod%d-%s.png", l, names[i]);
            c->cost_ratio = l ? 0.5 : 1.0;
            c->whole.psnr_db = l == 0 && i == 0 ? INFINITY : 30.0 + i + l;
        }
    report_lod_attach_measured(r);
}

static char *page_of(const report *r) {
    capture c;
    assert_int_equal(report_write_page(capture_open(&c), r), 0);
    return capture_close(&c);
}

static void test_lod_grid_shows_every_level_by_every_tier_that_ran(void **state) {
    (void)state;
    report r;
    sample_lod_report(&r);
    /* 0.25 measured: the quarter size, and its cells of the rows' geometry only */
    assert_true(r.lods.size == 0.25);
    assert_true(r.lods.cells[1][1].measured && r.lods.cells[1][1].measured_psnr_db == 31.25);
    assert_true(r.lods.cells[2][3].measured && r.lods.cells[2][3].measured_cost_ratio == 0.0625);
    assert_false(r.lods.cells[0][0].measured);
    assert_false(r.lods.cells[1][0].measured); /* 150 strands: not this row's level 1 */
    assert_int_equal(r.lods.measured_cells, 2);
    assert_int_equal(r.lods.other_cells, 1);
    char *html = page_of(&r);
    expect_in(html, "<h2>Geometry levels &#215; tiers at 0.25 of the scene&#8217;s size</h2>");
    expect_in(html, "Levels: <b>the bundle&#8217;s stored levels</b> (<code>lods.bin</code>, made from this "
                    "scene&#8217;s mesh): 2 strand levels and 1 of cards");
    expect_in(html, "against (level 0, <b>full</b>) at this size");
    expect_in(html, "<div class=\"lodhead\">level 1<br><span>200 strands</span></div>");
    expect_in(html, "<div class=\"lodhead\">cards<br><span>level 2: 25 cards of 16 strands</span></div>");
    for (int l = 0; l < 3; l++)
        for (const char *const *t = (const char *const[]){ "full", "vertex", "gl11", NULL }; *t; t++) {
            char tag[160];
            snprintf(tag, sizeof tag, "<img src=\"lod%d-%s.png\" width=\"16\" height=\"16\" alt=\"%s %d, %s\">", l, *t,
                     l == 2 ? "cards, level" : "level", l, *t);
            assert_int_equal(count_of(html, tag), 1);
        }
    assert_null(strstr(html, "lod0-fixed"));
    expect_in(html, "&#8734; dB, 1.00&#215;<br><span class=\"measured\">bundle: not measured</span>");
    expect_in(html, "32.0 dB, 0.50&#215;<br><span class=\"measured\">bundle 31.2 dB, 0.38&#215;</span>");
    expect_in(html, "34.0 dB, 0.50&#215;<br><span class=\"measured\">bundle 24.8 dB, 0.06&#215;</span>");
    expect_in(html, "1 of its measured cells at this size are of other geometry");
    /* sample_report's 5 images above, 9 grid cells; every row wraps rather than scroll */
    assert_int_equal(count_of(html, "<img "), 14);
    assert_int_equal(count_of(html, "<div class=\"lodrow\">"), 3);
    expect_in(html, ".lodrow{display:flex;flex-wrap:wrap;");
    free(html);
    report_free(&r);
}

/* Without the manifest's cells the grid shows this run's numbers alone
   and says the bundle has none; levels built from the scene say so. */
static void test_lod_grid_without_measured_cells_says_so_and_where_its_levels_came_from(void **state) {
    (void)state;
    report r;
    sample_lod_report(&r);
    r.measured_lods.cell_count = 0;
    r.lods.size = report_lod_size(&r.measured_lods);
    assert_true(r.lods.size == REPORT_LOD_SIZE);
    for (int l = 0; l < 3; l++)
        for (int t = 0; t < REPORT_MAX_TIERS; t++) r.lods.cells[l][t].measured = false;
    report_lod_attach_measured(&r);
    assert_int_equal(r.lods.measured_cells, 0);
    assert_int_equal(r.lods.other_cells, 0);
    char *html = page_of(&r);
    expect_in(html, "The bundle has no measured numbers for these cells (<code>hairgen --measure-lods</code>");
    assert_null(strstr(html, "class=\"measured\">bundle"));
    assert_null(strstr(html, "other geometry"));
    expect_in(html, "32.0 dB, 0.50&#215;</p></figure>");
    free(html);
    /* built from the scene: the bundle stores none, or another scene's */
    r.lods.levels = 2;
    r.lods.source = REPORT_LOD_BUILT;
    html = page_of(&r);
    expect_in(html, "Levels: <b>built from the scene</b> (levels 0 to 1 of <code>lod.h</code>&#8217;s ladder): "
                    "the bundle stores none.");
    assert_null(strstr(html, "cards"));
    free(html);
    r.lods.source = REPORT_LOD_BUILT_OTHER_SCENE;
    html = page_of(&r);
    expect_in(html, "the bundle&#8217;s <code>lods.bin</code> was made from another scene&#8217;s mesh.");
    free(html);
    /* no grid at all */
    r.lods.levels = 0;
    html = page_of(&r);
    assert_null(strstr(html, "Geometry levels"));
    free(html);
    report_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_escape_writes_every_markup_character_as_a_reference),
        cmocka_unit_test(test_lod_grid_shows_every_level_by_every_tier_that_ran),
        cmocka_unit_test(test_lod_grid_without_measured_cells_says_so_and_where_its_levels_came_from),
        cmocka_unit_test(test_table_has_a_row_per_tier_with_its_numbers_needs_and_drops),
        cmocka_unit_test(test_table_says_whether_psnr_and_flip_rank_tiers_alike),
        cmocka_unit_test(test_table_shows_the_bundles_measured_numbers_beside_its_own),
        cmocka_unit_test(test_every_label_names_the_reference_it_used),
        cmocka_unit_test(test_table_shows_dashes_where_full_did_not_run),
        cmocka_unit_test(test_axis_fits_round_steps_from_zero_to_at_or_above_the_maximum),
        cmocka_unit_test(test_plot_puts_each_compared_tier_at_its_cost_and_error),
        cmocka_unit_test(test_labels_that_would_overlap_are_stacked_below),
        cmocka_unit_test(test_heatmap_runs_black_to_white_with_rising_luminance),
        cmocka_unit_test(test_heatmap_image_scales_and_flips_gl_rows),
        cmocka_unit_test(test_page_links_every_image_relatively_and_runs_no_script),
        cmocka_unit_test(test_brightest_window_is_found_over_hair_pixels_only),
        cmocka_unit_test(test_zoom_repeats_each_pixel_scale_times),
        cmocka_unit_test(test_page_shows_each_tiers_crop_over_its_heatmaps),
        cmocka_unit_test_setup_teardown(test_bundle_gives_tiers_in_order_with_needs_and_drops, setup_scratch,
                                        teardown_scratch),
        cmocka_unit_test_setup_teardown(test_report_dir_is_written_whole_and_replaces_only_a_report, setup_scratch,
                                        teardown_scratch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

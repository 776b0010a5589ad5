/* support_results_svg.c — the cost and scaling plots (see the header). */
#include "support_results_svg.h"

#include <math.h>
#include <stdio.h>

#include "support_svg_plot.h"

#define MAX_RUNS 64
#define MAX_TIERS 16
#define PANEL_W 520
#define PANEL_H 340

/* One panel: each tier of the run a series of one labelled point. */
static bool cost_panel(FILE *f, const bench_rows *rows, size_t first, const char *const *tiers, size_t tier_count,
                       double x, double y) {
    double px[MAX_TIERS], py[MAX_TIERS];
    const char *labels[MAX_TIERS];
    bench_svg_series s[MAX_TIERS];
    size_t n = 0;
    for (size_t k = 0; k < tier_count; k++) {
        const bench_row *r = bench_rows_find(rows, first, tiers[k]);
        px[n] = r && r->ran ? r->per_full : NAN;
        py[n] = r && r->ran ? r->whole.psnr_db : NAN;
        /* Full against itself (infinite PSNR) is the dashed line, not a point. */
        if (!isfinite(px[n]) || !isfinite(py[n])) continue;
        labels[n] = tiers[k];
        s[n] = (bench_svg_series){ .name = tiers[k], .x = &px[n], .y = &py[n], .labels = &labels[n], .count = 1,
                                   .colour = (int)k };
        n++;
    }
    const bench_row *h = &rows->row[first];
    char title[160];
    snprintf(title, sizeof title, "%s × %s, %ld×%ld", h->scene, h->driver, h->width, h->height);
    bench_svg_plot p = { .title = title, .x_label = "frame time / full's (same run)",
                         .y_label = "PSNR against full, dB", .series = s, .series_count = n,
                         .x_from_zero = true, .x_ref = 1, .x_ref_label = "full" };
    return bench_svg_draw(f, &p, x, y, PANEL_W, PANEL_H);
}

bool bench_write_cost_svg(FILE *f, const bench_rows *rows) {
    const char *tiers[MAX_TIERS];
    size_t t = bench_rows_tiers(rows, tiers, MAX_TIERS);
    size_t runs[MAX_RUNS];
    size_t n = bench_rows_matrix_runs(rows, runs, MAX_RUNS);
    /* Two panels a row: the drivers of a scene side by side. */
    int cols = n > 1 ? 2 : 1, lines = (int)((n + 1) / 2);
    bool ok = bench_svg_begin(f, cols * PANEL_W, (lines ? lines : 1) * PANEL_H);
    for (size_t i = 0; ok && i < n; i++)
        ok = cost_panel(f, rows, runs[i], tiers, t, (double)(i % 2) * PANEL_W, (double)(i / 2) * PANEL_H);
    return ok && bench_svg_end(f);
}

bool bench_write_scaling_svg(FILE *f, const bench_rows *rows) {
    const char *tiers[MAX_TIERS];
    size_t t = bench_rows_tiers(rows, tiers, MAX_TIERS);
    size_t runs[MAX_RUNS];
    size_t n = bench_rows_scaling_runs(rows, runs, MAX_RUNS);
    double xs[MAX_TIERS][MAX_RUNS], ys[MAX_TIERS][MAX_RUNS];
    bench_svg_series s[MAX_TIERS];
    for (size_t k = 0; k < t; k++) {
        for (size_t i = 0; i < n; i++) {
            const bench_row *r = bench_rows_find(rows, runs[i], tiers[k]);
            xs[k][i] = (double)rows->row[runs[i]].hairs;
            ys[k][i] = r && r->ran ? r->median_ms : NAN;
        }
        s[k] = (bench_svg_series){ .name = tiers[k], .x = xs[k], .y = ys[k], .count = n, .lines = true,
                                   .colour = (int)k };
    }
    char title[160] = "no scaling series";
    if (n) {
        const bench_row *h = &rows->row[runs[0]];
        snprintf(title, sizeof title, "frame cost against hair count: %s × %s, %ld×%ld", h->scene, h->driver,
                 h->width, h->height);
    }
    bench_svg_plot p = { .title = title, .x_label = "hairs", .y_label = "median frame ms", .series = s,
                         .series_count = t, .x_from_zero = true, .y_from_zero = true, .x_ref = NAN };
    return bench_svg_begin(f, 2 * PANEL_W, 420) && bench_svg_draw(f, &p, 0, 0, 2 * PANEL_W, 420) && bench_svg_end(f);
}

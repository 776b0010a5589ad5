/* support_results_md.c — the markdown report (see the header). */
#include "support_results_md.h"

#include <math.h>
#include <string.h>

#include "../compare/metric_order.h"

#define MAX_RUNS 64
#define MAX_TIERS 16

const char *bench_md_number(double v, const char *format, char *text, size_t size) {
    if (isnan(v)) snprintf(text, size, "—");
    else if (isinf(v)) snprintf(text, size, v > 0 ? "∞" : "−∞");
    else snprintf(text, size, format, v);
    return text;
}

/* Whether PSNR and FLIP rank the run's shading tiers (floor and full
   aside) alike (metric_order.h). */
static bool order_line(FILE *f, const bench_rows *rows, size_t first) {
    const bench_row *h = &rows->row[first];
    double psnr[MAX_TIERS], flip[MAX_TIERS];
    const char *name[MAX_TIERS];
    int n = 0;
    for (size_t i = first; i < rows->count && bench_rows_same_run(h, &rows->row[i]) && n < MAX_TIERS; i++) {
        const bench_row *r = &rows->row[i];
        if (!r->ran || !strcmp(r->tier, "floor") || !strcmp(r->tier, "full")) continue;
        psnr[n] = r->whole.psnr_db, flip[n] = r->flip_mean, name[n++] = r->tier;
    }
    if (n < 2) return true;
    metric_order o = metric_order_compare(psnr, flip, n);
    if (o.discordant == 0)
        return fprintf(f, "PSNR and FLIP rank these %d tiers alike (%d pairs both tell apart).\n\n", n, o.pairs) >= 0;
    return fprintf(f, "PSNR and FLIP disagree on %d of the %d pairs both tell apart; first: PSNR ranks %s closer, "
                      "FLIP %s.\n\n", o.discordant, o.pairs, name[o.a], name[o.b]) >= 0;
}

static bool matrix_table(FILE *f, const bench_rows *rows, size_t first) {
    const bench_row *h = &rows->row[first];
    const bool es = bench_row_is_es(h);
    bool ok = fprintf(f, "### %s × %s%s%s\n\n", h->scene, h->driver, es ? ", " : "", es ? h->series : "") >= 0;
    if (h->hairs >= 0) ok = ok && fprintf(f, "%ld hairs, ", h->hairs) >= 0;
    char note[192];
    if (es)
        snprintf(note, sizeof note, " (the floor on the GL ES context, full on a desktop GL context of the same "
                 "driver: `full-%s` / `full` is what GL ES costs the same tier)", h->series);
    else
        snprintf(note, sizeof note, " (a `-device` tier is that tier's device-only variant)");
    ok = ok && fprintf(f,
                       "%ld triangles, %ld×%ld, %s; median of %ld frames after one warm-up, tiers taken "
                       "round-robin, %s; ratios and errors against this run's floor and full%s.\n\n",
                       h->triangles, h->width, h->height, h->renderer, h->frames,
                       es ? "camera still" : "still and with the eye orbiting a little every frame", note) >= 0;
    ok = ok && fputs("| tier | still: median ms | / floor | / full | orbiting: median ms | / full | PSNR dB | SSIM | "
                     "ΔE00 mean | ΔE00 p95 | FLIP mean | CPU vertices per frame: still / orbiting |\n"
                     "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n", f) >= 0;
    for (size_t i = first; ok && i < rows->count && bench_rows_same_run(h, &rows->row[i]); i++) {
        const bench_row *r = &rows->row[i];
        if (!r->ran) {
            ok = fprintf(f, "| %s | does not run here | | | | | | | | | | |\n", r->tier) >= 0;
            continue;
        }
        char a[12][32];
        ok = fprintf(f, "| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s / %s |\n", r->tier,
                     bench_md_number(r->median_ms, "%.1f", a[0], 32), bench_md_number(r->per_floor, "%.2f", a[1], 32),
                     bench_md_number(r->per_full, "%.2f", a[2], 32), bench_md_number(r->orbit_ms, "%.1f", a[9], 32),
                     bench_md_number(r->orbit_per_full, "%.2f", a[10], 32),
                     bench_md_number(r->whole.psnr_db, "%.1f", a[3], 32),
                     bench_md_number(r->whole.ssim, "%.4f", a[4], 32),
                     bench_md_number(r->whole.delta_e00_mean, "%.2f", a[5], 32),
                     bench_md_number(r->whole.delta_e00_p95, "%.2f", a[6], 32),
                     bench_md_number(r->flip_mean, "%.4f", a[11], 32),
                     bench_md_number(r->cpu_still, "%.0f", a[7], 32),
                     bench_md_number(r->cpu_orbit, "%.0f", a[8], 32)) >= 0;
    }
    return ok && fputc('\n', f) != EOF && order_line(f, rows, first);
}

static bool scaling_table(FILE *f, const bench_rows *rows, const size_t *runs, size_t n) {
    const char *tiers[MAX_TIERS];
    size_t t = bench_rows_tiers(rows, tiers, MAX_TIERS);
    const bench_row *h = &rows->row[runs[0]];
    bool ok = fprintf(f,
                      "## Scaling: %s × %s, %ld×%ld\n\n"
                      "Median frame ms of each tier (its ratio to full from the same run in brackets) "
                      "against the hair count.\n\n| hairs | triangles |",
                      h->scene, h->driver, h->width, h->height) >= 0;
    for (size_t k = 0; ok && k < t; k++) ok = fprintf(f, " %s |", tiers[k]) >= 0;
    ok = ok && fputs("\n| ---: | ---: |", f) >= 0;
    for (size_t k = 0; ok && k < t; k++) ok = fputs(" ---: |", f) >= 0;
    for (size_t i = 0; ok && i < n; i++) {
        const bench_row *r0 = &rows->row[runs[i]];
        ok = fprintf(f, "\n| %ld | %ld |", r0->hairs, r0->triangles) >= 0;
        for (size_t k = 0; ok && k < t; k++) {
            const bench_row *r = bench_rows_find(rows, runs[i], tiers[k]);
            char ms[32], ratio[32];
            if (!r || !r->ran) ok = fputs(" — |", f) >= 0;
            else
                ok = fprintf(f, " %s (%s×) |", bench_md_number(r->median_ms, "%.1f", ms, sizeof ms),
                             bench_md_number(r->per_full, "%.2f", ratio, sizeof ratio)) >= 0;
        }
    }
    return ok && fputs("\n\n", f) >= 0;
}

static bool figures_table(FILE *f, const bench_rows *rows) {
    bool ok = true, any = false;
    for (size_t i = 0; ok && i < rows->count; i++) {
        const bench_row *r = &rows->row[i];
        if (bench_row_is_frame(r)) continue;
        if (!any) ok = fputs("## Generator figures\n\n| figure | value | unit |\n| --- | ---: | --- |\n", f) >= 0;
        any = true;
        char v[32];
        ok = ok && fprintf(f, "| %s | %s | %s |\n", r->figure, bench_md_number(r->value, "%g", v, sizeof v), r->unit) >= 0;
    }
    return ok && (!any || fputc('\n', f) != EOF);
}

bool bench_write_markdown(FILE *f, const bench_rows *rows, const bench_markdown *md) {
    bool ok = fputs("# hairtier benchmark results\n\n", f) >= 0;
    if (ok && md->preamble) ok = fprintf(f, "%s\n\n", md->preamble) >= 0;
    size_t runs[MAX_RUNS];
    size_t n = bench_rows_matrix_runs(rows, runs, MAX_RUNS);
    if (ok && n) ok = fputs("## Frame cost and error against full, per scene × driver\n\n", f) >= 0;
    for (size_t i = 0; ok && i < n; i++) ok = matrix_table(f, rows, runs[i]);
    if (ok && n && md->cost_svg)
        ok = fprintf(f, "![error against cost, one point per tier](%s)\n\n", md->cost_svg) >= 0;
    static const char *const es_series[] = { "gles2", "gles3" };
    bool es_heading = false;
    for (size_t s = 0; ok && s < sizeof es_series / sizeof es_series[0]; s++) {
        n = bench_rows_series_runs(rows, es_series[s], runs, MAX_RUNS);
        if (n && !es_heading) ok = fputs("## GL ES tiers beside desktop GL's full\n\n", f) >= 0;
        es_heading = es_heading || n;
        for (size_t i = 0; ok && i < n; i++) ok = matrix_table(f, rows, runs[i]);
    }
    n = bench_rows_scaling_runs(rows, runs, MAX_RUNS);
    if (ok && n) ok = scaling_table(f, rows, runs, n);
    if (ok && n && md->scaling_svg)
        ok = fprintf(f, "![frame ms against hair count, one line per tier](%s)\n\n", md->scaling_svg) >= 0;
    return ok && figures_table(f, rows);
}

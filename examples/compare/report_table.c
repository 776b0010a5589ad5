/* report_table.c — the report's tables (report.h): this run's numbers
   beside the bundle's measured ones, and what each tier needs and drops. */
#include <math.h>
#include <string.h>

#include "metric_order.h"
#include "report.h"

/* A number, or an en dash when there is none; infinite PSNR is "∞". */
static void number(FILE *f, bool have, double v, const char *fmt) {
    if (!have) fputs("&ndash;", f);
    else if (isinf(v)) fputs("&infin;", f);
    else if (isnan(v)) fputs("n/a", f);
    else fprintf(f, fmt, v);
}

static void cell(FILE *f, const char *cls, bool have, double v, const char *fmt) {
    fprintf(f, "<td class=\"%s\">", cls);
    number(f, have, v, fmt);
    fputs("</td>", f);
}

/* The first tier that carries measured numbers, NULL when none does. */
static const ht_manifest_measured *any_measured(const report *r) {
    for (int t = 0; t < r->tier_count; t++)
        if (r->tiers[t].measured.present) return &r->tiers[t].measured;
    return NULL;
}

/* The manifest's own precision (measure.h rounds to it), so the numbers
   read as the bundle wrote them. */
static void measured_cells(FILE *f, const ht_manifest_measured *m) {
    if (!m->present) {
        fputs("<td colspan=\"6\" class=\"measured none\">not measured</td>", f);
        return;
    }
    cell(f, "num measured", true, m->cost_ratio, "%.2f&times;");
    cell(f, "num measured", true, m->psnr_db, "%.2f");
    cell(f, "num measured", true, m->ssim, "%.4f");
    cell(f, "num measured", true, m->delta_e00_mean, "%.3f");
    cell(f, "num measured", true, m->delta_e00_p95, "%.3f");
    fputs("<td class=\"num measured\">", f);
    number(f, true, m->flip_mean, "%.4f"); /* NaN ("n/a"): measured before FLIP */
    fputs(" / ", f);
    number(f, true, m->flip_p95, "%.4f");
    fputs("</td>", f);
}

metric_order report_metric_order(const report *r) {
    double psnr[REPORT_MAX_TIERS], flip[REPORT_MAX_TIERS];
    int index[REPORT_MAX_TIERS], n = 0;
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        if (!p->compared || t == r->reference) continue;
        psnr[n] = p->whole.psnr_db, flip[n] = p->flip.mean, index[n++] = t;
    }
    metric_order o = metric_order_compare(psnr, flip, n);
    if (o.discordant) o.a = index[o.a], o.b = index[o.b];
    return o;
}

static void write_order(FILE *f, const report *r) {
    int n = 0;
    for (int t = 0; t < r->tier_count; t++) n += r->tiers[t].compared && t != r->reference;
    if (n < 2) return;
    metric_order o = report_metric_order(r);
    fprintf(f, "<p class=\"note order\">PSNR and FLIP ");
    if (o.discordant == 0) {
        fprintf(f, "rank the %d compared tiers alike (%d pair%s both tell apart).</p>\n", n, o.pairs,
                o.pairs == 1 ? "" : "s");
        return;
    }
    fprintf(f, "disagree on %d of the %d pairs both tell apart; first: PSNR ranks <b>", o.discordant, o.pairs);
    report_escape(f, r->tiers[o.a].name);
    fputs("</b> closer, FLIP <b>", f);
    report_escape(f, r->tiers[o.b].name);
    fputs("</b>.</p>\n", f);
}

void report_write_table(FILE *f, const report *r) {
    const ht_manifest_measured *bundle = any_measured(r);
    const char *ref = report_reference_name(r);
    fputs("<table class=\"metrics\">\n<thead><tr><th rowspan=\"2\">tier</th><th rowspan=\"2\">frame ms</th>"
          "<th colspan=\"7\" class=\"group\">this run, against <b>", f);
    report_escape(f, ref);
    fputs("</b></th>", f);
    if (bundle) fputs("<th colspan=\"6\" class=\"group measured\">the bundle&#8217;s <code>measured</code> "
                      "(manifest.json, hairgen --measure)</th>", f);
    fputs("</tr>\n<tr><th>cost</th><th>PSNR dB</th><th>SSIM</th><th>&#916;E00 mean</th><th>&#916;E00 p95</th>"
          "<th>FLIP mean / p95</th><th>hair pixels: &#916;E00 mean / p95</th>", f);
    if (bundle) fputs("<th class=\"measured\">cost</th><th class=\"measured\">PSNR dB</th><th class=\"measured\">SSIM"
                      "</th><th class=\"measured\">&#916;E00 mean</th><th class=\"measured\">&#916;E00 p95</th>"
                      "<th class=\"measured\">FLIP mean / p95</th>", f);
    fputs("</tr></thead>\n<tbody>\n", f);
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        fputs("<tr><th scope=\"row\">", f);
        report_escape(f, p->name);
        fputs("</th>", f);
        if (!p->ran) {
            fputs("<td colspan=\"8\" class=\"notrun\">not run: ", f);
            report_escape(f, p->reason);
            fputs("</td>", f);
        } else {
            cell(f, "num", true, p->frame_ms, "%.1f");
            cell(f, "num", p->compared, p->cost_ratio, "%.2f&times;");
            cell(f, "num", p->compared, p->whole.psnr_db, "%.1f");
            cell(f, "num", p->compared, p->whole.ssim, "%.4f");
            cell(f, "num", p->compared, p->whole.delta_e00_mean, "%.2f");
            cell(f, "num", p->compared, p->whole.delta_e00_p95, "%.2f");
            fputs("<td class=\"num\">", f);
            number(f, p->compared, p->flip.mean, "%.4f");
            fputs(" / ", f);
            number(f, p->compared, p->flip.p95, "%.4f");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->hair.delta_e00_mean, "%.2f");
            fputs(" / ", f);
            number(f, p->compared, p->hair.delta_e00_p95, "%.2f");
            fputs("</td>", f);
        }
        if (bundle) measured_cells(f, &p->measured);
        fputs("</tr>\n", f);
    }
    fputs("</tbody>\n</table>\n", f);
    write_order(f, r);
    if (!bundle) {
        fputs("<p class=\"note nomeasured\">The bundle has no measured numbers: no tier of its manifest.json "
              "carries a <code>measured</code> object (<code>hairgen --measure</code> writes them; the "
              "<code>error:DB</code> and <code>fastest</code> policies read them).</p>\n", f);
        return;
    }
    fputs("<p class=\"note\">The bundle&#8217;s measured numbers are what its manifest.json says, as "
          "<code>hairgen --measure</code> wrote them and the <code>error:DB</code> and <code>fastest</code> "
          "policies read them: over the whole frame against the bundle&#8217;s reference, on scene <code>", f);
    report_escape(f, bundle->scene[0] ? bundle->scene : "(not named)");
    fputs("</code> and driver <code>", f);
    report_escape(f, bundle->driver[0] ? bundle->driver : "(not named)");
    fputs("</code>; this run&#8217;s numbers beside them are measured here, on this report&#8217;s scene.</p>\n", f);
}

void report_write_needs(FILE *f, const report *r) {
    fputs("<table class=\"needs\">\n<thead><tr><th>tier</th><th>needs</th><th>features dropped</th></tr></thead>\n"
          "<tbody>\n", f);
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        fputs("<tr><th scope=\"row\">", f);
        report_escape(f, p->name);
        fputs("</th><td class=\"needs\">", f);
        report_escape(f, p->needs);
        fputs("</td><td class=\"dropped\">", f);
        if (p->dropped_count == 0) fputs("nothing", f);
        else {
            fputs("<ul>", f);
            for (int i = 0; i < p->dropped_count; i++) {
                fputs("<li>", f);
                report_escape(f, p->dropped[i]);
                fputs("</li>", f);
            }
            fputs("</ul>", f);
        }
        fputs("</td></tr>\n", f);
    }
    fputs("</tbody>\n</table>\n", f);
}

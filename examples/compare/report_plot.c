/* report_plot.c — the SVG plot of error against cost (report.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "report.h"

/* Plot area inside the PLOT_W x PLOT_H picture. */
#define PLOT_LEFT 72
#define PLOT_RIGHT 28
#define PLOT_TOP 20
#define PLOT_BOTTOM 58
#define PLOT_INSET 12       /* px between the x axis line and y = 0, so a point at 0 clears the axis */
#define LABEL_LINE 16       /* px between stacked labels */
#define LABEL_CHAR_W 8.5    /* a bold label character's width at 13 px, generous */
#define LABEL_PAD 4         /* px kept clear between two labels side by side */
#define POINT_R 6

plot_axis plot_axis_fit(double max_value) {
    if (!(max_value > 0.0) || !isfinite(max_value)) max_value = 1.0;
    double mag = pow(10.0, floor(log10(max_value / 5.0)));
    static const double mult[] = { 1.0, 2.0, 5.0, 10.0 };
    plot_axis a = { 0 };
    for (size_t i = 0; i < sizeof mult / sizeof mult[0]; i++) {
        double step = mult[i] * mag;
        double n = ceil(max_value / step - 1e-9);
        if (n <= 10.0) {
            a.step = step;
            a.ticks = (int)n + 1;
            a.hi = n * step;
            break;
        }
    }
    return a;
}

double plot_map(const plot_axis *a, double value, double px0, double px1) {
    return px0 + (px1 - px0) * value / a->hi;
}

static int decimals(double step) {
    int d = (int)-floor(log10(step) + 1e-9);
    return d < 0 ? 0 : d;
}

/* A label's box: [x, x + w] x [y - 12, y + 3] around its baseline y. */
static bool label_overlaps_label(double x0, double w0, double y0, double x1, double w1, double y1) {
    return x0 < x1 + w1 + LABEL_PAD && x1 < x0 + w0 + LABEL_PAD && fabs(y0 - y1) < LABEL_LINE - 1;
}

static bool label_overlaps_point(double x, double w, double y, double px, double py) {
    const double r = POINT_R + 2;
    return x < px + r && px - r < x + w && y - 12 < py + r && py - r < y + 3;
}

void plot_place_labels(const double *px, const double *py, const double *x, const double *w, int n, double *label_y) {
    int order[REPORT_MAX_TIERS];
    for (int i = 0; i < n; i++) order[i] = i;
    for (int i = 1; i < n; i++) /* by point height, top first; ties keep table order */
        for (int j = i; j > 0 && py[order[j]] < py[order[j - 1]]; j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
    for (int k = 0; k < n; k++) {
        int i = order[k];
        label_y[i] = py[i] + 4.0;
        /* Down past whatever it covers: labels placed before it, other
           points. Bounded: each step moves below one obstacle. */
        for (int step = 0; step < 4 * REPORT_MAX_TIERS; step++) {
            double below = -1.0;
            for (int m = 0; m < k; m++) {
                int j = order[m];
                if (label_overlaps_label(x[i], w[i], label_y[i], x[j], w[j], label_y[j])) below = label_y[j] + LABEL_LINE;
            }
            for (int j = 0; j < n && below < 0.0; j++)
                if (j != i && label_overlaps_point(x[i], w[i], label_y[i], px[j], py[j])) below = py[j] + POINT_R + 14;
            if (below < 0.0) break;
            label_y[i] = below;
        }
    }
}

static void axis_ticks(FILE *f, const plot_axis *a, bool horizontal, double x0, double x1, double y0, double y1) {
    int d = decimals(a->step);
    for (int i = 0; i < a->ticks; i++) {
        double v = a->step * i;
        if (horizontal) {
            double x = plot_map(a, v, x0, x1);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#2e2f36\"/>\n", x, y1, x, y0);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#aaa\"/>\n", x, y0, x, y0 + 5);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%.*f</text>\n", x, y0 + 19, d, v);
        } else {
            double y = plot_map(a, v, y0, y1);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#2e2f36\"/>\n", x0, y, x1, y);
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#aaa\"/>\n", x0 - 5, y, x0, y);
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%.*f</text>\n", x0 - 8, y + 4, d, v);
        }
    }
}

void report_write_plot(FILE *f, const report *r) {
    static const char *const colours[] = { "#f0c674", "#81a2be", "#b5bd68", "#cc6666", "#b294bb", "#8abeb7",
                                           "#de935f", "#c5c8c6" };
    const double x0 = PLOT_LEFT, x1 = PLOT_W - PLOT_RIGHT, axis_y = PLOT_H - PLOT_BOTTOM, y0 = axis_y - PLOT_INSET,
                 y1 = PLOT_TOP;
    int idx[REPORT_MAX_TIERS], n = 0;
    double max_cost = 1.0, max_err = 0.0;
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        if (!p->compared) continue;
        idx[n++] = t;
        if (p->cost_ratio > max_cost) max_cost = p->cost_ratio;
        if (p->whole.delta_e00_mean > max_err) max_err = p->whole.delta_e00_mean;
    }
    if (n == 0) {
        fputs("<p class=\"note\">No plot: no reference tier (marschner or full) ran here, so no tier has an error "
              "or a cost against it.</p>\n", f);
        return;
    }
    plot_axis ax = plot_axis_fit(max_cost * 1.15), ay = plot_axis_fit(max_err * 1.1);
    fprintf(f, "<svg class=\"plot\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
               "xmlns=\"http://www.w3.org/2000/svg\" font-size=\"13\" fill=\"#ddd\" role=\"img\" "
               "aria-label=\"error against cost, one point per tier\">\n",
            PLOT_W, PLOT_H, PLOT_W, PLOT_H);
    axis_ticks(f, &ax, true, x0, x1, axis_y, y1);
    axis_ticks(f, &ay, false, x0, x1, y0, y1);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ccc\"/>\n", x0, axis_y, x1, axis_y);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ccc\"/>\n", x0, axis_y, x0, y1);
    double one = plot_map(&ax, 1.0, x0, x1);
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#777\" stroke-dasharray=\"4 4\"/>\n",
            one, axis_y, one, y1);
    const char *ref = report_reference_name(r);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">cost: frame time / ", (x0 + x1) / 2,
            (double)PLOT_H - 14);
    report_escape(f, ref);
    fprintf(f, "&#8217;s</text>\n<text transform=\"translate(18 %.1f) rotate(-90)\" text-anchor=\"middle\">"
               "&#916;E00 mean against ", (y0 + y1) / 2);
    report_escape(f, ref);
    fputs(" (lower is better)</text>\n", f);

    double px[REPORT_MAX_TIERS], py[REPORT_MAX_TIERS], lx[REPORT_MAX_TIERS], lw[REPORT_MAX_TIERS],
        ly[REPORT_MAX_TIERS];
    char label[REPORT_MAX_TIERS][sizeof r->tiers[0].name];
    for (int k = 0; k < n; k++) {
        const report_tier *p = &r->tiers[idx[k]];
        px[k] = plot_map(&ax, p->cost_ratio, x0, x1);
        py[k] = plot_map(&ay, p->whole.delta_e00_mean, y0, y1);
        snprintf(label[k], sizeof label[k], "%s", p->name); /* the numbers are the table's */
        lw[k] = LABEL_CHAR_W * (double)strlen(label[k]);
        lx[k] = px[k] + lw[k] + 10 > x1 ? px[k] - 10 - lw[k] : px[k] + 10;
    }
    plot_place_labels(px, py, lx, lw, n, ly);
    for (int k = 0; k < n; k++) {
        const char *c = colours[idx[k] % (int)(sizeof colours / sizeof colours[0])];
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"%d\" fill=\"%s\" stroke=\"#111\"><title>", px[k], py[k],
                POINT_R, c);
        report_escape(f, label[k]);
        fprintf(f, ": cost %.2f&#215; ", r->tiers[idx[k]].cost_ratio);
        report_escape(f, ref);
        fprintf(f, ", &#916;E00 mean %.2f</title></circle>\n", r->tiers[idx[k]].whole.delta_e00_mean);
        if (fabs(ly[k] - (py[k] + 4.0)) > 0.5) /* moved off its point: a leader line */
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" stroke-width=\"0.8\"/>\n",
                    px[k], py[k], lx[k] < px[k] ? lx[k] + lw[k] : lx[k], ly[k] - 4.0, c);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" fill=\"%s\" font-weight=\"600\">", lx[k], ly[k], c);
        report_escape(f, label[k]);
        fputs("</text>\n", f);
    }
    fputs("</svg>\n", f);
}

/* support_svg_plot.c — plain SVG plots (see the header). */
#include "support_svg_plot.h"

#include <math.h>
#include <string.h>

/* Distinguishable on white, and in grey print by lightness. */
static const char *const palette[] = { "#666666", "#1f77b4", "#d62728", "#2ca02c",
                                       "#9467bd", "#ff7f0e", "#8c564b", "#17becf" };
enum { PALETTE = sizeof palette / sizeof palette[0] };

const char *bench_svg_colour(int i) { return palette[((i % PALETTE) + PALETTE) % PALETTE]; }

static bool text_escaped(FILE *f, const char *s) {
    for (; s && *s; s++) {
        int ok;
        switch (*s) {
        case '&': ok = fputs("&amp;", f); break;
        case '<': ok = fputs("&lt;", f); break;
        case '>': ok = fputs("&gt;", f); break;
        case '"': ok = fputs("&quot;", f); break;
        default: ok = fputc(*s, f) == EOF ? -1 : 0;
        }
        if (ok < 0) return false;
    }
    return true;
}

/* <text ...>escaped</text>; attrs are the caller's literal attributes. */
static bool text(FILE *f, double x, double y, const char *attrs, const char *s) {
    return fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" %s>", x, y, attrs) >= 0 && text_escaped(f, s) &&
           fputs("</text>\n", f) >= 0;
}

bool bench_svg_begin(FILE *f, int width, int height) {
    return fprintf(f,
                   "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
                   "font-family=\"sans-serif\" font-size=\"12\">\n"
                   "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
                   width, height, width, height) >= 0;
}

bool bench_svg_end(FILE *f) { return fputs("</svg>\n", f) >= 0; }

double bench_nice_axis(double *lo, double *hi, int max_ticks) {
    if (!isfinite(*lo) || !isfinite(*hi) || *lo > *hi) *lo = 0, *hi = 1;
    if (*lo == *hi) {
        double pad = *lo == 0 ? 1 : fabs(*lo) * 0.1;
        *lo -= pad, *hi += pad;
    }
    /* Two ticks cannot span a range across zero with multiples of a step; three always can. */
    if (max_ticks < 3) max_ticks = 3;
    double rough = (*hi - *lo) / (max_ticks - 1);
    double base = pow(10, floor(log10(rough)));
    static const double steps[] = { 1, 2, 5, 10 };
    double step = base * 10;
    for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++)
        if (base * steps[i] >= rough * (1 - 1e-9)) {
            step = base * steps[i];
            break;
        }
    /* Rounding out can add a tick; one step up then keeps the promise. */
    for (;;) {
        double a = floor(*lo / step + 1e-9) * step, b = ceil(*hi / step - 1e-9) * step;
        if ((int)lround((b - a) / step) + 1 <= max_ticks) {
            *lo = a, *hi = b;
            return step;
        }
        step *= 2;
    }
}

typedef struct frame {
    double x0, y0, w, h;          /* plot area in document units */
    double xlo, xhi, ylo, yhi;
} frame;

static double px(const frame *fr, double x) { return fr->x0 + (x - fr->xlo) / (fr->xhi - fr->xlo) * fr->w; }
static double py(const frame *fr, double y) { return fr->y0 + fr->h - (y - fr->ylo) / (fr->yhi - fr->ylo) * fr->h; }

static void data_range(const bench_svg_plot *p, double *xlo, double *xhi, double *ylo, double *yhi) {
    *xlo = *ylo = INFINITY, *xhi = *yhi = -INFINITY;
    for (size_t s = 0; s < p->series_count; s++)
        for (size_t i = 0; i < p->series[s].count; i++) {
            double x = p->series[s].x[i], y = p->series[s].y[i];
            if (!isfinite(x) || !isfinite(y)) continue;
            *xlo = fmin(*xlo, x), *xhi = fmax(*xhi, x), *ylo = fmin(*ylo, y), *yhi = fmax(*yhi, y);
        }
    if (isfinite(p->x_ref) && *xlo <= *xhi) *xlo = fmin(*xlo, p->x_ref), *xhi = fmax(*xhi, p->x_ref);
    if (p->x_from_zero && *xlo > 0) *xlo = 0;
    if (p->y_from_zero && *ylo > 0) *ylo = 0;
    /* A margin, so a point or label on the data's edge is not on the frame. */
    double dx = 0.04 * (*xhi - *xlo), dy = 0.04 * (*yhi - *ylo);
    if (*xlo <= *xhi) {
        *xhi += dx, *yhi += dy;
        if (!(p->x_from_zero && *xlo == 0)) *xlo -= dx;
        if (!(p->y_from_zero && *ylo == 0)) *ylo -= dy;
    }
}

static bool axes(FILE *f, const bench_svg_plot *p, const frame *fr, double xstep, double ystep) {
    bool ok = fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" stroke=\"#999\"/>\n",
                      fr->x0, fr->y0, fr->w, fr->h) >= 0;
    char tick[32];
    for (double v = fr->xlo; ok && v <= fr->xhi + xstep * 1e-6; v += xstep) {
        double x = px(fr, v);
        snprintf(tick, sizeof tick, "%g", fabs(v) < xstep * 1e-6 ? 0.0 : v);
        ok = fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#eee\"/>\n", x, fr->y0, x,
                     fr->y0 + fr->h) >= 0 &&
             text(f, x, fr->y0 + fr->h + 14, "text-anchor=\"middle\"", tick);
    }
    for (double v = fr->ylo; ok && v <= fr->yhi + ystep * 1e-6; v += ystep) {
        double y = py(fr, v);
        snprintf(tick, sizeof tick, "%g", fabs(v) < ystep * 1e-6 ? 0.0 : v);
        ok = fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#eee\"/>\n", fr->x0, y,
                     fr->x0 + fr->w, y) >= 0 &&
             text(f, fr->x0 - 4, y + 4, "text-anchor=\"end\"", tick);
    }
    return ok && text(f, fr->x0 + fr->w / 2, fr->y0 + fr->h + 30, "text-anchor=\"middle\"", p->x_label) &&
           fprintf(f, "<g transform=\"translate(%.1f %.1f) rotate(-90)\">", fr->x0 - 42, fr->y0 + fr->h / 2) >= 0 &&
           text(f, 0, 0, "text-anchor=\"middle\"", p->y_label) && fputs("</g>\n", f) >= 0 &&
           text(f, fr->x0, fr->y0 - 8, "font-weight=\"bold\"", p->title);
}

static bool series(FILE *f, const bench_svg_series *s, int index, const frame *fr) {
    const char *colour = bench_svg_colour(s->colour < 0 ? index : s->colour);
    bool ok = true;
    if (s->lines) {
        ok = fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", colour) >= 0;
        for (size_t i = 0; ok && i < s->count; i++)
            if (isfinite(s->x[i]) && isfinite(s->y[i]))
                ok = fprintf(f, "%.1f,%.1f ", px(fr, s->x[i]), py(fr, s->y[i])) >= 0;
        ok = ok && fputs("\"/>\n", f) >= 0;
    }
    for (size_t i = 0; ok && i < s->count; i++) {
        if (!isfinite(s->x[i]) || !isfinite(s->y[i])) continue;
        double x = px(fr, s->x[i]), y = py(fr, s->y[i]);
        ok = fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4\" fill=\"%s\"/>\n", x, y, colour) >= 0;
        if (ok && s->labels && s->labels[i]) ok = text(f, x + 6, y - 6, "font-size=\"11\"", s->labels[i]);
    }
    return ok;
}

static bool legend(FILE *f, const bench_svg_plot *p, const frame *fr) {
    bool ok = true;
    for (size_t s = 0; ok && s < p->series_count; s++) {
        const bench_svg_series *se = &p->series[s];
        double x = fr->x0 + fr->w + 12, y = fr->y0 + 10 + 16 * (double)s;
        ok = fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"10\" height=\"10\" fill=\"%s\"/>\n", x, y - 9,
                     bench_svg_colour(se->colour < 0 ? (int)s : se->colour)) >= 0 &&
             text(f, x + 14, y, "", se->name);
    }
    return ok;
}

bool bench_svg_draw(FILE *f, const bench_svg_plot *p, double x, double y, double w, double h) {
    /* Margins: ticks and the y label left, the x label below, the legend right. */
    frame fr = { x + 60, y + 28, w - 60 - 110, h - 28 - 44, 0, 0, 0, 0 };
    if (fr.w < 10 || fr.h < 10) return false;
    data_range(p, &fr.xlo, &fr.xhi, &fr.ylo, &fr.yhi);
    double xstep = bench_nice_axis(&fr.xlo, &fr.xhi, 7), ystep = bench_nice_axis(&fr.ylo, &fr.yhi, 7);
    bool ok = axes(f, p, &fr, xstep, ystep);
    if (ok && isfinite(p->x_ref)) {
        double rx = px(&fr, p->x_ref);
        ok = fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#444\" stroke-dasharray=\"4 3\"/>\n",
                     rx, fr.y0, rx, fr.y0 + fr.h) >= 0 &&
             (!p->x_ref_label || text(f, rx + 4, fr.y0 + 12, "font-size=\"11\"", p->x_ref_label));
    }
    for (size_t s = 0; ok && s < p->series_count; s++) ok = series(f, &p->series[s], (int)s, &fr);
    return ok && legend(f, p, &fr);
}

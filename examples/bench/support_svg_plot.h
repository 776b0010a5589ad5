/* support_svg_plot.h — small line and scatter plots as plain SVG (no
   script, opens from disk), for the benchmark's figures: each series a
   colour, markers at the points (joined by lines if asked), optional labels
   beside points, axes with round ticks, a legend and an optional vertical
   reference line. Points that are not finite are left out.

   Usage:
       const double x[] = { 1000, 5000 }, y[] = { 12.5, 40.1 };
       bench_svg_series s = { .name = "full", .x = x, .y = y, .count = 2, .lines = true };
       bench_svg_plot p = { .title = "cost", .x_label = "hairs", .y_label = "ms",
                            .series = &s, .series_count = 1, .x_ref = NAN };
       bench_svg_begin(f, 640, 400);
       bench_svg_draw(f, &p, 0, 0, 640, 400);
       bench_svg_end(f); */
#ifndef HT_EXAMPLES_SUPPORT_SVG_PLOT_H
#define HT_EXAMPLES_SUPPORT_SVG_PLOT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct bench_svg_series {
    const char *name;                 /* legend text */
    const double *x, *y;
    const char *const *labels;        /* NULL, or one per point (NULL entries: none) */
    size_t count;
    bool lines;                       /* join the points in order */
    int colour;                       /* index into the palette; -1: the series' own index */
} bench_svg_series;

typedef struct bench_svg_plot {
    const char *title, *x_label, *y_label;
    const bench_svg_series *series;
    size_t series_count;
    bool x_from_zero, y_from_zero;    /* axis starts at 0 (when the data are positive) */
    double x_ref;                     /* NAN: none; else a dashed vertical line there */
    const char *x_ref_label;
} bench_svg_plot;

bool bench_svg_begin(FILE *f, int width, int height);
/* One plot in the rectangle (x, y, w, h) of the document. */
bool bench_svg_draw(FILE *f, const bench_svg_plot *plot, double x, double y, double w, double h);
bool bench_svg_end(FILE *f);

/* Widens [*lo, *hi] to multiples of a step of 1, 2 or 5 × 10^k giving at
   most max_ticks ticks (fewer than 3 counts as 3) and returns the step; an empty or
   non-finite range becomes [0, 1]; lo == hi is widened around the value. */
double bench_nice_axis(double *lo, double *hi, int max_ticks);

/* The palette's colour i (wraps), as "#rrggbb". */
const char *bench_svg_colour(int i);

#endif

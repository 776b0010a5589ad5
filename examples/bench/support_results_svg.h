/* support_results_svg.h — the benchmark's two plots, from its rows:
   - cost: one panel per matrix run (scene × driver), one point per tier at
     (frame time / full's, PSNR against full), full itself the dashed line
     at 1 (its PSNR against itself is infinite);
   - scaling: frame ms against hair count, one line per tier.
   A tier has the same colour in both. Plain SVG (support_svg_plot.h).

   Usage: bench_write_cost_svg(f, &rows); bench_write_scaling_svg(f, &rows); */
#ifndef HT_EXAMPLES_SUPPORT_RESULTS_SVG_H
#define HT_EXAMPLES_SUPPORT_RESULTS_SVG_H

#include <stdbool.h>
#include <stdio.h>

#include "support_results.h"

bool bench_write_cost_svg(FILE *f, const bench_rows *rows);
bool bench_write_scaling_svg(FILE *f, const bench_rows *rows);

#endif

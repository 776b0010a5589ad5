/* support_results_md.h — bench/results.md: the benchmark's rows as tables a
   person reads. One table per matrix run (scene × driver: every tier's
   median frame ms, its ratios to the floor and to full from that run, its
   error against full, its per-vertex CPU work), the scaling series (ms per
   tier against hair count), the generator figures, and the two plots.

   Usage:
       bench_write_markdown(f, &rows, &(bench_markdown){ .preamble = "Machine: ...",
                            .cost_svg = "results.svg", .scaling_svg = "scaling.svg" }); */
#ifndef HT_EXAMPLES_SUPPORT_RESULTS_MD_H
#define HT_EXAMPLES_SUPPORT_RESULTS_MD_H

#include <stdbool.h>
#include <stdio.h>

#include "support_results.h"

typedef struct bench_markdown {
    const char *preamble;       /* markdown under the title: machine, command, load; may be NULL */
    const char *cost_svg;       /* image links beside the tables; NULL: none */
    const char *scaling_svg;
} bench_markdown;

bool bench_write_markdown(FILE *f, const bench_rows *rows, const bench_markdown *md);

/* A number as the tables show it: "—" for NAN (not applicable), "∞" for
   +INFINITY, else printf's format. Returns text. */
const char *bench_md_number(double v, const char *format, char *text, size_t size);

#endif

/* support_figures.h — the figures a benchmark prints as text lines
   ("LABEL: VALUE [UNIT] [NOTE]", e.g. bench_hairgen's
   "hairgen, all tiers of 100 materials:  4800.0 ms (48.0 ms each)") read
   back as result rows, so `make bench` records a program's numbers without
   that program knowing about the results files.

   Usage:
       bench_row row;
       if (bench_parse_figure(line, "generator", &row)) ...   // row.figure, row.value, row.unit */
#ifndef HT_EXAMPLES_SUPPORT_FIGURES_H
#define HT_EXAMPLES_SUPPORT_FIGURES_H

#include <stdbool.h>

#include "support_results.h"

/* true when line is LABEL ":" VALUE ...: out becomes a blank row of the given
   series with figure "LABEL" or "LABEL NOTE" (the NOTE is what follows the
   unit), value VALUE (finite) and unit the word right after VALUE (empty when
   none). The first colon followed by a number splits label from value. false
   (out untouched) for any other line, an empty label, or one too long. */
bool bench_parse_figure(const char *line, const char *series, bench_row *out);

#endif

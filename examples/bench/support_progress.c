/* support_progress.c — ETA and durations (see the header). */
#include "support_progress.h"

#include <math.h>
#include <stdio.h>

static int usable(double x) { return isfinite(x) && x >= 0; }

double bench_eta_seconds(double elapsed_s, double done_weight, double remaining_weight) {
    if (!usable(elapsed_s) || !usable(done_weight) || !usable(remaining_weight)) return NAN;
    if (remaining_weight == 0) return 0;
    if (done_weight == 0) return NAN;
    return elapsed_s / done_weight * remaining_weight;
}

const char *bench_format_duration(double seconds, char *text, size_t size) {
    /* Beyond a year it is no estimate worth printing. */
    if (!usable(seconds) || seconds >= 365.0 * 86400) {
        snprintf(text, size, "--");
        return text;
    }
    long s = lround(seconds);
    long h = s / 3600, m = s / 60 % 60, rest = s % 60;
    if (h) snprintf(text, size, "%ldh%02ldm%02lds", h, m, rest);
    else if (m) snprintf(text, size, "%ldm%02lds", m, rest);
    else snprintf(text, size, "%lds", rest);
    return text;
}

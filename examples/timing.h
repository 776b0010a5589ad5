/* timing.h — the examples' clock and median (header only: every
   example .c file is a program of its own). */
#ifndef HT_EXAMPLES_TIMING_H
#define HT_EXAMPLES_TIMING_H

#include <stdlib.h>
#include <time.h>

/* Milliseconds on the monotonic clock. */
static inline double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

static inline int timing_compare(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* The median of v[0..n-1], n >= 1 (v is sorted in place). */
static inline double median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, timing_compare);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

#endif

/* support_progress.h — the benchmark's progress line: how long the rest of a
   run will take, from the time the finished steps took against their
   predicted weight, and durations a person reads ("3m05s").

   Usage:
       double eta = bench_eta_seconds(elapsed_s, done_weight, remaining_weight);
       char text[32];
       printf("ETA %s\n", bench_format_duration(eta, text, sizeof text)); */
#ifndef HT_EXAMPLES_SUPPORT_PROGRESS_H
#define HT_EXAMPLES_SUPPORT_PROGRESS_H

#include <stddef.h>

/* Seconds left: remaining_weight at the pace the done steps ran
   (elapsed_s / done_weight). NAN when nothing is done yet or an input is not
   a finite non-negative number; 0 when nothing remains. */
double bench_eta_seconds(double elapsed_s, double done_weight, double remaining_weight);

/* "42s", "3m05s", "1h02m05s" (rounded to the second); "--" for NAN, a
   negative or an infinite value. Returns text. */
const char *bench_format_duration(double seconds, char *text, size_t size);

#endif

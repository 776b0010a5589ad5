/* trace.h — with HAIRGEN_TRACE set in the environment, one line on stderr
   per traced step: milliseconds since the first traced line, the thread
   (1 = the first to trace), and what happened (trace.c). Unset, a call
   costs one cached getenv. For finding where a bundle's time goes:
   HAIRGEN_TRACE=1 hairgen M.json -o DIR -q. */
#ifndef HT_TRACE_H
#define HT_TRACE_H

#include <stdbool.h>

bool ht_gen_trace_on(void);
void ht_gen_trace(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif

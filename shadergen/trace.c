/* trace.c — trace.h. One fprintf per line: stderr is unbuffered, so a
   line is one write and lines of different threads do not interleave. */
#include "trace.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <sys/resource.h>

static pthread_once_t once = PTHREAD_ONCE_INIT;
static bool on;
static struct timespec epoch;
static atomic_int threads;
static _Thread_local int thread_number;

static void init(void) {
    const char *v = getenv("HAIRGEN_TRACE");
    on = v && v[0] && !(v[0] == '0' && !v[1]);
    clock_gettime(CLOCK_MONOTONIC, &epoch);
}

bool ht_gen_trace_on(void) {
    pthread_once(&once, init);
    return on;
}

void ht_gen_trace(const char *fmt, ...) {
    if (!ht_gen_trace_on()) return;
    struct timespec now, cpu;
    clock_gettime(CLOCK_MONOTONIC, &now);
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &cpu);
    if (!thread_number) thread_number = atomic_fetch_add(&threads, 1) + 1;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    double ms = (double)(now.tv_sec - epoch.tv_sec) * 1e3 + (double)(now.tv_nsec - epoch.tv_nsec) / 1e6;
    double cpu_ms = (double)cpu.tv_sec * 1e3 + (double)cpu.tv_nsec / 1e6;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    fprintf(stderr, "hairgen: trace %7.2f ms (process: CPU %6.2f ms, %4ld page faults) [%d] %s\n", ms, cpu_ms,
            ru.ru_minflt + ru.ru_majflt, thread_number, line);
}

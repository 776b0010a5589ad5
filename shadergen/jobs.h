/* jobs.h — a few dependent jobs run on a few threads (jobs.c): each job
   once, after every job it waits for, by whichever thread is free; among
   the jobs ready to start, the first in the list goes first, so the list
   order is the priority (put the longest chain first). Each job writes only
   its own outputs, so the results do not depend on the thread count or on
   which thread ran what. */
#ifndef HT_JOBS_H
#define HT_JOBS_H

#include <stdint.h>

#define HT_JOBS_MAX 32

typedef struct ht_job {
    const char *name;   /* for HAIRGEN_TRACE (trace.h) */
    void (*run)(void *arg);
    void *arg;
    uint32_t waits;   /* bit i: starts after job i has finished (i < this job's index) */
} ht_job;

/* Runs jobs[0..count) on the calling thread and up to threads - 1 more
   (threads < 1: one per online core); returns when every job has finished.
   A thread that cannot be started is done without: with one thread the jobs
   run in list order. count is at most HT_JOBS_MAX. */
void ht_jobs_run(const ht_job *jobs, int count, int threads);

/* The threads ht_jobs_run(..., 0) uses: the online cores (at least 1). */
int ht_jobs_default_threads(void);

#endif

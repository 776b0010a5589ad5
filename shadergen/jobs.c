/* jobs.c — jobs.h: one lock, one condition variable, a bit per job started
   and per job finished. Threads are made per call and joined before it
   returns (a bundle's jobs take milliseconds; a pool kept between calls
   would only move the cost). */
#include "jobs.h"

#include <pthread.h>
#include <stdbool.h>
#include <unistd.h>

#include "trace.h"

typedef struct job_run {
    const ht_job *jobs;
    int count;
    pthread_mutex_t lock;
    pthread_cond_t changed;   /* a job finished */
    uint32_t started, finished;
} job_run;

/* The first job not started whose waits have all finished: its index, or
   -1 (every job started, or none ready yet). Called with the lock held. */
static int next_ready(const job_run *run) {
    for (int i = 0; i < run->count; i++) {
        const uint32_t bit = (uint32_t)1 << i;
        if (!(run->started & bit) && (run->jobs[i].waits & ~run->finished) == 0) return i;
    }
    return -1;
}

static void run_one(const ht_job *job) {
    ht_gen_trace("%s: start", job->name);
    job->run(job->arg);
    ht_gen_trace("%s: end", job->name);
}

static void *worker(void *arg) {
    job_run *run = arg;
    const uint32_t all = run->count == 32 ? UINT32_MAX : ((uint32_t)1 << run->count) - 1;
    pthread_mutex_lock(&run->lock);
    while (run->started != all) {
        int i = next_ready(run);
        if (i < 0) {
            pthread_cond_wait(&run->changed, &run->lock);
            continue;
        }
        run->started |= (uint32_t)1 << i;
        pthread_mutex_unlock(&run->lock);
        run_one(&run->jobs[i]);
        pthread_mutex_lock(&run->lock);
        run->finished |= (uint32_t)1 << i;
        pthread_cond_broadcast(&run->changed);
    }
    pthread_mutex_unlock(&run->lock);
    return NULL;
}

int ht_jobs_default_threads(void) {
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > HT_JOBS_MAX ? HT_JOBS_MAX : (int)n;
}

void ht_jobs_run(const ht_job *jobs, int count, int threads) {
    if (count < 1) return;
    if (count > HT_JOBS_MAX) count = HT_JOBS_MAX;
    if (threads < 1) threads = ht_jobs_default_threads();
    if (threads > count) threads = count;
    if (threads == 1) {
        /* The list order respects every wait (a job waits only for earlier
           ones): no lock needed. */
        for (int i = 0; i < count; i++) run_one(&jobs[i]);
        return;
    }
    job_run run = { .jobs = jobs, .count = count };
    pthread_mutex_init(&run.lock, NULL);
    pthread_cond_init(&run.changed, NULL);
    pthread_t tids[HT_JOBS_MAX];
    int started = 0;
    while (started < threads - 1 && pthread_create(&tids[started], NULL, worker, &run) == 0) started++;
    worker(&run);
    for (int t = 0; t < started; t++) pthread_join(tids[t], NULL);
    pthread_cond_destroy(&run.changed);
    pthread_mutex_destroy(&run.lock);
}

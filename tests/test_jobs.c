/* test_jobs.c — shadergen/jobs.h: every job runs exactly once, never
   before a job it waits for has finished, on 1, 2 and 8 threads; with one
   thread in list order. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdatomic.h>

#include <cmocka.h>

#include "jobs.h"

enum { JOBS = 20 };

typedef struct record {
    atomic_int clock;                 /* ticks at every start and end */
    int runs[JOBS];
    int started[JOBS], finished[JOBS];
} record;

typedef struct job_arg {
    record *rec;
    int index;
} job_arg;

static void run(void *arg) {
    job_arg *a = arg;
    a->rec->started[a->index] = atomic_fetch_add(&a->rec->clock, 1);
    a->rec->runs[a->index]++;
    /* a little work, so that threads overlap */
    volatile unsigned spin = 0;
    for (unsigned i = 0; i < 20000u * (unsigned)(a->index % 5 + 1); i++) spin += i;
    a->rec->finished[a->index] = atomic_fetch_add(&a->rec->clock, 1);
}

/* A diamond-rich graph: job i waits for i - 1 when i is odd, for i - 3 and
   i - 5 when i is a multiple of 3; the rest wait for nothing. */
static uint32_t waits_of(int i) {
    uint32_t w = 0;
    if (i % 2 == 1) w |= (uint32_t)1 << (i - 1);
    if (i % 3 == 0 && i >= 5) w |= (uint32_t)1 << (i - 3) | (uint32_t)1 << (i - 5);
    return w;
}

static void check(int threads) {
    record rec = { 0 };
    job_arg args[JOBS];
    ht_job jobs[JOBS];
    for (int i = 0; i < JOBS; i++) {
        args[i] = (job_arg){ &rec, i };
        jobs[i] = (ht_job){ "job", run, &args[i], waits_of(i) };
    }
    ht_jobs_run(jobs, JOBS, threads);
    for (int i = 0; i < JOBS; i++) {
        assert_int_equal(rec.runs[i], 1);
        for (int k = 0; k < JOBS; k++)
            if (waits_of(i) & (uint32_t)1 << k) assert_true(rec.finished[k] < rec.started[i]);
        if (threads == 1 && i > 0) assert_true(rec.started[i] > rec.finished[i - 1]);
    }
}

static void test_every_job_once_after_what_it_waits_for(void **state) {
    (void)state;
    for (int round = 0; round < 20; round++) {
        check(1);
        check(2);
        check(8);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_job_once_after_what_it_waits_for),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

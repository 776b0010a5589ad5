/* test_lod_job.c — the chain's jobs (runtime/render/lod_job.h) without GL:
   each kind on its thread gives what the same work gives in the caller
   (a level's range of `all` sorted, the rest of the buffer as it was; a
   widened copy; the widened level sorted again, its vertices not
   copied), and out of memory inside the job is its result with nothing
   left allocated (a child process under an address-space limit; skipped
   under ASan, as test_mesh's). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "lod_job.h"
#include "support_child.h"

static const float eye[3] = { 0.5f, 1.0f, 4.0f };

static struct ht_lod_job *job_new(lod_job_kind kind, const ht_mesh *src) {
    struct ht_lod_job *j = calloc(1, sizeof *j);
    assert_non_null(j);
    j->kind = kind;
    j->src = *src;
    j->factor = 2.0;
    memcpy(j->eye, eye, sizeof j->eye);
    return j;
}

static void job_kinds_match_the_work_done_here(void **state) {
    (void)state;
    ht_mesh full;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 2000 }, &full), HT_OK);
    ht_mesh_sort_inside_out(&full);
    ht_lod_chain c;
    assert_int_equal(ht_lod_chain_build(&full, &c), HT_OK);

    /* the order of level 1's range; every other index as built */
    struct ht_lod_job *j = job_new(LOD_JOB_ORDER, &c.all);
    j->first = c.first[1];
    j->count = c.index_count[1];
    lod_job_start(j);
    lod_job_wait(j);
    assert_true(lod_job_done(j));
    assert_int_equal(j->result, HT_OK);
    uint32_t *here;
    assert_int_equal(lod_level_order(&c.all, j->first, j->count, eye, &here), HT_OK);
    assert_memory_equal(j->order, here, sizeof *here * c.all.index_count);
    assert_memory_equal(here, c.all.indices, sizeof *here * j->first);
    const uint32_t end = j->first + j->count;
    assert_memory_equal(here + end, c.all.indices + end, sizeof *here * (c.all.index_count - end));
    assert_true(memcmp(here + j->first, c.all.indices + j->first, sizeof *here * j->count) != 0);
    free(here);
    lod_job_free(j);

    /* level 2 widened 2x, back to front */
    j = job_new(LOD_JOB_WIDEN, &c.levels[2]);
    lod_job_start(j);
    lod_job_wait(j);
    assert_int_equal(j->result, HT_OK);
    ht_mesh wide;
    assert_int_equal(ht_mesh_widen_back_to_front(&c.levels[2], 2.0, eye, &wide), HT_OK);
    assert_int_equal(j->out.vertex_count, wide.vertex_count);
    assert_int_equal(j->out.component_count, wide.component_count);
    assert_memory_equal(j->out.vertices, wide.vertices, sizeof *wide.vertices * wide.vertex_count);
    assert_memory_equal(j->out.indices, wide.indices, sizeof *wide.indices * wide.index_count);
    lod_job_free(j);

    /* that copy sorted again from another eye: indices and segments only */
    j = job_new(LOD_JOB_RESORT, &wide);
    j->eye[0] = 4.0f;
    j->eye[2] = 0.5f;
    lod_job_start(j);
    lod_job_wait(j);
    assert_int_equal(j->result, HT_OK);
    assert_null(j->out.vertices);
    ht_mesh_sort_back_to_front(&wide, j->eye);
    assert_int_equal(j->out.component_count, wide.component_count);
    assert_memory_equal(j->out.indices, wide.indices, sizeof *wide.indices * wide.index_count);
    assert_memory_equal(j->out.components, wide.components, sizeof *wide.components * wide.component_count);
    lod_job_free(j);
    lod_job_free(NULL);
    ht_mesh_free(&wide);
    ht_lod_chain_free(&c);
    ht_mesh_free(&full);
}

#ifndef HT_UNDER_ASAN
/* 100 000 hairs, `all` 36 MB of indices; the limit filled first, so no
   copy of the job's fits (nor, then, a thread's stack: the job runs in
   the caller, lod_job_start's fallback, with the same result). */
static int out_of_memory_child(void) {
    ht_mesh full;
    if (ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 100000 }, &full) != HT_OK) return 10;
    if (!ht_test_limit_address_space((size_t)16 << 20)) return 11;
    void *filler[HT_TEST_FILL_BLOCKS];
    const int fills = ht_test_fill_memory(filler);
    static const lod_job_kind kinds[] = { LOD_JOB_ORDER, LOD_JOB_WIDEN, LOD_JOB_RESORT };
    for (int k = 0; k < 3; k++) {
        struct ht_lod_job *j = calloc(1, sizeof *j);
        if (!j) return 12;
        j->kind = kinds[k];
        j->src = full;
        j->count = full.index_count;
        j->factor = 2.0;
        lod_job_start(j);
        lod_job_wait(j);
        if (j->result != HT_ERR_OUT_OF_MEMORY) return 1 + k;
        if (j->order || j->out.vertices || j->out.indices || j->out.components) return 4 + k;
        lod_job_free(j);
    }
    ht_test_unfill(filler, fills);
    ht_mesh_free(&full);
    return 0;
}
#endif

static void out_of_memory_is_the_jobs_result(void **state) {
    (void)state;
    HT_TEST_FORK_MEMORY_CHILD(out_of_memory_child);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(job_kinds_match_the_work_done_here),
        cmocka_unit_test(out_of_memory_is_the_jobs_result),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

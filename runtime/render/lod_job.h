/* lod_job.h — the CPU work of an ht_lod_chain's level switch (lod.h,
   chain.async) on a thread of its own: a level's range of `all` sorted
   back to front, a level widened and sorted, or the widened level sorted
   again. The job reads only meshes the chain leaves alone while it runs
   (their arrays, through its own copy of the struct) and writes only its
   own fields; lod_chain.c uploads its result on the caller's thread. Not
   part of the public API. */
#ifndef HT_LOD_JOB_H
#define HT_LOD_JOB_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include <hairtier/lod.h>

typedef enum lod_job_kind {
    LOD_JOB_ORDER,  /* src (`all`): [first, first + count) sorted back to front into order */
    LOD_JOB_WIDEN,  /* src (a level): ht_mesh_widen_back_to_front by factor into out */
    LOD_JOB_RESORT, /* src (the widened level): its indices and segments sorted again into out (no vertices) */
} lod_job_kind;

struct ht_lod_job {
    lod_job_kind kind;
    int level;
    double factor, soften;   /* LOD_JOB_WIDEN, _RESORT: the widened level's (ht_lod_chain.wide_*) */
    float eye[3];
    ht_mesh src;             /* borrowed arrays, read only */
    uint32_t first, count;
    ht_result result;        /* once done */
    uint32_t *order;         /* LOD_JOB_ORDER: src's indices, the level's range sorted */
    ht_mesh out;             /* LOD_JOB_WIDEN: the mesh; _RESORT: indices and components only */
    bool threaded, joined;
    pthread_t thread;
    atomic_bool done;
};

/* all's indices with level range [first, first + count) sorted back to
   front from eye (its components split into segments as
   ht_mesh_sort_back_to_front splits them) into *order (malloc'd); the
   mesh itself unchanged. HT_ERR_OUT_OF_MEMORY (*order NULL). */
ht_result lod_level_order(const ht_mesh *all, uint32_t first, uint32_t count, const float eye[3], uint32_t **order);

/* Runs job (filled in by the caller, zeroed otherwise) on a new thread;
   where no thread can be made, here and now. */
void lod_job_start(struct ht_lod_job *job);
/* Whether job's work is done (its thread joined then). */
bool lod_job_done(struct ht_lod_job *job);
/* Blocks until job's work is done. */
void lod_job_wait(struct ht_lod_job *job);
/* Waits for job, then frees it and its results (NULL: nothing). */
void lod_job_free(struct ht_lod_job *job);

#endif

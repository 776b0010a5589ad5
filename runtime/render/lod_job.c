/* lod_job.c — a chain's sort or widened copy on a thread of its own
   (lod_job.h): the work a level switch would otherwise do in the frame
   that switches. One thread a job: switches are seconds apart, and a
   thread made per job needs no pool to shut down. */
#include <stdlib.h>
#include <string.h>

#include "lod_job.h"

ht_result lod_level_order(const ht_mesh *all, uint32_t first, uint32_t count, const float eye[3], uint32_t **order) {
    uint32_t n = 0;
    for (uint32_t i = 0; i < all->component_count; i++) n += all->components[i].first_index - first < count;
    ht_mesh view = { .vertices = all->vertices, .vertex_count = all->vertex_count,
                     .indices = malloc(sizeof(uint32_t) * (count ? count : 1)), .index_count = count,
                     .components = malloc(sizeof(ht_component) * (n ? n : 1)), .component_count = n };
    *order = malloc(sizeof(uint32_t) * (all->index_count ? all->index_count : 1));
    ht_result res = view.indices && view.components && *order ? HT_OK : HT_ERR_OUT_OF_MEMORY;
    if (res == HT_OK) {
        memcpy(view.indices, all->indices + first, sizeof(uint32_t) * count);
        for (uint32_t i = 0, k = 0; i < all->component_count; i++)
            if (all->components[i].first_index - first < count) {
                view.components[k] = all->components[i];
                view.components[k++].first_index -= first;
            }
        ht_mesh_sort_back_to_front(&view, eye);
        memcpy(*order, all->indices, sizeof(uint32_t) * all->index_count);
        memcpy(*order + first, view.indices, sizeof(uint32_t) * count);
    } else {
        free(*order);
        *order = NULL;
    }
    free(view.indices);
    free(view.components);
    return res;
}

/* The widened level's indices and segments, copied, sorted from the
   job's eye; its vertices stay the chain's. */
static ht_result resort(struct ht_lod_job *j) {
    ht_mesh m = { .vertices = j->src.vertices, .vertex_count = j->src.vertex_count,
                  .indices = malloc(sizeof(uint32_t) * (j->src.index_count ? j->src.index_count : 1)),
                  .index_count = j->src.index_count,
                  .components = malloc(sizeof(ht_component) * (j->src.component_count ? j->src.component_count : 1)),
                  .component_count = j->src.component_count };
    if (!m.indices || !m.components) {
        free(m.indices);
        free(m.components);
        return HT_ERR_OUT_OF_MEMORY;
    }
    memcpy(m.indices, j->src.indices, sizeof(uint32_t) * m.index_count);
    memcpy(m.components, j->src.components, sizeof(ht_component) * m.component_count);
    ht_mesh_sort_back_to_front(&m, j->eye);
    m.vertices = NULL; /* the chain's, not the job's */
    m.vertex_count = 0;
    j->out = m;
    return HT_OK;
}

static void *run(void *arg) {
    struct ht_lod_job *j = arg;
    switch (j->kind) {
    case LOD_JOB_ORDER: j->result = lod_level_order(&j->src, j->first, j->count, j->eye, &j->order); break;
    case LOD_JOB_WIDEN: j->result = ht_mesh_widen_back_to_front(&j->src, j->factor, j->eye, &j->out); break;
    case LOD_JOB_RESORT: j->result = resort(j); break;
    }
    atomic_store_explicit(&j->done, true, memory_order_release);
    return NULL;
}

void lod_job_start(struct ht_lod_job *j) {
    atomic_init(&j->done, false);
    j->threaded = pthread_create(&j->thread, NULL, run, j) == 0;
    if (!j->threaded) run(j); /* a stall, as without async, rather than no level */
}

bool lod_job_done(struct ht_lod_job *j) {
    if (!atomic_load_explicit(&j->done, memory_order_acquire)) return false;
    lod_job_wait(j);
    return true;
}

void lod_job_wait(struct ht_lod_job *j) {
    if (j->threaded && !j->joined) pthread_join(j->thread, NULL);
    j->joined = true;
}

void lod_job_free(struct ht_lod_job *j) {
    if (!j) return;
    lod_job_wait(j);
    free(j->order);
    ht_mesh_free(&j->out);
    free(j);
}

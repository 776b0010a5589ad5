/* lod_chain.c — a mesh's levels switched per frame (lod.h,
   ht_lod_chain): the best rule with its hysteresis, every level in one
   uploaded mesh and a draw range each, through the public renderer API
   only. */
#include <math.h>
#include <string.h>

#include <hairtier/lod.h>
#include "mesh_internal.h"

/* The levels one after the other: vertices appended, indices shifted by
   the vertices before them, components kept (their first_index shifted). */
static ht_result concatenate(ht_lod_chain *c) {
    uint64_t vertices = 0, indices = 0, components = 0;
    for (int l = 0; l < c->count; l++) {
        const ht_mesh *m = ht_lod_chain_mesh(c, l);
        vertices += m->vertex_count;
        indices += m->index_count;
        components += m->component_count;
    }
    ht_result r = ht_mesh_alloc(&c->all, vertices, indices, components);
    if (r != HT_OK) return r;
    memcpy(c->all.center, c->full->center, sizeof c->all.center);
    uint32_t v = 0, i = 0, k = 0;
    for (int l = 0; l < c->count; l++) {
        const ht_mesh *m = ht_lod_chain_mesh(c, l);
        memcpy(c->all.vertices + v, m->vertices, sizeof *m->vertices * m->vertex_count);
        for (uint32_t j = 0; j < m->index_count; j++) c->all.indices[i + j] = m->indices[j] + v;
        for (uint32_t j = 0; j < m->component_count; j++) {
            c->all.components[k + j] = m->components[j];
            c->all.components[k + j].first_index += i;
        }
        c->first[l] = i;
        c->index_count[l] = m->index_count;
        v += m->vertex_count;
        i += m->index_count;
        k += m->component_count;
    }
    return HT_OK;
}

ht_result ht_lod_chain_build(const ht_mesh *full, ht_lod_chain *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    out->current = -1;
    if (!full || !full->component_count) return HT_ERR_INVALID_ARGUMENT;
    out->full = full;
    out->width = ht_mesh_mean_width(full);
    out->count = 1;
    const int max = ht_lod_max_level(full);
    for (int l = 1; l <= max; l++) {
        ht_lod_desc d;
        ht_lod_level(l, &d);
        ht_result r = ht_mesh_build_lod(full, &d, &out->levels[l]);
        if (r != HT_OK) {
            ht_lod_chain_free(out);
            return r;
        }
        out->count++;
    }
    ht_result r = concatenate(out);
    if (r != HT_OK) ht_lod_chain_free(out);
    return r;
}

ht_result ht_lod_chain_from_file(const ht_lod_file *f, ht_lod_chain *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    out->current = -1;
    if (!f || f->level_count < 1 || f->level_count > HT_LOD_FILE_MAX_LEVELS ||
        f->levels[0].kind != HT_LOD_KIND_STRANDS)
        return HT_ERR_INVALID_ARGUMENT;
    ht_result r = ht_mesh_alloc(&out->all, f->mesh.vertex_count, f->mesh.index_count, f->mesh.component_count);
    if (r != HT_OK) return r;
    memcpy(out->all.center, f->mesh.center, sizeof out->all.center);
    memcpy(out->all.vertices, f->mesh.vertices, sizeof *f->mesh.vertices * f->mesh.vertex_count);
    memcpy(out->all.indices, f->mesh.indices, sizeof *f->mesh.indices * f->mesh.index_count);
    memcpy(out->all.components, f->mesh.components, sizeof *f->mesh.components * f->mesh.component_count);
    for (int l = 0; l < f->level_count && r == HT_OK; l++) {
        r = ht_lod_file_level_mesh(f, l, &out->levels[l]);
        out->first[l] = f->levels[l].first_index;
        out->index_count[l] = f->levels[l].index_count;
        out->count = l + 1;
    }
    if (r != HT_OK) {
        ht_lod_chain_free(out);
        return r;
    }
    out->full = &out->levels[0];
    out->width = ht_mesh_mean_width(out->full);
    return HT_OK;
}

ht_result ht_lod_chain_from_scene_file(const ht_lod_file *f, const ht_mesh *full, ht_lod_chain *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    if (f && f->level_count >= 1 && f->levels[0].kind != HT_LOD_KIND_SCENE) return ht_lod_chain_from_file(f, out);
    memset(out, 0, sizeof *out);
    out->current = -1;
    if (!f || !full || f->level_count < 1 || !ht_lod_file_matches(f, full)) return HT_ERR_INVALID_ARGUMENT;
    out->full = full;
    out->width = ht_mesh_mean_width(full);
    out->count = 1;
    ht_result r = HT_OK;
    for (int l = 1; l < f->level_count && r == HT_OK; l++)
        if ((r = ht_lod_file_level_mesh(f, l, &out->levels[l])) == HT_OK) out->count = l + 1;
    if (r == HT_OK) r = concatenate(out);
    if (r != HT_OK) ht_lod_chain_free(out);
    return r;
}

const ht_mesh *ht_lod_chain_mesh(const ht_lod_chain *c, int level) {
    if (!c || level < 0 || level >= c->count) return NULL;
    return level ? &c->levels[level] : c->full;
}

int ht_lod_chain_select(ht_lod_chain *c, ht_renderer *r, const ht_camera *camera, int viewport_h, ht_result *result) {
    if (result) *result = HT_OK;
    if (!c || !c->full || !r || !camera) {
        if (result) *result = HT_ERR_INVALID_ARGUMENT;
        return -1;
    }
    double d = 0;
    for (int k = 0; k < 3; k++) d += ((double)camera->eye[k] - c->full->center[k]) * (camera->eye[k] - c->full->center[k]);
    const double px = ht_projected_width_px(c->width, sqrt(d), camera->fov_y, viewport_h);
    const int level = ht_lod_pick_best(px, c->current, c->count - 1);
    if (level == c->current && c->uploaded == r) return level;
    ht_result res = c->uploaded == r ? HT_OK : ht_renderer_set_mesh(r, &c->all);
    if (res == HT_OK) {
        c->uploaded = r;
        res = ht_renderer_set_draw_range(r, c->first[level], c->index_count[level]);
    }
    if (res != HT_OK) {
        if (result) *result = res;
        return -1;
    }
    c->current = level;
    return level;
}

void ht_lod_chain_free(ht_lod_chain *c) {
    if (!c) return;
    for (int l = 0; l < HT_LOD_FILE_MAX_LEVELS; l++) ht_mesh_free(&c->levels[l]);
    ht_mesh_free(&c->all);
    memset(c, 0, sizeof *c);
    c->current = -1;
}

/* lod_chain.c — a mesh's levels switched per frame (lod.h,
   ht_lod_chain): the best rule with its hysteresis, or a (level, tier)
   pair by error:DB or frame:MS over measured cells; every level in one
   uploaded mesh and a draw range each, a tier by ht_renderer_set_tier,
   through the public renderer API only. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/lod.h>
#include "lod_job.h"
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

/* r draws level's range of `all`, its own vertices named (the CPU tiers
   touch only those). */
static ht_result set_level_range(const ht_lod_chain *c, ht_renderer *r, int level) {
    return ht_renderer_set_draw_range_vertices(r, c->first[level], c->index_count[level], c->first_vertex[level],
                                               c->vertex_count[level]);
}

/* An empty chain: no level drawn yet, no tier chosen. */
static void chain_init(ht_lod_chain *c) {
    memset(c, 0, sizeof *c);
    c->current = -1;
    c->tier = HT_TIER_COUNT;
    c->ordered_level = -1;
}

/* Each level's mean ribbon width (the width rule's per-draw factor) and
   the vertices its range of `all` uses. */
static void measure_widths(ht_lod_chain *c) {
    for (int l = 0; l < c->count; l++) {
        c->level_width[l] = ht_mesh_mean_width(ht_lod_chain_mesh(c, l));
        uint32_t lo = UINT32_MAX, hi = 0;
        for (uint32_t i = c->first[l]; i < c->first[l] + c->index_count[l] && i < c->all.index_count; i++) {
            lo = c->all.indices[i] < lo ? c->all.indices[i] : lo;
            hi = c->all.indices[i] > hi ? c->all.indices[i] : hi;
        }
        c->first_vertex[l] = lo <= hi ? lo : 0;
        c->vertex_count[l] = lo <= hi ? hi - lo + 1 : c->all.vertex_count;
    }
}

/* The levels built so far (r: how building them went) into one buffer, or
   the chain freed. */
static ht_result finish(ht_lod_chain *c, ht_result r) {
    if (r == HT_OK) r = concatenate(c);
    if (r != HT_OK) {
        ht_lod_chain_free(c);
        return r;
    }
    measure_widths(c);
    return HT_OK;
}

ht_result ht_lod_chain_build(const ht_mesh *full, ht_lod_chain *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    chain_init(out);
    if (!full || !full->component_count) return HT_ERR_INVALID_ARGUMENT;
    out->full = full;
    out->width = ht_mesh_mean_width(full);
    out->count = 1;
    const int max = ht_lod_max_level(full);
    ht_result r = HT_OK;
    for (int l = 1; l <= max && r == HT_OK; l++) {
        ht_lod_desc d;
        ht_lod_level(l, &d);
        if ((r = ht_mesh_build_lod(full, &d, &out->levels[l])) == HT_OK) out->count++;
    }
    return finish(out, r);
}

ht_result ht_lod_chain_from_file(const ht_lod_file *f, ht_lod_chain *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    chain_init(out);
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
    measure_widths(out);
    return HT_OK;
}

ht_result ht_lod_chain_from_scene_file(const ht_lod_file *f, const ht_mesh *full, ht_lod_chain *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    if (f && f->level_count >= 1 && f->levels[0].kind != HT_LOD_KIND_SCENE) return ht_lod_chain_from_file(f, out);
    chain_init(out);
    if (!f || !full || f->level_count < 1 || !ht_lod_file_matches(f, full)) return HT_ERR_INVALID_ARGUMENT;
    out->full = full;
    out->width = ht_mesh_mean_width(full);
    out->count = 1;
    ht_result r = HT_OK;
    for (int l = 1; l < f->level_count && r == HT_OK; l++)
        if ((r = ht_lod_file_level_mesh(f, l, &out->levels[l])) == HT_OK) out->count = l + 1;
    return finish(out, r);
}

const ht_mesh *ht_lod_chain_mesh(const ht_lod_chain *c, int level) {
    if (!c || level < 0 || level >= c->count) return NULL;
    return level ? &c->levels[level] : c->full;
}

/* A level-0 strand's projected width at this camera (the eye's distance
   to the mesh's centre). */
static double strand_px(const ht_lod_chain *c, const ht_camera *camera, int viewport_h) {
    double d = 0;
    for (int k = 0; k < 3; k++) d += ((double)camera->eye[k] - c->full->center[k]) * (camera->eye[k] - c->full->center[k]);
    return ht_projected_width_px(c->width, sqrt(d), camera->fov_y, viewport_h);
}

/* After r failed an upload (res): a refused argument or an unsupported
   mesh leaves r's mesh in place; anything else (a GL error, memory) may
   have released it (hairtier.h), so r is taken to hold nothing of the
   chain and draw no level: the next select uploads again. */
static ht_result upload_failed(ht_lod_chain *c, ht_renderer *r, ht_result res) {
    if (res == HT_ERR_INVALID_ARGUMENT || res == HT_ERR_UNSUPPORTED) return res;
    if (c->uploaded == r || c->wide_renderer == r) {
        ht_renderer_set_opacity_scale(r, 1.0f);
        ht_renderer_set_back_to_front(r, false);
    }
    if (c->uploaded == r) c->uploaded = NULL;
    if (c->wide_renderer == r) c->wide_renderer = NULL;
    c->ordered_level = -1;
    c->current = -1;
    return res;
}

/* `all` on r, uploaded once (an upload is in the order as built, drawn
   whole: no level yet). */
static ht_result hold_all(ht_lod_chain *c, ht_renderer *r) {
    if (c->uploaded == r) return HT_OK;
    ht_result res = ht_renderer_set_mesh(r, &c->all);
    if (res != HT_OK) return upload_failed(c, r, res);
    c->uploaded = r;
    c->ordered_level = -1;
    c->current = -1;
    return HT_OK;
}

/* A level drawn alone on r no more: opacity 1, blended split by facing. */
static void drop_wide(ht_lod_chain *c, ht_renderer *r) {
    if (c->wide_renderer != r) return;
    ht_renderer_set_opacity_scale(r, 1.0f);
    ht_renderer_set_back_to_front(r, false);
    c->wide_renderer = NULL;
    c->wide_factor = 1.0;
}

/* A select that failed (an upload, a job's result): *result, -1, and r's
   draw range on the level the chain says it draws (an upload of `all`
   resets the range to all of it). */
static int failed(ht_lod_chain *c, ht_renderer *r, ht_result res, ht_result *result) {
    if (c->uploaded == r && c->current >= 0) set_level_range(c, r, c->current);
    if (result) *result = res;
    return -1;
}

/* `all` on r (once), then level's range as built; *result and -1 on failure. */
static int draw_level(ht_lod_chain *c, ht_renderer *r, int level, ht_result *result) {
    ht_result res = hold_all(c, r);
    if (res == HT_OK) drop_wide(c, r);
    if (res == HT_OK && c->ordered_level >= 0) {
        /* a level sorted back to front (the width rule per vertex): as built again */
        if ((res = ht_renderer_set_mesh_order(r, &c->all)) == HT_OK) c->ordered_level = -1;
        else upload_failed(c, r, res);
        ht_renderer_set_back_to_front(r, false);
    }
    if (res == HT_OK) res = set_level_range(c, r, level);
    if (res != HT_OK) return failed(c, r, res, result);
    c->soften = 0.0f;
    c->current = level;
    return level;
}

/* The mesh r holds of this chain: `all`, the widened level, or none. */
static const ht_mesh *held_mesh(const ht_lod_chain *c, const ht_renderer *r) {
    return c->uploaded == r ? &c->all : c->wide_renderer == r ? &c->wide : NULL;
}

/* Whether an order sorted from eye `from` (wide_eye, ordered_eye) still
   serves eye: its direction from the centre turned by at most
   HT_LOD_RESORT_DEG and its distance within HT_LOD_RESORT_DISTANCE times. */
static bool order_serves(const ht_lod_chain *c, const float from[3], const float eye[3]) {
    double was = 0, now = 0, dot = 0;
    for (int k = 0; k < 3; k++) {
        const double a = (double)from[k] - c->full->center[k], b = (double)eye[k] - c->full->center[k];
        was += a * a, now += b * b, dot += a * b;
    }
    was = sqrt(was), now = sqrt(now);
    if (!(was > 0 && now > 0)) return was == now;
    return now <= was * HT_LOD_RESORT_DISTANCE && was <= now * HT_LOD_RESORT_DISTANCE &&
           dot / (was * now) >= cos(HT_LOD_RESORT_DEG * M_PI / 180.0);
}

/* The width rule per vertex on a level whose strands blend (lod.h): its
   range of `all` sorted back to front from eye, its indices uploaded
   alone, drawn at opacity 1; sorted again only for another level or past
   the order's reach. order: that order made already (a job's), NULL: made
   here when needed. */
static int draw_level_ordered(ht_lod_chain *c, ht_renderer *r, int level, const float eye[3], const uint32_t *order,
                              ht_result *result) {
    ht_result res = hold_all(c, r);
    if (res == HT_OK) drop_wide(c, r);
    uint32_t *made = NULL;
    if (res == HT_OK && !order && (c->ordered_level != level || !order_serves(c, c->ordered_eye, eye)))
        res = lod_level_order(&c->all, c->first[level], c->index_count[level], eye, &made), order = made;
    if (res == HT_OK && order) {
        ht_mesh sorted = c->all; /* `all` itself (the CPU copy) stays as built */
        sorted.indices = (uint32_t *)order;
        if ((res = ht_renderer_set_mesh_order(r, &sorted)) == HT_OK) {
            c->ordered_level = level;
            memcpy(c->ordered_eye, eye, sizeof c->ordered_eye);
        } else {
            upload_failed(c, r, res);
        }
    }
    free(made);
    if (res == HT_OK) res = set_level_range(c, r, level);
    if (res != HT_OK) return failed(c, r, res, result);
    ht_renderer_set_back_to_front(r, true);
    c->soften = 0.0f;
    c->current = level;
    return level;
}

/* r draws `wide` (level widened by factor, s of it the soft pair's, back
   to front from eye), uploaded alone, at opacity 1 / factor; the chain
   owns it from here (freed on failure, r keeping what it had). */
static int draw_wide(ht_lod_chain *c, ht_renderer *r, int level, double factor, double s, const float eye[3],
                     ht_mesh *wide, ht_result *result) {
    ht_result res = ht_renderer_set_mesh(r, wide);
    if (res != HT_OK) {
        ht_mesh_free(wide);
        return failed(c, r, upload_failed(c, r, res), result);
    }
    ht_renderer_set_opacity_scale(r, (float)(1.0 / factor)); /* factor in (1, HT_LOD_MAX_WIDEN]: taken */
    ht_renderer_set_back_to_front(r, true);
    ht_mesh_free(&c->wide);
    c->wide = *wide;
    c->wide_renderer = r;
    c->wide_level = level;
    c->wide_factor = factor;
    c->wide_soften = s;
    memcpy(c->wide_eye, eye, sizeof c->wide_eye);
    if (c->uploaded == r) c->uploaded = NULL; /* r holds the widened level now */
    c->ordered_level = -1;
    c->soften = s > 1.0 ? (float)s : 0.0f;
    c->current = level;
    return level;
}

/* The widened level r holds in a new order (sorted: its indices and
   segments, a job's), the indices uploaded alone. */
static int draw_wide_order(ht_lod_chain *c, ht_renderer *r, ht_mesh *sorted, const float eye[3], ht_result *result) {
    ht_mesh m = c->wide;
    m.indices = sorted->indices;
    m.components = sorted->components;
    m.component_count = sorted->component_count;
    ht_result res = ht_renderer_set_mesh_order(r, &m);
    if (res != HT_OK) return failed(c, r, upload_failed(c, r, res), result);
    free(c->wide.indices);
    free(c->wide.components);
    c->wide = m;
    sorted->indices = NULL;
    sorted->components = NULL;
    memcpy(c->wide_eye, eye, sizeof c->wide_eye);
    c->current = c->wide_level;
    return c->current;
}

/* What the width rule asks of one frame (draw_level_width_rule). */
typedef struct wanted {
    int level;
    double s, factor; /* the soft pair's soften (1: plain); the level widened by factor, 1: not */
    bool sorts;       /* unwidened, its range sorted back to front (the rule per vertex) */
} wanted;

static bool holds_wide(const ht_lod_chain *c, const ht_renderer *r, int level, double factor, double s) {
    return c->wide_renderer == r && c->wide_level == level && c->wide_factor == factor && c->wide_soften == s;
}

/* The CPU work w needs of r's chain for eye: a lod_job_kind, or -1 for
   none (what r holds serves, or a level as built). */
static int work_for(const ht_lod_chain *c, const ht_renderer *r, const wanted *w, const float eye[3]) {
    if (w->factor <= 1.0 && !w->sorts) return -1;
    if (w->factor <= 1.0)
        return c->uploaded == r && c->ordered_level == w->level && order_serves(c, c->ordered_eye, eye) ? -1
                                                                                                       : LOD_JOB_ORDER;
    if (!holds_wide(c, r, w->level, w->factor, w->s)) return LOD_JOB_WIDEN;
    return order_serves(c, c->wide_eye, eye) ? -1 : LOD_JOB_RESORT;
}

/* Whether job's result brings r nearer to w: the order of w's level; a
   widened w's level of w's soften (at any factor: the factor it was
   asked for is nearer than what r holds); the widened level r holds
   sorted again. */
static bool job_serves(const ht_lod_chain *c, const ht_renderer *r, const struct ht_lod_job *j, const wanted *w) {
    if (j->level != w->level) return false;
    if (j->kind == LOD_JOB_ORDER) return w->factor <= 1.0 && w->sorts;
    if (w->factor <= 1.0 || j->soften != w->s) return false;
    return j->kind == LOD_JOB_WIDEN || holds_wide(c, r, j->level, j->factor, j->soften);
}

/* A done job's result on r (the uploads, on this thread). */
static int apply_job(ht_lod_chain *c, ht_renderer *r, struct ht_lod_job *j, ht_result *result) {
    if (j->result != HT_OK) return failed(c, r, j->result, result);
    if (j->kind == LOD_JOB_ORDER) return draw_level_ordered(c, r, j->level, j->eye, j->order, result);
    if (j->kind == LOD_JOB_RESORT) return draw_wide_order(c, r, &j->out, j->eye, result);
    const int level = draw_wide(c, r, j->level, j->factor, j->soften, j->eye, &j->out, result);
    memset(&j->out, 0, sizeof j->out); /* the chain's now, or freed */
    return level;
}

/* A job for kind of w, from eye, started (its sources are meshes the
   chain leaves alone while it runs); false: out of memory. */
static bool start_job(ht_lod_chain *c, int kind, const wanted *w, const float eye[3]) {
    struct ht_lod_job *j = calloc(1, sizeof *j);
    if (!j) return false;
    j->kind = (lod_job_kind)kind;
    j->level = w->level;
    j->factor = w->factor;
    j->soften = w->s;
    memcpy(j->eye, eye, sizeof j->eye);
    j->src = kind == LOD_JOB_ORDER ? c->all : kind == LOD_JOB_WIDEN ? *ht_lod_chain_mesh(c, w->level) : c->wide;
    j->first = c->first[w->level];
    j->count = c->index_count[w->level];
    lod_job_start(j);
    c->job = j;
    return true;
}

/* chain.async (lod.h): w's CPU work on a job; the frame draws what r
   holds until a later select finds it done and uploads it. */
static int draw_async(ht_lod_chain *c, ht_renderer *r, const wanted *w, const ht_camera *camera, ht_result *result) {
    int work = work_for(c, r, w, camera->eye);
    if (c->job && lod_job_done(c->job)) {
        struct ht_lod_job *j = c->job;
        c->job = NULL;
        const int level = work >= 0 && job_serves(c, r, j, w) ? apply_job(c, r, j, result) : 0;
        lod_job_free(j); /* uploaded, or superseded: dropped */
        if (level < 0) return -1;
        work = work_for(c, r, w, camera->eye);
    }
    if (work < 0) {
        /* no sort or copy: as without async */
        if (w->factor > 1.0) return c->current = w->level;
        return w->sorts ? draw_level_ordered(c, r, w->level, camera->eye, NULL, result)
                        : draw_level(c, r, w->level, result);
    }
    /* one job at a time: a running one ends first, its result then taken if it serves (job_serves) */
    if (!c->job && !start_job(c, work, w, camera->eye)) {
        if (result) *result = HT_ERR_OUT_OF_MEMORY;
        return -1;
    }
    c->waiting = true;
    /* meanwhile: what r holds; nothing yet, the level as built */
    return held_mesh(c, r) && c->current >= 0 ? c->current : draw_level(c, r, w->level, result);
}

/* The level drawn alone (lod.h): widened by soften (a soft pair; 1:
   plain) times the width rule's f (1 where the renderer does the rule per
   vertex), sorted back to front from this eye, uploaded alone, the
   opacity 1 / that factor; the same level and factor again: nothing
   unless the eye moved past the order's reach (sorted again and
   uploaded); neither soft nor under a pixel: `all` again, opacity 1. */
static int draw_level_width_rule(ht_lod_chain *c, ht_renderer *r, int level, float soften, double px,
                                 const ht_camera *camera, ht_result *result) {
    const double s = soften > 1.0f ? soften : 1.0;
    const double level_px = px * s * c->level_width[level] / c->width; /* the level's strands, drawn */
    const bool applies = c->width_rule && ht_width_rule_applies(level_px, ht_renderer_samples(r));
    const double f = applies ? ht_width_rule_widen(level_px) : 1.0;
    /* per vertex is known once r holds a mesh of this chain (lod.h) */
    if (c->width_rule && !held_mesh(c, r) && draw_level(c, r, level, result) < 0) return -1;
    const bool per_vertex = c->width_rule && ht_renderer_width_rule_per_vertex(r);
    const double factor = fmin(s * (per_vertex ? 1.0 : f), HT_LOD_MAX_WIDEN);
    const bool sorts = per_vertex && applies;
    c->waiting = false;
    if (c->async) return draw_async(c, r, &(wanted){ level, s, factor, sorts }, camera, result);
    if (c->job) { /* async turned off: its result dropped */
        lod_job_free(c->job);
        c->job = NULL;
    }
    /* translucent strands (soft, widened, or per vertex under 1.5 px) blend far to near */
    if (factor <= 1.0 && sorts) return draw_level_ordered(c, r, level, camera->eye, NULL, result);
    if (factor <= 1.0) return draw_level(c, r, level, result);
    if (holds_wide(c, r, level, factor, s)) {
        if (!order_serves(c, c->wide_eye, camera->eye)) {
            /* the same vertices in a new order: the indices go up alone */
            ht_mesh_sort_back_to_front(&c->wide, camera->eye);
            ht_result res = ht_renderer_set_mesh_order(r, &c->wide);
            if (res != HT_OK) return failed(c, r, upload_failed(c, r, res), result);
            memcpy(c->wide_eye, camera->eye, sizeof c->wide_eye);
        }
        c->current = level;
        return level;
    }
    ht_mesh wide;
    ht_result res = ht_mesh_widen_back_to_front(ht_lod_chain_mesh(c, level), factor, camera->eye, &wide);
    if (res != HT_OK) return failed(c, r, res, result);
    return draw_wide(c, r, level, factor, s, camera->eye, &wide, result);
}

bool ht_lod_chain_pending(const ht_lod_chain *c) { return c && c->job && c->waiting; }

void ht_lod_chain_wait(ht_lod_chain *c) {
    if (c && c->job) lod_job_wait(c->job);
}

int ht_lod_chain_select(ht_lod_chain *c, ht_renderer *r, const ht_camera *camera, int viewport_h, ht_result *result) {
    if (result) *result = HT_OK;
    if (!c || !c->full || !r || !camera) {
        if (result) *result = HT_ERR_INVALID_ARGUMENT;
        return -1;
    }
    const double px = strand_px(c, camera, viewport_h);
    const int level = ht_lod_pick_best(px, c->current, c->count - 1);
    if (level == c->current && c->uploaded == r && !c->width_rule && !c->job) return level;
    return draw_level_width_rule(c, r, level, 0.0f, px, camera, result);
}


/* The measured size the rule reads its cells at: the nearest to `size`
   (in log2), but the one in use (held) while it is within
   HT_LOD_HYSTERESIS octaves of being the nearest, so a size jittering
   between two measured ones does not flip the pair. */
static double measured_size(const ht_lod_cell *cells, int n, double size, double held) {
    double nearest = 0, nearest_octaves = INFINITY;
    bool has_held = false;
    for (int i = 0; i < n; i++) {
        if (!(cells[i].size > 0)) continue;
        const double octaves = fabs(log2(cells[i].size / size));
        if (octaves < nearest_octaves) nearest = cells[i].size, nearest_octaves = octaves;
        has_held |= cells[i].size == held;
    }
    return has_held && fabs(log2(held / size)) <= nearest_octaves + HT_LOD_HYSTERESIS ? held : nearest;
}

int ht_lod_chain_select_pair(ht_lod_chain *c, ht_renderer *r, const ht_camera *camera, int viewport_h,
                             const ht_lod_rule *rule, ht_result *result) {
    if (!rule || rule->kind == HT_POLICY_BEST) return ht_lod_chain_select(c, r, camera, viewport_h, result);
    if (result) *result = HT_OK;
    const bool frame = rule->kind == HT_POLICY_FRAME;
    if (!c || !c->full || !r || !camera || (!frame && rule->kind != HT_POLICY_ERROR) || !rule->cells ||
        rule->cell_count <= 0 || !(rule->size1_px > 0) || (frame && !(rule->reference_ms > 0))) {
        if (result) *result = HT_ERR_INVALID_ARGUMENT;
        return -1;
    }
    const double px = strand_px(c, camera, viewport_h);
    if (c->usable_capacity < rule->cell_count) {
        ht_lod_cell *grown = realloc(c->usable, (size_t)rule->cell_count * sizeof *grown);
        if (!grown) {
            if (result) *result = HT_ERR_OUT_OF_MEMORY;
            return -1;
        }
        c->usable = grown;
        c->usable_capacity = rule->cell_count;
    }
    ht_lod_cell *cells = c->usable;
    for (;;) {
        /* the cells of the levels this chain has and the tiers not refused */
        int n = 0, held = -1;
        for (int i = 0; i < rule->cell_count; i++) {
            const ht_lod_cell *cell = &rule->cells[i];
            const bool soft = cell->soften > 1.0f;
            if (cell->lod < 0 || cell->lod >= c->count || (unsigned)cell->tier >= HT_TIER_COUNT ||
                (c->refused_tiers >> cell->tier & 1u) || (soft && (cell->lod == 0 || !(cell->soften <= HT_LOD_MAX_SOFTEN))))
                continue;
            if (ht_lod_cell_same_pair(cell, &(ht_lod_cell){ .lod = c->current, .tier = c->tier, .soften = c->soften }))
                held = n;
            cells[n++] = *cell;
        }
        const double size = n ? measured_size(cells, n, px / rule->size1_px, c->size) : 0;
        const int pick = frame ? ht_lod_pick_frame(cells, n, size, rule->value, ht_lod_rule_reference_ms(rule, size), held)
                               : ht_lod_pick_error(cells, n, size, rule->value, held);
        if (pick < 0) {
            if (result) *result = HT_ERR_NO_TIER;
            return -1;
        }
        const int level = cells[pick].lod;
        const ht_tier tier = cells[pick].tier;
        const float soften = cells[pick].soften > 1.0f ? cells[pick].soften : 0.0f;
        c->size = size;
        if (level == c->current && tier == c->tier && c->uploaded == r && ht_renderer_tier(r) == tier &&
            !c->width_rule && soften == 0.0f && !c->job)
            return level;
        /* the mesh first: the tier's per-vertex data is made of it */
        ht_result res = held_mesh(c, r) ? HT_OK : hold_all(c, r);
        if (res == HT_OK && ht_renderer_tier(r) != tier) res = ht_renderer_set_tier(r, tier, held_mesh(c, r));
        if (res == HT_OK) {
            c->tier = tier;
            return draw_level_width_rule(c, r, level, soften, px, camera, result);
        }
        if (!held_mesh(c, r) || res == HT_ERR_OUT_OF_MEMORY) {
            if (result) *result = res;
            return -1;
        }
        c->refused_tiers |= 1u << tier; /* logged by the renderer; pick again without it */
    }
}

void ht_lod_chain_free(ht_lod_chain *c) {
    if (!c) return;
    lod_job_free(c->job); /* joined first: it reads the meshes freed below */
    for (int l = 0; l < HT_LOD_FILE_MAX_LEVELS; l++) ht_mesh_free(&c->levels[l]);
    ht_mesh_free(&c->all);
    ht_mesh_free(&c->wide);
    free(c->usable);
    chain_init(c);
}

/* lod_file.c — the stored ladder, lods.bin (lod.h has the layout): one
   writer and one guarded reader. Every size is checked against the bytes
   before anything is allocated; every range, index and box after. The
   vertices are quantized (lod_quant.h); a ribbon level's indices are not
   stored but implied by its components' rows. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "file_open.h"
#include "lod_quant.h"
#include "manifest.h"
#include "mesh_internal.h"
#include <hairtier/lod.h>

static const char magic[8] = { 'H', 'T', 'L', 'O', 'D', 'S', '3', '\n' };

/* magic, 5 counts, the centre, the scene's 3 counts and hash, 2 boxes */
#define HEADER_BYTES (8 + 5 * 4 + 3 * 4 + 3 * 4 + 8 + 2 * 6 * 4)
#define LEVEL_BYTES (6 * 4)
#define VERTEX_FLOATS 12
#define COMPONENT_BYTES 12
_Static_assert(sizeof(ht_vertex) == VERTEX_FLOATS * sizeof(float), "ht_vertex is 12 floats, unpadded");

static void vertex_floats(const ht_vertex *v, float out[VERTEX_FLOATS]) { memcpy(out, v, sizeof *v); }

typedef struct reader {
    const unsigned char *p, *end;
} reader;

static uint32_t get_u32(reader *r) {
    const unsigned char *p = r->p;
    r->p += 4;
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float get_f32(reader *r) {
    const uint32_t u = get_u32(r);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static void put_u32(unsigned char **p, uint32_t v) {
    for (int i = 0; i < 4; i++) (*p)[i] = (unsigned char)(v >> (8 * i));
    *p += 4;
}

static void put_f32(unsigned char **p, float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_u32(p, u);
}

static uint64_t file_bytes(uint64_t levels, uint64_t vertices, uint64_t stored_indices, uint64_t components) {
    return HEADER_BYTES + levels * LEVEL_BYTES + vertices * HT_LOD_QUANT_VERTEX_BYTES + stored_indices * 4 +
           components * COMPONENT_BYTES;
}

/* The run of vertices a level's indices reach: how many, *lo the first
   (0 for none). */
static uint32_t index_span(const ht_mesh *m, const ht_lod_range *r, uint32_t *lo) {
    uint32_t hi = 0;
    *lo = UINT32_MAX;
    for (uint32_t i = r->first_index; i < r->first_index + r->index_count; i++) {
        *lo = m->indices[i] < *lo ? m->indices[i] : *lo;
        hi = m->indices[i] > hi ? m->indices[i] : hi;
    }
    if (!r->index_count) *lo = hi = 0;
    return r->index_count ? hi - *lo + 1 : 0;
}

/* The six indices of a strip's segment q: rows of two vertices from a0. */
static void strip_segment(uint32_t *out, uint32_t a0) {
    const uint32_t a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
    const uint32_t tri[6] = { a0, b1, a1, a0, b0, b1 };
    memcpy(out, tri, sizeof tri);
}

/* The ranges and indices of a ladder, whoever made it; NULL when valid,
   else the array (and *at the element, *what what is wrong with it). */
static const char *check_ladder(const ht_lod_file *f, uint32_t *at, const char **what) {
    const ht_mesh *m = &f->mesh;
    *at = 0;
    *what = "not whole triangles";
    if (m->index_count % 3) return "indices";
    *what = "past the vertices";
    for (uint32_t i = 0; i < m->index_count; i++)
        if (m->indices[i] >= m->vertex_count) { *at = i; return "indices"; }
    *what = "index range past the indices, or sort key not finite";
    for (uint32_t c = 0; c < m->component_count; c++) {
        const ht_component *k = &m->components[c];
        *at = c;
        if (k->first_index > m->index_count || k->index_count > m->index_count - k->first_index || !isfinite(k->sort_key))
            return "components";
    }
    for (int l = 0; l < f->level_count; l++) {
        const ht_lod_range *r = &f->levels[l];
        *at = (uint32_t)l;
        *what = "kind neither strands, cards nor the scene's mesh";
        if (r->kind != HT_LOD_KIND_STRANDS && r->kind != HT_LOD_KIND_CARDS && r->kind != HT_LOD_KIND_SCENE)
            return "levels";
        *what = "the scene's mesh (not stored) is level 0 only, stride 1, no range";
        if (r->kind == HT_LOD_KIND_SCENE &&
            (l || r->param != 1 || r->first_index || r->index_count || r->first_component || r->component_count))
            return "levels";
        *what = "index range past the indices or not whole triangles";
        if (r->first_index % 3 || r->index_count % 3 || r->first_index > m->index_count ||
            r->index_count > m->index_count - r->first_index)
            return "levels";
        *what = "component range past the components";
        if (r->first_component > m->component_count || r->component_count > m->component_count - r->first_component)
            return "levels";
        *what = "a component outside the level's index range";
        for (uint32_t c = r->first_component; c < r->first_component + r->component_count; c++) {
            const ht_component *k = &m->components[c];
            if (k->first_index < r->first_index || k->first_index + k->index_count > r->first_index + r->index_count)
                return "levels";
        }
    }
    for (uint32_t v = 0; v < m->vertex_count; v++)
    {
        float f[VERTEX_FLOATS];
        vertex_floats(&m->vertices[v], f);
        *what = "not finite";
        if (!ht_all_finite(f, VERTEX_FLOATS)) { *at = v; return "vertices"; }
    }
    return NULL;
}

/* A level as the file stores it: its vertices are the next vertex_count
   of the buffer, its indices and components the next ones too. */
typedef struct level_span {
    uint32_t strips;                   /* 1: indices implied by the components' rows */
    uint32_t first_vertex, vertex_count;
} level_span;

/* A strips level's indices from its components, as read: each a ribbon
   of index_count / 6 + 1 rows of two vertices from its first vertex (the
   level's vertex number the file holds in first_index); their indices
   follow each other from the level's first. NULL when they fit, else the
   field at fault. */
static const char *derive_strips(ht_mesh *m, const ht_lod_range *r, const level_span *s, uint32_t *at,
                                 char *what, size_t what_size) {
    uint32_t index = r->first_index;
    for (uint32_t c = r->first_component; c < r->first_component + r->component_count; c++) {
        ht_component *k = &m->components[c];
        const uint32_t first_vertex = k->first_index, segments = k->index_count / 6;
        *at = c;
        if (k->index_count < 6 || k->index_count % 6) {
            snprintf(what, what_size, "%u, a ribbon is 6 indices a segment (rows of two vertices), at least one",
                     k->index_count);
            return "index_count";
        }
        if (k->index_count > r->first_index + r->index_count - index) {
            snprintf(what, what_size, "%u, past the level's %u indices", k->index_count, r->index_count);
            return "index_count";
        }
        if (first_vertex > s->vertex_count || segments + 1 > (s->vertex_count - first_vertex) / 2) {
            snprintf(what, what_size, "%u, its %u rows pass the level's %u vertices", first_vertex, segments + 1,
                     s->vertex_count);
            return "first_vertex";
        }
        for (uint32_t q = 0; q < segments; q++)
            strip_segment(m->indices + index + 6 * q, s->first_vertex + first_vertex + 2 * q);
        k->first_index = index;
        index += k->index_count;
    }
    if (index != r->first_index + r->index_count) {
        snprintf(what, what_size, "its ribbons take %u indices, it has %u", index - r->first_index, r->index_count);
        return "strips";
    }
    return NULL;
}

static ht_result refuse(ht_lod_file *out, char *err, size_t err_size, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static ht_result refuse(ht_lod_file *out, char *err, size_t err_size, const char *fmt, ...) {
    ht_lod_file_free(out);
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    return ht_fail(err, err_size, HT_ERR_PARSE, "%s", line);
}

static const char *const box_names[2] = { "position_box", "texture_box" };

ht_result ht_lod_file_parse(const void *data, size_t size, const char *name, ht_lod_file *out, char *err,
                            size_t err_size) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    name = name ? name : "<lods>";
    const unsigned char *bytes = data;
    if (data && size >= sizeof magic && memcmp(data, magic, 6) == 0 && bytes[7] == '\n' && bytes[6] >= '1' &&
        bytes[6] < magic[6])
        return ht_fail(err, err_size, HT_ERR_PARSE,
                       "%s: header: \"HTLODS%c\", this runtime reads HTLODS%c (" HT_MANIFEST_GENERATOR
                       " bundles): regenerate with " HT_MANIFEST_GENERATOR,
                       name, bytes[6], magic[6]);
    if (!data || size < HEADER_BYTES || memcmp(data, magic, sizeof magic) != 0)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: header: not a hairtier LOD file (%zu bytes)", name, size);
    reader r = { bytes + sizeof magic, bytes + size };
    const uint32_t levels = get_u32(&r), vertices = get_u32(&r), indices = get_u32(&r);
    const uint32_t stored_indices = get_u32(&r), components = get_u32(&r);
    float center[3];
    for (int k = 0; k < 3; k++) center[k] = get_f32(&r);
    const uint32_t scene_vertices = get_u32(&r), scene_indices = get_u32(&r), scene_components = get_u32(&r);
    const uint32_t hash_lo = get_u32(&r), hash_hi = get_u32(&r);
    ht_lod_box box[2];
    for (int b = 0; b < 2; b++) {
        for (int k = 0; k < 3; k++) box[b].min[k] = get_f32(&r);
        for (int k = 0; k < 3; k++) box[b].extent[k] = get_f32(&r);
    }
    if (levels < 1 || levels > HT_LOD_FILE_MAX_LEVELS)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: levels: %u, expected 1..%d", name, levels, HT_LOD_FILE_MAX_LEVELS);
    if (vertices > HT_LOD_FILE_MAX_VERTICES || indices / 3 > HT_LOD_FILE_MAX_VERTICES ||
        components > HT_LOD_FILE_MAX_VERTICES)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: counts: %u vertices, %u indices, %u components; at most %u each",
                       name, vertices, indices, components, HT_LOD_FILE_MAX_VERTICES);
    if (stored_indices > indices)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: stored_indices: %u, more than the %u indices", name,
                       stored_indices, indices);
    const uint64_t expected = file_bytes(levels, vertices, stored_indices, components);
    if (expected != size)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: size: %zu bytes, the counts say %llu", name, size,
                       (unsigned long long)expected);
    if (!ht_all_finite(center, 3)) return ht_fail(err, err_size, HT_ERR_PARSE, "%s: center: not finite", name);
    for (int b = 0; b < 2; b++) {
        int axis;
        if (!ht_lod_box_valid(&box[b], &axis))
            return ht_fail(err, err_size, HT_ERR_PARSE,
                           "%s: %s[%d]: min %g, extent %g: not a finite box of positive extent", name, box_names[b],
                           axis, (double)box[b].min[axis], (double)box[b].extent[axis]);
    }
    /* The levels follow each other in every buffer; their counts must add
       up to the header's (in 64 bits: no count can wrap). */
    level_span span[HT_LOD_FILE_MAX_LEVELS];
    uint64_t sum_v = 0, sum_i = 0, sum_c = 0, sum_stored = 0;
    for (uint32_t l = 0; l < levels; l++) {
        ht_lod_range *lv = &out->levels[l];
        const uint32_t kind = get_u32(&r);
        lv->kind = kind == 2 ? HT_LOD_KIND_SCENE : kind == 1 ? HT_LOD_KIND_CARDS : HT_LOD_KIND_STRANDS;
        lv->param = get_u32(&r);
        span[l].strips = get_u32(&r);
        span[l].vertex_count = get_u32(&r);
        lv->index_count = get_u32(&r);
        lv->component_count = get_u32(&r);
        span[l].first_vertex = (uint32_t)sum_v;
        lv->first_index = (uint32_t)sum_i;
        lv->first_component = (uint32_t)sum_c;
        const char *bad = kind > 2 ? "kind: expected 0, 1 or 2"
                          : span[l].strips > 1 ? "strips: expected 0 (indices stored) or 1 (implied by the rows)"
                          : kind == 2 && (span[l].strips || span[l].vertex_count)
                              ? "vertex_count: the scene's mesh is not stored, it has no vertices"
                          : lv->index_count % 3 ? "index_count: not whole triangles"
                          : NULL;
        if (bad) {
            memset(out, 0, sizeof *out);
            return ht_fail(err, err_size, HT_ERR_PARSE, "%s: levels[%u].%s", name, l, bad);
        }
        sum_v += span[l].vertex_count;
        sum_i += lv->index_count;
        sum_c += lv->component_count;
        sum_stored += span[l].strips ? 0 : lv->index_count;
        if (sum_v > vertices || sum_i > indices || sum_c > components) {
            memset(out, 0, sizeof *out);
            return ht_fail(err, err_size, HT_ERR_PARSE, "%s: levels[%u]: its counts pass the header's", name, l);
        }
    }
    if (sum_v != vertices || sum_i != indices || sum_c != components || sum_stored != stored_indices) {
        memset(out, 0, sizeof *out);
        return ht_fail(err, err_size, HT_ERR_PARSE,
                       "%s: levels: they hold %llu vertices, %llu indices (%llu stored), %llu components; the header "
                       "says %u, %u (%u), %u",
                       name, (unsigned long long)sum_v, (unsigned long long)sum_i, (unsigned long long)sum_stored,
                       (unsigned long long)sum_c, vertices, indices, stored_indices, components);
    }
    out->level_count = (int)levels;
    out->scene_vertices = scene_vertices;
    out->scene_indices = scene_indices;
    out->scene_components = scene_components;
    out->scene_hash = (uint64_t)hash_hi << 32 | hash_lo;
    ht_result res = ht_mesh_alloc(&out->mesh, vertices, indices, components);
    if (res != HT_OK) {
        memset(out, 0, sizeof *out);
        return ht_fail(err, err_size, res, "%s: %u vertices: %s", name, vertices, ht_result_string(res));
    }
    ht_mesh *m = &out->mesh;
    memcpy(m->center, center, sizeof center);
    for (uint32_t v = 0; v < vertices; v++, r.p += HT_LOD_QUANT_VERTEX_BYTES)
        ht_lod_vertex_decode(r.p, &box[0], &box[1], &m->vertices[v]);
    for (uint32_t l = 0; l < levels; l++) {
        const ht_lod_range *lv = &out->levels[l];
        for (uint32_t i = lv->first_index; !span[l].strips && i < lv->first_index + lv->index_count; i++) {
            const uint32_t rel = get_u32(&r);
            if (rel >= span[l].vertex_count)
                return refuse(out, err, err_size, "%s: indices[%u]: %u, past the level's %u vertices", name, i, rel,
                              span[l].vertex_count);
            m->indices[i] = span[l].first_vertex + rel;
        }
    }
    for (uint32_t c = 0; c < components; c++) {
        m->components[c].first_index = get_u32(&r);
        m->components[c].index_count = get_u32(&r);
        m->components[c].sort_key = get_f32(&r);
    }
    for (uint32_t l = 0; l < levels; l++) {
        char what[160];
        uint32_t at = 0;
        const char *field = span[l].strips ? derive_strips(m, &out->levels[l], &span[l], &at, what, sizeof what) : NULL;
        if (field && strcmp(field, "strips") == 0)
            return refuse(out, err, err_size, "%s: levels[%u]: %s", name, l, what);
        if (field) return refuse(out, err, err_size, "%s: components[%u].%s: %s", name, at, field, what);
    }
    /* a level's vertices are those its indices reach, no more (what the
       writer stores, and all it can store again) */
    for (uint32_t l = 0; l < levels; l++) {
        const ht_lod_range *lv = &out->levels[l];
        uint32_t lo;
        const uint32_t reached = index_span(m, lv, &lo);
        if (reached != span[l].vertex_count || (reached && lo != span[l].first_vertex))
            return refuse(out, err, err_size, "%s: levels[%u].vertex_count: %u, its indices reach %u of them", name, l,
                          span[l].vertex_count, reached);
    }
    uint32_t at = 0;
    const char *what = "", *bad = check_ladder(out, &at, &what);
    if (bad) return refuse(out, err, err_size, "%s: %s[%u]: %s", name, bad, at, what);
    return HT_OK;
}

ht_result ht_lod_file_read(const char *path, ht_lod_file *out, char *err, size_t err_size) {
    if (out) memset(out, 0, sizeof *out);
    size_t size = 0;
    void *data = ht_file_read_bytes(path, file_bytes(HT_LOD_FILE_MAX_LEVELS, HT_LOD_FILE_MAX_VERTICES,
                                                      3ull * HT_LOD_FILE_MAX_VERTICES, HT_LOD_FILE_MAX_VERTICES),
                                    &size, err, err_size);
    if (!data) return HT_ERR_IO;
    ht_result r = ht_lod_file_parse(data, size, path, out, err, err_size);
    free(data);
    return r;
}

/* Each level's vertices, the run its indices reach: the levels must
   follow each other in the vertex, index and component buffers, as the
   file stores them. Whether its indices are strips the rows imply. false
   when the ladder is not laid out so. */
static bool level_spans(const ht_lod_file *f, level_span span[HT_LOD_FILE_MAX_LEVELS]) {
    const ht_mesh *m = &f->mesh;
    uint32_t vertex = 0, index = 0, component = 0;
    for (int l = 0; l < f->level_count; l++) {
        const ht_lod_range *r = &f->levels[l];
        if (r->first_index != index || r->first_component != component) return false;
        uint32_t lo;
        span[l] = (level_span){ 0, vertex, index_span(m, r, &lo) };
        if (span[l].vertex_count && lo != vertex) return false;
        /* strips when every component is one ribbon, their indices one
           after the other */
        uint32_t at_i = index;
        bool strips = r->index_count > 0;
        for (uint32_t c = r->first_component; strips && c < r->first_component + r->component_count; c++) {
            const ht_component *k = &m->components[c];
            strips = k->first_index == at_i && k->index_count >= 6 && k->index_count % 6 == 0;
            for (uint32_t q = 0; strips && q < k->index_count / 6; q++) {
                uint32_t want[6];
                strip_segment(want, m->indices[at_i] + 2 * q);
                strips = memcmp(want, m->indices + at_i + 6 * q, sizeof want) == 0;
            }
            at_i += k->index_count;
        }
        span[l].strips = strips && at_i == index + r->index_count;
        vertex += span[l].vertex_count;
        index += r->index_count;
        component += r->component_count;
    }
    return vertex == m->vertex_count && index == m->index_count && component == m->component_count;
}

ht_result ht_lod_file_encode(const ht_lod_file *f, unsigned char **data, size_t *size) {
    if (!f || !data || !size || f->level_count < 1 || f->level_count > HT_LOD_FILE_MAX_LEVELS) return HT_ERR_INVALID_ARGUMENT;
    *data = NULL;
    *size = 0;
    const ht_mesh *m = &f->mesh;
    uint32_t at;
    const char *what;
    level_span span[HT_LOD_FILE_MAX_LEVELS];
    ht_lod_box box[2];
    if (m->vertex_count > HT_LOD_FILE_MAX_VERTICES || m->index_count / 3 > HT_LOD_FILE_MAX_VERTICES ||
        m->component_count > HT_LOD_FILE_MAX_VERTICES || check_ladder(f, &at, &what) || !level_spans(f, span) ||
        !ht_lod_box_of(m->vertices, m->vertex_count, false, &box[0]) ||
        !ht_lod_box_of(m->vertices, m->vertex_count, true, &box[1]))
        return HT_ERR_INVALID_ARGUMENT;
    uint32_t stored = 0;
    for (int l = 0; l < f->level_count; l++) stored += span[l].strips ? 0 : f->levels[l].index_count;
    const uint64_t bytes = file_bytes((uint64_t)f->level_count, m->vertex_count, stored, m->component_count);
    unsigned char *buf = malloc(bytes), *p = buf;
    if (!buf) return HT_ERR_OUT_OF_MEMORY;
    memcpy(p, magic, sizeof magic);
    p += sizeof magic;
    const uint32_t counts[5] = { (uint32_t)f->level_count, m->vertex_count, m->index_count, stored, m->component_count };
    for (int k = 0; k < 5; k++) put_u32(&p, counts[k]);
    for (int k = 0; k < 3; k++) put_f32(&p, m->center[k]);
    put_u32(&p, f->scene_vertices);
    put_u32(&p, f->scene_indices);
    put_u32(&p, f->scene_components);
    put_u32(&p, (uint32_t)f->scene_hash);
    put_u32(&p, (uint32_t)(f->scene_hash >> 32));
    for (int b = 0; b < 2; b++) {
        for (int k = 0; k < 3; k++) put_f32(&p, box[b].min[k]);
        for (int k = 0; k < 3; k++) put_f32(&p, box[b].extent[k]);
    }
    for (int l = 0; l < f->level_count; l++) {
        const ht_lod_range *r = &f->levels[l];
        const uint32_t fields[6] = { (uint32_t)r->kind, r->param, span[l].strips, span[l].vertex_count, r->index_count,
                                     r->component_count };
        for (int k = 0; k < 6; k++) put_u32(&p, fields[k]);
    }
    for (uint32_t v = 0; v < m->vertex_count; v++, p += HT_LOD_QUANT_VERTEX_BYTES)
        ht_lod_vertex_encode(&m->vertices[v], &box[0], &box[1], p);
    for (int l = 0; l < f->level_count; l++)
        for (uint32_t i = 0; !span[l].strips && i < f->levels[l].index_count; i++)
            put_u32(&p, m->indices[f->levels[l].first_index + i] - span[l].first_vertex);
    for (int l = 0; l < f->level_count; l++)
        for (uint32_t c = f->levels[l].first_component; c < f->levels[l].first_component + f->levels[l].component_count;
             c++) {
            const ht_component *k = &m->components[c];
            put_u32(&p, span[l].strips ? m->indices[k->first_index] - span[l].first_vertex : k->first_index);
            put_u32(&p, k->index_count);
            put_f32(&p, k->sort_key);
        }
    *data = buf;
    *size = (size_t)bytes;
    return HT_OK;
}

ht_result ht_lod_file_level_mesh(const ht_lod_file *f, int level, ht_mesh *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (!f || level < 0 || level >= f->level_count || f->levels[level].kind == HT_LOD_KIND_SCENE)
        return HT_ERR_INVALID_ARGUMENT;
    const ht_lod_range *r = &f->levels[level];
    const ht_mesh *m = &f->mesh;
    uint32_t lo;
    const uint32_t vertices = index_span(m, r, &lo);
    ht_result res = ht_mesh_alloc(out, vertices, r->index_count, r->component_count);
    if (res != HT_OK) return res;
    memcpy(out->center, m->center, sizeof out->center);
    if (vertices) memcpy(out->vertices, m->vertices + lo, sizeof *out->vertices * vertices);
    for (uint32_t i = 0; i < r->index_count; i++) out->indices[i] = m->indices[r->first_index + i] - lo;
    for (uint32_t c = 0; c < r->component_count; c++) {
        out->components[c] = m->components[r->first_component + c];
        out->components[c].first_index -= r->first_index;
    }
    return HT_OK;
}

void ht_lod_file_free(ht_lod_file *f) {
    if (!f) return;
    ht_mesh_free(&f->mesh);
    memset(f, 0, sizeof *f);
}

/* FNV-1a 64 over a mesh's vertex positions (their bits, little-endian)
   and indices: what a stored ladder was made from. */
static uint64_t scene_hash(const ht_mesh *m) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (uint64_t k = 0; k < 3ull * m->vertex_count + m->index_count; k++) {
        uint32_t u;
        if (k < 3ull * m->vertex_count) memcpy(&u, &m->vertices[k / 3].position[k % 3], sizeof u);
        else u = m->indices[k - 3ull * m->vertex_count];
        for (int b = 0; b < 4; b++) h = (h ^ ((u >> (8 * b)) & 0xff)) * 0x100000001b3ull;
    }
    return h;
}

void ht_lod_file_set_scene(ht_lod_file *f, const ht_mesh *full) {
    f->scene_vertices = full->vertex_count;
    f->scene_indices = full->index_count;
    f->scene_components = full->component_count;
    f->scene_hash = scene_hash(full);
}

bool ht_lod_file_matches(const ht_lod_file *f, const ht_mesh *full) {
    return f && full && f->level_count >= 1 && f->scene_vertices == full->vertex_count &&
           f->scene_indices == full->index_count && f->scene_components == full->component_count &&
           f->scene_hash == scene_hash(full);
}

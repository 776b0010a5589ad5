/* lod_file.c — the stored ladder, lods.bin (lod.h has the layout): one
   writer and one guarded reader. Every size is checked against the bytes
   before anything is allocated; every range, index and float after. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "file_open.h"
#include "mesh_internal.h"
#include <hairtier/lod.h>

static const char magic[8] = { 'H', 'T', 'L', 'O', 'D', 'S', '2', '\n' };

#define HEADER_BYTES (8 + 4 * 4 + 3 * 4 + 3 * 4 + 8)
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

static uint64_t file_bytes(uint64_t levels, uint64_t vertices, uint64_t indices, uint64_t components) {
    return HEADER_BYTES + levels * LEVEL_BYTES + vertices * VERTEX_FLOATS * 4 + indices * 4 + components * COMPONENT_BYTES;
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

ht_result ht_lod_file_parse(const void *data, size_t size, const char *name, ht_lod_file *out, char *err,
                            size_t err_size) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    name = name ? name : "<lods>";
    if (!data || size < HEADER_BYTES || memcmp(data, magic, sizeof magic) != 0)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: header: not a hairtier LOD file (%zu bytes)", name, size);
    reader r = { (const unsigned char *)data + sizeof magic, (const unsigned char *)data + size };
    const uint32_t levels = get_u32(&r), vertices = get_u32(&r), indices = get_u32(&r), components = get_u32(&r);
    float center[3];
    for (int k = 0; k < 3; k++) center[k] = get_f32(&r);
    const uint32_t scene_vertices = get_u32(&r), scene_indices = get_u32(&r), scene_components = get_u32(&r);
    const uint32_t hash_lo = get_u32(&r), hash_hi = get_u32(&r);
    if (levels < 1 || levels > HT_LOD_FILE_MAX_LEVELS)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: levels: %u, expected 1..%d", name, levels, HT_LOD_FILE_MAX_LEVELS);
    if (vertices > HT_LOD_FILE_MAX_VERTICES || indices / 3 > HT_LOD_FILE_MAX_VERTICES ||
        components > HT_LOD_FILE_MAX_VERTICES)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: counts: %u vertices, %u indices, %u components; at most %u each",
                       name, vertices, indices, components, HT_LOD_FILE_MAX_VERTICES);
    const uint64_t expected = file_bytes(levels, vertices, indices, components);
    if (expected != size)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: size: %zu bytes, the counts say %llu", name, size,
                       (unsigned long long)expected);
    if (!ht_all_finite(center, 3)) return ht_fail(err, err_size, HT_ERR_PARSE, "%s: center: not finite", name);
    for (uint32_t l = 0; l < levels; l++) {
        ht_lod_range *lv = &out->levels[l];
        const uint32_t kind = get_u32(&r);
        lv->kind = kind == 2 ? HT_LOD_KIND_SCENE : kind == 1 ? HT_LOD_KIND_CARDS : HT_LOD_KIND_STRANDS;
        lv->param = get_u32(&r);
        lv->first_index = get_u32(&r);
        lv->index_count = get_u32(&r);
        lv->first_component = get_u32(&r);
        lv->component_count = get_u32(&r);
        if (kind > 2) {
            memset(out, 0, sizeof *out);
            return ht_fail(err, err_size, HT_ERR_PARSE, "%s: levels[%u].kind: %u, expected 0, 1 or 2", name, l, kind);
        }
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
    memcpy(out->mesh.center, center, sizeof center);
    for (uint32_t v = 0; v < vertices; v++) {
        float f[VERTEX_FLOATS];
        for (int k = 0; k < VERTEX_FLOATS; k++) f[k] = get_f32(&r);
        memcpy(&out->mesh.vertices[v], f, sizeof f);
    }
    for (uint32_t i = 0; i < indices; i++) out->mesh.indices[i] = get_u32(&r);
    for (uint32_t c = 0; c < components; c++) {
        out->mesh.components[c].first_index = get_u32(&r);
        out->mesh.components[c].index_count = get_u32(&r);
        out->mesh.components[c].sort_key = get_f32(&r);
    }
    uint32_t at = 0;
    const char *what = "", *bad = check_ladder(out, &at, &what);
    if (bad) {
        ht_lod_file_free(out);
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: %s[%u]: %s", name, bad, at, what);
    }
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

ht_result ht_lod_file_encode(const ht_lod_file *f, unsigned char **data, size_t *size) {
    if (!f || !data || !size || f->level_count < 1 || f->level_count > HT_LOD_FILE_MAX_LEVELS) return HT_ERR_INVALID_ARGUMENT;
    *data = NULL;
    *size = 0;
    const ht_mesh *m = &f->mesh;
    uint32_t at;
    const char *what;
    if (m->vertex_count > HT_LOD_FILE_MAX_VERTICES || m->index_count / 3 > HT_LOD_FILE_MAX_VERTICES ||
        m->component_count > HT_LOD_FILE_MAX_VERTICES || check_ladder(f, &at, &what))
        return HT_ERR_INVALID_ARGUMENT;
    const uint64_t bytes = file_bytes((uint64_t)f->level_count, m->vertex_count, m->index_count, m->component_count);
    unsigned char *buf = malloc(bytes), *p = buf;
    if (!buf) return HT_ERR_OUT_OF_MEMORY;
    memcpy(p, magic, sizeof magic);
    p += sizeof magic;
    put_u32(&p, (uint32_t)f->level_count);
    put_u32(&p, m->vertex_count);
    put_u32(&p, m->index_count);
    put_u32(&p, m->component_count);
    for (int k = 0; k < 3; k++) put_f32(&p, m->center[k]);
    put_u32(&p, f->scene_vertices);
    put_u32(&p, f->scene_indices);
    put_u32(&p, f->scene_components);
    put_u32(&p, (uint32_t)f->scene_hash);
    put_u32(&p, (uint32_t)(f->scene_hash >> 32));
    for (int l = 0; l < f->level_count; l++) {
        const ht_lod_range *r = &f->levels[l];
        const uint32_t fields[6] = { (uint32_t)r->kind, r->param, r->first_index, r->index_count, r->first_component,
                                     r->component_count };
        for (int k = 0; k < 6; k++) put_u32(&p, fields[k]);
    }
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        float fl[VERTEX_FLOATS];
        vertex_floats(&m->vertices[v], fl);
        for (int k = 0; k < VERTEX_FLOATS; k++) put_f32(&p, fl[k]);
    }
    for (uint32_t i = 0; i < m->index_count; i++) put_u32(&p, m->indices[i]);
    for (uint32_t c = 0; c < m->component_count; c++) {
        put_u32(&p, m->components[c].first_index);
        put_u32(&p, m->components[c].index_count);
        put_f32(&p, m->components[c].sort_key);
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
    uint32_t lo = UINT32_MAX, hi = 0;
    for (uint32_t i = r->first_index; i < r->first_index + r->index_count; i++) {
        lo = m->indices[i] < lo ? m->indices[i] : lo;
        hi = m->indices[i] > hi ? m->indices[i] : hi;
    }
    if (!r->index_count) lo = hi = 0;
    const uint32_t vertices = r->index_count ? hi - lo + 1 : 0;
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

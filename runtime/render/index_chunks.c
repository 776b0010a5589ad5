/* index_chunks.c — see index_chunks.h. */
#include "index_chunks.h"

#include <stdlib.h>
#include <string.h>

void ht_index_chunks_free(ht_index_chunks *c) {
    free(c->vertices);
    free(c->source);
    free(c->indices);
    free(c->chunks);
    memset(c, 0, sizeof *c);
}

static bool grow(void **p, uint32_t *capacity, uint32_t need, size_t size) {
    if (need <= *capacity) return true;
    uint32_t cap = *capacity ? *capacity : 64;
    while (cap < need) cap = cap > UINT32_MAX / 2 ? need : cap * 2;
    void *q = realloc(*p, (size_t)cap * size);
    if (!q) return false;
    *p = q;
    *capacity = cap;
    return true;
}

bool ht_index_chunks_split(const ht_mesh *mesh, ht_index_chunks *out) {
    memset(out, 0, sizeof *out);
    const uint32_t n = mesh->vertex_count;
    /* which chunk last gave vertex v a slot (chunk + 1; 0: none), and the slot */
    uint32_t *owner = calloc(n ? n : 1, sizeof *owner), *slot = malloc((n ? n : 1) * sizeof *slot);
    uint32_t vertex_cap = 0, chunk_cap = 0, used = 0; /* vertices of the open chunk */
    out->indices = malloc((mesh->index_count ? mesh->index_count : 1) * sizeof *out->indices);
    bool ok = owner && slot && out->indices && grow((void **)&out->chunks, &chunk_cap, 1, sizeof *out->chunks);
    if (ok) out->chunks[out->chunk_count++] = (ht_index_chunk){ 0, 0, 0 };
    for (uint32_t i = 0; ok && i < mesh->index_count; i += 3) {
        const uint32_t *tri = mesh->indices + i;
        uint32_t id = out->chunk_count, fresh = 0;
        for (int k = 0; k < 3; k++)
            fresh += owner[tri[k]] != id && (k < 1 || tri[k] != tri[0]) && (k < 2 || tri[k] != tri[1]);
        if (used + fresh > HT_CHUNK_VERTICES) {
            ht_index_chunk *open = &out->chunks[out->chunk_count - 1];
            open->index_count = i - open->first_index;
            if (!(ok = grow((void **)&out->chunks, &chunk_cap, out->chunk_count + 1, sizeof *out->chunks))) break;
            out->chunks[out->chunk_count++] = (ht_index_chunk){ i, 0, out->vertex_count };
            id = out->chunk_count;
            used = 0;
        }
        for (int k = 0; k < 3 && ok; k++) {
            const uint32_t v = tri[k];
            if (owner[v] != id) {
                uint32_t source_cap = vertex_cap;
                if (!(ok = grow((void **)&out->vertices, &vertex_cap, out->vertex_count + 1, sizeof *out->vertices) &&
                           grow((void **)&out->source, &source_cap, vertex_cap, sizeof *out->source)))
                    break;
                owner[v] = id;
                slot[v] = used++;
                out->source[out->vertex_count] = v;
                out->vertices[out->vertex_count++] = mesh->vertices[v];
            }
            out->indices[i + (uint32_t)k] = (uint16_t)slot[v];
        }
    }
    if (ok) {
        ht_index_chunk *last = &out->chunks[out->chunk_count - 1];
        last->index_count = mesh->index_count - last->first_index;
    }
    free(owner);
    free(slot);
    if (!ok) ht_index_chunks_free(out);
    return ok;
}

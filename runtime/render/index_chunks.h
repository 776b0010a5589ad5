/* index_chunks.h — a mesh split for 16-bit indices (GL ES 2.0 without
   GL_OES_element_index_uint): the sorted index list cut, in its order,
   into runs whose triangles name at most HT_CHUNK_VERTICES vertices, each
   run with a block of vertices of its own (first use order) and indices
   relative to that block. Drawing the runs in order draws the triangles
   in the mesh's order, so the inside-out sort and the passes are kept. */
#ifndef HT_INDEX_CHUNKS_H
#define HT_INDEX_CHUNKS_H

#include <stdint.h>

#include <hairtier/hairtier.h>

#define HT_CHUNK_VERTICES 65536u

typedef struct ht_index_chunk {
    uint32_t first_index, index_count; /* a run of the mesh's index list */
    uint32_t first_vertex;             /* its block in the split vertices */
} ht_index_chunk;

typedef struct ht_index_chunks {
    ht_vertex *vertices; /* blocks in chunk order; a vertex two runs name is in both */
    uint32_t *source;    /* vertices[i] is the mesh's vertex source[i] (per-vertex data split alike) */
    uint32_t vertex_count;
    uint16_t *indices;   /* index_count of them, each relative to its chunk's block */
    ht_index_chunk *chunks;
    uint32_t chunk_count;
} ht_index_chunks;

/* Splits mesh (whole triangles, valid indices: ht_renderer_check_mesh's).
   false only when out of memory (out then empty). */
bool ht_index_chunks_split(const ht_mesh *mesh, ht_index_chunks *out);
void ht_index_chunks_free(ht_index_chunks *c);

#endif

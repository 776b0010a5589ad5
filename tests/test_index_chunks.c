/* test_index_chunks — a mesh split for 16-bit indices (index_chunks.h), no
   GL: the chunks tile the index list in order, each names at most 65536
   vertices of its own block, and its triangles, read back through the
   block, are the mesh's triangles in the mesh's order (and each block
   vertex names the mesh vertex it copies); with good
   locality (a strip), shuffled triangles, repeated and shared vertices,
   and a mesh that needs no split. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "index_chunks.h"

/* vertex v carries v in its position, so a triangle can be read back */
static ht_mesh mesh_of(uint32_t vertices, uint32_t triangles) {
    ht_mesh m = { .vertex_count = vertices, .index_count = 3 * triangles };
    m.vertices = calloc(vertices, sizeof *m.vertices);
    m.indices = calloc(m.index_count, sizeof *m.indices);
    assert_non_null(m.vertices);
    assert_non_null(m.indices);
    for (uint32_t v = 0; v < vertices; v++) m.vertices[v].position[0] = (float)v;
    return m;
}

static void expect_split(const ht_mesh *m, uint32_t want_chunks) {
    ht_index_chunks c;
    assert_true(ht_index_chunks_split(m, &c));
    if (want_chunks) assert_int_equal(c.chunk_count, want_chunks);
    uint32_t next = 0;
    for (uint32_t k = 0; k < c.chunk_count; k++) {
        const ht_index_chunk *ch = &c.chunks[k];
        assert_int_equal(ch->first_index, next);
        assert_true(ch->index_count > 0 && ch->index_count % 3 == 0);
        const uint32_t end = k + 1 < c.chunk_count ? c.chunks[k + 1].first_vertex : c.vertex_count;
        assert_true(end - ch->first_vertex <= HT_CHUNK_VERTICES);
        for (uint32_t i = ch->first_index; i < ch->first_index + ch->index_count; i++) {
            assert_true(ch->first_vertex + c.indices[i] < end);
            const ht_vertex *v = &c.vertices[ch->first_vertex + c.indices[i]];
            assert_true(v->position[0] == (float)m->indices[i]);
            /* where it came from: per-vertex data (a_side) is split by it */
            assert_int_equal(c.source[ch->first_vertex + c.indices[i]], m->indices[i]);
        }
        next += ch->index_count;
    }
    assert_int_equal(next, m->index_count);
    ht_index_chunks_free(&c);
}

/* A strip: triangle t is (t, t+1, t+2); the chunks share two vertices. */
static void test_a_strip_splits_with_its_shared_vertices_copied(void **state) {
    (void)state;
    const uint32_t n = 200000;
    ht_mesh m = mesh_of(n, n - 2);
    for (uint32_t t = 0; t < n - 2; t++)
        for (int k = 0; k < 3; k++) m.indices[3 * t + (uint32_t)k] = t + (uint32_t)k;
    expect_split(&m, 4); /* 65536 vertices a chunk, two of each shared with the next */
    ht_mesh_free(&m);
}

/* Triangles in random order name vertices anywhere: still correct. */
static void test_shuffled_triangles_and_repeated_vertices(void **state) {
    (void)state;
    const uint32_t n = 100000, triangles = 90000;
    ht_mesh m = mesh_of(n, triangles);
    uint64_t x = 21;
    for (uint32_t i = 0; i < m.index_count; i++) {
        x = x * 6364136223846793005u + 1442695040888963407u;
        m.indices[i] = (uint32_t)(x >> 33) % n;
    }
    m.indices[3] = m.indices[4] = m.indices[5]; /* a degenerate triangle */
    expect_split(&m, 0);
    ht_mesh_free(&m);
}

static void test_a_small_mesh_is_one_chunk(void **state) {
    (void)state;
    ht_mesh m = mesh_of(4, 2);
    const uint32_t idx[] = { 0, 1, 2, 2, 1, 3 };
    memcpy(m.indices, idx, sizeof idx);
    expect_split(&m, 1);
    ht_mesh_free(&m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_strip_splits_with_its_shared_vertices_copied),
        cmocka_unit_test(test_shuffled_triangles_and_repeated_vertices),
        cmocka_unit_test(test_a_small_mesh_is_one_chunk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

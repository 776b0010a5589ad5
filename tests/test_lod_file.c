/* test_lod_file — the stored ladder, lods.bin (lod.h): a chain's levels
   written and read back are the same meshes and ranges; every hostile
   file (cut anywhere, a bad magic, counts or ranges out of bounds, an
   index past the vertices, a non-finite float, trailing bytes) is refused
   with one line naming the file and the field, and nothing allocated. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/lod.h>
#include "lods_store.h"

#define LEVELS_AT 56 /* the header's bytes: magic, 4 counts, the centre, the scene's 3 counts and hash */
#define LEVEL_BYTES 24

/* A chain of a 300-hair fur ball as a ladder file (strand levels). */
static void make_ladder(ht_mesh *full, ht_lod_chain *chain, ht_lod_file *f) {
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 300, .joints = 6 }, full), HT_OK);
    ht_mesh_sort_inside_out(full);
    assert_int_equal(ht_lod_chain_build(full, chain), HT_OK);
    memset(f, 0, sizeof *f);
    f->mesh = chain->all;
    f->level_count = chain->count;
    uint32_t component = 0;
    for (int l = 0; l < chain->count; l++) {
        const uint32_t n = ht_lod_chain_mesh(chain, l)->component_count;
        f->levels[l] = (ht_lod_range){ HT_LOD_KIND_STRANDS, 1u << l, chain->first[l], chain->index_count[l], component, n };
        component += n;
    }
    ht_lod_file_set_scene(f, full);
}

static void round_trip(void **state) {
    (void)state;
    ht_mesh full;
    ht_lod_chain chain;
    ht_lod_file f, back;
    make_ladder(&full, &chain, &f);
    unsigned char *data;
    size_t size;
    char err[256] = "";
    assert_int_equal(ht_lod_file_encode(&f, &data, &size), HT_OK);
    if (ht_lod_file_parse(data, size, "lods.bin", &back, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_int_equal(back.level_count, f.level_count);
    assert_memory_equal(back.levels, f.levels, sizeof f.levels);
    assert_int_equal(back.mesh.vertex_count, f.mesh.vertex_count);
    assert_memory_equal(back.mesh.vertices, f.mesh.vertices, sizeof *f.mesh.vertices * f.mesh.vertex_count);
    assert_memory_equal(back.mesh.indices, f.mesh.indices, sizeof *f.mesh.indices * f.mesh.index_count);
    assert_memory_equal(back.mesh.components, f.mesh.components, sizeof *f.mesh.components * f.mesh.component_count);
    /* Each level, taken out on its own, is the chain's level. */
    for (int l = 0; l < back.level_count; l++) {
        ht_mesh m;
        const ht_mesh *want = ht_lod_chain_mesh(&chain, l);
        assert_int_equal(ht_lod_file_level_mesh(&back, l, &m), HT_OK);
        assert_int_equal(m.vertex_count, want->vertex_count);
        assert_memory_equal(m.vertices, want->vertices, sizeof *m.vertices * m.vertex_count);
        assert_memory_equal(m.indices, want->indices, sizeof *m.indices * m.index_count);
        assert_memory_equal(m.components, want->components, sizeof *m.components * m.component_count);
        ht_mesh_free(&m);
    }
    printf("%d levels, %zu bytes\n", back.level_count, size);
    ht_lod_file_free(&back);
    free(data);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

/* ht_lod_file_matches: its level 0 is the mesh it was made from, not one
   with a vertex moved nor another fur ball. */
static void matches_only_its_own_mesh(void **state) {
    (void)state;
    ht_mesh full, other;
    ht_lod_chain chain;
    ht_lod_file f;
    make_ladder(&full, &chain, &f);
    assert_true(ht_lod_file_matches(&f, &full));
    full.vertices[full.vertex_count / 2].position[1] += 1e-3f;
    assert_false(ht_lod_file_matches(&f, &full));
    full.vertices[full.vertex_count / 2].position[1] -= 1e-3f;
    full.vertices[full.vertex_count / 2].uv[0] += 0.25f; /* a cards atlas moves uv only */
    assert_true(ht_lod_file_matches(&f, &full));
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 299, .joints = 6 }, &other), HT_OK);
    ht_mesh_sort_inside_out(&other);
    assert_false(ht_lod_file_matches(&f, &other));
    ht_mesh_free(&other);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

/* A plain bundle's ladder (lods_store.h): level 0 not stored but the
   scene's mesh (SCENE), the other levels as the chain's; written and read
   back, its chain from the scene's mesh is ht_lod_chain_build's buffer
   byte for byte; another mesh is refused, and so is taking level 0 out. */
static void scene_level_round_trip(void **state) {
    (void)state;
    ht_mesh full;
    ht_lod_chain chain, back_chain;
    ht_lod_file stored, unused, back;
    make_ladder(&full, &chain, &unused);
    assert_int_equal(ht_lods_ladder(&chain, false, NULL, 0, &stored), HT_OK);
    assert_int_equal(stored.levels[0].kind, HT_LOD_KIND_SCENE);
    assert_int_equal(stored.mesh.vertex_count, chain.all.vertex_count - full.vertex_count);
    unsigned char *data;
    size_t size;
    char err[256] = "";
    assert_int_equal(ht_lod_file_encode(&stored, &data, &size), HT_OK);
    if (ht_lod_file_parse(data, size, "lods.bin", &back, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_mesh m;
    assert_int_equal(ht_lod_file_level_mesh(&back, 0, &m), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_lod_chain_from_file(&back, &back_chain), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_lod_chain_from_scene_file(&back, &full, &back_chain), HT_OK);
    assert_int_equal(back_chain.count, chain.count);
    assert_memory_equal(back_chain.first, chain.first, sizeof chain.first);
    assert_memory_equal(back_chain.index_count, chain.index_count, sizeof chain.index_count);
    assert_int_equal(back_chain.all.vertex_count, chain.all.vertex_count);
    assert_memory_equal(back_chain.all.vertices, chain.all.vertices, sizeof *chain.all.vertices * chain.all.vertex_count);
    assert_memory_equal(back_chain.all.indices, chain.all.indices, sizeof *chain.all.indices * chain.all.index_count);
    assert_memory_equal(back_chain.all.components, chain.all.components,
                        sizeof *chain.all.components * chain.all.component_count);
    printf("%d levels, level 0 the scene's: %zu bytes\n", back.level_count, size);
    ht_lod_chain_free(&back_chain);
    full.vertices[0].position[0] += 1e-3f;
    assert_int_equal(ht_lod_chain_from_scene_file(&back, &full, &back_chain), HT_ERR_INVALID_ARGUMENT);
    ht_lod_file_free(&back);
    ht_lod_file_free(&stored);
    free(data);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

static void put32(unsigned char *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (8 * i));
}

/* The edited copy is refused with one line naming the file and `field`. */
static void expect_refused(const unsigned char *good, size_t size, size_t at, uint32_t value, size_t new_size,
                           const char *field) {
    unsigned char *bad = malloc(size + 8);
    assert_non_null(bad);
    memcpy(bad, good, size);
    memset(bad + size, 0, 8);
    if (at + 4 <= size) put32(bad + at, value);
    ht_lod_file f;
    char err[256] = "";
    assert_int_equal(ht_lod_file_parse(bad, new_size, "bad.bin", &f, err, sizeof err), HT_ERR_PARSE);
    printf("%s\n", err);
    assert_null(f.mesh.vertices);
    assert_int_equal(f.level_count, 0);
    assert_null(strchr(err, '\n'));
    assert_true(strncmp(err, "bad.bin: ", 9) == 0);
    if (!strstr(err, field)) fail_msg("expected the field %s in: %s", field, err);
    free(bad);
}

static void hostile_files_refused(void **state) {
    (void)state;
    ht_mesh full;
    ht_lod_chain chain;
    ht_lod_file f;
    make_ladder(&full, &chain, &f);
    unsigned char *data;
    size_t size;
    assert_int_equal(ht_lod_file_encode(&f, &data, &size), HT_OK);
    const size_t L = (size_t)f.level_count, vertices_at = LEVELS_AT + L * LEVEL_BYTES;
    const size_t indices_at = vertices_at + 48 * (size_t)f.mesh.vertex_count;
    const size_t components_at = indices_at + 4 * (size_t)f.mesh.index_count;
    const size_t none = SIZE_MAX - 8;
    expect_refused(data, size, 0, 0x4c4c4548, size, "header");                        /* magic */
    expect_refused(data, size, none, 0, 20, "header");                                 /* cut in the header */
    expect_refused(data, size, none, 0, size - 1, "size");                             /* cut at the end */
    expect_refused(data, size, none, 0, size / 2, "size");                             /* cut in the middle */
    expect_refused(data, size, none, 0, size + 4, "size");                             /* trailing bytes */
    expect_refused(data, size, 8, 0, size, "levels");
    expect_refused(data, size, 8, HT_LOD_FILE_MAX_LEVELS + 1, size, "levels");
    expect_refused(data, size, 12, 0xffffffffu, size, "counts");                       /* vertices */
    expect_refused(data, size, 16, f.mesh.index_count + 3, size, "size");              /* indices */
    expect_refused(data, size, 24, 0x7fc00000u, size, "center");                       /* NaN */
    expect_refused(data, size, LEVELS_AT, 3, size, "levels[0].kind");
    expect_refused(data, size, LEVELS_AT, 2, size, "levels[0]: the scene's mesh");          /* with a range */
    expect_refused(data, size, LEVELS_AT + LEVEL_BYTES, 2, size, "levels[1]: the scene's mesh");
    expect_refused(data, size, LEVELS_AT + 12, f.mesh.index_count + 3, size, "levels[0]: index range");
    expect_refused(data, size, LEVELS_AT + 8, 1, size, "levels[0]: index range");                 /* not whole triangles */
    expect_refused(data, size, LEVELS_AT + 20, f.mesh.component_count + 1, size, "levels[0]: component range");
    expect_refused(data, size, LEVELS_AT + LEVEL_BYTES + 16, 0, size, "levels[1]: a component outside");     /* level 1 claims level 0's */
    expect_refused(data, size, vertices_at + 4, 0x7f800000u, size, "vertices[0]: not finite");        /* Inf */
    expect_refused(data, size, indices_at + 8, f.mesh.vertex_count, size, "indices[2]: past the vertices");
    expect_refused(data, size, components_at, f.mesh.index_count, size, "components");
    expect_refused(data, size, components_at + 8, 0xff800000u, size, "components");    /* -Inf sort key */
    /* A file that is not there: one line naming it. */
    ht_lod_file g;
    char err[256] = "";
    assert_int_equal(ht_lod_file_read("/nonexistent/lods.bin", &g, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "/nonexistent/lods.bin"));
    assert_null(strchr(err, '\n'));
    free(data);
    /* The writer refuses what the reader would. */
    f.levels[0].index_count = f.mesh.index_count + 3;
    assert_int_equal(ht_lod_file_encode(&f, &data, &size), HT_ERR_INVALID_ARGUMENT);
    assert_null(data);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trip),
        cmocka_unit_test(matches_only_its_own_mesh),
        cmocka_unit_test(scene_level_round_trip),
        cmocka_unit_test(hostile_files_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

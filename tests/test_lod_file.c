/* test_lod_file — the stored ladder, lods.bin (lod.h): a chain's levels
   written and read back are the same ranges, indices and components and
   vertices within lod.h's bounds, in a file 2.4x smaller than HTLODS2's;
   a level that is not ribbons keeps its indices; every hostile file (cut
   anywhere, a bad or older magic, counts, ranges, ribbons or boxes out of
   bounds, an index past its level's vertices, a non-finite float, trailing
   bytes) is refused with one line naming the file and the field, and
   nothing allocated. */
#include <float.h>
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
#include "lod_quant.h"
#include "manifest.h"
#include "lods_store.h"
#include "support_lod_bound.h"

#define LEVELS_AT 108 /* the header's bytes: magic, 5 counts, the centre, the scene's 3 counts and hash, 2 boxes */
#define LEVEL_BYTES 24
#define VERTEX_BYTES 22
#define BOXES_AT 60
/* An HTLODS2 file of the same ladder: 56 header bytes, 24 a level, 48 a
   vertex, 4 an index, 12 a component (the format before this one). */
#define HTLODS2_BYTES(m, levels) \
    (56u + 24u * (levels) + 48u * (m)->vertex_count + 4u * (m)->index_count + 12u * (m)->component_count)
/* what HTLODS3 saves on a ribbon ladder at least (measured: 2.49x on the
   300-hair fixture below, 2.62x on the shipped fur ball's) */
#define SMALLER_THAN_HTLODS2 2.4

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

static void assert_within_bound(const ht_vertex *got, const ht_vertex *want, uint32_t n, const ht_vertex *all,
                                uint32_t all_count) {
    char why[256];
    if (!ht_test_lod_within_bound(got, want, n, all, all_count, why, sizeof why)) fail_msg("%s", why);
    printf("%s\n", why);
}

/* The file's bytes with no index stored. */
static size_t bytes_without_indices(const ht_lod_file *f) {
    return LEVELS_AT + LEVEL_BYTES * (size_t)f->level_count + VERTEX_BYTES * (size_t)f->mesh.vertex_count +
           12 * (size_t)f->mesh.component_count;
}

/* A strips level's tangents still run root to tip: along the next row. */
static void assert_root_to_tip(const ht_mesh *m) {
    for (uint32_t c = 0; c < m->component_count; c++) {
        const ht_component *k = &m->components[c];
        for (uint32_t i = k->first_index; i < k->first_index + k->index_count; i += 6) {
            const ht_vertex *a = &m->vertices[m->indices[i]], *b = &m->vertices[m->indices[i + 4]]; /* a0, b0 */
            double along = 0;
            for (int j = 0; j < 3; j++) along += (double)a->tangent[j] * (b->position[j] - a->position[j]);
            assert_true(along > 0);
        }
    }
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
    assert_within_bound(back.mesh.vertices, f.mesh.vertices, f.mesh.vertex_count, f.mesh.vertices, f.mesh.vertex_count);
    assert_memory_equal(back.mesh.indices, f.mesh.indices, sizeof *f.mesh.indices * f.mesh.index_count);
    assert_memory_equal(back.mesh.components, f.mesh.components, sizeof *f.mesh.components * f.mesh.component_count);
    /* Every level is ribbons: no index stored, 22 bytes a vertex. */
    assert_int_equal(size, bytes_without_indices(&f));
    const double smaller = (double)HTLODS2_BYTES(&f.mesh, (unsigned)f.level_count) / (double)size;
    if (!(smaller >= SMALLER_THAN_HTLODS2)) fail_msg("%zu bytes, only %.3fx fewer than HTLODS2", size, smaller);
    /* Each level, taken out on its own, is the chain's level. */
    for (int l = 0; l < back.level_count; l++) {
        ht_mesh m;
        const ht_mesh *want = ht_lod_chain_mesh(&chain, l);
        assert_int_equal(ht_lod_file_level_mesh(&back, l, &m), HT_OK);
        assert_int_equal(m.vertex_count, want->vertex_count);
        assert_within_bound(m.vertices, want->vertices, m.vertex_count, f.mesh.vertices, f.mesh.vertex_count);
        assert_memory_equal(m.indices, want->indices, sizeof *m.indices * m.index_count);
        assert_memory_equal(m.components, want->components, sizeof *m.components * m.component_count);
        assert_root_to_tip(&m);
        ht_mesh_free(&m);
    }
    printf("%d levels, %zu bytes, %.2fx fewer than HTLODS2's %u\n", back.level_count, size, smaller,
           HTLODS2_BYTES(&f.mesh, (unsigned)f.level_count));
    ht_lod_file_free(&back);
    free(data);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

/* A level whose indices are not the ribbons' rows (one triangle turned
   over) keeps its indices stored, 4 bytes each, and reads back exact; the
   other levels stay implied. */
static void explicit_indices_round_trip(void **state) {
    (void)state;
    ht_mesh full;
    ht_lod_chain chain;
    ht_lod_file f, back;
    make_ladder(&full, &chain, &f);
    uint32_t *tri = f.mesh.indices + f.levels[1].first_index + 3;
    const uint32_t t = tri[1];
    tri[1] = tri[2];
    tri[2] = t;
    unsigned char *data;
    size_t size;
    char err[256] = "";
    assert_int_equal(ht_lod_file_encode(&f, &data, &size), HT_OK);
    assert_int_equal(size, bytes_without_indices(&f) + 4 * (size_t)f.levels[1].index_count);
    if (ht_lod_file_parse(data, size, "lods.bin", &back, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_memory_equal(back.levels, f.levels, sizeof f.levels);
    assert_memory_equal(back.mesh.indices, f.mesh.indices, sizeof *f.mesh.indices * f.mesh.index_count);
    assert_memory_equal(back.mesh.components, f.mesh.components, sizeof *f.mesh.components * f.mesh.component_count);
    assert_within_bound(back.mesh.vertices, f.mesh.vertices, f.mesh.vertex_count, f.mesh.vertices, f.mesh.vertex_count);
    printf("level 1 stored: %zu bytes, %u of them its indices\n", size, 4 * f.levels[1].index_count);
    /* an index of it past its own vertices (into level 2's) is refused */
    const uint32_t explicit_at = LEVELS_AT + LEVEL_BYTES * (uint32_t)f.level_count + VERTEX_BYTES * f.mesh.vertex_count;
    const uint32_t level1_vertices = back.mesh.indices[f.levels[2].first_index] - back.mesh.indices[f.levels[1].first_index];
    ht_lod_file g;
    for (int b = 0; b < 4; b++) data[explicit_at + 8 + b] = (unsigned char)(level1_vertices >> (8 * b));
    assert_int_equal(ht_lod_file_parse(data, size, "bad.bin", &g, err, sizeof err), HT_ERR_PARSE);
    printf("%s\n", err);
    assert_non_null(strstr(err, "bad.bin: indices["));
    assert_non_null(strstr(err, "past the level's"));
    assert_null(g.mesh.vertices);
    ht_lod_file_free(&back);
    free(data);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

/* The 32-bit pair of an octahedral direction never decodes to anything
   but a unit vector, and every direction comes back within the bound
   (the six axes, where the fold meets, and a sweep). */
static void directions_within_bound(void **state) {
    (void)state;
    double worst = 0;
    for (int i = 0; i < 200000; i++) {
        const double th = acos(1 - 2 * (i + 0.5) / 200000), ph = i * 2.399963229728653;
        float d[3] = { (float)(sin(th) * cos(ph)), (float)(sin(th) * sin(ph)), (float)cos(th) };
        if (i < 6) d[0] = d[1] = d[2] = 0, d[i / 2] = i % 2 ? -1.0f : 1.0f;
        ht_vertex v = { .normal = { d[0], d[1], d[2] }, .tangent = { d[2], d[0], d[1] } }, back;
        ht_lod_box box = { { 0, 0, 0 }, { 1, 1, 1 } };
        unsigned char bytes[HT_LOD_QUANT_VERTEX_BYTES];
        ht_lod_vertex_encode(&v, &box, &box, bytes);
        ht_lod_vertex_decode(bytes, &box, &box, &back);
        char why[256];
        if (!ht_test_lod_within_bound(&back, &v, 1, &v, 1, why, sizeof why)) fail_msg("direction %d: %s", i, why);
        worst = fmax(worst, ht_test_angle(v.normal, back.normal));
    }
    for (uint32_t q = 0; q < 65536; q += 257) {
        const uint16_t pair[2] = { (uint16_t)q, (uint16_t)(65535 - q) };
        float n[3];
        ht_lod_oct_decode(pair, n);
        assert_true(fabs(sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]) - 1) <= 4 * FLT_EPSILON);
    }
    printf("directions: worst %.3g rad, bound %.3g\n", worst, HT_LOD_FILE_DIRECTION_ERROR);
    assert_true(worst <= HT_LOD_FILE_DIRECTION_ERROR);
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
   (indices and components exact, the stored vertices within the bound);
   another mesh is refused, and so is taking level 0 out. */
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
    /* level 0 is the scene's mesh itself; the stored levels within the bound */
    assert_memory_equal(back_chain.all.vertices, chain.all.vertices, sizeof *chain.all.vertices * full.vertex_count);
    assert_within_bound(back_chain.all.vertices + full.vertex_count, chain.all.vertices + full.vertex_count,
                        chain.all.vertex_count - full.vertex_count, stored.mesh.vertices, stored.mesh.vertex_count);
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

static uint32_t f32_bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static uint32_t get32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* expect_refused on a copy of good with a first edit at at0 already made
   (two fields that must change together). */
static void expect_refused2(const unsigned char *good, size_t size, size_t at0, uint32_t value0, size_t at, uint32_t value,
                            const char *field) {
    unsigned char *copy = malloc(size);
    assert_non_null(copy);
    memcpy(copy, good, size);
    put32(copy + at0, value0);
    expect_refused(copy, size, at, value, size, field);
    free(copy);
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
    const size_t components_at = vertices_at + VERTEX_BYTES * (size_t)f.mesh.vertex_count; /* no index stored */
    const size_t none = SIZE_MAX - 8, level1 = LEVELS_AT + LEVEL_BYTES;
    const uint32_t v0 = get32(data + LEVELS_AT + 12), v1 = get32(data + level1 + 12);
    const uint32_t c0 = get32(data + LEVELS_AT + 20), c1 = get32(data + level1 + 20);
    expect_refused(data, size, 0, 0x4c4c4548, size, "header");                        /* magic */
    expect_refused(data, size, 4, 0x0a325344u, size,
                   "header: \"HTLODS2\", this runtime reads HTLODS3 (" HT_MANIFEST_GENERATOR
                   " bundles): regenerate with " HT_MANIFEST_GENERATOR);              /* the older format */
    expect_refused(data, size, none, 0, 20, "header");                                 /* cut in the header */
    expect_refused(data, size, none, 0, size - 1, "size");                             /* cut at the end */
    expect_refused(data, size, none, 0, size / 2, "size");                             /* cut in the middle */
    expect_refused(data, size, none, 0, size + 4, "size");                             /* trailing bytes */
    expect_refused(data, size, 8, 0, size, "levels");
    expect_refused(data, size, 8, HT_LOD_FILE_MAX_LEVELS + 1, size, "levels");
    expect_refused(data, size, 12, 0xffffffffu, size, "counts");                       /* vertices */
    expect_refused(data, size, 16, f.mesh.index_count + 6, size, "levels: they hold"); /* indices (implied) */
    expect_refused(data, size, 20, f.mesh.index_count + 3, size, "stored_indices");
    expect_refused(data, size, 20, 3, size, "size");                                   /* 3 stored: 12 bytes missing */
    expect_refused(data, size, 24, f.mesh.component_count + 1, size, "size");
    expect_refused(data, size, 28, 0x7fc00000u, size, "center");                       /* NaN */
    expect_refused(data, size, BOXES_AT, 0x7fc00000u, size, "position_box[0]");       /* min NaN */
    expect_refused(data, size, BOXES_AT + 16, 0x7f800000u, size, "position_box[1]");  /* extent Inf */
    expect_refused(data, size, BOXES_AT + 20, 0, size, "position_box[2]");            /* zero extent */
    expect_refused(data, size, BOXES_AT + 12, f32_bits(-1.0f), size, "position_box[0]");
    expect_refused2(data, size, BOXES_AT, f32_bits(3e38f), BOXES_AT + 12, f32_bits(3e38f), "position_box[0]"); /* min + extent: Inf */
    expect_refused(data, size, BOXES_AT + 36, 0, size, "texture_box[0]");             /* zero extent */
    expect_refused(data, size, BOXES_AT + 44, 0xff800000u, size, "texture_box[2]");   /* ao extent -Inf */
    expect_refused(data, size, LEVELS_AT, 3, size, "levels[0].kind");
    expect_refused(data, size, LEVELS_AT, 2, size, "levels[0].vertex_count: the scene's mesh"); /* with vertices */
    expect_refused(data, size, level1, 2, size, "levels[1].vertex_count: the scene's mesh");
    expect_refused(data, size, LEVELS_AT + 8, 2, size, "levels[0].strips");
    expect_refused(data, size, LEVELS_AT + 8, 0, size, "levels: they hold");          /* stored now, none in the file */
    /* level 1 two vertices short: its last ribbon's rows pass them */
    expect_refused2(data, size, LEVELS_AT + 12, v0 + 2, level1 + 12, v1 - 2, "first_vertex");
    expect_refused(data, size, LEVELS_AT + 16, 1, size, "levels[0].index_count: not whole triangles");
    expect_refused(data, size, LEVELS_AT + 16, get32(data + LEVELS_AT + 16) + 6, size, "its counts pass the header's");
    expect_refused(data, size, LEVELS_AT + 20, f.mesh.component_count + 1, size, "levels[0]: its counts pass");
    expect_refused2(data, size, LEVELS_AT + 20, c0 + 1, level1 + 20, c1 - 1, "index_count: 6, past the level's");
    expect_refused2(data, size, LEVELS_AT + 20, c0 - 1, level1 + 20, c1 + 1, "levels[0]: its ribbons take");
    /* a ribbon with half a row, none, or rows past the level's vertices */
    expect_refused(data, size, components_at + 4, 9, size, "components[0].index_count: 9");
    expect_refused(data, size, components_at + 4, 0, size, "components[0].index_count: 0");
    expect_refused(data, size, components_at, v0 - 10, size, "components[0].first_vertex");
    expect_refused(data, size, components_at, 0xfffffffeu, size, "components[0].first_vertex");
    /* level 0's ribbon at vertex 0 moved two on: vertices 0 and 1 unused */
    size_t at_vertex0 = components_at;
    while (get32(data + at_vertex0) != 0) at_vertex0 += 12;
    expect_refused(data, size, at_vertex0, 2, size, "levels[0].vertex_count: 3600, its indices reach 3598");
    expect_refused(data, size, components_at + 8, 0xff800000u, size, "components[0]: index range past the indices, or sort key");
    /* A file that is not there: one line naming it. */
    ht_lod_file g;
    char err[256] = "";
    assert_int_equal(ht_lod_file_read("/nonexistent/lods.bin", &g, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "/nonexistent/lods.bin"));
    assert_null(strchr(err, '\n'));
    free(data);
    /* The writer refuses what the reader would, and a layout it cannot
       hold (level 1 before level 0 in the vertex buffer). */
    f.levels[0].index_count = f.mesh.index_count + 3;
    assert_int_equal(ht_lod_file_encode(&f, &data, &size), HT_ERR_INVALID_ARGUMENT);
    assert_null(data);
    f.levels[0].index_count = chain.index_count[0];
    f.levels[1].first_index += 6;
    f.levels[1].index_count -= 6;
    assert_int_equal(ht_lod_file_encode(&f, &data, &size), HT_ERR_INVALID_ARGUMENT);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&full);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trip),
        cmocka_unit_test(explicit_indices_round_trip),
        cmocka_unit_test(directions_within_bound),
        cmocka_unit_test(matches_only_its_own_mesh),
        cmocka_unit_test(scene_level_round_trip),
        cmocka_unit_test(hostile_files_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

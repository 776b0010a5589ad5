/* test_strands — the strand file readers (TressFX 4.0 .tfx, Cem Yuksel's
   .hair) on files written here: good files read back exactly; every class
   of bad header, every truncation, non-finite values and huge counts are
   refused with one line naming the file and the field, nothing left
   allocated; huge counts are refused before allocating (a child whose
   address space is capped would fail with out-of-memory otherwise). Then
   the shipped ratboy-mohawk.tfx reads as its README says. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include <hairtier/ht_limits.h>
#include <hairtier/strands.h>
#include "support_child.h"
#include "support_scratch.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "strands") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* ---- writing files ---- */

typedef struct bytes {
    uint8_t *data;
    size_t size;
} bytes;

static void put_u32(uint8_t *p, uint32_t v) {
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}
static void put_f32(uint8_t *p, float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_u32(p, u);
}

/* Point j of strand i of the test files: a gentle curve, all distinct. */
static void test_point(uint32_t i, uint32_t j, float p[3]) {
    p[0] = (float)i + 0.1f * (float)j;
    p[1] = 1.0f + 0.5f * (float)j;
    p[2] = -0.25f * (float)i + 0.01f * (float)(j * j);
}

/* strands x per_strand .tfx: header, positions, strand UVs, and (with
   thickness) a thickness per strand, 0.5 + i. */
static bytes make_tfx(uint32_t strands, uint32_t per_strand, bool thickness) {
    const size_t points = (size_t)strands * per_strand;
    const size_t pos = 160, uv = pos + 16 * points, th = uv + 8 * strands;
    bytes b = { calloc(1, th + (thickness ? 4 * strands : 0)), th + (thickness ? 4 * strands : 0) };
    assert_non_null(b.data);
    put_f32(b.data, 4.0f);
    put_u32(b.data + 4, strands);
    put_u32(b.data + 8, per_strand);
    put_u32(b.data + 12, (uint32_t)pos);
    put_u32(b.data + 16, (uint32_t)uv);
    put_u32(b.data + 24, thickness ? (uint32_t)th : 0);
    for (uint32_t i = 0; i < strands; i++) {
        for (uint32_t j = 0; j < per_strand; j++) {
            float p[3];
            test_point(i, j, p);
            uint8_t *q = b.data + pos + 16 * ((size_t)i * per_strand + j);
            for (int k = 0; k < 3; k++) put_f32(q + 4 * k, p[k]);
            put_f32(q + 12, j == 0 ? 0.0f : 1.0f);
        }
        put_f32(b.data + uv + 8 * i, 0.5f);
        put_f32(b.data + uv + 8 * i + 4, 0.25f);
        if (thickness) put_f32(b.data + th + 4 * i, 0.5f + (float)i);
    }
    return b;
}

enum { H_SEGMENTS = 1, H_POINTS = 2, H_THICKNESS = 4, H_TRANSPARENCY = 8, H_COLORS = 16 };

/* A .hair of `strands` strands; strand i has segments[i] segments (or
   default_segments each when segments is NULL); arrays as the bit field
   says. Thickness 0.01 (i + 1) per point, transparency 0.5, colour grey. */
static bytes make_hair(uint32_t strands, const uint16_t *segments, uint32_t default_segments, uint32_t arrays) {
    size_t points = 0;
    for (uint32_t i = 0; i < strands; i++) points += (size_t)(segments ? segments[i] : default_segments) + 1;
    const size_t size = 128 + (arrays & H_SEGMENTS ? 2 * strands : 0) + (arrays & H_POINTS ? 12 * points : 0) +
                        (arrays & H_THICKNESS ? 4 * points : 0) + (arrays & H_TRANSPARENCY ? 4 * points : 0) +
                        (arrays & H_COLORS ? 12 * points : 0);
    bytes b = { calloc(1, size), size };
    assert_non_null(b.data);
    memcpy(b.data, "HAIR", 4);
    put_u32(b.data + 4, strands);
    put_u32(b.data + 8, (uint32_t)points);
    put_u32(b.data + 12, arrays);
    put_u32(b.data + 16, default_segments);
    put_f32(b.data + 20, 0.02f);
    put_f32(b.data + 24, 0.0f);
    for (int k = 0; k < 3; k++) put_f32(b.data + 28 + 4 * k, 0.5f);
    memcpy(b.data + 40, "written by test_strands", 23);
    uint8_t *c = b.data + 128;
    if (arrays & H_SEGMENTS)
        for (uint32_t i = 0; i < strands; i++, c += 2) { c[0] = (uint8_t)segments[i]; c[1] = (uint8_t)(segments[i] >> 8); }
    if (arrays & H_POINTS) {
        for (uint32_t i = 0; i < strands; i++)
            for (uint32_t j = 0; j <= (segments ? segments[i] : default_segments); j++, c += 12) {
                float p[3];
                test_point(i, j, p);
                for (int k = 0; k < 3; k++) put_f32(c + 4 * k, p[k]);
            }
    }
    if (arrays & H_THICKNESS) {
        size_t n = 0;
        for (uint32_t i = 0; i < strands; i++)
            for (uint32_t j = 0; j <= (segments ? segments[i] : default_segments); j++, n++)
                put_f32(c + 4 * n, 0.01f * (float)(i + 1));
        c += 4 * points;
    }
    if (arrays & H_TRANSPARENCY) {
        for (size_t n = 0; n < points; n++) put_f32(c + 4 * n, 0.5f);
        c += 4 * points;
    }
    if (arrays & H_COLORS)
        for (size_t n = 0; n < 3 * points; n++) put_f32(c + 4 * n, 0.25f);
    return b;
}

static const char *write_bytes(const char *name, bytes b) {
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", work, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b.data, 1, b.size, f), b.size);
    assert_int_equal(fclose(f), 0);
    return path;
}

static void assert_zeroed(const ht_strands *s) {
    assert_null(s->first_point);
    assert_null(s->points);
    assert_null(s->thickness);
    assert_int_equal(s->strand_count, 0);
    assert_int_equal(s->point_count, 0);
}

typedef ht_result (*parse_fn)(const uint8_t *, size_t, const char *, ht_strands *, char *, size_t);

/* A refusal: the result, one line, the file name and the field in it,
   nothing allocated. */
static void assert_refused(parse_fn parse, bytes b, const char *field) {
    ht_strands s;
    char err[512] = "";
    memset(&s, 0xab, sizeof s);
    ht_result r = parse(b.data, b.size, "bad.strands", &s, err, sizeof err);
    if (r != HT_ERR_PARSE || !strstr(err, "bad.strands: ") || !strstr(err, field) || strchr(err, '\n'))
        fail_msg("expected a refusal naming \"%s\", got %d: %s", field, (int)r, err);
    assert_zeroed(&s);
}

static void assert_strand_points_are_test_points(const ht_strands *s) {
    for (uint32_t i = 0; i < s->strand_count; i++)
        for (uint32_t j = 0; j < s->first_point[i + 1] - s->first_point[i]; j++) {
            float p[3];
            test_point(i, j, p);
            assert_memory_equal(s->points[s->first_point[i] + j], p, sizeof p);
        }
}

/* ---- .tfx ---- */

static void test_tfx_good_file_reads_back(void **state) {
    (void)state;
    for (int with_thickness = 0; with_thickness < 2; with_thickness++) {
        bytes b = make_tfx(3, 5, with_thickness);
        ht_strands s;
        char err[256];
        assert_int_equal(ht_strands_load(write_bytes("good.tfx", b), &s, err, sizeof err), HT_OK);
        assert_int_equal(s.strand_count, 3);
        assert_int_equal(s.point_count, 15);
        for (uint32_t i = 0; i <= 3; i++) assert_int_equal(s.first_point[i], 5 * i);
        assert_strand_points_are_test_points(&s);
        if (with_thickness) {
            assert_non_null(s.thickness);
            for (uint32_t i = 0; i < 15; i++) assert_true(s.thickness[i] == 0.5f + (float)(i / 5));
        } else {
            assert_null(s.thickness);
        }
        ht_strands_free(&s);
        assert_zeroed(&s);
        free(b.data);
    }
}

static void test_tfx_every_bad_header_is_refused_by_field(void **state) {
    (void)state;
    const struct {
        size_t at;     /* byte of the header to change; SIZE_MAX: cut the file */
        uint32_t value;
        bool is_float;
        float f;
        const char *field;
    } cases[] = {
        { 0, 0, true, 3.0f, "version" },
        { 0, 0, true, NAN, "version" },
        { 4, 0, false, 0, "numHairStrands" },
        { 4, HT_LIMIT_STRANDS + 1, false, 0, "numHairStrands" },
        { 8, 1, false, 0, "numVerticesPerStrand" },
        { 8, HT_LIMIT_STRAND_POINTS + 1, false, 0, "numVerticesPerStrand" },
        { 12, 0, false, 0, "offsetVertexPosition" },
        { 12, 96, false, 0, "offsetVertexPosition" },        /* inside the header */
        { 12, 162, false, 0, "offsetVertexPosition" },       /* not aligned */
        { 12, 0xfffffff0u, false, 0, "offsetVertexPosition" }, /* past the end */
        { 16, 176, false, 0, "offsetStrandUV" },             /* overlaps the positions */
        { 20, 160 + 16 * 12, false, 0, "offsetVertexUV" },   /* runs past the end */
        { 24, 1u << 30, false, 0, "offsetStrandThickness" },
        { 28, 4, false, 0, "offsetVertexColor" },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        bytes b = make_tfx(3, 4, false);
        if (cases[c].is_float) put_f32(b.data + cases[c].at, cases[c].f);
        else put_u32(b.data + cases[c].at, cases[c].value);
        assert_refused(ht_strands_parse_tfx, b, cases[c].field);
        free(b.data);
    }
    /* Each count allowed, their product not. */
    bytes b = make_tfx(3, 4, false);
    put_u32(b.data + 4, HT_LIMIT_STRANDS);
    put_u32(b.data + 8, 5);
    assert_refused(ht_strands_parse_tfx, b, "numVerticesPerStrand");
    free(b.data);
}

static void test_tfx_every_truncation_is_refused(void **state) {
    (void)state;
    bytes b = make_tfx(3, 4, true);
    for (size_t n = 0; n < b.size; n++) {
        bytes cut = { b.data, n };
        /* Cut inside the header: "header"; after it, the block cut short. */
        assert_refused(ht_strands_parse_tfx, cut, n < 160 ? "header" : "offset");
    }
    free(b.data);
}

static void test_tfx_non_finite_values_are_refused(void **state) {
    (void)state;
    const float bad[] = { NAN, INFINITY, -INFINITY, 1e30f };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        bytes b = make_tfx(3, 4, true);
        put_f32(b.data + 160 + 16 * (1 * 4 + 2) + 4, bad[i]); /* strand 1, point 2, y */
        assert_refused(ht_strands_parse_tfx, b, "positions[1][2]");
        free(b.data);
        b = make_tfx(3, 4, true);
        put_f32(b.data + 160 + 16 * 12 + 8 * 3 + 4 * 2, i == 3 ? -1.0f : bad[i]); /* thickness of strand 2 */
        assert_refused(ht_strands_parse_tfx, b, "thickness[2]");
        free(b.data);
    }
    bytes b = make_tfx(2, 2, false);
    put_f32(b.data + 160 + 12, NAN); /* w of the first root */
    assert_refused(ht_strands_parse_tfx, b, "positions[0][0]");
    free(b.data);
}

/* ---- .hair ---- */

static void test_hair_good_files_read_back(void **state) {
    (void)state;
    const uint16_t segments[3] = { 1, 4, 2 };
    bytes b = make_hair(3, segments, 0, H_SEGMENTS | H_POINTS | H_THICKNESS | H_TRANSPARENCY | H_COLORS);
    ht_strands s;
    char err[256];
    assert_int_equal(ht_strands_load(write_bytes("good.hair", b), &s, err, sizeof err), HT_OK);
    assert_int_equal(s.strand_count, 3);
    assert_int_equal(s.point_count, 10);
    const uint32_t first[4] = { 0, 2, 7, 10 };
    assert_memory_equal(s.first_point, first, sizeof first);
    assert_strand_points_are_test_points(&s);
    assert_non_null(s.thickness);
    assert_true(s.thickness[0] == 0.01f && s.thickness[9] == 0.03f);
    ht_strands_free(&s);
    free(b.data);

    /* No arrays but the points: default segments and the default thickness. */
    b = make_hair(4, NULL, 3, H_POINTS);
    assert_int_equal(ht_strands_parse_hair(b.data, b.size, "d.hair", &s, err, sizeof err), HT_OK);
    assert_int_equal(s.strand_count, 4);
    assert_int_equal(s.point_count, 16);
    assert_int_equal(s.first_point[4], 16);
    assert_strand_points_are_test_points(&s);
    for (uint32_t i = 0; i < 16; i++) assert_true(s.thickness[i] == 0.02f);
    ht_strands_free(&s);
    /* A default thickness of 0 and no array: no thickness. */
    put_f32(b.data + 20, 0.0f);
    assert_int_equal(ht_strands_parse_hair(b.data, b.size, "d.hair", &s, err, sizeof err), HT_OK);
    assert_null(s.thickness);
    ht_strands_free(&s);
    free(b.data);
}

static void test_hair_every_bad_header_is_refused_by_field(void **state) {
    (void)state;
    const struct {
        size_t at;
        uint32_t value;
        bool is_float;
        float f;
        const char *field;
    } cases[] = {
        { 0, 0x52494148u + 1, false, 0, "signature" },
        { 4, 0, false, 0, "hair count" },
        { 4, HT_LIMIT_STRANDS + 1, false, 0, "hair count" },
        { 8, 1, false, 0, "point count" },
        { 8, HT_LIMIT_STRANDS_POINTS + 1, false, 0, "point count" },
        { 8, 11, false, 0, "arrays" },                        /* the file holds 10 points */
        { 12, 0x23, false, 0, "arrays" },                     /* an unknown bit */
        { 12, 0x1d, false, 0, "arrays" },                     /* no points */
        { 12, 0x02, false, 0, "default segments" },           /* no segments array, default 0 */
        { 20, 0, true, NAN, "default thickness" },
        { 20, 0, true, -1.0f, "default thickness" },
        { 24, 0, true, 2.0f, "default transparency" },
        { 24, 0, true, NAN, "default transparency" },
        { 32, 0, true, INFINITY, "default color" },
    };
    const uint16_t segments[3] = { 1, 4, 2 };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        bytes b = make_hair(3, segments, 0, H_SEGMENTS | H_POINTS | H_THICKNESS | H_TRANSPARENCY | H_COLORS);
        if (cases[c].is_float) put_f32(b.data + cases[c].at, cases[c].f);
        else put_u32(b.data + cases[c].at, cases[c].value);
        assert_refused(ht_strands_parse_hair, b, cases[c].field);
        free(b.data);
    }
    /* Default segments that do not make the point count; a file one byte
       long or short; a zero segment count; segments adding up wrong. */
    bytes b = make_hair(4, NULL, 3, H_POINTS);
    put_u32(b.data + 16, 2);
    assert_refused(ht_strands_parse_hair, b, "point count");
    put_u32(b.data + 16, 3);
    assert_refused(ht_strands_parse_hair, (bytes){ b.data, b.size - 1 }, "arrays");
    bytes longer = { realloc(b.data, b.size + 1), b.size + 1 };
    longer.data[b.size] = 0;
    assert_refused(ht_strands_parse_hair, longer, "arrays");
    free(longer.data);
    const uint16_t zero[3] = { 1, 0, 3 };
    b = make_hair(3, zero, 0, H_SEGMENTS | H_POINTS);
    assert_refused(ht_strands_parse_hair, b, "segments[1]");
    free(b.data);
    b = make_hair(3, segments, 0, H_SEGMENTS | H_POINTS);
    b.data[128 + 2] = 3; /* strand 1: 3 segments, the header still counts 10 points */
    assert_refused(ht_strands_parse_hair, b, "point count");
    free(b.data);
}

static void test_hair_every_truncation_is_refused(void **state) {
    (void)state;
    const uint16_t segments[3] = { 1, 4, 2 };
    bytes b = make_hair(3, segments, 0, H_SEGMENTS | H_POINTS | H_THICKNESS | H_COLORS);
    for (size_t n = 0; n < b.size; n++)
        assert_refused(ht_strands_parse_hair, (bytes){ b.data, n }, n < 128 ? "header" : "arrays");
    free(b.data);
}

static void test_hair_non_finite_values_are_refused(void **state) {
    (void)state;
    const uint16_t segments[3] = { 1, 4, 2 };
    const uint32_t all = H_SEGMENTS | H_POINTS | H_THICKNESS | H_TRANSPARENCY | H_COLORS;
    const size_t points = 128 + 6, thickness = points + 120, transparency = thickness + 40, colors = transparency + 40;
    const struct {
        size_t at;
        float value;
        const char *field;
    } cases[] = {
        { points + 12 * 3 + 4, NAN, "points[3]" },
        { points + 12 * 9, INFINITY, "points[9]" },
        { points, -1e30f, "points[0]" },
        { thickness + 4 * 5, NAN, "thickness[5]" },
        { thickness + 4 * 5, -0.5f, "thickness[5]" },
        { transparency + 4 * 2, 1.5f, "transparency[2]" },
        { colors + 12 * 7 + 8, NAN, "colors[7]" },
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        bytes b = make_hair(3, segments, 0, all);
        assert_int_equal(b.size, colors + 120);
        put_f32(b.data + cases[c].at, cases[c].value);
        assert_refused(ht_strands_parse_hair, b, cases[c].field);
        free(b.data);
    }
}

/* ---- both: huge counts, files that are not strand files ---- */

#ifndef HT_UNDER_ASAN
/* Headers claiming the most points the limits allow (64 MiB of positions
   and more) over a file of a few hundred bytes: refused as a parse error
   with 8 MiB of address space to spare, so before any allocation for them. */
static int huge_counts_child(void) {
    bytes tfx = make_tfx(2, 2, false), hair = make_hair(2, NULL, 1, H_POINTS);
    if (!ht_test_limit_address_space((size_t)8 << 20)) return 11;
    ht_strands s;
    char err[512];
    put_u32(tfx.data + 4, HT_LIMIT_STRANDS);
    put_u32(tfx.data + 8, HT_LIMIT_STRANDS_POINTS / HT_LIMIT_STRANDS);
    if (ht_strands_parse_tfx(tfx.data, tfx.size, "huge.tfx", &s, err, sizeof err) != HT_ERR_PARSE) return 1;
    if (!strstr(err, "offsetVertexPosition")) return 2;
    put_u32(hair.data + 4, HT_LIMIT_STRANDS);
    put_u32(hair.data + 8, HT_LIMIT_STRANDS_POINTS);
    put_u32(hair.data + 16, HT_LIMIT_STRANDS_POINTS / HT_LIMIT_STRANDS - 1);
    if (ht_strands_parse_hair(hair.data, hair.size, "huge.hair", &s, err, sizeof err) != HT_ERR_PARSE) return 3;
    if (!strstr(err, "arrays")) return 4;
    /* The same counts in a file that does hold them would be read: the
       limit itself is what a 2 GB mesh needs (test_render_strands
       renders a real file). */
    return 0;
}
#endif

static void test_huge_counts_are_refused_before_allocating(void **state) {
    (void)state;
    HT_TEST_FORK_MEMORY_CHILD(huge_counts_child);
}

static void test_files_that_are_not_strand_files_are_refused(void **state) {
    (void)state;
    ht_strands s;
    char err[512], path[256];
    snprintf(path, sizeof path, "%s/a-directory.tfx", work);
    assert_int_equal(mkdir(path, 0700), 0);
    assert_int_equal(ht_strands_load(path, &s, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "not a regular file"));
    assert_zeroed(&s);
    snprintf(path, sizeof path, "%s/missing.hair", work);
    assert_int_equal(ht_strands_load(path, &s, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "missing.hair"));
    bytes b = make_tfx(1, 2, false);
    assert_int_equal(ht_strands_load(write_bytes("strands.obj", b), &s, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, ".tfx"));
    /* A .tfx named .hair is read as .hair and refused by its signature. */
    assert_int_equal(ht_strands_load(write_bytes("tfx-inside.hair", b), &s, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "signature"));
    assert_zeroed(&s);
    free(b.data);
}

/* ---- the shipped file ---- */

static void test_ratboy_mohawk_reads_as_its_readme_says(void **state) {
    (void)state;
    ht_strands s;
    char err[512];
    assert_int_equal(ht_strands_load("scenes/ratboy-mohawk.tfx", &s, err, sizeof err), HT_OK);
    assert_int_equal(s.strand_count, 2226);
    assert_int_equal(s.point_count, 2226 * 32);
    assert_null(s.thickness);
    float lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t i = 0; i < s.point_count; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], s.points[i][k]);
            hi[k] = fmaxf(hi[k], s.points[i][k]);
        }
    /* "about x −9.5…11.7, y 21.4…111.0, z −33.6…27.1" */
    const float want_lo[3] = { -9.5f, 21.4f, -33.6f }, want_hi[3] = { 11.7f, 111.0f, 27.1f };
    for (int k = 0; k < 3; k++) {
        assert_true(fabsf(lo[k] - want_lo[k]) < 0.1f);
        assert_true(fabsf(hi[k] - want_hi[k]) < 0.1f);
    }
    ht_strands_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tfx_good_file_reads_back),
        cmocka_unit_test(test_tfx_every_bad_header_is_refused_by_field),
        cmocka_unit_test(test_tfx_every_truncation_is_refused),
        cmocka_unit_test(test_tfx_non_finite_values_are_refused),
        cmocka_unit_test(test_hair_good_files_read_back),
        cmocka_unit_test(test_hair_every_bad_header_is_refused_by_field),
        cmocka_unit_test(test_hair_every_truncation_is_refused),
        cmocka_unit_test(test_hair_non_finite_values_are_refused),
        cmocka_unit_test(test_huge_counts_are_refused_before_allocating),
        cmocka_unit_test(test_files_that_are_not_strand_files_are_refused),
        cmocka_unit_test(test_ratboy_mohawk_reads_as_its_readme_says),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* strands_hair.c — Cem Yuksel's `.hair` strand files (cemyuksel.com/
   research/hairmodels; what pbrt and much research use).

   Little-endian. A 128-byte header:
     0   char[4]  "HAIR"
     4   uint32   hair count (strands)
     8   uint32   point count (all strands)
     12  uint32   arrays: bit 0 segments, 1 points, 2 thickness,
                  3 transparency, 4 colours
     16  uint32   default segments per strand (when there is no segments array)
     20  float    default thickness
     24  float    default transparency
     28  float[3] default colour
     40  char[88] information (free text, not read)
   then the arrays present, in this order: segments (uint16 per strand),
   points (float3 per point), thickness (float per point), transparency
   (float per point), colours (float3 per point). Strand i has segments + 1
   points, root first.

   Checked before anything is allocated: the signature, both counts within
   ht_limits.h, no unknown array bit, a points array, the defaults finite
   (thickness >= 0, transparency in [0, 1]), the file exactly as long as the
   arrays declared, every segment count >= 1 and the points they add up to
   equal to the point count. Then every point finite and within
   HT_LIMIT_STRANDS_COORD, every thickness finite in [0, that], every
   transparency in [0, 1] and colour finite. Thickness is kept (the array,
   or the default when it is above 0); transparency and colour are not
   used. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "errfmt.h"
#include <hairtier/ht_limits.h>
#include "strands_internal.h"
#include "vecmath.h"

#define HAIR_HEADER_BYTES 128u

enum {
    HAIR_SEGMENTS = 1u << 0,
    HAIR_POINTS = 1u << 1,
    HAIR_THICKNESS = 1u << 2,
    HAIR_TRANSPARENCY = 1u << 3,
    HAIR_COLORS = 1u << 4,
    HAIR_KNOWN = (1u << 5) - 1,
};

typedef struct hair_header {
    uint32_t strands, points, arrays, default_segments;
    float default_thickness, default_transparency, default_color[3];
} hair_header;

static ht_result read_header(const uint8_t *data, size_t size, const char *file, hair_header *h, char *err,
                             size_t err_size) {
    if (size < HAIR_HEADER_BYTES)
        return ht_strands_fail(err, err_size, file, "header", "the file is %zu bytes, a .hair header takes %u", size,
                               HAIR_HEADER_BYTES);
    if (memcmp(data, "HAIR", 4) != 0) return ht_strands_fail(err, err_size, file, "signature", "not \"HAIR\"");
    h->strands = ht_le_u32(data + 4);
    h->points = ht_le_u32(data + 8);
    h->arrays = ht_le_u32(data + 12);
    h->default_segments = ht_le_u32(data + 16);
    h->default_thickness = ht_le_f32(data + 20);
    h->default_transparency = ht_le_f32(data + 24);
    for (int k = 0; k < 3; k++) h->default_color[k] = ht_le_f32(data + 28 + 4 * k);
    if (h->strands < 1 || h->strands > HT_LIMIT_STRANDS)
        return ht_strands_fail(err, err_size, file, "hair count", "%u, must be 1 to %u", h->strands, HT_LIMIT_STRANDS);
    if (h->points < 2 || h->points > HT_LIMIT_STRANDS_POINTS)
        return ht_strands_fail(err, err_size, file, "point count", "%u, must be 2 to %u", h->points,
                               HT_LIMIT_STRANDS_POINTS);
    if (h->arrays & ~(uint32_t)HAIR_KNOWN)
        return ht_strands_fail(err, err_size, file, "arrays", "0x%x has bits beyond the five arrays (0x1f)", h->arrays);
    if (!(h->arrays & HAIR_POINTS))
        return ht_strands_fail(err, err_size, file, "arrays", "0x%x has no points array (bit 1)", h->arrays);
    if (!(h->arrays & HAIR_SEGMENTS)) {
        if (h->default_segments < 1 || h->default_segments >= HT_LIMIT_STRAND_POINTS)
            return ht_strands_fail(err, err_size, file, "default segments", "%u, must be 1 to %u without a segments array",
                                   h->default_segments, HT_LIMIT_STRAND_POINTS - 1);
        if ((uint64_t)h->strands * (h->default_segments + 1) != h->points)
            return ht_strands_fail(err, err_size, file, "point count",
                                   "%u, but %u strands of %u segments have %llu points", h->points, h->strands,
                                   h->default_segments, (unsigned long long)h->strands * (h->default_segments + 1));
    }
    if (!(isfinite(h->default_thickness) && h->default_thickness >= 0 &&
          h->default_thickness <= (float)HT_LIMIT_STRANDS_COORD))
        return ht_strands_fail(err, err_size, file, "default thickness", "%g, must be 0 to %g",
                               (double)h->default_thickness, HT_LIMIT_STRANDS_COORD);
    if (!(h->default_transparency >= 0 && h->default_transparency <= 1))
        return ht_strands_fail(err, err_size, file, "default transparency", "%g, must be 0 to 1",
                               (double)h->default_transparency);
    if (!ht_all_finite(h->default_color, 3))
        return ht_strands_fail(err, err_size, file, "default color", "not finite");

    const uint64_t n = h->points;
    const uint64_t expected = HAIR_HEADER_BYTES + (h->arrays & HAIR_SEGMENTS ? 2ull * h->strands : 0) + 12 * n +
                              (h->arrays & HAIR_THICKNESS ? 4 * n : 0) + (h->arrays & HAIR_TRANSPARENCY ? 4 * n : 0) +
                              (h->arrays & HAIR_COLORS ? 12 * n : 0);
    if (size != expected)
        return ht_strands_fail(err, err_size, file, "arrays",
                               "the file is %zu bytes, but the header and the arrays it declares (0x%x) take %llu",
                               size, h->arrays, (unsigned long long)expected);
    return HT_OK;
}

/* Sums the segments array (or the default) into first_point-style offsets
   without allocating: the sum must equal the header's point count. */
static ht_result check_segments(const uint8_t *segments, const hair_header *h, const char *file, char *err,
                                size_t err_size) {
    if (!segments) return HT_OK;
    uint64_t points = 0;
    for (uint32_t s = 0; s < h->strands; s++) {
        const uint16_t n = ht_le_u16(segments + 2 * (size_t)s);
        if (n < 1) {
            char field[64];
            snprintf(field, sizeof field, "segments[%u]", s);
            return ht_strands_fail(err, err_size, file, field, "0, a strand needs at least 1 segment");
        }
        points += (uint64_t)n + 1;
    }
    if (points != h->points)
        return ht_strands_fail(err, err_size, file, "point count", "%u, but the segments array adds up to %llu points",
                               h->points, (unsigned long long)points);
    return HT_OK;
}

static ht_result per_point_field(const char *name, uint32_t i, const char *file, char *err, size_t err_size,
                                 const char *what) {
    char field[64];
    snprintf(field, sizeof field, "%s[%u]", name, i);
    return ht_strands_fail(err, err_size, file, field, "%s", what);
}

ht_result ht_strands_parse_hair(const uint8_t *data, size_t size, const char *file_name, ht_strands *out,
                                char *err, size_t err_size) {
    const char *file = file_name ? file_name : "<input>";
    memset(out, 0, sizeof *out);
    hair_header h;
    ht_result r = read_header(data, size, file, &h, err, err_size);
    if (r != HT_OK) return r;
    const uint8_t *cursor = data + HAIR_HEADER_BYTES;
    const uint8_t *segments = NULL, *thickness = NULL, *transparency = NULL, *colors = NULL;
    if (h.arrays & HAIR_SEGMENTS) { segments = cursor; cursor += 2 * (size_t)h.strands; }
    const uint8_t *points = cursor;
    cursor += 12 * (size_t)h.points;
    if (h.arrays & HAIR_THICKNESS) { thickness = cursor; cursor += 4 * (size_t)h.points; }
    if (h.arrays & HAIR_TRANSPARENCY) { transparency = cursor; cursor += 4 * (size_t)h.points; }
    if (h.arrays & HAIR_COLORS) colors = cursor;
    r = check_segments(segments, &h, file, err, err_size);
    if (r != HT_OK) return r;

    const bool keep_thickness = thickness || h.default_thickness > 0;
    r = ht_strands_alloc(out, h.strands, h.points, keep_thickness, file, err, err_size);
    if (r != HT_OK) return r;
    uint32_t first = 0;
    for (uint32_t s = 0; s < h.strands; s++) {
        out->first_point[s] = first;
        first += (segments ? ht_le_u16(segments + 2 * (size_t)s) : h.default_segments) + 1u;
    }
    out->first_point[h.strands] = first;

    for (uint32_t i = 0; i < h.points; i++) {
        for (int k = 0; k < 3; k++) out->points[i][k] = ht_le_f32(points + 12 * (size_t)i + 4 * k);
        if (!ht_strands_coord_ok(out->points[i])) {
            r = per_point_field("points", i, file, err, err_size, "not finite or beyond the coordinate limit (1e7)");
            break;
        }
        const float t = thickness ? ht_le_f32(thickness + 4 * (size_t)i) : h.default_thickness;
        if (!(isfinite(t) && t >= 0 && t <= (float)HT_LIMIT_STRANDS_COORD)) {
            r = per_point_field("thickness", i, file, err, err_size, "not finite, negative or beyond 1e7");
            break;
        }
        if (out->thickness) out->thickness[i] = t;
        if (transparency) {
            const float a = ht_le_f32(transparency + 4 * (size_t)i);
            if (!(a >= 0 && a <= 1)) {
                r = per_point_field("transparency", i, file, err, err_size, "outside [0, 1]");
                break;
            }
        }
        if (colors) {
            float c[3];
            for (int k = 0; k < 3; k++) c[k] = ht_le_f32(colors + 12 * (size_t)i + 4 * k);
            if (!ht_all_finite(c, 3)) {
                r = per_point_field("colors", i, file, err, err_size, "not finite");
                break;
            }
        }
    }
    if (r != HT_OK) ht_strands_free(out);
    return r;
}

ht_result ht_strands_load_hair(const char *path, ht_strands *out, char *err, size_t err_size) {
    return ht_strands_load_with(ht_strands_parse_hair, path, out, err, err_size);
}

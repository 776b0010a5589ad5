/* strands_tfx.c — TressFX 4.0 `.tfx` strand files (AMD's exporters).

   Little-endian. A 160-byte header: float version (4.0), uint32
   numHairStrands, uint32 numVerticesPerStrand, then uint32 byte offsets of
   five blocks (0: absent), then 32 reserved uint32 (not read):
     offsetVertexPosition   strands x vertices x float4 (x, y, z, w); required
     offsetStrandUV         strands x float2
     offsetVertexUV         strands x vertices x float2
     offsetStrandThickness  strands x float
     offsetVertexColor      strands x vertices x float4
   Strands are stored root first. w is the vertex's inverse mass in the
   simulation (0: pinned); only its finiteness is checked.

   Checked before anything is allocated: the header fits, version is 4.0,
   both counts within ht_limits.h (strands, points per strand, points in
   all), every present block 4-byte aligned, after the header, inside the
   file and overlapping no other. Then every position must be finite and
   within HT_LIMIT_STRANDS_COORD, every thickness finite, not negative and
   within it too. UVs and colours are not used (their blocks are only
   placed). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "errfmt.h"
#include <hairtier/ht_limits.h>
#include "strands_internal.h"

#define TFX_HEADER_BYTES 160u

enum { BLOCK_POSITION, BLOCK_STRAND_UV, BLOCK_VERTEX_UV, BLOCK_THICKNESS, BLOCK_COLOR, BLOCK_COUNT };

static const char *const block_names[BLOCK_COUNT] = {
    "offsetVertexPosition", "offsetStrandUV", "offsetVertexUV", "offsetStrandThickness", "offsetVertexColor",
};

typedef struct block {
    uint64_t offset, bytes; /* offset 0: absent */
} block;

static ht_result check_blocks(const block b[BLOCK_COUNT], uint64_t size, const char *file, char *err,
                              size_t err_size) {
    if (b[BLOCK_POSITION].offset == 0)
        return ht_strands_fail(err, err_size, file, block_names[BLOCK_POSITION], "0, but the positions are required");
    for (int i = 0; i < BLOCK_COUNT; i++) {
        if (b[i].offset == 0) continue;
        if (b[i].offset < TFX_HEADER_BYTES)
            return ht_strands_fail(err, err_size, file, block_names[i], "%llu points into the %u-byte header",
                                   (unsigned long long)b[i].offset, TFX_HEADER_BYTES);
        if (b[i].offset % 4)
            return ht_strands_fail(err, err_size, file, block_names[i], "%llu is not a multiple of 4",
                                   (unsigned long long)b[i].offset);
        if (b[i].bytes > size || b[i].offset > size - b[i].bytes)
            return ht_strands_fail(err, err_size, file, block_names[i],
                                   "a block of %llu bytes at %llu runs past the end of the file (%llu bytes)",
                                   (unsigned long long)b[i].bytes, (unsigned long long)b[i].offset,
                                   (unsigned long long)size);
        for (int j = 0; j < i; j++)
            if (b[j].offset && b[i].offset < b[j].offset + b[j].bytes && b[j].offset < b[i].offset + b[i].bytes)
                return ht_strands_fail(err, err_size, file, block_names[i], "its block overlaps %s's", block_names[j]);
    }
    return HT_OK;
}

ht_result ht_strands_parse_tfx(const uint8_t *data, size_t size, const char *file_name, ht_strands *out,
                               char *err, size_t err_size) {
    const char *file = file_name ? file_name : "<input>";
    memset(out, 0, sizeof *out);
    if (size < TFX_HEADER_BYTES)
        return ht_strands_fail(err, err_size, file, "header", "the file is %zu bytes, a TressFX 4.0 header takes %u",
                               size, TFX_HEADER_BYTES);
    const float version = ht_le_f32(data);
    if (version != 4.0f)
        return ht_strands_fail(err, err_size, file, "version", "%g, only TressFX 4.0 files are read", (double)version);
    const uint32_t strands = ht_le_u32(data + 4), per_strand = ht_le_u32(data + 8);
    if (strands < 1 || strands > HT_LIMIT_STRANDS)
        return ht_strands_fail(err, err_size, file, "numHairStrands", "%u, must be 1 to %u", strands, HT_LIMIT_STRANDS);
    if (per_strand < 2 || per_strand > HT_LIMIT_STRAND_POINTS)
        return ht_strands_fail(err, err_size, file, "numVerticesPerStrand", "%u, must be 2 to %u", per_strand,
                               HT_LIMIT_STRAND_POINTS);
    const uint64_t points = (uint64_t)strands * per_strand;
    if (points > HT_LIMIT_STRANDS_POINTS)
        return ht_strands_fail(err, err_size, file, "numVerticesPerStrand",
                               "%u strands x %u vertices = %llu points, more than the %u a strand file may have",
                               strands, per_strand, (unsigned long long)points, HT_LIMIT_STRANDS_POINTS);
    block b[BLOCK_COUNT];
    const uint64_t block_bytes[BLOCK_COUNT] = { points * 16, (uint64_t)strands * 8, points * 8,
                                                (uint64_t)strands * 4, points * 16 };
    for (int i = 0; i < BLOCK_COUNT; i++) b[i] = (block){ ht_le_u32(data + 12 + 4 * i), block_bytes[i] };
    ht_result r = check_blocks(b, size, file, err, err_size);
    if (r != HT_OK) return r;

    r = ht_strands_alloc(out, strands, (uint32_t)points, b[BLOCK_THICKNESS].offset != 0, file, err, err_size);
    if (r != HT_OK) return r;
    const uint8_t *thickness = data + b[BLOCK_THICKNESS].offset;
    for (uint32_t s = 0; s < strands; s++) {
        out->first_point[s] = s * per_strand;
        float t = 0;
        if (out->thickness) {
            t = ht_le_f32(thickness + 4 * (size_t)s);
            if (!(isfinite(t) && t >= 0 && t <= (float)HT_LIMIT_STRANDS_COORD)) {
                char field[64];
                snprintf(field, sizeof field, "thickness[%u]", s);
                ht_strands_free(out);
                return ht_strands_fail(err, err_size, file, field, "%g, must be 0 to %g", (double)t,
                                       HT_LIMIT_STRANDS_COORD);
            }
        }
        for (uint32_t v = 0; v < per_strand; v++) {
            const size_t i = (size_t)s * per_strand + v;
            const uint8_t *p = data + b[BLOCK_POSITION].offset + 16 * i;
            for (int k = 0; k < 3; k++) out->points[i][k] = ht_le_f32(p + 4 * k);
            if (!ht_strands_coord_ok(out->points[i]) || !isfinite(ht_le_f32(p + 12))) {
                char field[64];
                snprintf(field, sizeof field, "positions[%u][%u]", s, v);
                ht_strands_free(out);
                return ht_strands_fail(err, err_size, file, field, "(%g, %g, %g, %g): not finite or beyond ±%g",
                                       (double)ht_le_f32(p), (double)ht_le_f32(p + 4), (double)ht_le_f32(p + 8),
                                       (double)ht_le_f32(p + 12), HT_LIMIT_STRANDS_COORD);
            }
            if (out->thickness) out->thickness[i] = t;
        }
    }
    out->first_point[strands] = (uint32_t)points;
    return HT_OK;
}

ht_result ht_strands_load_tfx(const char *path, ht_strands *out, char *err, size_t err_size) {
    return ht_strands_load_with(ht_strands_parse_tfx, path, out, err, err_size);
}

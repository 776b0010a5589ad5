/* lod_quant.c — lods.bin's 22-byte vertex (lod_quant.h). */
#include "lod_quant.h"

#include <math.h>
#include <string.h>

bool ht_lod_box_of(const ht_vertex *v, uint32_t count, bool texture, ht_lod_box *out) {
    for (int k = 0; k < 3; k++) {
        double lo = INFINITY, hi = -INFINITY;
        for (uint32_t i = 0; i < count; i++) {
            const double x = texture ? (k < 2 ? v[i].uv[k] : v[i].ao) : v[i].position[k];
            lo = x < lo ? x : lo;
            hi = x > hi ? x : hi;
        }
        if (!count) lo = hi = 0;
        float extent = (float)(hi - lo);
        if ((double)extent < hi - lo) extent = nextafterf(extent, INFINITY);
        out->min[k] = (float)lo;
        out->extent[k] = hi > lo ? extent : 1.0f;
    }
    int axis;
    return ht_lod_box_valid(out, &axis);
}

bool ht_lod_box_valid(const ht_lod_box *b, int *axis) {
    for (int k = 0; k < 3; k++) {
        *axis = k;
        if (!isfinite(b->min[k]) || !isfinite(b->extent[k]) || !(b->extent[k] > 0) ||
            !isfinite((float)((double)b->min[k] + b->extent[k])))
            return false;
    }
    return true;
}

uint32_t ht_lod_quantize(float v, float min, float extent, uint32_t steps) {
    const double s = rint(((double)v - min) / extent * steps);
    return (uint32_t)(s > 0 ? (s < steps ? s : steps) : 0);
}

float ht_lod_dequantize(uint32_t q, float min, float extent, uint32_t steps) {
    return (float)(min + (double)extent * q / steps);
}

void ht_lod_oct_encode(const float n[3], uint16_t out[2]) {
    const double l1 = fabs((double)n[0]) + fabs((double)n[1]) + fabs((double)n[2]);
    double x = l1 > 0 ? n[0] / l1 : 0, y = l1 > 0 ? n[1] / l1 : 0;
    if (l1 > 0 && n[2] < 0) { /* the lower half folded over the diagonals */
        const double fx = (1 - fabs(y)) * (x >= 0 ? 1 : -1), fy = (1 - fabs(x)) * (y >= 0 ? 1 : -1);
        x = fx;
        y = fy;
    }
    out[0] = (uint16_t)ht_lod_quantize((float)x, -1.0f, 2.0f, HT_LOD_QUANT_STEPS);
    out[1] = (uint16_t)ht_lod_quantize((float)y, -1.0f, 2.0f, HT_LOD_QUANT_STEPS);
}

void ht_lod_oct_decode(const uint16_t q[2], float out[3]) {
    double x = ht_lod_dequantize(q[0], -1.0f, 2.0f, HT_LOD_QUANT_STEPS), y = ht_lod_dequantize(q[1], -1.0f, 2.0f, HT_LOD_QUANT_STEPS);
    const double z = 1 - fabs(x) - fabs(y);
    if (z < 0) {
        const double fx = (1 - fabs(y)) * (x >= 0 ? 1 : -1), fy = (1 - fabs(x)) * (y >= 0 ? 1 : -1);
        x = fx;
        y = fy;
    }
    const double len = sqrt(x * x + y * y + z * z); /* >= 1/sqrt(3): |x| + |y| + |z| = 1 */
    out[0] = (float)(x / len);
    out[1] = (float)(y / len);
    out[2] = (float)(z / len);
}

static void put_u16(unsigned char **p, uint16_t v) {
    (*p)[0] = (unsigned char)v;
    (*p)[1] = (unsigned char)(v >> 8);
    *p += 2;
}

static uint16_t get_u16(const unsigned char **p) {
    const uint16_t v = (uint16_t)((*p)[0] | (*p)[1] << 8);
    *p += 2;
    return v;
}

void ht_lod_vertex_encode(const ht_vertex *v, const ht_lod_box *position, const ht_lod_box *texture,
                          unsigned char out[HT_LOD_QUANT_VERTEX_BYTES]) {
    unsigned char *p = out;
    uint64_t packed = 0;
    for (int k = 0; k < 3; k++)
        packed |= (uint64_t)ht_lod_quantize(v->position[k], position->min[k], position->extent[k],
                                            HT_LOD_QUANT_POSITION_STEPS) << (HT_LOD_QUANT_POSITION_BITS * k);
    for (int b = 0; b < 8; b++) *p++ = (unsigned char)(packed >> (8 * b));
    uint16_t oct[2];
    ht_lod_oct_encode(v->normal, oct);
    put_u16(&p, oct[0]);
    put_u16(&p, oct[1]);
    ht_lod_oct_encode(v->tangent, oct);
    put_u16(&p, oct[0]);
    put_u16(&p, oct[1]);
    const float tex[3] = { v->uv[0], v->uv[1], v->ao };
    for (int k = 0; k < 3; k++)
        put_u16(&p, (uint16_t)ht_lod_quantize(tex[k], texture->min[k], texture->extent[k], HT_LOD_QUANT_STEPS));
}

void ht_lod_vertex_decode(const unsigned char in[HT_LOD_QUANT_VERTEX_BYTES], const ht_lod_box *position,
                          const ht_lod_box *texture, ht_vertex *out) {
    const unsigned char *p = in;
    uint64_t packed = 0;
    for (int b = 0; b < 8; b++) packed |= (uint64_t)*p++ << (8 * b);
    for (int k = 0; k < 3; k++)
        out->position[k] = ht_lod_dequantize((uint32_t)(packed >> (HT_LOD_QUANT_POSITION_BITS * k)) & HT_LOD_QUANT_POSITION_STEPS,
                                             position->min[k], position->extent[k], HT_LOD_QUANT_POSITION_STEPS);
    uint16_t oct[2];
    oct[0] = get_u16(&p);
    oct[1] = get_u16(&p);
    ht_lod_oct_decode(oct, out->normal);
    oct[0] = get_u16(&p);
    oct[1] = get_u16(&p);
    ht_lod_oct_decode(oct, out->tangent);
    float tex[3];
    for (int k = 0; k < 3; k++) tex[k] = ht_lod_dequantize(get_u16(&p), texture->min[k], texture->extent[k], HT_LOD_QUANT_STEPS);
    out->uv[0] = tex[0];
    out->uv[1] = tex[1];
    out->ao = tex[2];
}

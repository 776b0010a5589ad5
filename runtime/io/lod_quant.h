/* lod_quant.h — how lods.bin (HTLODS3, lod_file.c) stores a vertex in 22
   bytes: positions as 21-bit and (u, v, ao) as 16-bit steps of a box the
   file carries, normals and tangents as octahedral 16-bit pairs. Internal
   to libhairtier; the error bounds are lod.h's (HT_LOD_FILE_*_ERROR). */
#ifndef HT_LOD_QUANT_H
#define HT_LOD_QUANT_H

#include <stdbool.h>
#include <stdint.h>

#include <hairtier/hairtier.h>
#include <hairtier/lod.h>

#define HT_LOD_QUANT_STEPS 65535u
#define HT_LOD_QUANT_POSITION_BITS HT_LOD_FILE_POSITION_BITS
#define HT_LOD_QUANT_POSITION_STEPS ((1u << HT_LOD_QUANT_POSITION_BITS) - 1)
#define HT_LOD_QUANT_VERTEX_BYTES 22

/* Three axes' range: a value v is stored as round((v - min) / extent x
   steps). Positions use one, (u, v, ao) another. */
typedef struct ht_lod_box {
    float min[3], extent[3];
} ht_lod_box;

/* The box holding `count` vertices' positions (texture false) or (u, v,
   ao) (texture true), its extent rounded up so the largest value is the
   last step; an axis with one value gets extent 1 (a box of zero extent is
   not a valid one). false when an extent or min + extent is not finite. */
bool ht_lod_box_of(const ht_vertex *v, uint32_t count, bool texture, ht_lod_box *out);
/* Whether a box read from a file decodes every step to a finite value:
   min finite, extent finite and > 0, min + extent finite; *axis the first
   bad axis. */
bool ht_lod_box_valid(const ht_lod_box *b, int *axis);

/* v as one of `steps` + 1 values of [min, min + extent], clamped; back. */
uint32_t ht_lod_quantize(float v, float min, float extent, uint32_t steps);
float ht_lod_dequantize(uint32_t q, float min, float extent, uint32_t steps);
/* A direction as an octahedral pair; a zero vector is stored as +z. */
void ht_lod_oct_encode(const float n[3], uint16_t out[2]);
/* Always a unit vector (renormalized), whatever the bits. */
void ht_lod_oct_decode(const uint16_t q[2], float out[3]);

/* One vertex to its 22 bytes (little-endian: u64 of the position's three
   21-bit steps, x lowest; u16 normal[2], tangent[2], u, v, ao) and back. */
void ht_lod_vertex_encode(const ht_vertex *v, const ht_lod_box *position, const ht_lod_box *texture,
                          unsigned char out[HT_LOD_QUANT_VERTEX_BYTES]);
void ht_lod_vertex_decode(const unsigned char in[HT_LOD_QUANT_VERTEX_BYTES], const ht_lod_box *position,
                          const ht_lod_box *texture, ht_vertex *out);

#endif

/* strands_internal.h — what the strand file readers (strands_tfx.c,
   strands_hair.c) share (strands_common.c): reading a whole file, little-endian
   fields, allocation after the counts are known good, the checks on
   coordinates. Not part of any API. */
#ifndef HT_STRANDS_INTERNAL_H
#define HT_STRANDS_INTERNAL_H

#include <stdbool.h>
#include <string.h>

#include <hairtier/strands.h>

static inline uint32_t ht_le_u32(const uint8_t *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline uint16_t ht_le_u16(const uint8_t *p) { return (uint16_t)(p[0] | p[1] << 8); }
static inline float ht_le_f32(const uint8_t *p) {
    uint32_t u = ht_le_u32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* One reader's parse function, as ht_strands_parse_tfx. */
typedef ht_result (*ht_strands_parse_fn)(const uint8_t *data, size_t size, const char *file, ht_strands *out,
                                         char *err, size_t err_size);
/* path read whole (ht_strands_read_file) and given to parse. */
ht_result ht_strands_load_with(ht_strands_parse_fn parse, const char *path, ht_strands *out, char *err,
                               size_t err_size);
/* The whole of a regular file of at most HT_LIMIT_FILE_STRANDS bytes
   (file_open.h), malloc'd, or NULL with "PATH: why" in err. */
uint8_t *ht_strands_read_file(const char *path, size_t *size, char *err, size_t err_size);
/* Zeroes *out and allocates first_point, points and (when with_thickness)
   thickness for counts the caller has already checked against the limits. */
ht_result ht_strands_alloc(ht_strands *out, uint32_t strands, uint32_t points, bool with_thickness,
                           const char *file, char *err, size_t err_size);
/* "FILE: FIELD: " + message, HT_ERR_PARSE. */
ht_result ht_strands_fail(char *err, size_t err_size, const char *file, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* A position the ribbon builder can use: finite, |x| <= HT_LIMIT_STRANDS_COORD. */
bool ht_strands_coord_ok(const float p[3]);

#endif

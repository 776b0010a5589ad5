/* strands_common.c — what the two strand file readers (strands_tfx.c,
   strands_hair.c) share: the bounded read of a whole file, allocation, the
   coordinate check, errors (strands_internal.h). */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>

#include "errfmt.h"
#include "file_open.h"
#include <hairtier/ht_limits.h>
#include "strands_internal.h"

uint8_t *ht_strands_read_file(const char *path, size_t *size, char *err, size_t err_size) {
    return ht_file_read_bytes(path, HT_LIMIT_FILE_STRANDS, size, err, err_size);
}

ht_result ht_strands_fail(char *err, size_t err_size, const char *file, const char *field, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    ht_set_field_error_v(err, err_size, file, field, fmt, ap);
    va_end(ap);
    return HT_ERR_PARSE;
}

ht_result ht_strands_alloc(ht_strands *out, uint32_t strands, uint32_t points, bool with_thickness,
                           const char *file, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->first_point = malloc(sizeof *out->first_point * ((size_t)strands + 1));
    out->points = malloc(sizeof *out->points * (size_t)points);
    out->thickness = with_thickness ? malloc(sizeof *out->thickness * (size_t)points) : NULL;
    if (!out->first_point || !out->points || (with_thickness && !out->thickness)) {
        ht_strands_free(out);
        ht_set_error(err, err_size, "%s: out of memory for %u strands of %u points", file, strands, points);
        return HT_ERR_OUT_OF_MEMORY;
    }
    out->strand_count = strands;
    out->point_count = points;
    return HT_OK;
}

bool ht_strands_coord_ok(const float p[3]) {
    for (int k = 0; k < 3; k++)
        if (!isfinite(p[k]) || fabsf(p[k]) > (float)HT_LIMIT_STRANDS_COORD) return false;
    return true;
}

void ht_strands_free(ht_strands *s) {
    if (!s) return;
    free(s->first_point);
    free(s->points);
    free(s->thickness);
    memset(s, 0, sizeof *s);
}

ht_result ht_strands_load_with(ht_strands_parse_fn parse, const char *path, ht_strands *out, char *err,
                               size_t err_size) {
    memset(out, 0, sizeof *out);
    size_t size;
    uint8_t *data = ht_strands_read_file(path, &size, err, err_size);
    if (!data) return HT_ERR_IO;
    ht_result r = parse(data, size, path, out, err, err_size);
    free(data);
    return r;
}

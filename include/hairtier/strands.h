/* strands.h — hair strands read from the files people exchange them in:
   TressFX 4.0 `.tfx` (strands_tfx.c) and Cem Yuksel's `.hair`
   (strands_hair.c); mesh_strands.c turns them into ribbons. Internal to
   libhairtier (the scene reader and the examples use it).

   Usage:
       ht_strands s;
       char err[512];
       if (ht_strands_load("scenes/ratboy-mohawk.tfx", &s, err, sizeof err) != HT_OK) puts(err);
       for (uint32_t i = 0; i < s.strand_count; i++)   // strand i: its points, root first
           printf("%u points\n", s.first_point[i + 1] - s.first_point[i]);
       ht_strands_free(&s);

   Every reader is hostile-input safe: each header field, count and offset
   is checked against the file size and the limits of ht_limits.h
   (HT_LIMIT_STRANDS*) before anything is allocated for it, every
   coordinate and thickness must be finite, and a refusal is one line
   "FILE: FIELD: what is wrong" with nothing left allocated. */
#ifndef HT_STRANDS_H
#define HT_STRANDS_H

#include "export.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hairtier.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ht_strands {
    uint32_t strand_count;  /* >= 1 */
    uint32_t point_count;   /* all strands together */
    uint32_t *first_point;  /* strand_count + 1 entries; strand i is [first_point[i], first_point[i + 1]) */
    float (*points)[3];     /* root first, in the file's units */
    float *thickness;       /* per point, file units; NULL when the file carries none */
} ht_strands;

/* By extension: ".tfx" or ".hair" (any case); anything else is refused. */
HT_API ht_result ht_strands_load(const char *path, ht_strands *out, char *err, size_t err_size);
HT_API ht_result ht_strands_load_tfx(const char *path, ht_strands *out, char *err, size_t err_size);
HT_API ht_result ht_strands_load_hair(const char *path, ht_strands *out, char *err, size_t err_size);
/* The same readers on a file's bytes already in memory; file_name names it
   in messages. The fuzz targets call these. */
HT_API ht_result ht_strands_parse_tfx(const uint8_t *data, size_t size, const char *file_name, ht_strands *out,
                               char *err, size_t err_size);
HT_API ht_result ht_strands_parse_hair(const uint8_t *data, size_t size, const char *file_name, ht_strands *out,
                                char *err, size_t err_size);
HT_API void ht_strands_free(ht_strands *s);

/* How mesh_strands.c turns strands into ribbons (scene units are the
   file's units times scale, the point `center` of the file at the origin). */
typedef struct ht_strands_ribbon_desc {
    float scale;            /* file units to scene units, > 0 */
    float center[3];        /* file units: the point placed at the scene origin */
    float width;            /* ribbon width at the root, scene units, > 0 */
    float tip_width;        /* width at the tip / at the root, [0, 1] */
    bool use_thickness;     /* width = the file's thickness x scale instead */
    float ao;               /* occlusion per typical cell of hair above a vertex, >= 0 (0: none) */
    float head_center[3];   /* scene units: ribbons face away from it, the sort measures from it */
    float facing[3];        /* not zero: ribbons face this way instead (a crest seen side-on) */
} ht_strands_ribbon_desc;

/* One ribbon per strand, sorted inside out (mesh_strands.c says how).
   HT_ERR_INVALID_ARGUMENT with err "FIELD: why" for a bad desc (or
   use_thickness on strands without thickness), HT_ERR_OUT_OF_MEMORY; on
   failure *out is zeroed. */
HT_API ht_result ht_mesh_build_strands(const ht_strands *strands, const ht_strands_ribbon_desc *desc, ht_mesh *out,
                                char *err, size_t err_size);

#ifdef __cplusplus
}
#endif

#endif

/* material_marschner.h — the "marschner" object of a material file
   (docs/materials.md): read from JSON in degrees, held in radians, and
   checked again for materials built in memory. */
#ifndef HT_MATERIAL_MARSCHNER_H
#define HT_MATERIAL_MARSCHNER_H

#include <stddef.h>

#include "json_check.h"
#include <hairtier/model_marschner.h>

/* Ranges, in the file's units (degrees for angles). */
#define HT_MARSCHNER_ABSORPTION_MAX 50.0
#define HT_MARSCHNER_SHIFT_MAX_DEG 20.0  /* |alpha_R| */
#define HT_MARSCHNER_WIDTH_MIN_DEG 1.0   /* beta_R */
#define HT_MARSCHNER_WIDTH_MAX_DEG 60.0
#define HT_MARSCHNER_ETA_MIN 1.1
#define HT_MARSCHNER_ETA_MAX 3.0

/* Defaults when a field is absent. */
#define HT_MARSCHNER_SHIFT_DEFAULT_DEG (-7.0)
#define HT_MARSCHNER_WIDTH_DEFAULT_DEG 7.0
#define HT_MARSCHNER_ETA_DEFAULT 1.55

/* Reads root's required "marschner" object into *out. */
ht_result ht_material_parse_marschner(const ht_jctx *c, const cJSON *root, ht_marschner *out);

/* Every field finite and in range; "FILE: marschner.FIELD: ..." otherwise. */
ht_result ht_material_check_marschner(const char *file, const ht_marschner *m, char *err,
                                      size_t err_size);

#endif

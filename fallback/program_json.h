/* program_json.h — what the tier programs that carry the material's
   constants (fixed4.json, gl11.json) write and read alike: the model, the
   diffuse term and the lobes, and the printed text. One place, so the two
   formats spell and check these fields the same way. Internal.

   Usage (writer):  cJSON *root = ...; ht_program_json_add_shading(root, &shading);
                    r = ht_program_json_print(root, "gl11.json", &text, err, sizeof err);
   Usage (reader):  r = ht_program_json_parse_shading(&c, root, &shading); */
#ifndef HT_PROGRAM_JSON_H
#define HT_PROGRAM_JSON_H

#include <stddef.h>

#include <cJSON.h>

#include <hairtier/hairtier.h>
#include "json_check.h"
#include <hairtier/model.h>

/* "diffuse": {color, wrap}, "primary" and (Scheuermann) "secondary":
   {color, exponent, shift}; the caller writes "model" where its format
   puts it. */
void ht_program_json_add_shading(cJSON *root, const ht_shading *s);

/* Prints root (and deletes it) as *text with a final newline (malloc'd);
   an out-of-memory error names file. */
ht_result ht_program_json_print(cJSON *root, const char *file, char **text, char *err, size_t err_size);

/* "model": "scheuermann" or "kajiya-kay", required. */
ht_result ht_program_json_parse_model(const ht_jctx *c, const cJSON *root, ht_model_kind *out);

/* Reads what ht_program_json_add_shading writes, checking every range; a
   Kajiya-Kay program may not carry "secondary". Errors name the field. */
ht_result ht_program_json_parse_shading(const ht_jctx *c, const cJSON *root, ht_shading *s);

#endif

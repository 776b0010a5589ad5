/* program_json.c — see program_json.h. */
#include "program_json.h"

#include <stdlib.h>
#include <string.h>

#include <hairtier/ht_limits.h>
#include "errfmt.h"

static void add_vec3(cJSON *obj, const char *key, const double v[3]) {
    cJSON *a = cJSON_AddArrayToObject(obj, key);
    for (int i = 0; i < 3; i++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[i]));
}

static void add_lobe(cJSON *root, const char *key, const ht_lobe *l) {
    cJSON *o = cJSON_AddObjectToObject(root, key);
    add_vec3(o, "color", l->color);
    cJSON_AddNumberToObject(o, "exponent", l->exponent);
    cJSON_AddNumberToObject(o, "shift", l->shift);
}

void ht_program_json_add_shading(cJSON *root, const ht_shading *s) {
    const bool kajiya_kay = s->model == HT_MODEL_KAJIYA_KAY;
    cJSON *d = cJSON_AddObjectToObject(root, "diffuse");
    add_vec3(d, "color", s->diffuse_color);
    cJSON_AddNumberToObject(d, "wrap", s->wrap);
    add_lobe(root, "primary", &s->primary);
    if (!kajiya_kay) add_lobe(root, "secondary", &s->secondary);
}

ht_result ht_program_json_print(cJSON *root, const char *file, char **text, char *err, size_t err_size) {
    *text = NULL;
    char *printed = cJSON_Print(root);
    cJSON_Delete(root);
    if (!printed) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", file);
    size_t n = strlen(printed);
    *text = malloc(n + 2);
    if (!*text) {
        cJSON_free(printed);
        return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", file);
    }
    memcpy(*text, printed, n);
    (*text)[n] = '\n';
    (*text)[n + 1] = '\0';
    cJSON_free(printed);
    return HT_OK;
}

static ht_result parse_lobe(const ht_jctx *c, const cJSON *root, const char *key, ht_lobe *l) {
    static const char *const keys[] = { "color", "exponent", "shift", NULL };
    const cJSON *o = NULL;
    ht_result r = ht_json_object(c, root, "", key, true, &o);
    if (r == HT_OK) r = ht_json_keys(c, o, key, keys);
    if (r == HT_OK) r = ht_json_vec(c, o, key, "color", NULL, 3, HT_JRANGE(0, 1), l->color);
    if (r == HT_OK) r = ht_json_number(c, o, key, "exponent", NULL, HT_JRANGE(0, HT_LIMIT_EXPONENT), &l->exponent);
    if (r == HT_OK) r = ht_json_number(c, o, key, "shift", NULL, HT_JRANGE(-HT_LIMIT_SHIFT, HT_LIMIT_SHIFT), &l->shift);
    return r;
}

ht_result ht_program_json_parse_model(const ht_jctx *c, const cJSON *root, ht_model_kind *out) {
    static const char *const models[] = { "scheuermann", "kajiya-kay", NULL };
    int model = 0;
    ht_result r = ht_json_enum(c, root, "", "model", -1, models, &model);
    *out = model == 1 ? HT_MODEL_KAJIYA_KAY : HT_MODEL_SCHEUERMANN;
    return r;
}

ht_result ht_program_json_parse_shading(const ht_jctx *c, const cJSON *root, ht_shading *s) {
    static const char *const diffuse_keys[] = { "color", "wrap", NULL };
    const cJSON *d = NULL;
    ht_result r = ht_json_object(c, root, "", "diffuse", true, &d);
    if (r == HT_OK) r = ht_json_keys(c, d, "diffuse", diffuse_keys);
    if (r == HT_OK) r = ht_json_vec(c, d, "diffuse", "color", NULL, 3, HT_JRANGE(0, 1), s->diffuse_color);
    if (r == HT_OK) r = ht_json_number(c, d, "diffuse", "wrap", NULL, HT_JRANGE(0, 1), &s->wrap);
    if (r == HT_OK) r = parse_lobe(c, root, "primary", &s->primary);
    if (r == HT_OK && s->model == HT_MODEL_SCHEUERMANN) r = parse_lobe(c, root, "secondary", &s->secondary);
    if (r == HT_OK && s->model == HT_MODEL_KAJIYA_KAY)
        r = ht_json_forbid(c, root, "", "secondary", "Kajiya-Kay has one lobe");
    return r;
}

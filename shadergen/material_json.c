/* material_json.c — reads "hairtier-material/1" files into ht_material.
   Every rule (required fields, defaults, ranges) is listed in
   docs/materials.md; keep the two in step. */
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include <hairtier/hairgen.h>
#include "json_check.h"
#include "material_marschner.h"
#include "shading_check.h"

#define MATERIAL_FORMAT "hairtier-material/1"

static const char *const slot_names[HT_TEX_COUNT + 1] = { "base", "alpha", "shift", "sparkle", NULL };

/* The one generator each slot accepts: a slot's texture means one thing
   (colour, coverage, jitter, mask), so a generator made for another slot
   would be a silent mistake. */
static const char *const slot_generators[HT_TEX_COUNT] = {
    "stretched-noise", "strand-alpha", "noise", "sparkle",
};

const char *ht_texture_slot_name(ht_texture_slot s) {
    return (s >= 0 && s < HT_TEX_COUNT) ? slot_names[s] : "unknown";
}

static const ht_jrange COLOR_RANGE = { 0, 1, false, false };

static ht_result parse_name(const ht_jctx *c, const cJSON *root, char name[64]) {
    ht_result r = ht_json_string(c, root, "", "name", NULL, name, 64);
    if (r != HT_OK) return r;
    for (const char *p = name; *p; p++) {
        char ch = *p;
        bool ok = (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') ||
                  (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
        /* The name becomes file and symbol names downstream. */
        if (!ok)
            return ht_json_fail(c, "name", "character %ld is '%c'; names use only A-Z a-z 0-9 _ -",
                                (long)(p - name) + 1, ch >= 0x20 && ch < 0x7f ? ch : '?');
    }
    return HT_OK;
}

/* A lobe object: "color" and "exponent" required, "shift" optional. */
static ht_result parse_lobe(const ht_jctx *c, const cJSON *root, const char *key,
                            bool shift_allowed, const char *model_name, ht_lobe *out) {
    static const char *const keys[] = { "color", "exponent", "shift", NULL };
    const cJSON *obj;
    ht_result r = ht_json_object(c, root, "", key, true, &obj);
    if (r == HT_OK) r = ht_json_keys(c, obj, key, keys);
    if (r == HT_OK) r = ht_json_vec(c, obj, key, "color", NULL, 3, COLOR_RANGE, out->color);
    if (r == HT_OK) r = ht_json_number(c, obj, key, "exponent", NULL, HT_JRANGE(0, HT_LIMIT_EXPONENT), &out->exponent);
    if (r == HT_OK && !shift_allowed) {
        char why[128];
        snprintf(why, sizeof why, "model \"%s\" has one unshifted highlight; remove \"shift\"", model_name);
        r = ht_json_forbid(c, obj, key, "shift", why);
    }
    if (r == HT_OK) r = ht_json_number(c, obj, key, "shift", &(double){ 0 }, HT_JRANGE(-HT_LIMIT_SHIFT, HT_LIMIT_SHIFT), &out->shift);
    return r;
}

static ht_result parse_diffuse(const ht_jctx *c, const cJSON *root, bool wrap_allowed,
                               const char *model_name, ht_shading *out) {
    static const char *const keys[] = { "color", "wrap", NULL };
    const cJSON *obj;
    ht_result r = ht_json_object(c, root, "", "diffuse", true, &obj);
    if (r == HT_OK) r = ht_json_keys(c, obj, "diffuse", keys);
    if (r == HT_OK) r = ht_json_vec(c, obj, "diffuse", "color", NULL, 3, COLOR_RANGE, out->diffuse_color);
    if (r == HT_OK && !wrap_allowed) {
        char why[128];
        snprintf(why, sizeof why, "model \"%s\" uses sin(T,L) diffuse, which has no wrap; remove \"wrap\"",
                 model_name);
        r = ht_json_forbid(c, obj, "diffuse", "wrap", why);
    }
    if (r == HT_OK) r = ht_json_number(c, obj, "diffuse", "wrap", &(double){ 0.25 }, HT_JRANGE(0, 1), &out->wrap);
    return r;
}

/* dir of `file_name` + rel, unless rel is absolute or there is no dir. */
/* "transmission" (Scheuermann only, optional; model.h's ht_transmission):
   "color" required, "centre", "sharpness", "azimuth" default 0. Absent:
   no lobe. The ranges are ht_shading_check's, run by the material check. */
static ht_result parse_transmission(const ht_jctx *c, const cJSON *root, ht_transmission *out) {
    static const char *const keys[] = { "color", "centre", "sharpness", "azimuth", NULL };
    const cJSON *obj = NULL;
    ht_result r = ht_json_object(c, root, "", "transmission", false, &obj);
    if (r != HT_OK || !obj) return r;
    r = ht_json_keys(c, obj, "transmission", keys);
    if (r == HT_OK)
        r = ht_json_vec(c, obj, "transmission", "color", NULL, 3, HT_JRANGE(0, HT_LIMIT_TRANSMISSION), out->color);
    if (r == HT_OK) r = ht_json_number(c, obj, "transmission", "centre", &(double){ 0 }, HT_JRANGE(-1, 1), &out->centre);
    if (r == HT_OK)
        r = ht_json_number(c, obj, "transmission", "sharpness", &(double){ 0 }, HT_JRANGE(0, HT_LIMIT_EXPONENT),
                           &out->sharpness);
    if (r == HT_OK)
        r = ht_json_number(c, obj, "transmission", "azimuth", &(double){ 0 }, HT_JRANGE(0, HT_LIMIT_EXPONENT),
                           &out->azimuth);
    return r;
}

static ht_result resolve_path(const ht_jctx *c, const char *field, const char *file_name,
                              const char *rel, char out[1024]) {
    size_t dir_len = 0;
    if (rel[0] != '/' && file_name) {
        const char *slash = strrchr(file_name, '/');
        if (slash) dir_len = (size_t)(slash - file_name) + 1;
    }
    int n = snprintf(out, 1024, "%.*s%s", (int)dir_len, file_name ? file_name : "", rel);
    if (n < 0 || n >= 1024) return ht_json_fail(c, field, "path longer than 1023 bytes once resolved");
    return HT_OK;
}

static ht_result parse_texture(const ht_jctx *c, const cJSON *obj, const char *path,
                               ht_texture_slot slot, const char *file_name,
                               ht_texture_source *out) {
    static const char *const keys[] = { "procedural", "file", "size", "seed", NULL };
    ht_result r = ht_json_keys(c, obj, path, keys);
    if (r != HT_OK) return r;
    bool procedural = cJSON_HasObjectItem(obj, "procedural");
    bool file = cJSON_HasObjectItem(obj, "file");
    if (procedural && file)
        return ht_json_fail(c, path, "has both \"procedural\" and \"file\"; give one");
    if (!procedural && !file)
        return ht_json_fail(c, path, "needs \"procedural\": \"%s\" or \"file\": \"PATH\"",
                            slot_generators[slot]);
    memset(out, 0, sizeof *out);
    if (file) {
        r = ht_json_forbid(c, obj, path, "size", "only procedural textures take a size; a file has its own");
        if (r == HT_OK) r = ht_json_forbid(c, obj, path, "seed", "only procedural textures take a seed");
        char rel[1024], field[HT_JSON_PATH_MAX];
        if (r == HT_OK) r = ht_json_string(c, obj, path, "file", NULL, rel, sizeof rel);
        ht_json_path_key(field, path, "file");
        if (r == HT_OK) r = resolve_path(c, field, file_name, rel, out->path);
        out->origin = HT_TEXTURE_FILE;
        return r;
    }
    const char *const generator[] = { slot_generators[slot], NULL };
    int which;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, "procedural");
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(obj, "procedural");
    if (cJSON_IsString(g) && strcmp(g->valuestring, generator[0]) != 0) {
        for (int s = 0; s < HT_TEX_COUNT; s++)
            if (strcmp(g->valuestring, slot_generators[s]) == 0)
                return ht_json_fail(c, field, "\"%s\" makes %s textures; the %s slot takes \"%s\"",
                                    slot_generators[s], slot_names[s], slot_names[slot], generator[0]);
    }
    r = ht_json_enum(c, obj, path, "procedural", -1, generator, &which);
    if (r != HT_OK) return r;
    int64_t size, seed;
    r = ht_json_int(c, obj, path, "size", &(int64_t){ 256 }, 16, 2048, &size);
    if (r != HT_OK) return r;
    if (size & (size - 1)) {
        ht_json_path_key(field, path, "size");
        return ht_json_fail(c, field, "must be a power of two (16, 32, ..., 2048), got %lld", (long long)size);
    }
    r = ht_json_int(c, obj, path, "seed", &(int64_t){ 1 }, 0, UINT32_MAX, &seed);
    if (r != HT_OK) return r;
    out->origin = HT_TEXTURE_PROCEDURAL;
    snprintf(out->procedural, sizeof out->procedural, "%s", generator[0]);
    out->size = (int)size;
    out->seed = (uint32_t)seed;
    return HT_OK;
}

static ht_result parse_textures(const ht_jctx *c, const cJSON *root, bool kajiya_kay,
                                bool marschner, const char *file_name, ht_material *m) {
    const cJSON *obj;
    ht_result r = ht_json_object(c, root, "", "textures", false, &obj);
    if (r != HT_OK || !obj) return r;
    r = ht_json_keys(c, obj, "textures", slot_names);
    if (r != HT_OK) return r;
    if (marschner) {
        r = ht_json_forbid(c, obj, "textures", "shift",
                           "model \"marschner\" has no shifted tangent; its shifts are marschner.shift");
        if (r == HT_OK)
            r = ht_json_forbid(c, obj, "textures", "sparkle",
                               "model \"marschner\" has no secondary highlight to sparkle; remove the sparkle texture");
        if (r != HT_OK) return r;
    }
    if (kajiya_kay) {
        r = ht_json_forbid(c, obj, "textures", "shift",
                           "model \"kajiya-kay\" has one unshifted highlight; remove the shift texture");
        if (r == HT_OK)
            r = ht_json_forbid(c, obj, "textures", "sparkle",
                               "model \"kajiya-kay\" has no secondary highlight to sparkle; remove the sparkle texture");
        if (r != HT_OK) return r;
    }
    for (int s = 0; s < HT_TEX_COUNT; s++) {
        const cJSON *t;
        r = ht_json_object(c, obj, "textures", slot_names[s], false, &t);
        if (r != HT_OK) return r;
        if (!t) continue;
        char path[HT_JSON_PATH_MAX];
        ht_json_path_key(path, "textures", slot_names[s]);
        r = parse_texture(c, t, path, (ht_texture_slot)s, file_name, &m->textures[s]);
        if (r != HT_OK) return r;
    }
    return HT_OK;
}

static ht_result parse_alpha(const ht_jctx *c, const cJSON *root, ht_material *m) {
    static const char *const keys[] = { "opaque_cutoff", NULL };
    const cJSON *obj;
    m->opaque_cutoff = 0.98;
    ht_result r = ht_json_object(c, root, "", "alpha", false, &obj);
    if (r != HT_OK || !obj) return r;
    r = ht_json_keys(c, obj, "alpha", keys);
    if (r == HT_OK)
        r = ht_json_number(c, obj, "alpha", "opaque_cutoff", &(double){ 0.98 },
                           HT_JRANGE_LO_OPEN(0, 1), &m->opaque_cutoff);
    return r;
}

static ht_result parse_material(const ht_jctx *c, const cJSON *root, const char *file_name,
                                ht_material *m) {
    static const char *const keys[] = {
        "format", "name", "model", "diffuse", "primary", "secondary", "transmission", "marschner", "textures", "alpha",
        NULL,
    };
    static const char *const models[] = { "scheuermann", "kajiya-kay", "marschner", NULL };
    /* The format first: a scene file handed over by mistake should say so,
       not complain about its keys. */
    ht_result r = ht_json_format(c, root, MATERIAL_FORMAT, "material file");
    if (r == HT_OK) r = ht_json_keys(c, root, "", keys);
    if (r == HT_OK) r = parse_name(c, root, m->name);
    int model = 0;
    if (r == HT_OK) r = ht_json_enum(c, root, "", "model", -1, models, &model);
    if (r != HT_OK) return r;
    bool kk = model == 1, marschner = model == 2;
    m->shading.model = kk ? HT_MODEL_KAJIYA_KAY : (marschner ? HT_MODEL_MARSCHNER : HT_MODEL_SCHEUERMANN);
    r = parse_diffuse(c, root, !kk && !marschner, models[model], &m->shading);
    if (r == HT_OK && model != 0)
        r = ht_json_forbid(c, root, "", "transmission", "only model \"scheuermann\" has a transmission lobe");
    if (r == HT_OK && marschner) {
        r = ht_json_forbid(c, root, "", "primary",
                           "model \"marschner\" has no Scheuermann highlights; its lobes come from \"marschner\"");
        if (r == HT_OK)
            r = ht_json_forbid(c, root, "", "secondary",
                               "model \"marschner\" has no Scheuermann highlights; its lobes come from \"marschner\"");
        if (r == HT_OK) r = ht_material_parse_marschner(c, root, &m->shading.marschner);
        if (r == HT_OK) r = parse_textures(c, root, false, true, file_name, m);
        if (r == HT_OK) r = parse_alpha(c, root, m);
        return r;
    }
    if (r == HT_OK) {
        char why[96];
        snprintf(why, sizeof why, "only model \"marschner\" takes it; this material is \"%s\"", models[model]);
        r = ht_json_forbid(c, root, "", "marschner", why);
    }
    if (r == HT_OK && model == 0) r = parse_transmission(c, root, &m->shading.transmission);
    if (r == HT_OK) r = parse_lobe(c, root, "primary", !kk, models[model], &m->shading.primary);
    if (r == HT_OK) {
        if (kk)
            r = ht_json_forbid(c, root, "", "secondary",
                               "model \"kajiya-kay\" has one highlight; remove \"secondary\" or use \"scheuermann\"");
        else
            r = parse_lobe(c, root, "secondary", true, models[model], &m->shading.secondary);
    }
    if (r == HT_OK) r = parse_textures(c, root, kk, false, file_name, m);
    if (r == HT_OK) r = parse_alpha(c, root, m);
    return r;
}

ht_result ht_material_parse(const char *json_text, const char *file_name,
                            ht_material *out, char *err, size_t err_size) {
    ht_jctx c = { file_name ? file_name : "<input>", err, err_size };
    cJSON *root;
    ht_result r = ht_json_parse_entry(&c, json_text, out, &root);
    if (r != HT_OK) return r;
    /* Built aside so a failed parse leaves *out untouched. */
    ht_material *m = calloc(1, sizeof *m);
    if (!m) {
        cJSON_Delete(root);
        ht_set_error(err, err_size, "%s: out of memory", c.file);
        return HT_ERR_OUT_OF_MEMORY;
    }
    r = parse_material(&c, root, file_name, m);
    cJSON_Delete(root);
    if (file_name) snprintf(m->file, sizeof m->file, "%s", file_name);
    if (r == HT_OK) {
        *out = *m;
        if (err && err_size) err[0] = '\0';
    }
    free(m);
    return r;
}

ht_result ht_material_load(const char *path, ht_material *out, char *err, size_t err_size) {
    char *text;
    ht_result r = ht_json_load_entry(path, out, &text, err, err_size);
    if (r != HT_OK) return r;
    r = ht_material_parse(text, path, out, err, err_size);
    free(text);
    return r;
}

/* ---- a material built in memory ---- */

typedef struct check_ctx {
    const char *file;
    char *err;
    size_t err_size;
} check_ctx;

static ht_result check_fail(const check_ctx *c, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static ht_result check_fail(const check_ctx *c, const char *field, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    ht_set_field_error_v(c->err, c->err_size, c->file, field, fmt, ap);
    va_end(ap);
    return HT_ERR_INVALID_ARGUMENT;
}

ht_result ht_material_check(const ht_material *m, char *err, size_t err_size) {
    check_ctx c = { "<material>", err, err_size };
    if (!m) return check_fail(&c, "material", "required");
    if (m->file[0] && memchr(m->file, '\0', sizeof m->file)) c.file = m->file;
    if (!memchr(m->name, '\0', sizeof m->name)) return check_fail(&c, "name", "not NUL-terminated");
    if (!m->name[0]) return check_fail(&c, "name", "empty");
    for (const char *p = m->name; *p; p++) {
        char ch = *p;
        if (!((ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') ||
              ch == '_' || ch == '-'))
            return check_fail(&c, "name", "character %ld is '%c'; names use only A-Z a-z 0-9 _ -",
                              (long)(p - m->name) + 1, ch >= 0x20 && ch < 0x7f ? ch : '?');
    }
    const ht_shading *s = &m->shading;
    if (s->model != HT_MODEL_SCHEUERMANN && s->model != HT_MODEL_KAJIYA_KAY && s->model != HT_MODEL_MARSCHNER)
        return check_fail(&c, "model", "unknown model %d", (int)s->model);
    bool kk = s->model == HT_MODEL_KAJIYA_KAY, marschner = s->model == HT_MODEL_MARSCHNER;
    /* Marschner's constants are its own; its diffuse colour is checked as
       every shading's is. */
    ht_result r = HT_OK;
    if (marschner) {
        if (!ht_shading_check_color(s->diffuse_color, c.file, "diffuse", err, err_size)) r = HT_ERR_INVALID_ARGUMENT;
        if (r == HT_OK) r = ht_material_check_marschner(c.file, &s->marschner, err, err_size);
    } else if (!ht_shading_check(s, c.file, err, err_size)) {
        r = HT_ERR_INVALID_ARGUMENT;
    }
    if (r != HT_OK) return r;
    /* 0 means the default (0.98), as in ht_plan_make. */
    if (m->opaque_cutoff != 0.0 &&
        (!isfinite(m->opaque_cutoff) || m->opaque_cutoff <= 0.0 || m->opaque_cutoff > 1.0))
        return check_fail(&c, "alpha.opaque_cutoff", "must be 0 (default) or in (0, 1], got %.17g",
                          m->opaque_cutoff);
    for (int i = 0; i < HT_TEX_COUNT; i++) {
        const ht_texture_source *t = &m->textures[i];
        char field[64];
        snprintf(field, sizeof field, "textures.%s", slot_names[i]);
        if (t->origin == HT_TEXTURE_ABSENT) continue;
        if ((kk || marschner) && (i == HT_TEX_SHIFT || i == HT_TEX_SPARKLE))
            return check_fail(&c, field, "model \"%s\" has no %s texture", kk ? "kajiya-kay" : "marschner",
                              slot_names[i]);
        if (t->origin == HT_TEXTURE_FILE) {
            if (!memchr(t->path, '\0', sizeof t->path) || !t->path[0])
                return check_fail(&c, field, "file texture without a path");
        } else if (t->origin == HT_TEXTURE_PROCEDURAL) {
            if (!memchr(t->procedural, '\0', sizeof t->procedural) ||
                strcmp(t->procedural, slot_generators[i]) != 0)
                return check_fail(&c, field, "the %s slot takes procedural \"%s\"", slot_names[i],
                                  slot_generators[i]);
            if (t->size < 16 || t->size > 2048 || (t->size & (t->size - 1)))
                return check_fail(&c, field, "size must be a power of two (16, 32, ..., 2048), got %d", t->size);
        } else {
            return check_fail(&c, field, "unknown origin %d", (int)t->origin);
        }
    }
    return HT_OK;
}

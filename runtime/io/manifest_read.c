/* manifest_read.c — reads DIR/manifest.json (docs/bundle.md) with
   json_check.h's checked getters; the keys are manifest.h's. The bundle's
   files come through bundle_source.h (a directory or memory). Only the
   documented fields are read; anything else is ignored so newer generators
   can add information. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "manifest.h"
#include "bundle_source.h"
#include "json_check.h"
#include "caps.h"
#include "errfmt.h"

/* Field access goes through json_check.h's getters, so a manifest's
   messages read like every other format's. */
#define K(name) HT_MANIFEST_KEY_##name

/* Only this generator's bundles: another version's files may hold other
   programs (a hairgen 2 bundle's fixed tier draws differently) or another
   layout, so it is refused before any other field is read. */
static ht_result check_generator(const ht_jctx *c, const cJSON *root) {
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(root, K(GENERATOR));
    if (cJSON_IsString(g) && strcmp(g->valuestring, HT_MANIFEST_GENERATOR) == 0) return HT_OK;
    char got[64];
    if (cJSON_IsString(g))
        snprintf(got, sizeof got, "\"%.40s%s\"", g->valuestring, strlen(g->valuestring) > 40 ? "..." : "");
    else snprintf(got, sizeof got, "%s", g ? "not a string" : "missing");
    return ht_json_fail(c, K(GENERATOR), "%s, this runtime reads " HT_MANIFEST_GENERATOR " bundles: regenerate with "
                        HT_MANIFEST_GENERATOR, got);
}

/* A file name must stay inside the bundle directory. */
static ht_result check_file_name(const ht_jctx *c, const char *field, const char *name) {
    if (!name[0]) return ht_json_fail(c, field, "empty file name");
    if (strchr(name, '/') || strchr(name, '\\') || strcmp(name, ".") == 0 || strcmp(name, "..") == 0)
        return ht_json_fail(c, field, "\"%s\" is not a plain file name inside the bundle", name);
    return HT_OK;
}

static ht_result parse_textures(const ht_jctx *c, const cJSON *obj, const char *parent,
                                ht_manifest_texture *out, int *count) {
    *count = 0;
    if (!obj || cJSON_IsNull(obj)) return HT_OK;
    if (!cJSON_IsObject(obj)) return ht_json_fail(c, parent, "expected an object");
    const cJSON *t;
    cJSON_ArrayForEach(t, obj) {
        char field[HT_JSON_PATH_MAX];
        ht_json_path_key(field, parent, t->string);
        if (*count >= HT_MANIFEST_MAX_TEXTURES) return ht_json_fail(c, field, "more than %d textures", HT_MANIFEST_MAX_TEXTURES);
        if (!cJSON_IsObject(t)) return ht_json_fail(c, field, "expected an object");
        ht_manifest_texture *tex = &out[*count];
        if (strlen(t->string) >= sizeof tex->name) return ht_json_fail(c, field, "texture name too long");
        /* JSON parsers keep duplicate keys; which one wins would be arbitrary. */
        for (int k = 0; k < *count; k++)
            if (strcmp(out[k].name, t->string) == 0) return ht_json_fail(c, field, "listed twice");
        snprintf(tex->name, sizeof tex->name, "%s", t->string);
        ht_result r;
        char file_field[HT_JSON_PATH_MAX];
        ht_json_path_key(file_field, field, K(FILE));
        if ((r = ht_json_string(c, t, field, K(FILE), NULL, tex->file, sizeof tex->file)) != HT_OK ||
            (r = check_file_name(c, file_field, tex->file)) != HT_OK ||
            (r = ht_json_int32(c, t, field, K(WIDTH), NULL, 1, HT_MANIFEST_MAX_TEXTURE_SIZE, &tex->width)) != HT_OK ||
            (r = ht_json_int32(c, t, field, K(HEIGHT), NULL, 1, HT_MANIFEST_MAX_TEXTURE_SIZE, &tex->height)) != HT_OK ||
            (r = ht_json_int32(c, t, field, K(DEPTH), &(int){ 1 }, 1, HT_MANIFEST_MAX_TEXTURE_DEPTH, &tex->depth)) != HT_OK)
            return r;
        (*count)++;
    }
    return HT_OK;
}

/* Exactly MAJOR.MINOR, one or two digits each: "2.1", "1.20"; not
   "2.1.9.9.9", "2.", " 2.1" or "2.1 beta". */
static bool plain_version(const char *t) {
    size_t a = strspn(t, "0123456789");
    if (a < 1 || a > 2 || t[a] != '.') return false;
    size_t b = strspn(t + a + 1, "0123456789");
    return b >= 1 && b <= 2 && t[a + 1 + b] == '\0';
}

static ht_result parse_version_field(const ht_jctx *c, const cJSON *req, const char *parent,
                                     const char *key, bool glsl, bool optional, int *major, int *minor) {
    char text[16], field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, parent, key);
    ht_result r = optional ? ht_json_string_or_null(c, req, parent, key, text, sizeof text)
                           : ht_json_string(c, req, parent, key, NULL, text, sizeof text);
    if (r != HT_OK) return r;
    *major = *minor = 0;
    if (!text[0]) {
        if (optional) return HT_OK;
        return ht_json_fail(c, field, "empty version");
    }
    if (!plain_version(text) || !ht_parse_version(text, glsl, major, minor))
        return ht_json_fail(c, field, "\"%s\" is not a version like \"%s\"", text, glsl ? "1.20" : "2.1");
    return HT_OK;
}

/* flip_mean and flip_p95: both or neither (NAN), each in [0, 1]. */
static ht_result parse_flip(const ht_jctx *c, const cJSON *m, const char *path, ht_manifest_measured *out) {
    bool has_mean = cJSON_GetObjectItemCaseSensitive(m, K(FLIP_MEAN)) != NULL;
    bool has_p95 = cJSON_GetObjectItemCaseSensitive(m, K(FLIP_P95)) != NULL;
    const double *absent = has_mean || has_p95 ? NULL : &(double){ NAN };
    ht_result r = ht_json_number(c, m, path, K(FLIP_MEAN), absent, HT_JRANGE(0, 1), &out->flip_mean);
    if (r == HT_OK) r = ht_json_number(c, m, path, K(FLIP_P95), absent, HT_JRANGE(0, 1), &out->flip_p95);
    return r;
}

/* The optional per-tier "measured" and "measured_device" objects (manifest.h). */
static ht_result parse_measured(const ht_jctx *c, const cJSON *t, const char *base, const char *key,
                                ht_manifest_measured *out) {
    static const char *const known[] = { K(PSNR_DB), K(SSIM), K(DELTA_E00_MEAN), K(DELTA_E00_P95), K(COST_RATIO),
                                         K(FLIP_MEAN), K(FLIP_P95), K(SCENE), K(DRIVER), NULL };
    char path[HT_JSON_PATH_MAX];
    ht_json_path_key(path, base, key);
    const cJSON *m;
    ht_result r = ht_json_object(c, t, base, key, false, &m);
    if (r != HT_OK || !m) return r;
    if ((r = ht_json_keys(c, m, path, known)) != HT_OK) return r;
    out->present = true;
    const cJSON *psnr = cJSON_GetObjectItemCaseSensitive(m, K(PSNR_DB));
    if (cJSON_IsNull(psnr)) {
        out->psnr_db = INFINITY;
    } else if ((r = ht_json_number(c, m, path, K(PSNR_DB), NULL, HT_JRANGE(0, HT_MANIFEST_MAX_PSNR_DB),
                                   &out->psnr_db)) != HT_OK) {
        return r;
    }
    if ((r = ht_json_number(c, m, path, K(SSIM), NULL, HT_JRANGE(-1, 1), &out->ssim)) != HT_OK ||
        (r = ht_json_number(c, m, path, K(DELTA_E00_MEAN), NULL, HT_JRANGE(0, HT_MANIFEST_MAX_DELTA_E),
                            &out->delta_e00_mean)) != HT_OK ||
        (r = ht_json_number(c, m, path, K(DELTA_E00_P95), NULL, HT_JRANGE(0, HT_MANIFEST_MAX_DELTA_E),
                            &out->delta_e00_p95)) != HT_OK ||
        (r = ht_json_number(c, m, path, K(COST_RATIO), NULL, HT_JRANGE_LO_OPEN(0, HT_MANIFEST_MAX_COST_RATIO),
                            &out->cost_ratio)) != HT_OK ||
        (r = parse_flip(c, m, path, out)) != HT_OK ||
        (r = ht_json_string_or_null(c, m, path, K(SCENE), out->scene, sizeof out->scene)) != HT_OK ||
        (r = ht_json_string_or_null(c, m, path, K(DRIVER), out->driver, sizeof out->driver)) != HT_OK)
        return r;
    return HT_OK;
}

/* A string field that must be one of the given words (NULL-terminated). */
static ht_result parse_word(const ht_jctx *c, const cJSON *obj, const char *parent, const char *key,
                            const char *const *words, int *which) {
    char text[16], field[HT_JSON_PATH_MAX];
    ht_result r = ht_json_string(c, obj, parent, key, NULL, text, sizeof text);
    if (r != HT_OK) return r;
    for (int i = 0; words[i]; i++)
        if (strcmp(text, words[i]) == 0) {
            *which = i;
            return HT_OK;
        }
    ht_json_path_key(field, parent, key);
    return ht_json_fail(c, field, "\"%s\" is not \"%s\"%s%s%s", text, words[0], words[1] ? " or \"" : "",
                        words[1] ? words[1] : "", words[1] ? "\"" : "");
}

/* The optional "es" list: each entry a GL ES target of the tier, its two
   texts plain names inside the bundle. */
static ht_result parse_es(const ht_jctx *c, const cJSON *t, const char *base, ht_manifest_tier *out) {
    static const char *const api[] = { HT_MANIFEST_API_GLES, NULL };
    static const char *const precision[] = { HT_MANIFEST_PRECISION_HIGHP, HT_MANIFEST_PRECISION_MEDIUMP, NULL };
    static const char *const known[] = { K(API), K(ES_VERSION), K(ESSL), K(PRECISION), K(VERTEX), K(FRAGMENT), NULL };
    char path[HT_JSON_PATH_MAX], field[HT_JSON_PATH_MAX], ff[HT_JSON_PATH_MAX];
    ht_json_path_key(path, base, K(ES));
    const cJSON *list;
    int items;
    ht_result r = ht_json_array(c, t, base, K(ES), false, 1, HT_MANIFEST_MAX_ES, &list, &items);
    if (r != HT_OK || !list) return r;
    for (const cJSON *e = list->child; e; e = e->next) {
        ht_json_path_index(field, path, out->es_count);
        if (!cJSON_IsObject(e)) return ht_json_fail(c, field, "expected an object");
        ht_manifest_es *es = &out->es[out->es_count];
        int which = 0, prec = 0;
        if ((r = ht_json_keys(c, e, field, known)) != HT_OK ||
            (r = parse_word(c, e, field, K(API), api, &which)) != HT_OK ||
            (r = parse_version_field(c, e, field, K(ES_VERSION), false, false, &es->es_major, &es->es_minor)) != HT_OK ||
            (r = parse_version_field(c, e, field, K(ESSL), true, false, &es->essl_major, &es->essl_minor)) != HT_OK ||
            (r = parse_word(c, e, field, K(PRECISION), precision, &prec)) != HT_OK ||
            (r = ht_json_string(c, e, field, K(VERTEX), NULL, es->vertex, sizeof es->vertex)) != HT_OK ||
            (r = check_file_name(c, (ht_json_path_key(ff, field, K(VERTEX)), ff), es->vertex)) != HT_OK ||
            (r = ht_json_string(c, e, field, K(FRAGMENT), NULL, es->fragment, sizeof es->fragment)) != HT_OK ||
            (r = check_file_name(c, (ht_json_path_key(ff, field, K(FRAGMENT)), ff), es->fragment)) != HT_OK)
            return r;
        /* ESSL 1.00 reads as {1, 0}: the GLSL rule's two-digit minor. */
        if (!((es->es_major == 2 && es->es_minor == 0 && es->essl_major == 1 && es->essl_minor == 0) ||
              (es->es_major == 3 && es->es_minor == 0 && es->essl_major == 3 && es->essl_minor == 0))) {
            ht_json_path_key(ff, field, K(ESSL));
            return ht_json_fail(c, ff, "ES %d.%d with ESSL %d.%02d: expected ES 2.0 with \"1.00\" or ES 3.0 with \"3.00\"",
                                es->es_major, es->es_minor, es->essl_major, es->essl_minor);
        }
        es->mediump = prec == 1;
        out->es_count++;
    }
    return HT_OK;
}

static ht_result parse_tier(const ht_jctx *c, const cJSON *t, int index, ht_manifest_tier *out) {
    char base[64], field[HT_JSON_PATH_MAX];
    snprintf(base, sizeof base, K(TIERS) "[%d]", index);
    memset(out, 0, sizeof *out);
    if (!cJSON_IsObject(t)) return ht_json_fail(c, base, "expected an object");
    ht_result r = ht_json_string(c, t, base, K(NAME), NULL, out->name, sizeof out->name);
    if (r != HT_OK) return r;
    out->tier = ht_tier_from_name(out->name);
    if (out->tier == HT_TIER_AUTO) {
        ht_json_path_key(field, base, K(NAME));
        return ht_json_fail(c, field, "\"auto\" is not a tier");
    }

    char req_path[HT_JSON_PATH_MAX];
    ht_json_path_key(req_path, base, K(REQUIRES));
    const cJSON *req, *ext;
    int ext_count;
    static const char *const desktop_api[] = { HT_MANIFEST_API_GL, NULL };
    int api = 0;
    if ((r = ht_json_object(c, t, base, K(REQUIRES), true, &req)) != HT_OK ||
        (r = parse_version_field(c, req, req_path, K(GL), false, false, &out->gl_major, &out->gl_minor)) != HT_OK ||
        (r = parse_version_field(c, req, req_path, K(GLSL), true, true, &out->glsl_major, &out->glsl_minor)) != HT_OK ||
        (r = ht_json_int32(c, req, req_path, K(TEXTURE_UNITS), &(int){ 0 }, 0, 64, &out->texture_units)) != HT_OK ||
        (r = ht_json_array(c, req, req_path, K(EXTENSIONS), false, 0, HT_MANIFEST_MAX_EXTENSIONS,
                           &ext, &ext_count)) != HT_OK ||
        (r = parse_word(c, req, req_path, K(API), desktop_api, &api)) != HT_OK)
        return r;
    ht_json_path_key(field, req_path, K(EXTENSIONS));
    for (const cJSON *e = ext ? ext->child : NULL; e; e = e->next) {
        char ef[HT_JSON_PATH_MAX];
        ht_json_path_index(ef, field, out->extension_count);
        if (!cJSON_IsString(e) || !e->valuestring[0] || strchr(e->valuestring, ' ') ||
            strlen(e->valuestring) >= sizeof out->extensions[0])
            return ht_json_fail(c, ef, "expected an extension name like \"GL_ARB_multitexture\"");
        snprintf(out->extensions[out->extension_count++], sizeof out->extensions[0], "%s", e->valuestring);
    }

    char files_path[HT_JSON_PATH_MAX];
    ht_json_path_key(files_path, base, K(FILES));
    const cJSON *files;
    if ((r = ht_json_object(c, t, base, K(FILES), true, &files)) != HT_OK) return r;
    const cJSON *f;
    cJSON_ArrayForEach(f, files) {
        ht_json_path_key(field, files_path, f->string);
        if (out->file_count >= HT_MANIFEST_MAX_FILES) return ht_json_fail(c, field, "more than %d files", HT_MANIFEST_MAX_FILES);
        ht_manifest_file *bf = &out->files[out->file_count];
        if (strlen(f->string) >= sizeof bf->role) return ht_json_fail(c, field, "role name too long");
        if (ht_manifest_tier_file(out, f->string)) return ht_json_fail(c, field, "listed twice");
        snprintf(bf->role, sizeof bf->role, "%s", f->string);
        if ((r = ht_json_string(c, files, files_path, f->string, NULL, bf->file, sizeof bf->file)) != HT_OK ||
            (r = check_file_name(c, field, bf->file)) != HT_OK)
            return r;
        out->file_count++;
    }

    char tex_path[HT_JSON_PATH_MAX];
    ht_json_path_key(tex_path, base, K(TEXTURES));
    if ((r = parse_textures(c, cJSON_GetObjectItemCaseSensitive(t, K(TEXTURES)), tex_path,
                            out->textures, &out->texture_count)) != HT_OK)
        return r;

    char smp_path[HT_JSON_PATH_MAX];
    ht_json_path_key(smp_path, base, K(SAMPLERS));
    const cJSON *samplers;
    int sampler_items;
    if ((r = ht_json_array(c, t, base, K(SAMPLERS), false, 0, HT_MANIFEST_MAX_SAMPLERS,
                           &samplers, &sampler_items)) != HT_OK)
        return r;
    for (const cJSON *s = samplers ? samplers->child : NULL; s; s = s->next) {
        ht_json_path_index(field, smp_path, out->sampler_count);
        if (!cJSON_IsObject(s)) return ht_json_fail(c, field, "expected an object");
        ht_manifest_sampler *bs = &out->samplers[out->sampler_count];
        if ((r = ht_json_string(c, s, field, K(UNIFORM), NULL, bs->uniform, sizeof bs->uniform)) != HT_OK ||
            (r = ht_json_string(c, s, field, K(TEXTURE), NULL, bs->texture, sizeof bs->texture)) != HT_OK ||
            (r = ht_json_int32(c, s, field, K(UNIT), NULL, 0, 31, &bs->unit)) != HT_OK)
            return r;
        for (int k = 0; k < out->sampler_count; k++)
            if (strcmp(out->samplers[k].uniform, bs->uniform) == 0) {
                char uf[HT_JSON_PATH_MAX];
                ht_json_path_key(uf, field, K(UNIFORM));
                return ht_json_fail(c, uf, "\"%s\" already bound by %s[%d]", bs->uniform, smp_path, k);
            }
        for (int k = 0; k < out->sampler_count; k++)
            if (out->samplers[k].unit == bs->unit) {
                char uf[HT_JSON_PATH_MAX];
                ht_json_path_key(uf, field, K(UNIT));
                return ht_json_fail(c, uf, "unit %d already used by %s", bs->unit, out->samplers[k].uniform);
            }
        out->sampler_count++;
    }
    if ((r = parse_es(c, t, base, out)) != HT_OK) return r;
    if ((r = parse_measured(c, t, base, K(MEASURED), &out->measured)) != HT_OK) return r;
    return parse_measured(c, t, base, K(MEASURED_DEVICE), &out->measured_device);
}

ht_result ht_manifest_parse(const char *json_text, const char *dir, const char *file_name,
                          ht_manifest *out, char *err, size_t err_size) {
    ht_jctx c = { .file = file_name ? file_name : "manifest.json", .err = err, .err_size = err_size };
    if (!json_text || !out) return ht_json_fail(&c, "manifest", "no input");
    memset(out, 0, sizeof *out);
    /* Cut, the directory would name another one's files (defect D). */
    if (dir && strlen(dir) > HT_LIMIT_DIR_PATH)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%.200s...: bundle directory path is %zu bytes, "
                       "more than %d", dir, strlen(dir), HT_LIMIT_DIR_PATH);
    snprintf(out->dir, sizeof out->dir, "%s", dir ? dir : ".");

    /* Syntax errors say line and column, as every other format's do. */
    cJSON *root;
    ht_result r = ht_json_parse_root(&c, json_text, &root);
    if (r != HT_OK) return r;
    static const char *const light_names[] = { "directional", "point", NULL };
    const cJSON *lights, *tiers;
    int light_items, tier_items;
    if ((r = ht_json_format(&c, root, HT_MANIFEST_FORMAT, "bundle manifest")) != HT_OK ||
        (r = check_generator(&c, root)) != HT_OK ||
        (r = ht_json_string_or_null(&c, root, "", K(MATERIAL), out->material, sizeof out->material)) != HT_OK ||
        (r = ht_json_string_or_null(&c, root, "", K(MODEL), out->model, sizeof out->model)) != HT_OK ||
        (r = ht_json_float(&c, root, "", K(OPAQUE_CUTOFF), NULL, HT_JRANGE_LO_OPEN(0, 1), &out->opaque_cutoff)) != HT_OK ||
        (r = ht_json_array(&c, root, "", K(LIGHTS), true, 1, HT_MAX_LIGHTS, &lights, &light_items)) != HT_OK)
        goto done;
    for (const cJSON *l = lights->child; l; l = l->next) {
        char field[HT_JSON_PATH_MAX];
        ht_json_path_index(field, K(LIGHTS), out->light_count);
        int which = -1;
        for (int i = 0; cJSON_IsString(l) && light_names[i]; i++)
            if (strcmp(l->valuestring, light_names[i]) == 0) which = i;
        if (which < 0) { r = ht_json_fail(&c, field, "expected \"directional\" or \"point\""); goto done; }
        out->lights[out->light_count++] = which == 1 ? HT_LIGHT_POINT : HT_LIGHT_DIRECTIONAL;
    }

    if ((r = parse_textures(&c, cJSON_GetObjectItemCaseSensitive(root, K(TEXTURES)), K(TEXTURES),
                            out->textures, &out->texture_count)) != HT_OK ||
        (r = ht_json_array(&c, root, "", K(TIERS), true, 1, HT_MANIFEST_MAX_TIERS, &tiers, &tier_items)) != HT_OK ||
        (r = ht_manifest_parse_lods(&c, root, &out->lods)) != HT_OK)
        goto done;
    for (const cJSON *t = tiers->child; t; t = t->next) {
        if ((r = parse_tier(&c, t, out->tier_count, &out->tiers[out->tier_count])) != HT_OK) goto done;
        /* A second entry of a tier would never be selected by name and
           would shadow the first for ht_manifest_find_tier. */
        for (int k = 0; k < out->tier_count; k++)
            if (strcmp(out->tiers[k].name, out->tiers[out->tier_count].name) == 0) {
                char field[48];
                snprintf(field, sizeof field, K(TIERS) "[%d]." K(NAME), out->tier_count);
                r = ht_json_fail(&c, field, "\"%s\" already listed as tiers[%d]", out->tiers[k].name, k);
                goto done;
            }
        out->tier_count++;
    }

    /* Samplers must name a texture the bundle lists. */
    for (int i = 0; i < out->tier_count; i++) {
        const ht_manifest_tier *bt = &out->tiers[i];
        for (int s = 0; s < bt->sampler_count; s++)
            if (!ht_manifest_find_texture(out, bt, bt->samplers[s].texture)) {
                char field[96];
                snprintf(field, sizeof field, K(TIERS) "[%d]." K(SAMPLERS) "[%d]." K(TEXTURE), i, s);
                r = ht_json_fail(&c, field, "\"%s\" is not listed in textures", bt->samplers[s].texture);
                goto done;
            }
    }
done:
    cJSON_Delete(root);
    return r;
}

/* manifest.json from the source, parsed; on success out reads its other
   files from the same source. */
static ht_result load(ht_bundle_source src, ht_manifest *out, char *err, size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    if (strlen(src.label) > HT_LIMIT_DIR_PATH || !ht_bundle_path(src, HT_MANIFEST_FILE, path, sizeof path)) {
        snprintf(err, err_size, "%.200s...: bundle directory path is %zu bytes, more than %d", src.label,
                 strlen(src.label), HT_LIMIT_DIR_PATH);
        return HT_ERR_INVALID_ARGUMENT;
    }
    char *text;
    ht_result r = ht_bundle_read_json(src, HT_MANIFEST_FILE, &text, err, err_size);
    if (r != HT_OK) return HT_ERR_IO;
    r = ht_manifest_parse(text, src.label, path, out, err, err_size);
    free(text);
    out->memory = src.memory;
    return r;
}

ht_result ht_manifest_load(const char *dir, ht_manifest *out, char *err, size_t err_size) {
    if (!dir || !dir[0] || !out) {
        snprintf(err, err_size, "bundle: bundle_dir: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    return load((ht_bundle_source){ .label = dir }, out, err, err_size);
}

ht_result ht_manifest_load_memory(const ht_bundle_memory *m, ht_manifest *out, char *err, size_t err_size) {
    if (!out) {
        snprintf(err, err_size, "bundle: bundle_memory: no output");
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_result r = ht_bundle_memory_check(m, err, err_size);
    if (r != HT_OK) return r;
    return load((ht_bundle_source){ .label = ht_bundle_memory_label(m), .memory = m }, out, err, err_size);
}

const ht_manifest_tier *ht_manifest_find_tier(const ht_manifest *b, ht_tier tier) {
    for (int i = 0; b && i < b->tier_count; i++)
        if (b->tiers[i].tier == tier) return &b->tiers[i];
    return NULL;
}

const char *ht_manifest_tier_file(const ht_manifest_tier *t, const char *role) {
    for (int i = 0; t && role && i < t->file_count; i++)
        if (strcmp(t->files[i].role, role) == 0) return t->files[i].file;
    return NULL;
}

const ht_manifest_texture *ht_manifest_find_texture(const ht_manifest *b, const ht_manifest_tier *t,
                                                const char *name) {
    for (int i = 0; t && name && i < t->texture_count; i++)
        if (strcmp(t->textures[i].name, name) == 0) return &t->textures[i];
    for (int i = 0; b && name && i < b->texture_count; i++)
        if (strcmp(b->textures[i].name, name) == 0) return &b->textures[i];
    return NULL;
}

ht_bundle_source ht_manifest_source(const ht_manifest *b) {
    return (ht_bundle_source){ .label = b->dir, .memory = b->memory };
}

bool ht_manifest_path(const ht_manifest *b, const char *file, char *out, size_t out_size) {
    return ht_bundle_path(ht_manifest_source(b), file, out, out_size);
}

/* A role the tier does not list: one line naming the manifest. */
static bool role_listed(const ht_manifest *b, const char *file, char *err, size_t err_size) {
    if (!file) snprintf(err, err_size, "%s/" HT_MANIFEST_FILE ": " K(FILES) ": role missing", b->dir);
    return file != NULL;
}

char *ht_manifest_read_text(const ht_manifest *b, const char *file, char *err, size_t err_size) {
    char *text = NULL;
    if (role_listed(b, file, err, err_size)) ht_bundle_read_json(ht_manifest_source(b), file, &text, err, err_size);
    return text;
}

char *ht_manifest_read_shader(const ht_manifest *b, const char *file, char *err, size_t err_size) {
    return role_listed(b, file, err, err_size) ? ht_bundle_read_shader(ht_manifest_source(b), file, err, err_size)
                                               : NULL;
}

ht_result ht_manifest_read_texture(const ht_manifest *b, const ht_manifest_texture *t, ht_image *img, char *path,
                                   size_t path_size, char *err, size_t err_size) {
    return ht_bundle_read_png(ht_manifest_source(b), t->file, t->width, t->height, img, path, path_size, err,
                              err_size);
}

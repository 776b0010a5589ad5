/* manifest_read.c — reads DIR/manifest.json (docs/bundle.md) with cJSON. Only the
   documented fields are read; anything else is ignored so newer generators
   can add information. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "manifest.h"
#include "json_check.h"
#include "caps.h"
#include "errfmt.h"

/* A string field copied into out; absent is an error unless optional. */
static ht_result get_string(const ht_jctx *c, const cJSON *obj, const char *parent, const char *key,
                            bool optional, char *out, size_t out_size) {
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, parent, key);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v || cJSON_IsNull(v)) {
        if (optional) { out[0] = '\0'; return HT_OK; }
        return ht_json_fail(c, field, "missing");
    }
    if (!cJSON_IsString(v)) return ht_json_fail(c, field, "expected a string");
    if (strlen(v->valuestring) >= out_size)
        return ht_json_fail(c, field, "longer than %zu characters", out_size - 1);
    memcpy(out, v->valuestring, strlen(v->valuestring) + 1);
    return HT_OK;
}

static ht_result get_int(const ht_jctx *c, const cJSON *obj, const char *parent, const char *key,
                         int def, int lo, int hi, int *out) {
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, parent, key);
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) {
        if (def < lo) return ht_json_fail(c, field, "missing");
        *out = def;
        return HT_OK;
    }
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble) || v->valuedouble != floor(v->valuedouble))
        return ht_json_fail(c, field, "expected an integer");
    if (v->valuedouble < lo || v->valuedouble > hi)
        return ht_json_fail(c, field, "%g outside [%d, %d]", v->valuedouble, lo, hi);
    *out = (int)v->valuedouble;
    return HT_OK;
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
        ht_json_path_key(file_field, field, "file");
        if ((r = get_string(c, t, field, "file", false, tex->file, sizeof tex->file)) != HT_OK ||
            (r = check_file_name(c, file_field, tex->file)) != HT_OK ||
            (r = get_int(c, t, field, "width", 0, 1, HT_MANIFEST_MAX_TEXTURE_SIZE, &tex->width)) != HT_OK ||
            (r = get_int(c, t, field, "height", 0, 1, HT_MANIFEST_MAX_TEXTURE_SIZE, &tex->height)) != HT_OK ||
            (r = get_int(c, t, field, "depth", 1, 1, HT_MANIFEST_MAX_TEXTURE_DEPTH, &tex->depth)) != HT_OK)
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
    ht_result r = get_string(c, req, parent, key, optional, text, sizeof text);
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

static ht_result parse_tier(const ht_jctx *c, const cJSON *t, int index, ht_manifest_tier *out) {
    char base[64], field[HT_JSON_PATH_MAX];
    snprintf(base, sizeof base, "tiers[%d]", index);
    memset(out, 0, sizeof *out);
    if (!cJSON_IsObject(t)) return ht_json_fail(c, base, "expected an object");
    ht_result r = get_string(c, t, base, "name", false, out->name, sizeof out->name);
    if (r != HT_OK) return r;
    out->tier = ht_tier_from_name(out->name);
    if (out->tier == HT_TIER_AUTO) {
        ht_json_path_key(field, base, "name");
        return ht_json_fail(c, field, "\"auto\" is not a tier");
    }

    char req_path[HT_JSON_PATH_MAX];
    ht_json_path_key(req_path, base, "requires");
    const cJSON *req = cJSON_GetObjectItemCaseSensitive(t, "requires");
    if (!cJSON_IsObject(req)) return ht_json_fail(c, req_path, req ? "expected an object" : "missing");
    if ((r = parse_version_field(c, req, req_path, "gl", false, false, &out->gl_major, &out->gl_minor)) != HT_OK ||
        (r = parse_version_field(c, req, req_path, "glsl", true, true, &out->glsl_major, &out->glsl_minor)) != HT_OK ||
        (r = get_int(c, req, req_path, "texture_units", 0, 0, 64, &out->texture_units)) != HT_OK)
        return r;
    const cJSON *ext = cJSON_GetObjectItemCaseSensitive(req, "extensions");
    ht_json_path_key(field, req_path, "extensions");
    if (ext && !cJSON_IsNull(ext)) {
        if (!cJSON_IsArray(ext)) return ht_json_fail(c, field, "expected an array of strings");
        const cJSON *e;
        cJSON_ArrayForEach(e, ext) {
            char ef[HT_JSON_PATH_MAX];
            ht_json_path_index(ef, field, out->extension_count);
            if (out->extension_count >= HT_MANIFEST_MAX_EXTENSIONS)
                return ht_json_fail(c, ef, "more than %d extensions", HT_MANIFEST_MAX_EXTENSIONS);
            if (!cJSON_IsString(e) || !e->valuestring[0] || strchr(e->valuestring, ' ') ||
                strlen(e->valuestring) >= sizeof out->extensions[0])
                return ht_json_fail(c, ef, "expected an extension name like \"GL_ARB_multitexture\"");
            snprintf(out->extensions[out->extension_count++], sizeof out->extensions[0], "%s", e->valuestring);
        }
    }

    char files_path[HT_JSON_PATH_MAX];
    ht_json_path_key(files_path, base, "files");
    const cJSON *files = cJSON_GetObjectItemCaseSensitive(t, "files");
    if (!cJSON_IsObject(files)) return ht_json_fail(c, files_path, files ? "expected an object" : "missing");
    const cJSON *f;
    cJSON_ArrayForEach(f, files) {
        ht_json_path_key(field, files_path, f->string);
        if (out->file_count >= HT_MANIFEST_MAX_FILES) return ht_json_fail(c, field, "more than %d files", HT_MANIFEST_MAX_FILES);
        ht_manifest_file *bf = &out->files[out->file_count];
        if (strlen(f->string) >= sizeof bf->role) return ht_json_fail(c, field, "role name too long");
        if (ht_manifest_tier_file(out, f->string)) return ht_json_fail(c, field, "listed twice");
        snprintf(bf->role, sizeof bf->role, "%s", f->string);
        if ((r = get_string(c, files, files_path, f->string, false, bf->file, sizeof bf->file)) != HT_OK ||
            (r = check_file_name(c, field, bf->file)) != HT_OK)
            return r;
        out->file_count++;
    }

    char tex_path[HT_JSON_PATH_MAX];
    ht_json_path_key(tex_path, base, "textures");
    if ((r = parse_textures(c, cJSON_GetObjectItemCaseSensitive(t, "textures"), tex_path,
                            out->textures, &out->texture_count)) != HT_OK)
        return r;

    char smp_path[HT_JSON_PATH_MAX];
    ht_json_path_key(smp_path, base, "samplers");
    const cJSON *samplers = cJSON_GetObjectItemCaseSensitive(t, "samplers");
    if (samplers && !cJSON_IsNull(samplers)) {
        if (!cJSON_IsArray(samplers)) return ht_json_fail(c, smp_path, "expected an array");
        const cJSON *s;
        cJSON_ArrayForEach(s, samplers) {
            ht_json_path_index(field, smp_path, out->sampler_count);
            if (out->sampler_count >= HT_MANIFEST_MAX_SAMPLERS)
                return ht_json_fail(c, field, "more than %d samplers", HT_MANIFEST_MAX_SAMPLERS);
            if (!cJSON_IsObject(s)) return ht_json_fail(c, field, "expected an object");
            ht_manifest_sampler *bs = &out->samplers[out->sampler_count];
            if ((r = get_string(c, s, field, "uniform", false, bs->uniform, sizeof bs->uniform)) != HT_OK ||
                (r = get_string(c, s, field, "texture", false, bs->texture, sizeof bs->texture)) != HT_OK ||
                (r = get_int(c, s, field, "unit", -1, 0, 31, &bs->unit)) != HT_OK)
                return r;
            for (int k = 0; k < out->sampler_count; k++)
                if (strcmp(out->samplers[k].uniform, bs->uniform) == 0) {
                    char uf[HT_JSON_PATH_MAX];
                    ht_json_path_key(uf, field, "uniform");
                    return ht_json_fail(c, uf, "\"%s\" already bound by %s[%d]", bs->uniform, smp_path, k);
                }
            for (int k = 0; k < out->sampler_count; k++)
                if (out->samplers[k].unit == bs->unit) {
                    char uf[HT_JSON_PATH_MAX];
                    ht_json_path_key(uf, field, "unit");
                    return ht_json_fail(c, uf, "unit %d already used by %s", bs->unit, out->samplers[k].uniform);
                }
            out->sampler_count++;
        }
    }
    return HT_OK;
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
    char format[32];
    if ((r = get_string(&c, root, "", "format", false, format, sizeof format)) != HT_OK) goto done;
    if (strcmp(format, HT_MANIFEST_FORMAT) != 0) {
        r = ht_json_fail(&c, "format", "\"%s\" is not \"%s\"", format, HT_MANIFEST_FORMAT);
        goto done;
    }
    if ((r = get_string(&c, root, "", "material", true, out->material, sizeof out->material)) != HT_OK ||
        (r = get_string(&c, root, "", "model", true, out->model, sizeof out->model)) != HT_OK)
        goto done;

    const cJSON *cutoff = cJSON_GetObjectItemCaseSensitive(root, "opaque_cutoff");
    if (!cutoff) { r = ht_json_fail(&c, "opaque_cutoff", "missing"); goto done; }
    if (!cJSON_IsNumber(cutoff) || !isfinite(cutoff->valuedouble) ||
        cutoff->valuedouble <= 0 || cutoff->valuedouble > 1) {
        r = ht_json_fail(&c, "opaque_cutoff", "expected a number in (0, 1]");
        goto done;
    }
    out->opaque_cutoff = (float)cutoff->valuedouble;

    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    if (!cJSON_IsArray(lights)) { r = ht_json_fail(&c, "lights", lights ? "expected an array" : "missing"); goto done; }
    const cJSON *l;
    cJSON_ArrayForEach(l, lights) {
        char field[32];
        snprintf(field, sizeof field, "lights[%d]", out->light_count);
        if (out->light_count >= HT_MAX_LIGHTS) { r = ht_json_fail(&c, field, "more than %d lights", HT_MAX_LIGHTS); goto done; }
        if (cJSON_IsString(l) && strcmp(l->valuestring, "directional") == 0)
            out->lights[out->light_count++] = HT_LIGHT_DIRECTIONAL;
        else if (cJSON_IsString(l) && strcmp(l->valuestring, "point") == 0)
            out->lights[out->light_count++] = HT_LIGHT_POINT;
        else { r = ht_json_fail(&c, field, "expected \"directional\" or \"point\""); goto done; }
    }
    if (out->light_count == 0) { r = ht_json_fail(&c, "lights", "empty"); goto done; }

    if ((r = parse_textures(&c, cJSON_GetObjectItemCaseSensitive(root, "textures"), "textures",
                            out->textures, &out->texture_count)) != HT_OK)
        goto done;

    const cJSON *tiers = cJSON_GetObjectItemCaseSensitive(root, "tiers");
    if (!cJSON_IsArray(tiers)) { r = ht_json_fail(&c, "tiers", tiers ? "expected an array" : "missing"); goto done; }
    const cJSON *t;
    cJSON_ArrayForEach(t, tiers) {
        if (out->tier_count >= HT_MANIFEST_MAX_TIERS) {
            r = ht_json_fail(&c, "tiers", "more than %d tiers", HT_MANIFEST_MAX_TIERS);
            goto done;
        }
        if ((r = parse_tier(&c, t, out->tier_count, &out->tiers[out->tier_count])) != HT_OK) goto done;
        /* A second entry of a tier would never be selected by name and
           would shadow the first for ht_manifest_find_tier. */
        for (int k = 0; k < out->tier_count; k++)
            if (strcmp(out->tiers[k].name, out->tiers[out->tier_count].name) == 0) {
                char field[48];
                snprintf(field, sizeof field, "tiers[%d].name", out->tier_count);
                r = ht_json_fail(&c, field, "\"%s\" already listed as tiers[%d]", out->tiers[k].name, k);
                goto done;
            }
        out->tier_count++;
    }
    if (out->tier_count == 0) { r = ht_json_fail(&c, "tiers", "empty"); goto done; }

    /* Samplers must name a texture the bundle lists. */
    for (int i = 0; i < out->tier_count; i++) {
        const ht_manifest_tier *bt = &out->tiers[i];
        for (int s = 0; s < bt->sampler_count; s++)
            if (!ht_manifest_find_texture(out, bt, bt->samplers[s].texture)) {
                char field[96];
                snprintf(field, sizeof field, "tiers[%d].samplers[%d].texture", i, s);
                r = ht_json_fail(&c, field, "\"%s\" is not listed in textures", bt->samplers[s].texture);
                goto done;
            }
    }
done:
    cJSON_Delete(root);
    return r;
}

/* The whole file, or NULL with one line in err (json_check.h's reader:
   unreadable, over its size cap, or holding a NUL byte). */
static char *read_file(const char *path, char *err, size_t err_size) {
    char *text = NULL;
    return ht_json_read_file(path, &text, err, err_size) == HT_OK ? text : NULL;
}

ht_result ht_manifest_load(const char *dir, ht_manifest *out, char *err, size_t err_size) {
    if (!dir || !dir[0] || !out) {
        snprintf(err, err_size, "bundle: bundle_dir: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    if (strlen(dir) > HT_LIMIT_DIR_PATH ||
        (size_t)snprintf(path, sizeof path, "%s/" HT_MANIFEST_FILE, dir) >= sizeof path) {
        snprintf(err, err_size, "%.200s...: bundle directory path is %zu bytes, more than %d", dir, strlen(dir),
                 HT_LIMIT_DIR_PATH);
        return HT_ERR_INVALID_ARGUMENT;
    }
    char *text = read_file(path, err, err_size);
    if (!text) return HT_ERR_IO;
    ht_result r = ht_manifest_parse(text, dir, path, out, err, err_size);
    free(text);
    return r;
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

bool ht_manifest_path(const ht_manifest *b, const char *file, char *out, size_t out_size) {
    return (size_t)snprintf(out, out_size, "%s/%s", b->dir, file) < out_size;
}

char *ht_manifest_read_text(const ht_manifest *b, const char *file, char *err, size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    if (!file) {
        snprintf(err, err_size, "%s/manifest.json: files: role missing", b->dir);
        return NULL;
    }
    if (!ht_manifest_path(b, file, path, sizeof path)) {
        snprintf(err, err_size, "%s: path too long", file);
        return NULL;
    }
    return read_file(path, err, err_size);
}

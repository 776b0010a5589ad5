/* generate.c — the generator's two steps (hairgen.h). Build: every tier of
   one (material, scene) in memory (ht_generate). Write: those files as a
   directory (docs/bundle.md), atomically (ht_generate_bundle): files go into
   a temporary sibling directory which is renamed into place only once
   complete, so a failure leaves no DIR and an existing DIR is either the old
   or the new one. */
#define _GNU_SOURCE /* renameat2(RENAME_EXCHANGE): swap a finished bundle in */
#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <locale.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "build.h"
#include "bundle_sums.h"
#include "c_locale.h"
#include "depfile.h"
#include "emit.h"
#include "errfmt.h"
#include "file_atomic.h"
#include "file_open.h"
#include "json_check.h"
#include "lods_store.h"
#include "hairgen_internal.h"
#include "manifest.h"
#include "marschner_fit.h"
#include "strbuf.h"
#include "trace.h"

/* Hashed into input_hash and written to the manifest: a new generator
   invalidates caches keyed on the hash (the number is manifest.h's). */
#define GENERATOR_VERSION HT_MANIFEST_GENERATOR

/* FNV-1a 64 over every input file's bytes: the key a build cache can use. */
typedef struct input_hash { uint64_t value; } input_hash;

/* The hash as the manifest's input_hash holds it: "fnv1a64:" and 16 hex digits. */
#define HASH_TEXT_SIZE 32
static void hash_as_text(uint64_t hash, char out[HASH_TEXT_SIZE]) {
    snprintf(out, HASH_TEXT_SIZE, "fnv1a64:%016llx", (unsigned long long)hash);
}

static void hash_bytes(input_hash *h, const void *data, size_t size) {
    const unsigned char *p = data;
    for (size_t i = 0; i < size; i++) {
        h->value ^= p[i];
        h->value *= 0x100000001b3ull;
    }
}

/* The generator's version and the LOD ladder it builds lods.bin with: a
   bundle made with another ladder is out of date. */
static void hash_generator(input_hash *h) {
    hash_bytes(h, GENERATOR_VERSION, sizeof GENERATOR_VERSION);
    for (int l = 0; l < HT_LOD_LEVELS; l++) {
        ht_lod_desc d;
        ht_lod_level(l, &d);
        const double v[2] = { d.strand_stride, d.max_turn_deg };
        hash_bytes(h, v, sizeof v);
    }
}

/* Only regular files of at most max_bytes are hashed: /dev/zero would be
   hashed forever and a FIFO would wait for a writer (defects C2, C3). label,
   when given, is "MATERIAL: FIELD" naming where the path came from. */
static ht_result hash_file(input_hash *h, const char *path, uint64_t max_bytes, const char *label,
                           char *err, size_t err_size) {
    FILE *f;
    char why[1200];
    if (ht_file_open_regular(path, max_bytes, &f, NULL, why, sizeof why) != HT_OK)
        return label ? ht_fail(err, err_size, HT_ERR_IO, "%s: %s", label, why)
                     : ht_fail(err, err_size, HT_ERR_IO, "%s", why);
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) hash_bytes(h, buf, n);
    bool bad = ferror(f);
    fclose(f);
    if (bad) return ht_fail(err, err_size, HT_ERR_IO, "%s: read error", path);
    hash_bytes(h, "", 1); /* separates files */
    return HT_OK;
}

/* dir/name into path; false when it does not fit. */
static bool join_path(char *path, size_t size, const char *dir, const char *name) {
    int n = snprintf(path, size, "%s/%s", dir, name);
    return n >= 0 && (size_t)n < size;
}

static ht_result write_file(const char *dir, const char *name, const char *text, size_t len,
                            char *err, size_t err_size) {
    char path[4096];
    if (!join_path(path, sizeof path, dir, name))
        return ht_fail(err, err_size, HT_ERR_IO, "%s: path too long", dir);
    /* write(2), not stdio: one buffer, three system calls. */
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) return ht_fail(err, err_size, HT_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    size_t done = 0;
    errno = 0;
    while (done < len) {
        ssize_t n = write(fd, text + done, len - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        done += (size_t)n;
    }
    int e = done == len ? 0 : errno ? errno : ENOSPC;
    if (close(fd) != 0 && !e) e = errno;
    if (e) return ht_fail(err, err_size, HT_ERR_IO, "%s: write failed: %s", path, strerror(e));
    return HT_OK;
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw) {
    (void)st, (void)flag, (void)ftw;
    return remove(path) == 0 ? 0 : -1;
}

/* The temporary directory, whole: what this module wrote, or after a
   swap the old bundle (check_target let no folder in, but one may have
   been made since). Links are removed, never followed. */
static void remove_tree(const char *dir) { nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS); }

static cJSON *string_array(const char (*items)[160], int count) {
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < count; i++) cJSON_AddItemToArray(a, cJSON_CreateString(items[i]));
    return a;
}

static cJSON *texture_entry(const char *file, const ht_image *img, int depth, const char *contents) {
    cJSON *t = cJSON_CreateObject();
    cJSON_AddStringToObject(t, HT_MANIFEST_KEY_FILE, file);
    cJSON_AddNumberToObject(t, HT_MANIFEST_KEY_WIDTH, img->width);
    cJSON_AddNumberToObject(t, HT_MANIFEST_KEY_HEIGHT, img->height / depth);
    cJSON_AddNumberToObject(t, HT_MANIFEST_KEY_DEPTH, depth);
    cJSON_AddStringToObject(t, HT_MANIFEST_KEY_CONTENTS, contents);
    return t;
}

static cJSON *tier_entry(const ht_tier_output *t) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, HT_MANIFEST_KEY_NAME, ht_tier_name(t->tier));
    cJSON *req = cJSON_AddObjectToObject(o, HT_MANIFEST_KEY_REQUIRES);
    cJSON_AddStringToObject(req, HT_MANIFEST_KEY_API, HT_MANIFEST_API_GL);
    cJSON_AddStringToObject(req, HT_MANIFEST_KEY_GL, t->requires.gl);
    if (t->requires.glsl[0]) cJSON_AddStringToObject(req, HT_MANIFEST_KEY_GLSL, t->requires.glsl);
    else cJSON_AddNullToObject(req, HT_MANIFEST_KEY_GLSL);
    cJSON *ext = cJSON_AddArrayToObject(req, HT_MANIFEST_KEY_EXTENSIONS);
    for (int i = 0; i < t->requires.extension_count; i++)
        cJSON_AddItemToArray(ext, cJSON_CreateString(t->requires.extensions[i]));
    cJSON_AddNumberToObject(req, HT_MANIFEST_KEY_TEXTURE_UNITS, t->requires.texture_units);

    cJSON *files = cJSON_AddObjectToObject(o, HT_MANIFEST_KEY_FILES);
    for (int i = 0; i < t->text_count; i++)
        if (t->texts[i].role[0]) cJSON_AddStringToObject(files, t->texts[i].role, t->texts[i].file);
    /* The GL ES texts are listed by their targets, not as desktop files. */
    if (t->es_count > 0) {
        cJSON *es = cJSON_AddArrayToObject(o, HT_MANIFEST_KEY_ES);
        for (int i = 0; i < t->es_count; i++) {
            cJSON *e = cJSON_CreateObject();
            cJSON_AddStringToObject(e, HT_MANIFEST_KEY_API, HT_MANIFEST_API_GLES);
            cJSON_AddStringToObject(e, HT_MANIFEST_KEY_ES_VERSION, t->es[i].version);
            cJSON_AddStringToObject(e, HT_MANIFEST_KEY_ESSL, t->es[i].essl);
            cJSON_AddStringToObject(e, HT_MANIFEST_KEY_PRECISION, t->es[i].precision);
            cJSON_AddStringToObject(e, HT_MANIFEST_KEY_VERTEX, t->es[i].vertex);
            cJSON_AddStringToObject(e, HT_MANIFEST_KEY_FRAGMENT, t->es[i].fragment);
            cJSON_AddItemToArray(es, e);
        }
    }
    if (t->image_count > 0) {
        cJSON *tex = cJSON_AddObjectToObject(o, HT_MANIFEST_KEY_TEXTURES);
        for (int i = 0; i < t->image_count; i++)
            cJSON_AddItemToObject(tex, t->images[i].name,
                                  texture_entry(t->images[i].file, &t->images[i].image,
                                                t->images[i].depth, t->images[i].contents));
    }
    cJSON *samplers = cJSON_AddArrayToObject(o, HT_MANIFEST_KEY_SAMPLERS);
    for (int i = 0; i < t->sampler_count; i++) {
        cJSON *s = cJSON_CreateObject();
        cJSON_AddStringToObject(s, HT_MANIFEST_KEY_UNIFORM, t->samplers[i].sampler);
        cJSON_AddStringToObject(s, HT_MANIFEST_KEY_TEXTURE, t->samplers[i].name);
        cJSON_AddNumberToObject(s, HT_MANIFEST_KEY_UNIT, t->samplers[i].unit);
        cJSON_AddItemToArray(samplers, s);
    }
    cJSON *features = cJSON_AddArrayToObject(o, HT_MANIFEST_KEY_FEATURES);
    for (int i = 0; i < t->feature_count; i++)
        cJSON_AddItemToArray(features, cJSON_CreateString(t->features[i]));
    cJSON_AddItemToObject(o, HT_MANIFEST_KEY_DROPPED, string_array(t->dropped, t->dropped_count));
    if (t->mediump.samples > 0) { /* docs/bundle.md "es2_mediump" */
        cJSON *mp = cJSON_AddObjectToObject(o, "es2_mediump");
        cJSON_AddStringToObject(mp, "api", "gles2");
        cJSON_AddStringToObject(mp, "essl", "1.00");
        cJSON_AddStringToObject(mp, "fragment_precision", "mediump");
        cJSON_AddStringToObject(mp, "vertex", "full-es2.vert");
        cJSON_AddStringToObject(mp, "fragment", "full-es2-mediump.frag");
        cJSON_AddNumberToObject(mp, "mirror_samples", (double)t->mediump.samples);
        cJSON_AddNumberToObject(mp, "mirror_max_error", t->mediump.max_byte);
        cJSON_AddNumberToObject(mp, "mirror_max_error_near_opposite", t->mediump.opposite_max_byte);
    }
    return o;
}

static const char *light_type_name(ht_light_type t) {
    return t == HT_LIGHT_POINT ? "point" : "directional";
}

/* The Scheuermann constants the lower tiers of a Marschner material draw,
   and how far they are from the fibre (marschner_fit.h). */
static cJSON *fit_entry(const ht_marschner_fit *fit) {
    cJSON *o = cJSON_CreateObject();
    const ht_shading *s = &fit->shading;
    cJSON_AddStringToObject(o, "model", "scheuermann");
    cJSON_AddStringToObject(o, "fitted_to", "marschner");
    cJSON_AddNumberToObject(o, "samples", HT_MARSCHNER_FIT_SAMPLES);
    cJSON_AddNumberToObject(o, "rms_error", fit->rms);
    cJSON_AddNumberToObject(o, "max_error", fit->max_error);
    cJSON *d = cJSON_AddObjectToObject(o, "diffuse");
    cJSON_AddItemToObject(d, "color", cJSON_CreateDoubleArray(s->diffuse_color, 3));
    cJSON_AddNumberToObject(d, "wrap", s->wrap);
    const ht_lobe *lobes[2] = { &s->primary, &s->secondary };
    const char *names[2] = { "primary", "secondary" };
    for (int i = 0; i < 2; i++) {
        cJSON *l = cJSON_AddObjectToObject(o, names[i]);
        cJSON_AddItemToObject(l, "color", cJSON_CreateDoubleArray(lobes[i]->color, 3));
        cJSON_AddNumberToObject(l, "exponent", lobes[i]->exponent);
        cJSON_AddNumberToObject(l, "shift", lobes[i]->shift);
    }
    cJSON *t = cJSON_AddObjectToObject(o, "transmission");
    cJSON_AddItemToObject(t, "color", cJSON_CreateDoubleArray(s->transmission.color, 3));
    cJSON_AddNumberToObject(t, "centre", s->transmission.centre);
    cJSON_AddNumberToObject(t, "sharpness", s->transmission.sharpness);
    cJSON_AddNumberToObject(t, "azimuth", s->transmission.azimuth);
    cJSON_AddNumberToObject(t, "rms_error", fit->tt_rms); /* its shape against M_TT N_TT alone */
    return o;
}

static cJSON *manifest_json(const ht_plan *plan, const ht_material *m, uint64_t hash,
                           const ht_image *albedo, const ht_image *detail,
                           const ht_tier_output *tiers, int tier_count, const ht_marschner_fit *fit) {
    cJSON *root = cJSON_CreateObject();
    char hash_text[HASH_TEXT_SIZE];
    hash_as_text(hash, hash_text);
    cJSON_AddStringToObject(root, HT_MANIFEST_KEY_FORMAT, HT_MANIFEST_FORMAT);
    cJSON_AddStringToObject(root, HT_MANIFEST_KEY_GENERATOR, GENERATOR_VERSION);
    cJSON_AddStringToObject(root, HT_MANIFEST_KEY_INPUT_HASH, hash_text);
    cJSON_AddStringToObject(root, HT_MANIFEST_KEY_MATERIAL, m->name);
    cJSON_AddStringToObject(root, HT_MANIFEST_KEY_MODEL,
                            plan->shading.model == HT_MODEL_KAJIYA_KAY  ? "kajiya-kay"
                            : plan->shading.model == HT_MODEL_MARSCHNER ? "marschner"
                                                                        : "scheuermann");
    cJSON *lights = cJSON_AddArrayToObject(root, HT_MANIFEST_KEY_LIGHTS);
    for (int i = 0; i < plan->light_count; i++)
        cJSON_AddItemToArray(lights, cJSON_CreateString(light_type_name(plan->light_types[i])));
    cJSON_AddNumberToObject(root, HT_MANIFEST_KEY_OPAQUE_CUTOFF, plan->opaque_cutoff);
    cJSON *textures = cJSON_AddObjectToObject(root, HT_MANIFEST_KEY_TEXTURES);
    for (int i = 0; i < plan->texture_count; i++) {
        const ht_plan_texture *pt = &plan->textures[i];
        const ht_image *img = strcmp(pt->name, "albedo") == 0 ? albedo : detail;
        char file[32];
        snprintf(file, sizeof file, "%s.png", pt->name);
        cJSON_AddItemToObject(textures, pt->name, texture_entry(file, img, 1, pt->contents));
    }
    cJSON_AddItemToObject(root, HT_MANIFEST_KEY_NOTES, string_array(plan->notes, plan->note_count));
    if (fit) cJSON_AddItemToObject(root, "fit", fit_entry(fit));
    cJSON *tier_list = cJSON_AddArrayToObject(root, HT_MANIFEST_KEY_TIERS);
    for (int i = 0; i < tier_count; i++) cJSON_AddItemToArray(tier_list, tier_entry(&tiers[i]));
    return root;
}

/* The tier table hairgen prints after its "hairgen: NAME -> DIR" line. */
static void print_summary(FILE *out, const ht_plan *plan, const ht_tier_output *tiers, int tier_count) {
    fprintf(out, "%-7s %-52s %-5s %s\n", "tier", "needs", "units", "features");
    for (int i = 0; i < tier_count; i++) {
        const ht_tier_output *t = &tiers[i];
        char needs[128];
        int n = snprintf(needs, sizeof needs, "GL %s", t->requires.gl);
        if (t->requires.glsl[0]) n += snprintf(needs + n, sizeof needs - n, ", GLSL %s", t->requires.glsl);
        for (int e = 0; e < t->requires.extension_count && n < (int)sizeof needs; e++)
            n += snprintf(needs + n, sizeof needs - n, ", %s", t->requires.extensions[e] + 3);
        char features[512] = "";
        int f = 0;
        for (int k = 0; k < t->feature_count && f < (int)sizeof features; k++)
            f += snprintf(features + f, sizeof features - f, "%s%s", k ? ", " : "", t->features[k]);
        fprintf(out, "%-7s %-52s %-5d %s\n", ht_tier_name(t->tier), needs, t->requires.texture_units, features);
        for (int k = 0; k < t->dropped_count; k++) fprintf(out, "%-7s   dropped: %s\n", "", t->dropped[k]);
    }
    for (int i = 0; i < plan->note_count; i++) fprintf(out, "note: %s\n", plan->notes[i]);
}

/* What may be replaced: nothing, an empty directory, or a bundle (a
   manifest.json of HT_MANIFEST_FORMAT). Anything else is refused before any work,
   so `-o` pointed at the wrong directory deletes nothing. */
static ht_result check_target(const char *dir, char *err, size_t err_size) {
    struct stat st;
    if (stat(dir, &st) != 0) return HT_OK;
    if (!S_ISDIR(st.st_mode)) return ht_fail(err, err_size, HT_ERR_IO, "%s: exists and is not a directory", dir);
    DIR *d = opendir(dir);
    if (!d) return ht_fail(err, err_size, HT_ERR_IO, "%s: cannot read: %s", dir, strerror(errno));
    bool empty = true;
    char sub[256] = "";
    struct dirent *e;
    /* A folder inside is none of hairgen's (a bundle is flat): replacing
       the bundle would delete it, so it is refused like any folder
       hairgen did not write. */
    while (!sub[0] && (e = readdir(d)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        empty = false;
        struct stat est;
        char path[4096];
        bool is_dir = e->d_type == DT_DIR ||
                      (e->d_type == DT_UNKNOWN && join_path(path, sizeof path, dir, e->d_name) &&
                       lstat(path, &est) == 0 && S_ISDIR(est.st_mode));
        if (is_dir) snprintf(sub, sizeof sub, "%s", e->d_name);
    }
    closedir(d);
    if (empty) return HT_OK;
    if (sub[0])
        return ht_fail(err, err_size, HT_ERR_IO, "%s: holds a folder hairgen did not write (%s); refusing to "
                       "replace it", dir, sub);

    char path[4096];
    bool bundle = false;
    if (join_path(path, sizeof path, dir, HT_MANIFEST_FILE)) {
        /* The regular-file opener: a FIFO there must not hang hairgen. */
        char why[256];
        size_t n = 0;
        char *text = ht_file_read_bytes(path, HT_FILE_MAX_JSON, &n, why, sizeof why);
        if (text) {
            text[n] = '\0'; /* ht_file_read_bytes leaves the byte past the end */
            cJSON *m = cJSON_ParseWithLength(text, n);
            const cJSON *format = cJSON_GetObjectItemCaseSensitive(m, HT_MANIFEST_KEY_FORMAT);
            bundle = cJSON_IsString(format) && strcmp(format->valuestring, HT_MANIFEST_FORMAT) == 0;
            cJSON_Delete(m);
            free(text);
        }
    }
    if (!bundle)
        return ht_fail(err, err_size, HT_ERR_IO,
                       "%s: exists and is not a hairtier bundle (no manifest.json of format %s); "
                       "refusing to replace it", dir, HT_MANIFEST_FORMAT);
    return HT_OK;
}

/* Moves the finished temporary directory to `dir`, replacing what was there. */
static ht_result publish(const char *tmp, const char *dir, char *err, size_t err_size) {
    if (rename(tmp, dir) == 0) return HT_OK;
    if (errno != EEXIST && errno != ENOTEMPTY)
        return ht_fail(err, err_size, HT_ERR_IO, "%s: cannot create: %s", dir, strerror(errno));
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return ht_fail(err, err_size, HT_ERR_IO, "%s: exists and is not a directory", dir);
    if (renameat2(AT_FDCWD, tmp, AT_FDCWD, dir, RENAME_EXCHANGE) != 0)
        return ht_fail(err, err_size, HT_ERR_IO, "%s: cannot replace: %s", dir, strerror(errno));
    remove_tree(tmp); /* now holds the old bundle */
    return HT_OK;
}

/* ---- build step: everything in memory ---- */

/* Takes ownership of text or image (the tier output no longer frees it). */
static ht_generated_file *add_file(ht_generated *g, const char *name, ht_tier tier, const char *role) {
    if (g->file_count >= HT_GENERATED_MAX_FILES) return NULL;
    ht_generated_file *f = &g->files[g->file_count++];
    memset(f, 0, sizeof *f);
    snprintf(f->name, sizeof f->name, "%s", name);
    snprintf(f->role, sizeof f->role, "%s", role);
    f->tier = tier;
    return f;
}

static void hash_string(input_hash *h, const char *s) { hash_bytes(h, s, strlen(s) + 1); }
static void hash_doubles(input_hash *h, const double *v, int n) { hash_bytes(h, v, sizeof *v * (size_t)n); }
static void hash_int(input_hash *h, int64_t v) { hash_bytes(h, &v, sizeof v); }

/* The in-memory key: every value of the material and scene the plan reads,
   field by field (never a struct's padding), and the texture files' bytes. */
static ht_result hash_values(input_hash *h, const ht_material *m, const ht_scene *scene,
                             char *err, size_t err_size) {
    hash_string(h, m->name);
    hash_int(h, m->shading.model);
    hash_doubles(h, m->shading.diffuse_color, 3);
    hash_doubles(h, &m->shading.wrap, 1);
    hash_doubles(h, m->shading.marschner.absorption, 3);
    hash_doubles(h, &m->shading.marschner.shift_r, 1);
    hash_doubles(h, &m->shading.marschner.width_r, 1);
    hash_doubles(h, &m->shading.marschner.eta, 1);
    const ht_lobe *lobes[2] = { &m->shading.primary, &m->shading.secondary };
    for (int i = 0; i < 2; i++) {
        hash_doubles(h, lobes[i]->color, 3);
        hash_doubles(h, &lobes[i]->exponent, 1);
        hash_doubles(h, &lobes[i]->shift, 1);
    }
    /* Only a lobe that draws is hashed: without one the key is as before. */
    if (ht_model_has_transmission(&m->shading)) {
        const ht_transmission *t = &m->shading.transmission;
        hash_doubles(h, t->color, 3);
        hash_doubles(h, &t->centre, 1);
        hash_doubles(h, &t->sharpness, 1);
        hash_doubles(h, &t->azimuth, 1);
    }
    hash_doubles(h, &m->opaque_cutoff, 1);
    for (int i = 0; i < HT_TEX_COUNT; i++) {
        const ht_texture_source *t = &m->textures[i];
        hash_int(h, t->origin);
        if (t->origin == HT_TEXTURE_PROCEDURAL) {
            hash_string(h, t->procedural);
            hash_int(h, t->size);
            hash_int(h, t->seed);
        } else if (t->origin == HT_TEXTURE_FILE) {
            ht_result r = hash_file(h, t->path, HT_FILE_MAX_PNG, NULL, err, err_size);
            if (r != HT_OK) return r;
        }
    }
    hash_int(h, scene->light_count);
    for (int i = 0; i < scene->light_count && i < HT_MAX_LIGHTS; i++) hash_int(h, scene->lights[i].type);
    return HT_OK;
}

static char *summary_text(const ht_plan *plan, const ht_tier_output *tiers, int tier_count) {
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    if (!f) return NULL;
    print_summary(f, plan, tiers, tier_count);
    if (fclose(f) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

/* Moves an image and its PNG bytes into a new file of g; false when g is full. */
static bool add_image_file(ht_generated *g, const char *name, ht_tier tier, const char *role, ht_image *image,
                           int depth, ht_built_png *png) {
    ht_generated_file *f = add_file(g, name, tier, role);
    if (!f) return false;
    f->image = *image;
    f->depth = depth;
    f->png = png->bytes;
    f->png_size = png->size;
    *image = (ht_image){ 0 };
    *png = (ht_built_png){ 0 };
    return true;
}

/* threads: what ht_build may use (0: every online core). */
static ht_result generate(const ht_generate_desc *desc, int threads, ht_generated *g, char *err, size_t err_size) {
    const ht_material *m = desc->material;
    ht_result r = ht_material_check(m, err, err_size);
    if (r != HT_OK) return r;
    ht_scene default_scene;
    const ht_scene *scene = desc->scene;
    if (!scene) {
        ht_scene_default(&default_scene);
        scene = &default_scene;
    }
    const char *file = m->file[0] ? m->file : "<material>";

    g->input_hash = desc->input_hash;
    if (!g->input_hash) {
        input_hash hash = { 0xcbf29ce484222325ull };
        hash_generator(&hash);
        r = hash_values(&hash, m, scene, err, err_size);
        if (r != HT_OK) return r;
        g->input_hash = hash.value;
    }

    ht_built *b = malloc(sizeof *b);
    if (!b) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", file);
    r = ht_build(m, scene, threads, b, err, err_size);
    if (r != HT_OK) {
        free(b);
        return r;
    }
    if (b->physical) {
        char line[160];
        snprintf(line, sizeof line, "the fibre: Scheuermann constants fitted to it, with a transmission lobe, "
                 "rms %.1f/255, max %.0f/255 over %d samples of the scene's lights (manifest \"fit\")", b->fit.rms * 255, b->fit.max_error * 255,
                 HT_MARSCHNER_FIT_SAMPLES);
        for (int t = 0; t < b->tier_count; t++)
            if (b->tiers[t].tier != HT_TIER_MARSCHNER) ht_output_add_dropped(&b->tiers[t], line);
    }

    /* The manifest is printed once the other files are in g: it lists
       their sizes and checksums (bundle_sums.h). */
    cJSON *root = manifest_json(&b->plan, m, g->input_hash, &b->albedo, &b->detail, b->tiers, b->tier_count,
                                b->physical ? &b->fit : NULL);
    char *manifest = NULL;
    g->summary = summary_text(&b->plan, b->tiers, b->tier_count);
    if (!root || !g->summary) r = ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", file);

    /* The files in the order a bundle is written: the packed textures, each
       tier's texts then images, the manifest last. Ownership moves into g. */
    if (r == HT_OK) {
        bool fits = (!b->albedo.pixels ||
                     add_image_file(g, "albedo.png", HT_TIER_AUTO, "albedo", &b->albedo, 1, &b->albedo_png)) &&
                    (!b->detail.pixels ||
                     add_image_file(g, "detail.png", HT_TIER_AUTO, "detail", &b->detail, 1, &b->detail_png));
        for (int t = 0; t < b->tier_count && fits; t++) {
            ht_tier_output *o = &b->tiers[t];
            for (int i = 0; i < o->text_count && fits; i++) {
                ht_out_text *ot = &o->texts[i];
                ht_generated_file *f = add_file(g, ot->file, o->tier, ot->role);
                if (!f) { fits = false; break; }
                f->text = ot->text;
                ot->text = NULL;
            }
            for (int i = 0; i < o->image_count && fits; i++) {
                ht_out_image *oi = &o->images[i];
                fits = add_image_file(g, oi->file, o->tier, oi->name, &oi->image, oi->depth, &b->tier_png[t][i]);
            }
        }
        cJSON *sums = fits ? ht_bundle_sums_json(g) : NULL;
        if (sums) cJSON_AddItemToObject(root, HT_MANIFEST_KEY_FILE_SUMS, sums);
        char *cj = sums ? cJSON_Print(root) : NULL;
        manifest = cj ? strdup(cj) : NULL;
        cJSON_free(cj);
        ht_generated_file *f = manifest ? add_file(g, HT_MANIFEST_FILE, HT_TIER_AUTO, "manifest") : NULL;
        if (f) {
            f->text = manifest;
            g->manifest = manifest;
            manifest = NULL;
        } else if (fits && !manifest) {
            r = ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", file);
        } else {
            r = ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "%s: more than %d bundle files", file,
                        HT_GENERATED_MAX_FILES);
        }
    }

    free(manifest);
    cJSON_Delete(root);
    ht_built_free(b);
    free(b);
    return r;
}

ht_result ht_generate(const ht_generate_desc *desc, ht_generated *out, char *err, size_t err_size) {
    if (!out) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_generate: no output");
    memset(out, 0, sizeof *out);
    if (!desc || !desc->material)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_generate: material: required");
    ht_c_locale_scope loc = ht_c_locale_enter();
    ht_result r = generate(desc, 0, out, err, err_size);
    ht_c_locale_leave(loc);
    if (r != HT_OK) ht_generated_free(out);
    return r;
}

void ht_generated_free(ht_generated *g) {
    if (!g) return;
    for (int i = 0; i < g->file_count && i < HT_GENERATED_MAX_FILES; i++) {
        free(g->files[i].text);
        free(g->files[i].png);
        ht_image_free(&g->files[i].image);
    }
    free(g->summary);
    memset(g, 0, sizeof *g);
}

const ht_generated_file *ht_generated_find(const ht_generated *g, const char *name) {
    for (int i = 0; g && name && i < g->file_count; i++)
        if (strcmp(g->files[i].name, name) == 0) return &g->files[i];
    return NULL;
}

/* ---- write step: the generated files into a directory ---- */

/* Every file into tmp, in bundle order (the first that fails is the error).
   The images' PNG bytes were made with the tiers (build.c). Nothing here
   is fsync'd: the bundle appears whole or not at all by the rename of its
   directory (publish), like a compiler's output, and a system crash may
   lose it as it may lose any file not yet on disk. (Writing the files on
   two threads was tried: starting the threads cost more than the 1.4 ms
   the 16 files take one after another on the 2-core VM.) */
static ht_result write_bundle(const char *tmp, const ht_generated *g, char *err, size_t err_size) {
    ht_result r = HT_OK;
    for (int i = 0; i < g->file_count && r == HT_OK; i++) {
        const ht_generated_file *f = &g->files[i];
        if (f->text) {
            r = write_file(tmp, f->name, f->text, strlen(f->text), err, err_size);
            continue;
        }
        unsigned char *bytes = f->png;
        size_t size = f->png_size;
        if (!bytes) r = ht_generated_file_bytes(f, &bytes, &size, err, err_size);
        if (r == HT_OK) r = write_file(tmp, f->name, (const char *)bytes, size, err, err_size);
        if (bytes != f->png) free(bytes);
    }
    return r;
}

/* mkdtemp makes a directory owner-only; a bundle is as readable as any
   file the caller creates. The umask is read once: reading it means
   setting it, which must not race between a batch's threads. */
static pthread_once_t umask_once = PTHREAD_ONCE_INIT;
static mode_t process_umask;

static void read_umask(void) {
    process_umask = umask(0);
    umask(process_umask);
}

/* Whether dir's manifest holds input_hash `hash`. hairgen writes the key
   third, within the first few hundred bytes: it is searched for there,
   not parsed (parsing every manifest was half of a no-change batch's
   time). */
static bool bundle_has_hash(const char *dir, input_hash hash) {
    char want[HASH_TEXT_SIZE];
    hash_as_text(hash.value, want);
    char path[4096], why[256];
    size_t size = 0;
    char *head = join_path(path, sizeof path, dir, HT_MANIFEST_FILE)
                     ? ht_file_read_bytes(path, HT_FILE_MAX_JSON, &size, why, sizeof why)
                     : NULL;
    if (!head) return false;
    head[size] = '\0'; /* ht_file_read_bytes leaves the byte past the end */
    /* The key is searched for in the first 1023 bytes (a copy), the
       checksums in the whole text. */
    char head_text[1024];
    memcpy(head_text, head, size < 1023 ? size : 1023);
    head_text[size < 1023 ? size : 1023] = '\0';
    const char *key = "\"" HT_MANIFEST_KEY_INPUT_HASH "\"";
    const char *p = strstr(head_text, key);
    bool same = false;
    if (p) {
        p += strlen(key);
        p += strspn(p, " \t\r\n");
        if (*p++ == ':') {
            p += strspn(p, " \t\r\n");
            size_t len = strlen(want);
            same = *p == '"' && strncmp(p + 1, want, len) == 0 && p[1 + len] == '"';
        }
    }
    /* The bundle it would keep, checked whole: every file the manifest
       lists, with its size and checksum. */
    same = same && ht_bundle_sums_match(dir, head, size);
    free(head);
    return same;
}

/* What a bundle is made from: the material read once (parsed, and its
   bytes hashed), the scene (rq->scene, or loaded here), every file they
   name (texture files; a strands scene's strand file) hashed and listed in
   rep->inputs. The hash is the bundle's input_hash. */
typedef struct bundle_inputs {
    ht_material material;
    ht_scene loaded_scene;
    const ht_scene *scene;
    input_hash hash;
} bundle_inputs;

/* The first part of every bundle's key: the generator and the material's
   bytes. */
static input_hash material_key(const char *material_text) {
    input_hash h = { 0xcbf29ce484222325ull };
    hash_generator(&h);
    hash_bytes(&h, material_text, strlen(material_text));
    hash_bytes(&h, "", 1); /* as hash_file separates files */
    return h;
}

/* The scene's part of the key (its bytes, a strands scene's strand file),
   its paths listed in rep->inputs. */
static ht_result hash_scene(const ht_bundle_request *rq, const ht_scene *scene, ht_bundle_report *rep,
                            input_hash *h, char *err, size_t err_size) {
    const char *scene_path = rq->scene_path;
    ht_result r = HT_OK;
    if (scene_path) {
        if (rq->scene_bytes) {
            hash_bytes(h, rq->scene_bytes, rq->scene_size);
            hash_bytes(h, "", 1); /* as hash_file separates files */
        } else {
            r = hash_file(h, scene_path, HT_FILE_MAX_JSON, NULL, err, err_size);
        }
        snprintf(rep->inputs[rep->input_count++], sizeof rep->inputs[0], "%s", scene_path);
    }
    /* A strands scene's geometry is its strand file: it changes the plan's
       extent and the bundle a measure step draws, so it is an input. */
    if (r == HT_OK && scene->geometry == HT_GEOMETRY_STRANDS) {
        char label[1200];
        snprintf(label, sizeof label, "%.1000s: geometry.file", scene_path ? scene_path : "<scene>");
        r = hash_file(h, scene->strands.file, HT_LIMIT_FILE_STRANDS, label, err, err_size);
        snprintf(rep->inputs[rep->input_count++], sizeof rep->inputs[0], "%s", scene->strands.file);
    }
    return r;
}

/* Every part of the key but the texture files, which only the parsed
   material names: the generator, the material's bytes, the scene's and a
   strands scene's strand file, their paths listed in rep->inputs. */
static ht_result key_before_textures(const ht_bundle_request *rq, const ht_scene *scene, const char *material_text,
                                     ht_bundle_report *rep, input_hash *h, char *err, size_t err_size) {
    *h = material_key(material_text);
    snprintf(rep->inputs[rep->input_count++], sizeof rep->inputs[0], "%s", rq->material_path);
    return hash_scene(rq, scene, rep, h, err, err_size);
}

/* The material's text (read by the caller, once) parsed, the scene loaded
   unless rq->scene is given, and the key finished with the texture files'
   bytes. keyed: in->hash and rep->inputs already hold key_before_textures'
   part, made from this text and rq->scene. */
static ht_result read_inputs(const ht_bundle_request *rq, ht_bundle_report *rep, bundle_inputs *in,
                             const char *material_text, bool keyed, char *err, size_t err_size) {
    const char *material_path = rq->material_path, *scene_path = rq->scene_path;
    in->scene = rq->scene;
    ht_result r = ht_material_parse(material_text, material_path, &in->material, err, err_size);
    if (r != HT_OK) return r;
    snprintf(rep->material_name, sizeof rep->material_name, "%s", in->material.name);
    if (!in->scene) {
        if (scene_path) r = ht_scene_load(scene_path, &in->loaded_scene, err, err_size);
        else ht_scene_default(&in->loaded_scene);
        if (r == HT_OK) r = ht_scene_check_strands(&in->loaded_scene, scene_path, err, err_size);
        if (r != HT_OK) return r;
        in->scene = &in->loaded_scene;
    }
    /* The bundle's key is its input files' bytes; the files are the
       bundle's dependencies. */
    if (!keyed) r = key_before_textures(rq, in->scene, material_text, rep, &in->hash, err, err_size);
    static const char *const slots[HT_TEX_COUNT] = { "base", "alpha", "shift", "sparkle" };
    for (int i = 0; i < HT_TEX_COUNT && r == HT_OK; i++)
        if (in->material.textures[i].origin == HT_TEXTURE_FILE) {
            char label[1200];
            snprintf(label, sizeof label, "%.1000s: textures.%s.file", material_path, slots[i]);
            r = hash_file(&in->hash, in->material.textures[i].path, HT_FILE_MAX_PNG, label, err, err_size);
            snprintf(rep->inputs[rep->input_count++], sizeof rep->inputs[0], "%s", in->material.textures[i].path);
        }
    return r;
}

/* A batch's key before the textures, made once from the text already read
   (read_inputs goes on from it), and a no-change re-run's shortcut: a
   material whose text names no file is keyed by that part alone, so
   whether its bundle is up to date is known without parsing it (the parse
   was 70% of a no-change batch's instructions: callgrind, 100 materials).
   Sound by construction: the key is made by the same steps as a full
   reading, so it equals the bundle's only when the bundle was made from
   these very bytes (a material that names files was keyed with their bytes
   too, so it never matches here, however its key is spelt) and identical
   bytes parse as they did. A text holding "file" is not compared. A scene
   the caller did not load, or a part that cannot be hashed, leaves *keyed
   false and the full reading to make the key and to say why. */
static bool up_to_date_unparsed(const ht_bundle_request *rq, const char *material_text, ht_bundle_report *rep,
                                input_hash *h, bool *keyed) {
    char err[1200];
    *keyed = rq->scene && key_before_textures(rq, rq->scene, material_text, rep, h, err, sizeof err) == HT_OK;
    if (!*keyed) rep->input_count = 0; /* read_inputs lists them again */
    return *keyed && !strstr(material_text, "\"file\"") && bundle_has_hash(rq->out_dir, *h);
}

ht_result ht_generate_files(const char *material_path, const char *scene_path, ht_material *material,
                            ht_generated *out, char *err, size_t err_size) {
    if (!out) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_generate_files: no output");
    memset(out, 0, sizeof *out);
    if (!material_path)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_generate_files: material: required");
    bundle_inputs *in = malloc(sizeof *in);
    ht_bundle_report *rep = calloc(1, sizeof *rep);
    ht_result r = in && rep ? HT_OK : ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", material_path);
    ht_c_locale_scope loc = ht_c_locale_enter();
    char *material_text = NULL;
    if (r == HT_OK) r = ht_json_read_file(material_path, &material_text, err, err_size);
    if (r == HT_OK)
        r = read_inputs(&(ht_bundle_request){ .material_path = material_path, .scene_path = scene_path }, rep, in,
                        material_text, false, err, err_size);
    free(material_text);
    if (r == HT_OK)
        r = ht_generate(&(ht_generate_desc){ .material = &in->material, .scene = in->scene,
                                             .input_hash = in->hash.value },
                        out, err, err_size);
    ht_c_locale_leave(loc);
    if (r == HT_OK && material) *material = in->material;
    free(in);
    free(rep);
    return r;
}

/* g's manifest replaced by dir/manifest.json as it is now. */
static ht_result reload_manifest(ht_generated *g, const char *dir, char *err, size_t err_size) {
    char path[4200];
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    char *text = ht_file_read_text(path, HT_FILE_MAX_JSON, err, err_size);
    if (!text) return HT_ERR_IO;
    ht_generated_file *f = &g->files[g->file_count - 1]; /* manifest.json is last (hairgen.h) */
    free(f->text);
    f->text = text;
    g->manifest = text;
    return HT_OK;
}

static ht_result bundle_make(const ht_bundle_request *rq, ht_bundle_report *rep, char *err, size_t err_size) {
    const char *out_dir = rq->out_dir;
    /* An up-to-date bundle is a bundle: a batch's re-run checks only its
       hash; any other run checks the target first, as it always has. */
    ht_result r = rq->skip_unchanged ? HT_OK : check_target(out_dir, err, err_size);
    if (r == HT_OK && rq->header_path) r = ht_file_check_output(rq->header_path, err, err_size);
    char *material_text = NULL;
    if (r == HT_OK) r = ht_json_read_file(rq->material_path, &material_text, err, err_size);
    if (r != HT_OK) return r;
    bundle_inputs inputs;
    bool keyed = false;
    if (rq->skip_unchanged && up_to_date_unparsed(rq, material_text, rep, &inputs.hash, &keyed)) {
        free(material_text);
        rep->skipped = true;
        return rq->depfile_names ? ht_depfile_check_report(out_dir, rep, err, err_size) : HT_OK;
    }
    r = read_inputs(rq, rep, &inputs, material_text, keyed, err, err_size);
    free(material_text);
    if (r == HT_OK && rq->depfile_names) r = ht_depfile_check_report(out_dir, rep, err, err_size);
    if (r != HT_OK) return r;
    const ht_material material = inputs.material;
    const ht_scene *scene = inputs.scene;
    const input_hash hash = inputs.hash;

    if (rq->skip_unchanged) {
        if (bundle_has_hash(out_dir, hash)) {
            rep->skipped = true;
            return HT_OK;
        }
        r = check_target(out_dir, err, err_size);
        if (r != HT_OK) return r;
    }

    ht_gen_trace("%s: inputs read", out_dir);
    ht_generated g;
    memset(&g, 0, sizeof g);
    r = generate(&(ht_generate_desc){ .material = &material, .scene = scene, .input_hash = hash.value },
                 rq->threads, &g, err, err_size);
    if (r != HT_OK) {
        ht_generated_free(&g);
        return r;
    }

    char tmp[4096] = "";
    int n = snprintf(tmp, sizeof tmp, "%s.tmp-XXXXXX", out_dir);
    if (n < 0 || (size_t)n >= sizeof tmp || !mkdtemp(tmp)) {
        r = ht_fail(err, err_size, HT_ERR_IO, "%s: cannot create a temporary directory beside it: %s",
                    out_dir, strerror(errno));
        tmp[0] = '\0';
    } else {
        pthread_once(&umask_once, read_umask);
        chmod(tmp, 0777 & ~process_umask);
    }
    if (r == HT_OK) {
        ht_gen_trace("%s: generated", out_dir);
        r = write_bundle(tmp, &g, err, err_size);
        ht_gen_trace("%s: written", out_dir);
        if (r == HT_OK && rq->store_lods && rq->scene_path && !rq->header_path)
            r = ht_lods_store(tmp, scene, rq->scene_path, rq->lods_cache, err, err_size);
        if (r == HT_OK && rq->step) r = rq->step(rq->step_user, tmp, scene, err, err_size);
        /* The temporary directory is removed below: name the bundle's own
           path for the file that failed (a full disk, a step), not the
           temporary's. */
        size_t tl = strlen(tmp);
        if (r != HT_OK && err && strncmp(err, tmp, tl) == 0) {
            char why[1200];
            snprintf(why, sizeof why, "%s", err + tl);
            ht_set_error(err, err_size, "%s%s (nothing written; %s is as it was)", out_dir, why, out_dir);
        }
    }
    /* A step may have rewritten the manifest (--measure): the header holds
       what the directory holds. */
    if (r == HT_OK && rq->header_path && rq->step) r = reload_manifest(&g, tmp, err, err_size);
    if (r == HT_OK) r = publish(tmp, out_dir, err, err_size);
    ht_gen_trace("%s: published", out_dir);
    if (r != HT_OK && tmp[0]) remove_tree(tmp);
    if (r == HT_OK && rq->header_path)
        r = ht_bundle_header_write(&g, material.name, rq->header_symbol, rq->header_path, err, err_size);
    if (r == HT_OK && rq->summary) {
        ht_print_line(rq->summary, "hairgen: %s -> %s", material.name, out_dir);
        fputs(g.summary, rq->summary);
        if (rq->header_path) ht_print_line(rq->summary, "hairgen: %s -> %s", material.name, rq->header_path);
    }
    ht_generated_free(&g);
    return r;
}

/* "dir/" and "dir" are the same bundle; the temporary sibling needs the
   name without the slash. */
static ht_result bundle_dir_name(const char *out_dir, char *dir, size_t dir_size, char *err, size_t err_size) {
    size_t len = out_dir ? strlen(out_dir) : 0;
    while (len > 1 && out_dir[len - 1] == '/') len--;
    if (len == 0 || len >= dir_size || (len == 1 && out_dir[0] == '/'))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: not a usable output directory",
                       out_dir ? out_dir : "(null)");
    if (len > HT_LIMIT_DIR_PATH)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%.200s...: output directory path is %zu bytes; "
                       "the runtime reads bundles at paths of at most %d", out_dir, len, HT_LIMIT_DIR_PATH);
    memcpy(dir, out_dir, len);
    dir[len] = '\0';
    return HT_OK;
}

ht_result ht_bundle_make(const ht_bundle_request *rq, ht_bundle_report *report, char *err, size_t err_size) {
    memset(report, 0, sizeof *report);
    char dir[4096];
    ht_result r = bundle_dir_name(rq->out_dir, dir, sizeof dir, err, err_size);
    if (r != HT_OK) return r;
    ht_bundle_request in_dir = *rq;
    in_dir.out_dir = dir;
    ht_c_locale_scope loc = ht_c_locale_enter();
    r = bundle_make(&in_dir, report, err, err_size);
    ht_c_locale_leave(loc);
    return r;
}

ht_result ht_generate_bundle(const char *material_path, const char *scene_path,
                             const char *out_dir, FILE *summary, char *err, size_t err_size) {
    return ht_generate_bundle_then(material_path, scene_path, out_dir, summary, NULL, NULL, err, err_size);
}

ht_result ht_generate_bundle_then(const char *material_path, const char *scene_path, const char *out_dir,
                                  FILE *summary, ht_bundle_step_fn step, void *step_user, char *err,
                                  size_t err_size) {
    ht_bundle_report report;
    return ht_bundle_make(&(ht_bundle_request){ .material_path = material_path, .scene_path = scene_path,
                                                .out_dir = out_dir, .summary = summary, .step = step,
                                                .step_user = step_user },
                          &report, err, err_size);
}

/* ht_generate_files, then the header at path: what hairgen --emit-header
   runs without -o (emit_header.c writes the text). */
ht_result ht_generate_header(const char *material_path, const char *scene_path, const char *path,
                             const char *symbol, FILE *summary, char *err, size_t err_size) {
    /* A bad symbol or output path is refused before anything is generated. */
    if (symbol) {
        ht_result r = ht_header_symbol_check(symbol, err, err_size);
        if (r != HT_OK) return r;
    }
    if (path) {
        ht_result r = ht_file_check_output(path, err, err_size);
        if (r != HT_OK) return r;
    }
    ht_material material;
    ht_generated g;
    ht_result r = ht_generate_files(material_path, scene_path, &material, &g, err, err_size);
    if (r == HT_OK) r = ht_bundle_header_write(&g, material.name, symbol, path, err, err_size);
    if (r == HT_OK && summary) {
        ht_print_line(summary, "hairgen: %s -> %s", material.name, path);
        fputs(g.summary, summary);
    }
    ht_generated_free(&g);
    return r;
}

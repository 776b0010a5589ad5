/* measure_lod.c — hairgen --measure-lods (measure_lod.h). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cJSON.h>

#include <hairtier/lod.h>
#include "errfmt.h"
#include "file_atomic.h"
#include "json_check.h"
#include "measure.h"
#include "measure_lod.h"
#include "offscreen.h"

static const double sizes[HT_MEASURE_LOD_SIZES] = { 1.0, 0.5, 0.25 };

/* The levels measured: the bundle's stored ones (lods.bin, when its level
   0 is the scene's mesh: the strand levels and any cards), else the
   ladder built from the scene's mesh. */
typedef struct lod_levels {
    ht_mesh mesh[HT_LOD_FILE_MAX_LEVELS];
    bool cards[HT_LOD_FILE_MAX_LEVELS];
    int count;
    /* soft[k][l]: strand level l >= 1 soft as the runtime derives it
       (ht_mesh_widen_back_to_front by soften[k] from the scene's eye);
       empty for level 0 and cards */
    ht_mesh soft[HT_LOD_MAX_SOFTENS][HT_LOD_FILE_MAX_LEVELS];
    float soften[HT_LOD_MAX_SOFTENS];
    int soften_count;
} lod_levels;

/* One frame on background, ended by glFinish. */
static ht_result draw_frame(offscreen *o, ht_renderer *r, const float background[3], const ht_frame_desc *f) {
    o->gl.ClearColor(background[0], background[1], background[2], 1.0f);
    o->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const ht_result res = ht_renderer_draw(r, f);
    o->gl.Finish();
    return res;
}

/* One level at one size, drawn at opacity (with width_rule, as the chain
   draws it: widened, back to front, opacity scaled, when its strands are
   under a pixel), warm-up frames (one, and more until
   offscreen_warmup_ms have passed) and the timed frames; its last frame
   copied into rgba. */
static ht_result draw_level(offscreen *o, ht_renderer *r, const ht_scene *s, const ht_frame_desc *f,
                            const ht_mesh *mesh, float opacity, bool width_rule, unsigned char *rgba, double *ms) {
    ht_mesh wide = { 0 };
    double factor = 1.0;
    const double px = ht_mesh_projected_width_px(mesh, &s->camera, s->height);
    ht_result res = width_rule ? ht_mesh_width_rule(mesh, px, ht_renderer_samples(r), s->camera.eye, &wide, &factor)
                               : HT_OK;
    if (res == HT_OK) res = ht_renderer_set_mesh(r, factor > 1.0 ? &wide : mesh);
    if (res == HT_OK) res = ht_renderer_set_opacity_scale(r, (float)(opacity / factor));
    ht_mesh_free(&wide);
    for (const double until = ht_measure_clock_ms() + offscreen_warmup_ms(o); res == HT_OK;) {
        res = draw_frame(o, r, s->background, f);
        if (ht_measure_clock_ms() >= until) break;
    }
    double t[HT_MEASURE_LOD_TIMED_FRAMES];
    for (int k = 0; k < HT_MEASURE_LOD_TIMED_FRAMES && res == HT_OK; k++) {
        const double t0 = ht_measure_clock_ms();
        res = draw_frame(o, r, s->background, f);
        t[k] = ht_measure_clock_ms() - t0;
    }
    ht_renderer_set_opacity_scale(r, 1.0f);
    if (res != HT_OK) return res;
    memcpy(rgba, offscreen_read(o), (size_t)o->width * (size_t)o->height * 4);
    *ms = ht_measure_median(t, HT_MEASURE_LOD_TIMED_FRAMES);
    return HT_OK;
}

/* Where a tier's cells are measured against: base (against samples LOD 0
   of the first tier, drawn by that tier's call; against the supersampled
   truth that; the first tier's LOD 0 sets base_ms), and the tier's level
   before (prev; zero: its level 0, the soft levels' start). */
typedef struct lod_images {
    unsigned char *base, *prev, *cur, *zero;
    double base_ms;
} lod_images;

/* One (level, tier) cell, plain or soft (soften > 1), at one size; strands
   the plain level's (a soft mesh's components are its sorted segments). */
static ht_result measure_cell(offscreen *o, ht_renderer *r, const ht_scene *s, const ht_frame_desc *f,
                              const char *tier, double size, const ht_mesh *mesh, uint32_t strands, int level,
                              float soften, bool cards,
                              bool reference, lod_images *im, ht_measure_lods *out, char *err, size_t err_size) {
    const size_t bytes = (size_t)s->width * (size_t)s->height * 4;
    const bool truth = out->reference == HT_LOD_REFERENCE_SUPERSAMPLE;
    char why[1024];
    if (out->count >= HT_MANIFEST_MAX_LOD_CELLS)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "measure: lods: more than %d cells",
                       HT_MANIFEST_MAX_LOD_CELLS);
    ht_measure_lod_cell *c = &out->cells[out->count];
    const char *soft = soften > 1 ? " soft" : "";
    ht_result res = draw_level(o, r, s, f, mesh, soften > 1 ? 1.0f / soften : 1.0f, truth, im->cur, &c->frame_ms);
    if (res != HT_OK)
        return ht_fail(err, err_size, res, "measure: lods: %s level %d%s at size %g: %s", tier, level, soft, size,
                       ht_result_string(res));
    if (reference) {
        if (!truth) memcpy(im->base, im->cur, bytes);
        im->base_ms = c->frame_ms;
    }
    c->level = level;
    snprintf(c->tier, sizeof c->tier, "%s", tier);
    c->strands = strands;
    c->cards = cards;
    c->soften = soften > 1 ? soften : 0.0f;
    c->size = size;
    c->cost_ratio = im->base_ms > 0 ? c->frame_ms / im->base_ms : 1.0;
    res = ht_metrics_compare(&(ht_metrics_desc){ .reference = im->base, .test = im->cur, .width = s->width,
                                                 .height = s->height },
                             &c->whole, NULL, why, sizeof why);
    ht_metrics pop = { .psnr_db = INFINITY };
    if (res == HT_OK && level > 0)
        res = ht_metrics_compare(&(ht_metrics_desc){ .reference = im->prev, .test = im->cur, .width = s->width,
                                                     .height = s->height },
                                 &pop, NULL, why, sizeof why);
    if (res != HT_OK)
        return ht_fail(err, err_size, res, "measure: lods: %s level %d%s at size %g: %s", tier, level, soft, size, why);
    /* The reference pair is itself exactly, whatever a redraw gives. */
    if (reference && !truth) c->whole.psnr_db = INFINITY;
    c->pop_psnr_db = pop.psnr_db;
    memcpy(im->prev, im->cur, bytes);
    if (level == 0) memcpy(im->zero, im->cur, bytes);
    out->count++;
    return HT_OK;
}

/* One tier's levels at one size into out->cells: the plain ones, then the
   soft ones of each factor (each soft level's pop against the tier's soft
   level before at that factor; soft level 1's against level 0, which is
   never soft). */
static ht_result measure_tier(offscreen *o, ht_renderer *r, const ht_scene *s, const ht_frame_desc *f,
                              const char *tier, double size, const lod_levels *levels, bool first, lod_images *im,
                              ht_measure_lods *out, char *err, size_t err_size) {
    ht_result res = HT_OK;
    for (int l = 0; l < levels->count && res == HT_OK; l++)
        res = measure_cell(o, r, s, f, tier, size, &levels->mesh[l], levels->mesh[l].component_count, l, 0.0f,
                           levels->cards[l], first && l == 0, im, out, err, err_size);
    for (int k = 0; k < levels->soften_count && res == HT_OK; k++) {
        memcpy(im->prev, im->zero, (size_t)s->width * (size_t)s->height * 4);
        for (int l = 1; l < levels->count && res == HT_OK; l++)
            if (levels->soft[k][l].component_count)
                res = measure_cell(o, r, s, f, tier, size, &levels->soft[k][l], levels->mesh[l].component_count, l,
                                   levels->soften[k], false, false, im, out, err, err_size);
    }
    return res;
}

ht_result ht_measure_truth(const ht_measure_truth_desc *d, unsigned char *rgba, char *err, size_t err_size) {
    const int w = d->width * HT_MEASURE_SUPERSAMPLE, h = d->height * HT_MEASURE_SUPERSAMPLE;
    char why[1024];
    offscreen *o = offscreen_open(&(offscreen_desc){ .kind = d->context, .width = w, .height = h,
                                                     .egl_device = d->egl_device },
                                  why, sizeof why);
    if (!o) return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "measure: the supersampled reference: %s", why);
    ht_renderer *r = NULL;
    ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = d->bundle_dir,
                                                            .tier = d->tier, .strict = true, .policy = "best",
                                                            .log = NULL },
                                       &r);
    if (res == HT_OK) res = ht_renderer_set_mesh(r, d->mesh);
    if (res == HT_OK) {
        o->gl.Viewport(0, 0, w, h);
        res = draw_frame(o, r, d->background, d->frame);
    }
    if (res == HT_OK) offscreen_read_box(o, HT_MEASURE_SUPERSAMPLE, 4, false, rgba);
    else
        ht_set_error(err, err_size, "measure: the supersampled reference (%s) at %dx%d: %s", ht_tier_name(d->tier), w,
                     h, ht_result_string(res));
    ht_renderer_destroy(r);
    offscreen_close(o);
    return res;
}

static void quiet(void *user, const char *line) { (void)user, (void)line; }

/* The reference pair timed again after every other cell of its size, the
   faster of its two times the size's base: its first frames in a new
   context can run slow (NVIDIA: level 0 of the vertex tier at 0.6x it at a
   quarter size, 1.1x at a half), and a slow base makes every cell look
   cheap. cells[0] is the reference, cells[0..n) the size's. */
static ht_result retime_reference(offscreen *o, const char *dir, const ht_manifest *bundle, const ht_scene *s,
                                  const ht_frame_desc *f, const ht_mesh *full, lod_images *im, ht_measure_lod_cell *cells,
                                  int n, bool truth, char *err, size_t err_size) {
    ht_renderer *r = NULL;
    double ms = 0;
    ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = dir,
                                                            .tier = bundle->tiers[0].tier, .strict = true,
                                                            .policy = "best", .log = quiet }, /* logged before */
                                       &r);
    if (res == HT_OK) res = draw_level(o, r, s, f, full, 1.0f, truth, im->cur, &ms);
    ht_renderer_destroy(r);
    if (res != HT_OK)
        return ht_fail(err, err_size, res, "measure: lods: %s level 0 again: %s", bundle->tiers[0].name,
                       ht_result_string(res));
    const double base = fmin(cells[0].frame_ms, ms);
    if (!(base > 0)) return HT_OK;
    cells[0].frame_ms = base;
    for (int i = 0; i < n; i++) cells[i].cost_ratio = cells[i].frame_ms / base;
    return HT_OK;
}

/* Every tier at every level at one size into out->cells. */
static ht_result measure_size(const char *dir, const ht_manifest *bundle, const ht_scene *scene, double size,
                              const lod_levels *levels, const ht_mesh *head, ht_measure_lods *out,
                              char *err, size_t err_size) {
    ht_scene s = *scene;
    s.width = (int)fmax(16, lround(scene->width * size));
    s.height = (int)fmax(16, lround(scene->height * size));
    char why[1024];
    const size_t bytes = (size_t)s.width * (size_t)s.height * 4;
    lod_images im = { .base = malloc(bytes), .prev = malloc(bytes), .cur = malloc(bytes), .zero = malloc(bytes) };
    ht_result res = im.base && im.prev && im.cur && im.zero ? HT_OK : HT_ERR_OUT_OF_MEMORY;
    const ht_frame_desc f = { .camera = s.camera, .lights = s.lights, .light_count = s.light_count,
                              .aspect = (float)s.width / (float)s.height, .opaque = head->index_count ? head : NULL };
    if (res == HT_OK && out->reference == HT_LOD_REFERENCE_SUPERSAMPLE)
        res = ht_measure_truth(&(ht_measure_truth_desc){ .bundle_dir = dir, .tier = bundle->tiers[0].tier,
                                                         .width = s.width, .height = s.height, .egl_device = -1,
                                                         .background = { s.background[0], s.background[1],
                                                                         s.background[2] },
                                                         .frame = &f, .mesh = &levels->mesh[0] },
                               im.base, err, err_size);
    offscreen *o = res == HT_OK ? offscreen_open(&(offscreen_desc){ .width = s.width, .height = s.height,
                                                                    .egl_device = -1, .samples = out->samples },
                                                 why, sizeof why)
                                : NULL;
    if (!o) {
        free(im.base);
        free(im.prev);
        free(im.cur);
        free(im.zero);
        return res != HT_OK ? res : ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "measure: lods: %s", why);
    }
    const int first_cell = out->count;
    out->warmup_ms = offscreen_warmup_ms(o);
    for (int t = 0; t < bundle->tier_count && res == HT_OK; t++) {
        const ht_manifest_tier *tier = &bundle->tiers[t];
        ht_renderer *r = NULL;
        ht_result made = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = dir,
                                                                 .tier = tier->tier, .strict = true,
                                                                 .policy = "best", .log = NULL },
                                            &r);
        if (made != HT_OK) {
            if (t == 0) {
                res = ht_fail(err, err_size, made, "measure: lods: %s at size %g: %s", tier->name, size,
                              ht_result_string(made));
            } else if (!strstr(out->skipped, tier->name)) {
                const size_t n = strlen(out->skipped);
                snprintf(out->skipped + n, sizeof out->skipped - n, "%s%s", n ? " " : "", tier->name);
            }
            continue;
        }
        res = measure_tier(o, r, &s, &f, tier->name, size, levels, t == 0, &im, out, err, err_size);
        ht_renderer_destroy(r);
    }
    if (res == HT_OK && im.base_ms <= 0 && !out->count)
        res = ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "measure: lods: no tier drew at size %g", size);
    if (res == HT_OK && out->count > first_cell)
        res = retime_reference(o, dir, bundle, &s, &f, &levels->mesh[0], &im, &out->cells[first_cell],
                               out->count - first_cell, out->reference == HT_LOD_REFERENCE_SUPERSAMPLE, err, err_size);
    free(im.base);
    free(im.prev);
    free(im.cur);
    free(im.zero);
    offscreen_close(o);
    return res;
}

/* dir/lods.bin's levels into levels (count 0: none, or another scene's:
   mesh[0], the scene's own, is kept). */
static ht_result stored_levels(const char *dir, lod_levels *levels, char *err, size_t err_size) {
    char path[4096], why[512];
    snprintf(path, sizeof path, "%s/%s", dir, HT_LOD_FILE_NAME);
    if (access(path, F_OK) != 0) return HT_OK;
    ht_lod_file f;
    if (ht_lod_file_read(path, &f, why, sizeof why) != HT_OK)
        return ht_fail(err, err_size, HT_ERR_PARSE, "measure: lods: %s", why);
    ht_result r = HT_OK;
    if (ht_lod_file_matches(&f, &levels->mesh[0])) {
        for (int l = 0; l < f.level_count && r == HT_OK; l++) {
            /* level 0 not stored (a plain bundle's): mesh[0], the scene's, is it */
            if (f.levels[l].kind != HT_LOD_KIND_SCENE) {
                ht_mesh_free(&levels->mesh[l]);
                r = ht_lod_file_level_mesh(&f, l, &levels->mesh[l]);
            }
            levels->cards[l] = f.levels[l].kind == HT_LOD_KIND_CARDS;
            levels->count = l + 1;
        }
        if (r != HT_OK) ht_set_error(err, err_size, "measure: lods: %s: %s", path, ht_result_string(r));
    }
    ht_lod_file_free(&f);
    return r;
}

bool ht_measure_lods_softens_valid(const ht_measure_lods_desc *d) {
    for (int k = 0; k < HT_LOD_MAX_SOFTENS && d->soften[k] != 0.0f; k++) {
        if (!(d->soften[k] > 1.0f && d->soften[k] <= HT_LOD_MAX_SOFTEN)) return false;
        for (int j = 0; j < k; j++)
            if (d->soften[j] == d->soften[k]) return false;
    }
    return true;
}

ht_result ht_measure_lods_run(const char *dir, const ht_scene *scene, const char *scene_file,
                              const ht_measure_lods_desc *desc, ht_measure_lods *out, char *err, size_t err_size) {
    if (err && err_size) err[0] = '\0';
    memset(out, 0, sizeof *out);
    const ht_measure_lods_desc d = desc ? *desc : (ht_measure_lods_desc){ 0 };
    if (d.samples != 0 && (d.samples < 2 || d.samples > HT_MANIFEST_MAX_LOD_SAMPLES))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "measure: lods: --lod-samples: %d, expected 2..%d",
                       d.samples, HT_MANIFEST_MAX_LOD_SAMPLES);
    if (!ht_measure_lods_softens_valid(&d))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT,
                       "measure: lods: --lod-soften: expected factors in (1, %g], each once", (double)HT_LOD_MAX_SOFTEN);
    out->samples = d.samples;
    out->reference = d.reference;
    ht_manifest *bundle = malloc(sizeof *bundle);
    lod_levels *levels = calloc(1, sizeof *levels);
    ht_mesh head = { 0 };
    char why[1024];
    if (levels) {
        for (int k = 0; k < HT_LOD_MAX_SOFTENS && d.soften[k] != 0.0f; k++) levels->soften[levels->soften_count++] = d.soften[k];
        static const float defaults[] = HT_LOD_DEFAULT_SOFTENS;
        _Static_assert(sizeof defaults / sizeof defaults[0] <= HT_LOD_MAX_SOFTENS, "HT_LOD_DEFAULT_SOFTENS");
        if (!levels->soften_count) {
            memcpy(levels->soften, defaults, sizeof defaults);
            levels->soften_count = (int)(sizeof defaults / sizeof defaults[0]);
        }
    }
    ht_result r = bundle && levels ? ht_manifest_load(dir, bundle, why, sizeof why) : HT_ERR_OUT_OF_MEMORY;
    if (r != HT_OK) {
        ht_set_error(err, err_size, "measure: lods: %s", bundle && levels ? why : "out of memory");
        free(bundle);
        free(levels);
        return r;
    }
    r = ht_scene_build_meshes(scene, scene_file ? scene_file : "<scene>", &levels->mesh[0], &head, why, sizeof why);
    if (r != HT_OK) ht_set_error(err, err_size, "measure: lods: %s", why);
    if (r == HT_OK) r = stored_levels(dir, levels, err, err_size);
    if (r == HT_OK && !levels->count) {
        levels->count = ht_lod_max_level(&levels->mesh[0]) + 1;
        for (int l = 1; l < levels->count && r == HT_OK; l++) {
            ht_lod_desc d;
            ht_lod_level(l, &d);
            r = ht_mesh_build_lod(&levels->mesh[0], &d, &levels->mesh[l]);
            if (r != HT_OK) ht_set_error(err, err_size, "measure: lods: level %d: %s", l, ht_result_string(r));
        }
    }
    for (int k = 0; k < (r == HT_OK ? levels->soften_count : 0); k++)
        for (int l = 1; l < levels->count && r == HT_OK; l++)
            if (!levels->cards[l] && (r = ht_mesh_widen_back_to_front(&levels->mesh[l], levels->soften[k],
                                                                       scene->camera.eye, &levels->soft[k][l])) != HT_OK)
                ht_set_error(err, err_size, "measure: lods: level %d soft %g: %s", l, (double)levels->soften[k],
                             ht_result_string(r));
    snprintf(out->tier, sizeof out->tier, "%s", bundle->tiers[0].name);
    for (int i = 0; i < HT_MEASURE_LOD_SIZES && r == HT_OK; i++)
        r = measure_size(dir, bundle, scene, sizes[i], levels, &head, out, err, err_size);
    for (int l = 0; l < HT_LOD_FILE_MAX_LEVELS; l++) {
        ht_mesh_free(&levels->mesh[l]);
        for (int k = 0; k < HT_LOD_MAX_SOFTENS; k++) ht_mesh_free(&levels->soft[k][l]);
    }
    free(levels);
    ht_mesh_free(&head);
    free(bundle);
    if (r != HT_OK) out->count = 0;
    return r;
}

static void add_psnr(cJSON *o, const char *key, double db) {
    if (isinf(db)) cJSON_AddNullToObject(o, key);
    else cJSON_AddNumberToObject(o, key, round(fmin(db, HT_MANIFEST_MAX_PSNR_DB) * 100) / 100);
}

static cJSON *lods_object(const ht_measure_lods *m) {
    cJSON *o = cJSON_CreateObject(), *cells = cJSON_CreateArray();
    cJSON_AddStringToObject(o, HT_MANIFEST_KEY_LOD_TIER, m->tier);
    if (m->samples) cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_SAMPLES, m->samples);
    if (m->reference == HT_LOD_REFERENCE_SUPERSAMPLE)
        cJSON_AddStringToObject(o, HT_MANIFEST_KEY_LOD_REFERENCE, "supersample");
    for (int i = 0; i < m->count; i++) {
        const ht_measure_lod_cell *c = &m->cells[i];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_LEVEL, c->level);
        if (c->cards) cJSON_AddStringToObject(j, HT_MANIFEST_KEY_LOD_KIND, "cards");
        if (c->soften > 1) cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_SOFTEN, c->soften);
        cJSON_AddStringToObject(j, HT_MANIFEST_KEY_LOD_TIER, c->tier);
        cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_STRANDS, c->strands);
        cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_SIZE, c->size);
        add_psnr(j, HT_MANIFEST_KEY_PSNR_DB, c->whole.psnr_db);
        cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_SSIM, round(c->whole.ssim * 1e4) / 1e4);
        cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_DELTA_E00_MEAN, round(c->whole.delta_e00_mean * 1e3) / 1e3);
        /* A frame too fast to time still costs something: never 0. */
        cJSON_AddNumberToObject(j, HT_MANIFEST_KEY_COST_RATIO, fmax(1e-4, round(c->cost_ratio * 1e4) / 1e4));
        add_psnr(j, HT_MANIFEST_KEY_POP_PSNR_DB, c->pop_psnr_db);
        cJSON_AddItemToArray(cells, j);
    }
    cJSON_AddItemToObject(o, HT_MANIFEST_KEY_CELLS, cells);
    return o;
}

static bool write_text(FILE *f, void *ctx, char *why, size_t why_size) {
    (void)why;
    (void)why_size;
    return fputs(ctx, f) >= 0;
}

ht_result ht_measure_lods_write(const char *dir, const ht_measure_lods *m, char *err, size_t err_size) {
    char path[4096], why[1024];
    if (snprintf(path, sizeof path, "%s/%s", dir, HT_MANIFEST_FILE) >= (int)sizeof path)
        return ht_fail(err, err_size, HT_ERR_IO, "measure: lods: %s: path too long", dir);
    char *text = NULL;
    ht_result r = ht_json_read_file(path, &text, why, sizeof why);
    if (r != HT_OK) return ht_fail(err, err_size, r, "measure: lods: %s", why);
    cJSON *root = cJSON_Parse(text);
    free(text);
    if (!root) return ht_fail(err, err_size, HT_ERR_PARSE, "measure: lods: %s: not JSON", path);
    cJSON_DeleteItemFromObjectCaseSensitive(root, HT_MANIFEST_KEY_LODS);
    cJSON_AddItemToObject(root, HT_MANIFEST_KEY_LODS, lods_object(m));
    char *out = cJSON_Print(root);
    cJSON_Delete(root);
    if (!out) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "measure: lods: out of memory");
    /* The runtime must read what is written. */
    ht_manifest *check = malloc(sizeof *check);
    r = check ? ht_manifest_parse(out, dir, path, check, why, sizeof why) : HT_ERR_OUT_OF_MEMORY;
    if (r != HT_OK) ht_set_error(err, err_size, "measure: lods: the runtime refuses the manifest: %s", check ? why : "out of memory");
    if (r == HT_OK) r = ht_file_write_atomic(path, write_text, out, err, err_size);
    free(check);
    cJSON_free(out);
    return r;
}

void ht_measure_lods_print(FILE *out, const ht_measure_lods *m) {
    fprintf(out, "lods: every (level, tier) against (level 0, %s) at each size; pop = PSNR against the tier's level before\n",
            m->tier);
    if (m->skipped[0]) fprintf(out, "lods: not run on this context: %s\n", m->skipped);
    if (m->samples) fprintf(out, "lods: every frame with %d samples a pixel\n", m->samples);
    if (m->warmup_ms > 0)
        fprintf(out, "lods: every cell timed after %g ms of warm-up frames (a GPU's clock rises under load)\n",
                m->warmup_ms);
    if (m->reference == HT_LOD_REFERENCE_SUPERSAMPLE)
        fprintf(out, "lods: against level 0 supersampled 4x4 (the truth), every cell drawn with the width rule\n");
    fprintf(out, "%5s %5s %-10s %8s %9s %7s %9s %9s %9s\n", "size", "level", "tier", "strands", "cost", "psnr_db", "ssim",
            "de00", "pop_db");
    for (int i = 0; i < m->count; i++) {
        const ht_measure_lod_cell *c = &m->cells[i];
        fprintf(out, "%5.2f %5d %-10s %8u %9.3f %7.2f %9.4f %9.3f %9.2f", c->size, c->level, c->tier, c->strands,
                c->cost_ratio, c->whole.psnr_db, c->whole.ssim, c->whole.delta_e00_mean, c->pop_psnr_db);
        if (c->soften > 1) fprintf(out, " soft %g", (double)c->soften);
        fprintf(out, "\n");
    }
}

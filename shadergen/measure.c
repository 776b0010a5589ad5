/* measure.c — hairgen --measure (measure.h): every tier of a finished
   bundle rendered offscreen (platform/offscreen.h: OSMesa, else EGL, both
   loaded with dlopen only here, so hairgen links no GL), compared with full
   and timed against it, the numbers written into the manifest. */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cJSON.h>

#include "errfmt.h"
#include "json_check.h"
#include "measure.h"
#include "offscreen.h"

/* ---- the clock (what examples/timing.h gives the programs) ---- */

double ht_measure_clock_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static int compare_doubles(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

double ht_measure_median(double *v, int n) {
    qsort(v, (size_t)n, sizeof *v, compare_doubles);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- measuring ---- */

/* One tier's context, renderer and timings. A context per tier keeps one
   tier's GL state from leaking into the next, as tier_sheet does. */
typedef struct tier_run {
    const ht_manifest_tier *entry;
    ht_variant variant;           /* HT_VARIANT_DEVICE: the tier's device-only variant */
    const unsigned char *rgba;    /* its last frame, rows bottom-up (the context's pixels) */
    offscreen *ctx;
    ht_renderer *renderer;
    double ms[HT_MEASURE_TIMED_FRAMES];
    char last_log[HT_LOG_LINE_MAX];
} tier_run;

static void keep_last_line(void *user, const char *line) {
    tier_run *t = user;
    const char *prefix = "hairtier: ";
    size_t n = strlen(prefix);
    snprintf(t->last_log, sizeof t->last_log, "%s", strncmp(line, prefix, n) == 0 ? line + n : line);
}

void ht_measure_scene_label(const char *scene_path, char out[64]) {
    if (!scene_path) {
        snprintf(out, 64, "%s", HT_MEASURE_BUILT_IN_SCENE);
        return;
    }
    const char *slash = strrchr(scene_path, '/');
    const char *base = slash ? slash + 1 : scene_path;
    size_t n = strlen(base);
    if (n > 63) {
        n = 63;
        while (n > 0 && ((unsigned char)base[n] & 0xC0) == 0x80) n--; /* not inside a UTF-8 character */
    }
    memcpy(out, base, n);
    out[n] = '\0';
}

/* HAIRGEN_OSMESA, HAIRGEN_EGL: other files to load (a Mesa built elsewhere). */
static const char *library_env(const char *name) {
    const char *named = getenv(name);
    return named && named[0] ? named : NULL;
}

static ht_result start_tier(tier_run *t, const char *dir, const ht_scene *s, const ht_mesh *hair, char *err,
                            size_t err_size) {
    char why[1024];
    t->ctx = offscreen_open(&(offscreen_desc){ .width = s->width, .height = s->height, .egl_device = -1,
                                               .osmesa_library = library_env("HAIRGEN_OSMESA"),
                                               .egl_library = library_env("HAIRGEN_EGL") },
                            why, sizeof why);
    if (!t->ctx)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "measure: %s (HAIRGEN_OSMESA, HAIRGEN_EGL name other "
                       "libraries)", why);
    /* Forced and strict: a tier that cannot run fails the measurement
       instead of measuring another tier under its name. The policy is
       explicit so that HAIRTIER_POLICY cannot fail the create. */
    t->last_log[0] = '\0';
    ht_result r = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = dir,
                                                          .tier = t->entry->tier, .strict = true,
                                                          .log = keep_last_line, .log_user = t, .policy = "best",
                                                          .variant = t->variant ? t->variant : HT_VARIANT_EXACT },
                                     &t->renderer);
    if (r == HT_OK) {
        t->last_log[0] = '\0';
        r = ht_renderer_set_mesh(t->renderer, hair);
    }
    if (r != HT_OK) {
        /* The runtime's line names the tier already ("full: needs GL 2.1, ..."). */
        const char *why = t->last_log[0] ? t->last_log : ht_result_string(r);
        size_t n = strlen(t->entry->name);
        bool named = strncmp(why, t->entry->name, n) == 0 && why[n] == ':';
        return ht_fail(err, err_size, r, "measure: a tier cannot run here: %s%s%s", named ? "" : t->entry->name,
                       named ? "" : ": ", why);
    }
    return HT_OK;
}

/* One frame of tier t: clear, draw, glFinish, timed together (what
   hairview and tier_sheet time). */
static ht_result draw_frame(tier_run *t, const ht_scene *s, const ht_frame_desc *frame, double *ms,
                            char *err, size_t err_size) {
    if (!offscreen_make_current(t->ctx))
        return ht_fail(err, err_size, HT_ERR_GL, "measure: %s: cannot make its context current (%s)",
                       t->entry->name, t->ctx->display);
    t->last_log[0] = '\0';
    const offscreen_gl *gl = &t->ctx->gl;
    double t0 = ht_measure_clock_ms();
    gl->ClearColor(s->background[0], s->background[1], s->background[2], 1.0f);
    gl->Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_result r = ht_renderer_draw(t->renderer, frame);
    gl->Finish();
    *ms = ht_measure_clock_ms() - t0;
    t->rgba = offscreen_read(t->ctx); /* untimed: EGL reads the frame back */
    if (r != HT_OK)
        return ht_fail(err, err_size, r, "measure: %s: draw failed: %s", t->entry->name,
                       t->last_log[0] ? t->last_log : ht_result_string(r));
    return HT_OK;
}

static void stop_tier(tier_run *t) {
    /* The renderer's GL objects live in its own context. */
    if (t->ctx && t->renderer && offscreen_make_current(t->ctx)) ht_renderer_destroy(t->renderer);
    offscreen_close(t->ctx);
    *t = (tier_run){ 0 };
}

/* Pixels of a frame that are not the scene's background (more than one
   step of 255 off in a channel: the clear colour is quantised). */
static long hair_pixels(const unsigned char *rgba, const ht_scene *s) {
    int bg[3];
    for (int c = 0; c < 3; c++) bg[c] = (int)lrintf(s->background[c] * 255.0f);
    long n = 0;
    for (size_t i = 0; i < (size_t)s->width * (size_t)s->height; i++)
        for (int c = 0; c < 3; c++)
            if (abs(rgba[i * 4 + c] - bg[c]) > 1) {
                n++;
                break;
            }
    return n;
}

static ht_result measure_all(tier_run *runs, int count, int full, const char *dir, const ht_scene *s,
                             const char *scene_file, const char *scene_label, ht_measure_result *out, char *err,
                             size_t err_size) {
    ht_mesh hair = { 0 }, head = { 0 };
    char why[1024];
    ht_result r = ht_scene_build_meshes(s, scene_file ? scene_file : scene_label, &hair, &head, why, sizeof why);
    if (r != HT_OK) {
        ht_set_error(err, err_size, "measure: %s", why);
        goto done;
    }
    for (int i = 0; i < count && r == HT_OK; i++) r = start_tier(&runs[i], dir, s, &hair, err, err_size);
    /* Each tier's device-only variant, where its backend has one here. */
    for (int i = 0; i < count && r == HT_OK; i++) {
        tier_run *d = &runs[count + i];
        d->entry = runs[i].entry;
        d->variant = HT_VARIANT_DEVICE;
        r = start_tier(d, dir, s, &hair, err, err_size);
        if (r == HT_OK && ht_renderer_variant(d->renderer) != HT_VARIANT_DEVICE) stop_tier(d);
    }
    const int all = 2 * count;

    ht_frame_desc frame = { .camera = s->camera, .lights = s->lights, .light_count = s->light_count,
                            .aspect = (float)s->width / (float)s->height,
                            .opaque = head.index_count ? &head : NULL };
    if (r != HT_OK) goto done;
    /* Round-robin: frame k of every tier before frame k + 1 of any, so a
       change in the machine's load lands on every tier alike. The warm-up
       rounds go on until ht_timing_warmup_ms has passed (a GPU's clock). */
    out->warmup_ms = ht_timing_warmup_ms(ht_renderer_caps(runs[full].renderer)->renderer);
    const double warm_until = ht_measure_clock_ms() + out->warmup_ms;
    out->warmup_rounds = 0;
    for (int k = 0; k < HT_MEASURE_TIMED_FRAMES && r == HT_OK;) {
        const bool warming = out->warmup_rounds < HT_MEASURE_WARMUP_FRAMES || ht_measure_clock_ms() < warm_until;
        for (int i = 0; i < all && r == HT_OK; i++) {
            if (!runs[i].renderer) continue;
            double ms = 0;
            r = draw_frame(&runs[i], s, &frame, &ms, err, err_size);
            if (!warming) runs[i].ms[k] = ms;
        }
        if (warming) out->warmup_rounds++;
        else k++;
    }
    if (r != HT_OK) goto done;

    snprintf(out->driver, sizeof out->driver, "%s", ht_renderer_caps(runs[full].renderer)->renderer);
    snprintf(out->reference, sizeof out->reference, "%s", runs[full].entry->name);
    double full_ms = ht_measure_median(runs[full].ms, HT_MEASURE_TIMED_FRAMES);
    for (int i = 0; i < count && r == HT_OK; i++) {
        ht_measure_tier *m = &out->tiers[i];
        snprintf(m->name, sizeof m->name, "%s", runs[i].entry->name);
        m->frame_ms = i == full ? full_ms : ht_measure_median(runs[i].ms, HT_MEASURE_TIMED_FRAMES);
        m->cost_ratio = m->frame_ms / full_ms;
        char why[512];
        r = ht_metrics_compare(&(ht_metrics_desc){ .reference = runs[full].rgba, .test = runs[i].rgba,
                                                   .width = s->width, .height = s->height },
                               &m->whole, NULL, why, sizeof why);
        /* The frames are bottom-up; FLIP's kernels are symmetric, so the
           mean and p95 do not depend on the row order. */
        if (r == HT_OK)
            r = ht_flip_compare(&(ht_flip_desc){ .reference = runs[full].rgba, .test = runs[i].rgba,
                                                 .width = s->width, .height = s->height },
                                NULL, &m->flip, why, sizeof why);
        if (r != HT_OK) ht_set_error(err, err_size, "measure: %s: %s", m->name, why);
        const tier_run *d = &runs[count + i];
        if (r != HT_OK || !d->renderer) continue;
        m->device.present = true;
        m->device.frame_ms = ht_measure_median(runs[count + i].ms, HT_MEASURE_TIMED_FRAMES);
        m->device.cost_ratio = m->device.frame_ms / full_ms;
        r = ht_metrics_compare(&(ht_metrics_desc){ .reference = runs[full].rgba, .test = d->rgba,
                                                   .width = s->width, .height = s->height },
                               &m->device.whole, NULL, why, sizeof why);
        if (r != HT_OK) ht_set_error(err, err_size, "measure: %s (device variant): %s", m->name, why);
    }
    /* A blank comparison scores every tier "identical": the reference must
       draw hair. Counted on a frame of the hair alone, so a head in view
       does not count as hair. */
    if (r == HT_OK && head.index_count) {
        frame.opaque = NULL;
        double ms;
        r = draw_frame(&runs[full], s, &frame, &ms, err, err_size);
    }
    if (r == HT_OK && hair_pixels(runs[full].rgba, s) == 0)
        r = ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "measure: %s: the reference tier (%s) draws no hair "
                    "pixel over the background: no hair in view to measure the tiers on", scene_label,
                    runs[full].entry->name);
    out->tier_count = count;
done:
    ht_mesh_free(&hair);
    ht_mesh_free(&head);
    return r;
}

ht_result ht_measure_bundle(const char *dir, const ht_scene *scene, const char *scene_file,
                            const char *scene_label, ht_measure_result *out, char *err, size_t err_size) {
    if (!dir || !scene || !scene_label || !out)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "measure: bundle, scene, label and output are required");
    memset(out, 0, sizeof *out);
    snprintf(out->scene, sizeof out->scene, "%s", scene_label);
    out->width = scene->width;
    out->height = scene->height;

    ht_manifest *bundle = malloc(sizeof *bundle);
    tier_run *runs = calloc(2 * HT_MANIFEST_MAX_TIERS, sizeof *runs); /* each tier, then its device variant */
    if (!bundle || !runs) {
        free(bundle);
        free(runs);
        return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "measure: out of memory");
    }
    char why[1024];
    ht_result r = ht_manifest_load(dir, bundle, why, sizeof why);
    if (r != HT_OK) ht_set_error(err, err_size, "measure: %s", why);
    int count = r == HT_OK ? bundle->tier_count : 0, full = -1;
    for (int i = 0; i < count; i++) {
        runs[i].entry = &bundle->tiers[i];
        /* The reference: a Marschner material's marschner tier (its lower
           tiers draw constants fitted to it), else full. */
        if (bundle->tiers[i].tier == HT_TIER_MARSCHNER || (bundle->tiers[i].tier == HT_TIER_FULL && full < 0))
            full = i;
    }
    if (r == HT_OK && full < 0)
        r = ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "measure: %s/%s: tiers: no full tier to measure against",
                    dir, HT_MANIFEST_FILE);
    if (r == HT_OK)
        r = measure_all(runs, count, full, dir, scene, scene_file, scene_label, out, err, err_size);
    for (int i = 0; i < 2 * count; i++) stop_tier(&runs[i]);
    free(runs);
    free(bundle);
    if (r != HT_OK) out->tier_count = 0;
    return r;
}

/* ---- the manifest's measured objects ---- */

static double round_to(double v, double step) { return round(v / step) * step; }

static double round_significant(double v, int digits) {
    if (v == 0.0 || !isfinite(v)) return v;
    double scale = pow(10.0, digits - 1 - floor(log10(fabs(v))));
    return round(v * scale) / scale;
}

/* The reader's ranges (manifest.h), checked before anything is written so
   that hairgen never makes a manifest the runtime refuses. */
/* flip NULL: a variant measured without FLIP (the device-only one). */
static ht_result check_numbers(const char *name, const ht_metrics *w, const ht_flip_result *flip, double cost_ratio,
                               char *err, size_t err_size) {
    const char *field = NULL, *range = NULL;
    double v = 0;
    if (!(w->psnr_db == INFINITY || (w->psnr_db >= 0 && w->psnr_db <= HT_MANIFEST_MAX_PSNR_DB)))
        field = HT_MANIFEST_KEY_PSNR_DB, v = w->psnr_db, range = "[0, 1000] or infinite";
    else if (!(w->ssim >= -1 && w->ssim <= 1))
        field = HT_MANIFEST_KEY_SSIM, v = w->ssim,
        range = "[-1, 1] (a frame under 11x11 pixels has no SSIM window)";
    else if (!(w->delta_e00_mean >= 0 && w->delta_e00_mean <= HT_MANIFEST_MAX_DELTA_E))
        field = HT_MANIFEST_KEY_DELTA_E00_MEAN, v = w->delta_e00_mean, range = "[0, 1000]";
    else if (!(w->delta_e00_p95 >= 0 && w->delta_e00_p95 <= HT_MANIFEST_MAX_DELTA_E))
        field = HT_MANIFEST_KEY_DELTA_E00_P95, v = w->delta_e00_p95, range = "[0, 1000]";
    else if (flip && !(flip->mean >= 0 && flip->mean <= 1))
        field = HT_MANIFEST_KEY_FLIP_MEAN, v = flip->mean, range = "[0, 1]";
    else if (flip && !(flip->p95 >= 0 && flip->p95 <= 1))
        field = HT_MANIFEST_KEY_FLIP_P95, v = flip->p95, range = "[0, 1]";
    else if (!(cost_ratio > 0 && cost_ratio <= HT_MANIFEST_MAX_COST_RATIO))
        field = HT_MANIFEST_KEY_COST_RATIO, v = cost_ratio, range = "(0, 1e6]";
    if (!field) return HT_OK;
    return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "measure: %s: %s: %g is outside %s", name, field, v, range);
}

static ht_result check_tier(const ht_measure_tier *m, char *err, size_t err_size) {
    ht_result r = check_numbers(m->name, &m->whole, &m->flip, m->cost_ratio, err, err_size);
    if (r == HT_OK && m->device.present)
        r = check_numbers(m->name, &m->device.whole, NULL, m->device.cost_ratio, err, err_size);
    return r;
}

static cJSON *measured_object(const ht_metrics *w, const ht_flip_result *flip, double cost_ratio,
                              const ht_measure_result *all) {
    cJSON *o = cJSON_CreateObject();
    /* Identical to full (full itself): null, the reader's "infinite". */
    if (isinf(w->psnr_db)) cJSON_AddNullToObject(o, HT_MANIFEST_KEY_PSNR_DB);
    else cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_PSNR_DB, round_to(w->psnr_db, 0.01));
    cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_SSIM, round_to(w->ssim, 1e-4));
    cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_DELTA_E00_MEAN, round_to(w->delta_e00_mean, 1e-3));
    cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_DELTA_E00_P95, round_to(w->delta_e00_p95, 1e-3));
    if (flip) {
        cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_FLIP_MEAN, round_to(flip->mean, 1e-5));
        cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_FLIP_P95, round_to(flip->p95, 1e-5));
    }
    cJSON_AddNumberToObject(o, HT_MANIFEST_KEY_COST_RATIO, round_significant(cost_ratio, 4));
    cJSON_AddStringToObject(o, HT_MANIFEST_KEY_SCENE, all->scene);
    cJSON_AddStringToObject(o, HT_MANIFEST_KEY_DRIVER, all->driver[0] ? all->driver : "unknown");
    return o;
}

static const ht_measure_tier *find_measured(const ht_measure_result *m, const char *name) {
    for (int i = 0; name && i < m->tier_count; i++)
        if (strcmp(m->tiers[i].name, name) == 0) return &m->tiers[i];
    return NULL;
}

/* The manifest text with every tier's measured object, or NULL with err. */
static char *measured_manifest(const char *path, const ht_measure_result *m, char *err, size_t err_size) {
    char *text = NULL, why[1024];
    if (ht_json_read_file(path, &text, why, sizeof why) != HT_OK) {
        ht_set_error(err, err_size, "measure: %s", why);
        return NULL;
    }
    cJSON *root = cJSON_Parse(text);
    free(text);
    cJSON *tiers = cJSON_GetObjectItemCaseSensitive(root, HT_MANIFEST_KEY_TIERS);
    if (!cJSON_IsArray(tiers)) {
        ht_set_error(err, err_size, "measure: %s: %s: not an array", path, HT_MANIFEST_KEY_TIERS);
        cJSON_Delete(root);
        return NULL;
    }
    int index = 0;
    cJSON *tier;
    cJSON_ArrayForEach(tier, tiers) {
        const char *name = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(tier, HT_MANIFEST_KEY_NAME));
        const ht_measure_tier *mt = find_measured(m, name);
        if (!mt) {
            ht_set_error(err, err_size, "measure: %s: tiers[%d]: \"%s\" was not measured", path, index,
                         name ? name : "(no name)");
            cJSON_Delete(root);
            return NULL;
        }
        cJSON_DeleteItemFromObjectCaseSensitive(tier, HT_MANIFEST_KEY_MEASURED);
        cJSON_AddItemToObject(tier, HT_MANIFEST_KEY_MEASURED, measured_object(&mt->whole, &mt->flip, mt->cost_ratio, m));
        cJSON_DeleteItemFromObjectCaseSensitive(tier, HT_MANIFEST_KEY_MEASURED_DEVICE);
        if (mt->device.present)
            cJSON_AddItemToObject(tier, HT_MANIFEST_KEY_MEASURED_DEVICE,
                                  measured_object(&mt->device.whole, NULL, mt->device.cost_ratio, m));
        index++;
    }
    char *out = cJSON_Print(root);
    cJSON_Delete(root);
    if (!out) ht_set_error(err, err_size, "measure: %s: out of memory", path);
    return out;
}

/* text to path through a temporary sibling renamed over it. */
static ht_result replace_file(const char *path, const char *text, char *err, size_t err_size) {
    char tmp[4200];
    if (snprintf(tmp, sizeof tmp, "%s.measure-tmp", path) >= (int)sizeof tmp)
        return ht_fail(err, err_size, HT_ERR_IO, "measure: %s: path too long", path);
    FILE *f = fopen(tmp, "wb");
    if (!f) return ht_fail(err, err_size, HT_ERR_IO, "measure: %s: cannot write: %s", tmp, strerror(errno));
    size_t len = strlen(text);
    bool ok = fwrite(text, 1, len, f) == len;
    ok = fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0) {
        ht_set_error(err, err_size, "measure: %s: cannot write: %s", path, strerror(errno));
        unlink(tmp);
        return HT_ERR_IO;
    }
    return HT_OK;
}

ht_result ht_measure_write_manifest(const char *dir, const ht_measure_result *m, char *err, size_t err_size) {
    if (!dir || !m) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "measure: bundle and result are required");
    for (int i = 0; i < m->tier_count; i++) {
        ht_result r = check_tier(&m->tiers[i], err, err_size);
        if (r != HT_OK) return r;
    }
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, HT_MANIFEST_FILE) >= (int)sizeof path)
        return ht_fail(err, err_size, HT_ERR_IO, "measure: %s: path too long", dir);
    char *text = measured_manifest(path, m, err, err_size);
    if (!text) return HT_ERR_PARSE;

    /* The runtime must read what is written, every tier measured. */
    ht_manifest *check = malloc(sizeof *check);
    char why[1024];
    ht_result r = check ? ht_manifest_parse(text, dir, path, check, why, sizeof why) : HT_ERR_OUT_OF_MEMORY;
    if (r != HT_OK) ht_set_error(err, err_size, "measure: the runtime refuses the measured manifest: %s",
                                 check ? why : "out of memory");
    for (int i = 0; r == HT_OK && i < check->tier_count; i++)
        if (!check->tiers[i].measured.present)
            r = ht_fail(err, err_size, HT_ERR_PARSE, "measure: %s: tiers[%d]: no measured object", path, i);
    if (r == HT_OK) r = replace_file(path, text, err, err_size);
    free(check);
    cJSON_free(text);
    return r;
}

void ht_measure_print(FILE *out, const ht_measure_result *m) {
    /* Named: a Marschner bundle is measured against its marschner tier. */
    const char *ref = m->reference[0] ? m->reference : "full";
    char warmup[64] = "";
    if (m->warmup_ms > 0) snprintf(warmup, sizeof warmup, " (%g ms of them: a GPU's clock)", m->warmup_ms);
    fprintf(out, "measured: scene %s (%dx%d), driver %s; whole frame against %s; frame ms: median of %d "
                 "after %d warm-up%s, tiers round-robin; cost = ms / %s's ms\n",
            m->scene, m->width, m->height, m->driver, ref, HT_MEASURE_TIMED_FRAMES, m->warmup_rounds, warmup, ref);
    fprintf(out, "%-7s %9s %6s %9s %7s %10s %9s %10s %9s\n", "tier", "frame_ms", "cost", "psnr_db", "ssim",
            "de00_mean", "de00_p95", "flip_mean", "flip_p95");
    for (int i = 0; i < m->tier_count; i++) {
        const ht_measure_tier *t = &m->tiers[i];
        char psnr[32];
        if (isinf(t->whole.psnr_db)) snprintf(psnr, sizeof psnr, "%s", "same");
        else snprintf(psnr, sizeof psnr, "%.2f", t->whole.psnr_db);
        fprintf(out, "%-7s %9.2f %6.3f %9s %7.4f %10.3f %9.3f %10.5f %9.5f\n", t->name, t->frame_ms, t->cost_ratio,
                psnr, t->whole.ssim, t->whole.delta_e00_mean, t->whole.delta_e00_p95, t->flip.mean, t->flip.p95);
        if (!t->device.present) continue;
        const ht_metrics *w = &t->device.whole;
        if (isinf(w->psnr_db)) snprintf(psnr, sizeof psnr, "%s", "same");
        else snprintf(psnr, sizeof psnr, "%.2f", w->psnr_db);
        fprintf(out, "%-7s %9.2f %6.3f %9s %7.4f %10.3f %9.3f  (%s, device-only variant)\n", "  device",
                t->device.frame_ms, t->device.cost_ratio, psnr, w->ssim, w->delta_e00_mean, w->delta_e00_p95,
                t->name);
    }
}

/* Every occurrence of from in s replaced by to (cut to size). */
static void replace_all(char *s, size_t size, const char *from, const char *to) {
    size_t from_len = strlen(from);
    if (!s || size == 0 || from_len == 0) return;
    char out[4096];
    size_t used = 0;
    for (const char *p = s; *p && used + 1 < sizeof out;) {
        if (strncmp(p, from, from_len) == 0) {
            used += (size_t)snprintf(out + used, sizeof out - used, "%s", to);
            if (used >= sizeof out) used = sizeof out - 1;
            p += from_len;
        } else {
            out[used++] = *p++;
        }
    }
    out[used] = '\0';
    snprintf(s, size, "%s", out);
}

ht_result ht_measure_step(void *user, const char *dir, const ht_scene *scene, char *err, size_t err_size) {
    ht_measure_job *job = user;
    /* The runtime reads the unpublished bundle at its temporary path, which
       is longer than out_dir by the suffix. */
    if (strlen(dir) > HT_LIMIT_DIR_PATH)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "measure: %.200s...: the bundle's temporary "
                       "directory path is %zu bytes, more than the %d the runtime reads; use a shorter -o",
                       job->out_dir ? job->out_dir : dir, strlen(dir), HT_LIMIT_DIR_PATH);
    char label[64];
    ht_measure_scene_label(job->scene_path, label);
    ht_result r = ht_measure_bundle(dir, scene, job->scene_path, label, &job->result, err, err_size);
    if (r == HT_OK) r = ht_measure_write_manifest(dir, &job->result, err, err_size);
    if (r == HT_OK && job->lods) r = ht_measure_lods_run(dir, scene, job->scene_path, &job->lod, &job->lods_result, err, err_size);
    if (r == HT_OK && job->lods) r = ht_measure_lods_write(dir, &job->lods_result, err, err_size);
    /* The temporary directory is removed on failure: name the bundle. */
    if (r != HT_OK && job->out_dir) replace_all(err, err_size, dir, job->out_dir);
    return r;
}

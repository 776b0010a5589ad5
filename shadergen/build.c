/* build.c — build.h: one material's tiers, textures and PNG files as jobs
   (jobs.h), so that a single bundle keeps every core busy:

     fit            a Marschner material's Scheuermann constants (lower tiers)
     full, marschner  the GLSL tiers: they read no texture measurement, so
                    they start at once, and glslang builds its tables for
                    their versions (most of validation) while the
                    textures are made
     slot x4        the material's textures, one job each
     pack           albedo and detail packed and measured (sparkle mean,
                    albedo maximum: what the tiers without the mask use)
     fixed, vertex, fixed4, gl11   the tiers that read those measurements
     png            each image encoded as its bundle file as soon as it exists

   The list order is the priority: the full tier's glslang chain is the
   longest, then the textures, then the fixed tier's LUT bake and encoding.
   Every job writes only its own outputs; the errors are picked afterwards
   in the order the steps would run one after another, so neither the
   bytes nor the error depend on the thread count. */
#include "build.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "c_locale.h"
#include "errfmt.h"
#include "jobs.h"

/* Best first: the order the runtime walks. */
enum { TIER_MARSCHNER, TIER_FULL, TIER_VERTEX, TIER_FIXED4, TIER_FIXED, TIER_GL11 };

/* The bundle's full tier carries its mediump variant's measured error. */
static ht_result emit_full_measured(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size) {
    ht_result r = ht_emit_full(plan, out, err, err_size);
    if (r == HT_OK) ht_emit_full_mediump_error(plan, out);
    return r;
}

static ht_result (*const emitters[HT_BUILD_TIERS])(const ht_plan *, ht_tier_output *, char *, size_t) = {
    ht_emit_marschner, emit_full_measured, ht_emit_vertex, ht_emit_fixed4, ht_emit_fixed, ht_emit_gl11
};

/* Whether a tier's emitter reads plan.sparkle_mean or plan.albedo_max, and
   so waits for the textures (test_generate holds the others to it). */
static const bool reads_measurements[HT_BUILD_TIERS] = { false, false, true, true, true, true };

typedef struct step_result {
    ht_result result;
    char err[2048];
} step_result;

typedef struct build {
    const ht_material *m;
    const ht_scene *scene;
    /* Set before the jobs start, then read only: the unmeasured plans the
       tiers that read no measurement use. lower_plan is set by the fit. */
    ht_plan plan, lower_plan;
    /* What the pack job measured into them, for every other tier. */
    ht_plan measured_plan, measured_lower;
    ht_built *out;
    step_result fit, pack, slots[HT_TEX_COUNT], tiers[HT_BUILD_TIERS], pngs[HT_BUILD_TIERS], packed_png[2];
    ht_image made[HT_TEX_COUNT];
    ht_tier_output tiers_out[HT_BUILD_TIERS];
} build;

typedef enum job_kind { JOB_FIT, JOB_TIER, JOB_SLOT, JOB_PACK, JOB_TIER_PNG, JOB_PACKED_PNG } job_kind;

typedef struct build_job {
    build *b;
    job_kind kind;
    int index;   /* the tier, slot or packed image (0 albedo, 1 detail) */
} build_job;

/* Mean of one channel in [0,1]: what a tier that cannot sample the texture
   uses in its place. */
static double channel_mean(const ht_image *img, int channel) {
    size_t n = (size_t)img->width * (size_t)img->height;
    uint64_t sum = 0;
    for (size_t i = 0; i < n; i++) sum += img->pixels[i * (size_t)img->channels + (size_t)channel];
    return n ? (double)sum / (255.0 * (double)n) : 1.0;
}

/* Brightest rgb channel in [0,1]. */
static double rgb_max(const ht_image *img) {
    size_t n = (size_t)img->width * (size_t)img->height;
    int most = 0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3 && c < img->channels; c++) {
            int v = img->pixels[i * (size_t)img->channels + (size_t)c];
            most = v > most ? v : most;
        }
    return (double)most / 255.0;
}

/* A Marschner material: its own tier from plan, every lower tier from
   Scheuermann constants fitted to it (lower_plan); otherwise one plan. */
static void run_fit(build *b) {
    const char *file = b->m->file[0] ? b->m->file : "<material>";
    if (!b->out->physical) return;
    ht_result r = ht_marschner_fit_scheuermann(&b->m->shading, b->scene, &b->out->fit);
    if (r != HT_OK) {
        b->fit.result = ht_fail(b->fit.err, sizeof b->fit.err, r, "%s: fitting Scheuermann constants: out of memory",
                                file);
        return;
    }
    ht_material *fitted = malloc(sizeof *fitted);
    if (!fitted) {
        b->fit.result = ht_fail(b->fit.err, sizeof b->fit.err, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", file);
        return;
    }
    *fitted = *b->m;
    fitted->shading = b->out->fit.shading;
    ht_plan_make(fitted, b->scene, &b->lower_plan);
    free(fitted);
}

static void run_pack(build *b) {
    for (int i = 0; i < HT_TEX_COUNT; i++)
        if (b->slots[i].result != HT_OK || b->fit.result != HT_OK) {
            b->pack.result = HT_ERR_INVALID_ARGUMENT; /* not run: an earlier step's error is the one */
            for (int k = 0; k < HT_TEX_COUNT; k++) ht_image_free(&b->made[k]);
            return;
        }
    ht_built *out = b->out;
    b->pack.result = ht_textures_pack_made(b->m, &b->plan, b->made, &out->albedo, &out->detail, b->pack.err,
                                           sizeof b->pack.err);
    if (b->pack.result != HT_OK) return;
    b->measured_plan = b->plan;
    if (b->plan.sparkle) b->measured_plan.sparkle_mean = channel_mean(&out->detail, 1);
    if (b->plan.base) b->measured_plan.albedo_max = rgb_max(&out->albedo);
    b->measured_lower = b->measured_plan;
    if (out->physical) {
        b->measured_lower = b->lower_plan;
        b->measured_lower.albedo_max = b->measured_plan.albedo_max; /* same textures; no sparkle */
    }
}

static void run_tier(build *b, int t) {
    step_result *s = &b->tiers[t];
    const bool waited = reads_measurements[t];
    /* The Marschner tier waits for nothing: it reads neither result. */
    if ((t != TIER_MARSCHNER && b->fit.result != HT_OK) || (waited && b->pack.result != HT_OK)) {
        s->result = HT_ERR_INVALID_ARGUMENT; /* not run: an earlier step's error is the one */
        return;
    }
    const ht_plan *plan = t == TIER_MARSCHNER ? (waited ? &b->measured_plan : &b->plan)
                                              : (waited ? &b->measured_lower : &b->lower_plan);
    s->result = emitters[t](plan, &b->tiers_out[t], s->err, sizeof s->err);
}

static void encode(const ht_image *img, const char *file, ht_built_png *png, step_result *s) {
    if (!img->pixels) return;
    s->result = ht_png_encode(img, &png->bytes, &png->size);
    if (s->result == HT_ERR_OUT_OF_MEMORY)
        ht_set_error(s->err, sizeof s->err, "%s: out of memory", file);
    else if (s->result != HT_OK)
        ht_set_error(s->err, sizeof s->err, "%s: a %d x %d image of %d channels has no PNG", file, img->width,
                     img->height, img->channels);
}

static void run_tier_png(build *b, int t) {
    if (b->tiers[t].result != HT_OK) return;
    const ht_tier_output *o = &b->tiers_out[t];
    for (int i = 0; i < o->image_count && b->pngs[t].result == HT_OK; i++)
        encode(&o->images[i].image, o->images[i].file, &b->out->tier_png[t][i], &b->pngs[t]);
}

static void run_job(void *arg) {
    build_job *j = arg;
    build *b = j->b;
    ht_c_locale_scope loc = ht_c_locale_enter();
    switch (j->kind) {
    case JOB_FIT: run_fit(b); break;
    case JOB_TIER: run_tier(b, j->index); break;
    case JOB_SLOT:
        b->slots[j->index].result = ht_texture_make_slot(b->m, &b->plan, (ht_texture_slot)j->index,
                                                         &b->made[j->index], b->slots[j->index].err,
                                                         sizeof b->slots[j->index].err);
        break;
    case JOB_PACK: run_pack(b); break;
    case JOB_TIER_PNG: run_tier_png(b, j->index); break;
    case JOB_PACKED_PNG:
        if (b->pack.result == HT_OK)
            encode(j->index == 0 ? &b->out->albedo : &b->out->detail, j->index == 0 ? "albedo.png" : "detail.png",
                   j->index == 0 ? &b->out->albedo_png : &b->out->detail_png, &b->packed_png[j->index]);
        break;
    }
    ht_c_locale_leave(loc);
}

static const char *const job_names[][HT_BUILD_TIERS] = {
    [JOB_FIT] = { "fit" },
    [JOB_TIER] = { "tier marschner", "tier full", "tier vertex", "tier fixed4", "tier fixed", "tier gl11" },
    [JOB_SLOT] = { "texture" },
    [JOB_PACK] = { "pack" },
    [JOB_TIER_PNG] = { "png marschner", "png full", "png vertex", "png fixed4", "png fixed", "png gl11" },
    [JOB_PACKED_PNG] = { "png packed" },
};

/* The job list: see the top of the file for the order. */
static int plan_jobs(build *b, build_job args[HT_JOBS_MAX], ht_job jobs[HT_JOBS_MAX]) {
    int n = 0;
    int tier_job[HT_BUILD_TIERS], pack_job = -1, slot_jobs[HT_TEX_COUNT];
#define ADD(kind_, index_, waits_) \
    (args[n] = (build_job){ b, kind_, index_ },                                                     \
     jobs[n] = (ht_job){ job_names[kind_][kind_ == JOB_TIER || kind_ == JOB_TIER_PNG ? index_ : 0], \
                         run_job, &args[n], waits_ },                                               \
     n++)
    const int fit_job = ADD(JOB_FIT, 0, 0);
    const uint32_t after_fit = (uint32_t)1 << fit_job;
    tier_job[TIER_FULL] = ADD(JOB_TIER, TIER_FULL, after_fit);
    tier_job[TIER_MARSCHNER] = ADD(JOB_TIER, TIER_MARSCHNER, 0);
    uint32_t after_slots = after_fit;
    for (int i = 0; i < HT_TEX_COUNT; i++) {
        slot_jobs[i] = ADD(JOB_SLOT, i, 0);
        after_slots |= (uint32_t)1 << slot_jobs[i];
    }
    pack_job = ADD(JOB_PACK, 0, after_slots);
    const uint32_t after_pack = (uint32_t)1 << pack_job | after_fit;
    tier_job[TIER_FIXED] = ADD(JOB_TIER, TIER_FIXED, after_pack);
    ADD(JOB_TIER_PNG, TIER_FIXED, (uint32_t)1 << tier_job[TIER_FIXED]);
    tier_job[TIER_VERTEX] = ADD(JOB_TIER, TIER_VERTEX, after_pack);
    ADD(JOB_PACKED_PNG, 0, after_pack);
    ADD(JOB_PACKED_PNG, 1, after_pack);
    tier_job[TIER_FIXED4] = ADD(JOB_TIER, TIER_FIXED4, after_pack);
    tier_job[TIER_GL11] = ADD(JOB_TIER, TIER_GL11, after_pack);
    for (int t = 0; t < HT_BUILD_TIERS; t++)
        if (t != TIER_FIXED) ADD(JOB_TIER_PNG, t, (uint32_t)1 << tier_job[t]);
#undef ADD
    return n;
}

static void free_pngs(ht_built_png *p, int count) {
    for (int i = 0; i < count; i++) {
        free(p[i].bytes);
        p[i] = (ht_built_png){ 0 };
    }
}

/* The first error in the order the steps would run one after another
   (the fit, the textures, every tier, then the images encoded in bundle
   order); HT_OK when none. Unsupported tiers are left out, not errors. */
static ht_result first_error(const build *b, char *err, size_t err_size) {
    const step_result *order[4 + HT_TEX_COUNT + 2 * HT_BUILD_TIERS];
    int n = 0;
    order[n++] = &b->fit;
    for (int i = 0; i < HT_TEX_COUNT; i++) order[n++] = &b->slots[i];
    order[n++] = &b->pack;
    for (int t = 0; t < HT_BUILD_TIERS; t++)
        if (b->tiers[t].result != HT_ERR_UNSUPPORTED) order[n++] = &b->tiers[t];
    order[n++] = &b->packed_png[0];
    order[n++] = &b->packed_png[1];
    for (int t = 0; t < HT_BUILD_TIERS; t++) order[n++] = &b->pngs[t];
    for (int i = 0; i < n; i++)
        if (order[i]->result != HT_OK) {
            ht_set_error(err, err_size, "%s", order[i]->err);
            return order[i]->result;
        }
    return HT_OK;
}

ht_result ht_build(const ht_material *m, const ht_scene *scene, int threads, ht_built *out, char *err,
                   size_t err_size) {
    memset(out, 0, sizeof *out);
    build *b = calloc(1, sizeof *b);
    if (!b) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: out of memory", m->file[0] ? m->file : "<material>");
    b->m = m;
    b->scene = scene;
    b->out = out;
    ht_plan_make(m, scene, &b->plan);
    b->lower_plan = b->plan;
    out->physical = m->shading.model == HT_MODEL_MARSCHNER;

    build_job args[HT_JOBS_MAX];
    ht_job jobs[HT_JOBS_MAX];
    ht_jobs_run(jobs, plan_jobs(b, args, jobs), threads);

    ht_result r = first_error(b, err, err_size);
    if (r == HT_OK) {
        out->plan = b->measured_plan;
        for (int t = 0; t < HT_BUILD_TIERS; t++) {
            if (b->tiers[t].result != HT_OK) {
                ht_tier_output_free(&b->tiers_out[t]);
                continue;
            }
            out->tiers[out->tier_count] = b->tiers_out[t];
            memcpy(out->tier_png[out->tier_count], out->tier_png[t], sizeof out->tier_png[t]);
            if (out->tier_count != t) memset(out->tier_png[t], 0, sizeof out->tier_png[t]);
            out->tier_count++;
        }
    } else {
        for (int t = 0; t < HT_BUILD_TIERS; t++) ht_tier_output_free(&b->tiers_out[t]);
        ht_built_free(out);
    }
    free(b);
    return r;
}

void ht_built_free(ht_built *b) {
    if (!b) return;
    for (int t = 0; t < b->tier_count; t++) ht_tier_output_free(&b->tiers[t]);
    for (int t = 0; t < HT_BUILD_TIERS; t++) free_pngs(b->tier_png[t], HT_OUT_MAX_IMAGES);
    free_pngs(&b->albedo_png, 1);
    free_pngs(&b->detail_png, 1);
    ht_image_free(&b->albedo);
    ht_image_free(&b->detail);
    memset(b, 0, sizeof *b);
}

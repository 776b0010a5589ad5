/* renderer.c — the renderer's life: probe the device, select a tier and
   create its backend (falling to the next tier when creation fails), and
   draw a frame between saving and restoring the application's GL state.
   What it orchestrates lives elsewhere, one job per file: caps.c (what the
   device offers), select.c (which tier), backends.c (the tier table),
   validate.c (what callers hand in), mesh_gpu.c (the mesh's buffers and
   arrays), gl_state.c (the app's state and the baseline), opaque_scene.c
   (the head), passes.c (the four passes and the trace). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "caps.h"
#include "errfmt.h"
#include "renderer_internal.h"
#include <hairtier/lod.h>

static void log_stderr(void *user, const char *line) {
    (void)user;
    fprintf(stderr, "%s\n", line);
}

/* Truncating copy (a reason longer than its slot is cut, not dropped). */
static void copy_text(char *dst, size_t size, const char *src) {
    size_t n = strlen(src);
    if (n >= size) n = size - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

static int clamp_int(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

/* Creates bundle tier i's backend be (its variant by the policy, *variant
   and variant_reason say which); err says why not. */
static ht_result make_backend(ht_renderer *r, int i, const ht_tier_backend *be, ht_variant *variant,
                              char *variant_reason, size_t reason_size, void **state, char *err, size_t err_size) {
    *variant = ht_select_variant(&r->bundle.tiers[i], &r->policy, r->variant_request, variant_reason, reason_size);
    ht_tier_context ctx = { .gl = &r->gl, .caps = &r->caps, .bundle = &r->bundle, .tier = &r->bundle.tiers[i],
                            .log = r->log, .log_user = r->log_user, .device_variant = *variant == HT_VARIANT_DEVICE };
    *state = NULL;
    while (r->gl.GetError() != GL_NO_ERROR) {}
    return be->create(&ctx, state, err, err_size);
}

/* A made backend draws from now on, and stays made (ht_renderer_set_tier). */
static void adopt_backend(ht_renderer *r, int i, const ht_tier_backend *be, void *state) {
    r->made[i].backend = be;
    r->made[i].state = state;
    r->made[i].mesh_serial = 0;
    r->backend = be;
    r->backend_state = state;
    r->backend_index = i;
    r->tier = r->bundle.tiers[i].tier;
}

/* Every backend made (the drawing one too): none draws. */
static void destroy_backends(ht_renderer *r) {
    for (int i = 0; i < HT_MANIFEST_MAX_TIERS; i++) {
        if (r->made[i].backend && r->made[i].backend->destroy) r->made[i].backend->destroy(r->made[i].state);
        r->made[i].backend = NULL;
        r->made[i].state = NULL;
    }
    r->backend = NULL;
    r->backend_state = NULL;
    r->tier = HT_TIER_COUNT;
}

/* Selects a tier (requested tier, policy, timings, the tiers already
   failed) and creates its backend, falling to the next tier on failure. */
static ht_result create_backend(ht_renderer *r) {
    char failed_text[HT_MANIFEST_MAX_TIERS][HT_SELECT_REASON];
    ht_select_desc sd = {
        .caps = &r->caps, .extensions = r->extensions, .bundle = &r->bundle, .requested = r->requested,
        .env_tier = getenv("HAIRTIER_TIER"), .strict = r->strict, .policy = r->policy,
    };
    memcpy(sd.frame_ms, r->frame_ms, sizeof sd.frame_ms);
    char err[1024];
    /* Each round's skipped list extends the previous round's (tiers are
       walked best first, a failed one joins the list): log only what is new. */
    int logged = 0;
    for (;;) {
        ht_selection sel;
        ht_result res = ht_select_tier(&sd, &sel, err, sizeof err);
        for (int i = logged; i < sel.skipped_count; i++)
            ht_log_linef(r->log, r->log_user, "hairtier: skipped %s", sel.skipped[i]);
        logged = sel.skipped_count;
        if (res != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
            return res;
        }
        const ht_tier_backend *be = ht_tier_backend_find(sel.tier);
        if (!be) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s: no backend in this runtime", ht_tier_name(sel.tier));
            return HT_ERR_NO_TIER;
        }
        char variant_reason[HT_SELECT_REASON];
        ht_variant variant;
        void *state = NULL;
        res = make_backend(r, sel.index, be, &variant, variant_reason, sizeof variant_reason, &state, err, sizeof err);
        if (res == HT_OK) {
            adopt_backend(r, sel.index, be, state);
            copy_text(r->reason, sizeof r->reason, sel.reason);
            ht_log_linef(r->log, r->log_user, "hairtier: tier %s (%s)", ht_tier_name(r->tier), r->reason);
            if (be->device_variant)
                ht_log_linef(r->log, r->log_user, "hairtier: %s variant: %s%s", ht_tier_name(r->tier), variant_reason,
                             variant == HT_VARIANT_DEVICE && !be->device_variant(state)
                                 ? " (none for this bundle: exact)" : "");
            return HT_OK;
        }
        copy_text(failed_text[sel.index], sizeof failed_text[0], err);
        sd.failed[sel.index] = failed_text[sel.index];
        while (r->gl.GetError() != GL_NO_ERROR) {}
    }
}

/* What this runtime draws on: desktop GL, GL ES 1.1 (the fixed-function
   tiers: combiners, VBOs and the state queries the frame's save needs) or
   GL ES 2.0 and later (a program per tier); a profile names one API. */
static ht_result check_api(ht_renderer *r, const ht_device_profile *p) {
    const ht_caps *c = &r->caps;
    char line[320] = "";
    if (p->es_major && !c->es)
        snprintf(line, sizeof line, "device profile: a GL ES %d.%d device, the context is desktop GL %d.%d (%s): "
                 "make a GL ES context (hairview --api gles%d)", p->es_major, p->es_minor, c->gl_major,
                 c->gl_minor, c->version, p->es_major >= 3 ? 3 : p->es_major);
    else if (c->es && (p->gl_major || p->gl_minor))
        snprintf(line, sizeof line, "device profile: a desktop GL %d.%d device, the context is %s", p->gl_major,
                 p->gl_minor, c->version);
    else if (c->es && p->es_major && (p->es_major < 2) != ht_caps_es1(c))
        snprintf(line, sizeof line, "device profile: a GL ES %d.%d device, the context is %s (ES 1.x is fixed "
                 "function, ES 2.0 on has programs only): make a GL ES %d context (hairview --api gles%d)",
                 p->es_major, p->es_minor, c->version, p->es_major, p->es_major >= 3 ? 3 : p->es_major);
    if (!line[0]) return HT_OK;
    ht_log_linef(r->log, r->log_user, "hairtier: %s", line);
    return HT_ERR_UNSUPPORTED;
}

/* GL ES 1.0 (a context or a profile): no glGetFloatv or glIsEnabled to
   read the application's state back, no combiners, no VBOs. */
static ht_result check_es1(ht_renderer *r) {
    const ht_caps *c = &r->caps;
    if (!ht_caps_es1(c)) return HT_OK;
    if (!ht_caps_gl_at_least(c, 1, 1))
        ht_log_linef(r->log, r->log_user, "hairtier: GL ES %d.%d (%s): needs GL ES 1.1 (ES 1.0 has no state "
                     "queries to save the application's state with, no combiners, no VBOs)", c->gl_major,
                     c->gl_minor, c->version);
    else if (!r->gl.has_fixed)
        ht_log_linef(r->log, r->log_user, "hairtier: %s: a fixed-function entry point is missing (getproc)",
                     c->version);
    else
        return HT_OK;
    return HT_ERR_UNSUPPORTED;
}

/* Asks the app's timer for every tier the device runs (frame:MS with
   desc.time_tier), logging each answer. */
static void time_tiers_by_hook(ht_renderer *r) {
    char why[HT_SELECT_REASON];
    for (int i = 0; i < r->bundle.tier_count; i++) {
        const ht_manifest_tier *t = &r->bundle.tiers[i];
        r->frame_ms[i] = 0.0;
        if (!ht_tier_backend_find(t->tier) || !ht_select_check_requirements(&r->caps, r->extensions, t, why, sizeof why))
            continue;
        double ms = r->time_tier(r->time_tier_user, t->tier);
        if (ms > 0.0 && isfinite(ms)) {
            r->frame_ms[i] = ms;
            ht_log_linef(r->log, r->log_user, "hairtier: timed %s: %.3f ms a frame (desc.time_tier)", t->name, ms);
        } else {
            ht_log_linef(r->log, r->log_user, "hairtier: timed %s: no time (desc.time_tier)", t->name);
        }
    }
}

ht_result ht_renderer_create(const ht_renderer_desc *desc, ht_renderer **out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    ht_log_fn log = desc && desc->log ? desc->log : log_stderr;
    void *log_user = desc ? desc->log_user : NULL;
    if (!desc || !desc->getproc) {
        log(log_user, "hairtier: ht_renderer_desc: getproc: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    const bool has_dir = desc->bundle_dir && desc->bundle_dir[0];
    if (!desc->flat && !has_dir && !desc->bundle_memory) {
        log(log_user, "hairtier: ht_renderer_desc: bundle_dir: required (or bundle_memory)");
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (has_dir && desc->bundle_memory) {
        log(log_user, "hairtier: ht_renderer_desc: bundle_dir and bundle_memory: give one, not both");
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_renderer *r = calloc(1, sizeof *r);
    if (!r) return HT_ERR_OUT_OF_MEMORY;
    r->log = log;
    r->log_user = log_user;
    r->record_trace = desc->record_trace;
    r->flat = desc->flat;
    r->tier = HT_TIER_COUNT;
    r->requested = desc->tier;
    r->strict = desc->strict;
    r->time_tier = desc->time_tier;
    r->time_tier_user = desc->time_tier_user;

    char err[1024];
    const char *policy = desc->policy ? desc->policy : getenv("HAIRTIER_POLICY");
    ht_result res = ht_policy_parse(policy && policy[0] ? policy : NULL, &r->policy, err, sizeof err);
    if (res != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: %s%s", desc->policy ? "ht_renderer_desc: " : "HAIRTIER_POLICY: ", err);
        goto fail;
    }
    const char *variant = getenv("HAIRTIER_VARIANT");
    r->variant_request = desc->variant;
    if (desc->variant == HT_VARIANT_AUTO &&
        (res = ht_variant_parse(variant, &r->variant_request, err, sizeof err)) != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: HAIRTIER_VARIANT: %s", err);
        goto fail;
    }
    res = ht_gl_load(&r->gl, desc->getproc, err, sizeof err);
    if (res != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
        goto fail;
    }
    if ((res = ht_caps_probe_gl(&r->gl, &r->caps, &r->extensions)) != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: glGetString(GL_VERSION): no answer (is a GL context current?)");
        goto fail;
    }
    ht_device_profile profile = desc->profile;
    const char *profile_env = getenv("HAIRTIER_DEVICE_PROFILE");
    if (ht_device_profile_is_zero(&profile) && profile_env && profile_env[0]) {
        if ((res = ht_device_profile_parse(profile_env, &profile, err, sizeof err)) != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: HAIRTIER_DEVICE_PROFILE: %s", err);
            goto fail;
        }
        ht_log_linef(r->log, r->log_user, "hairtier: device profile %s (HAIRTIER_DEVICE_PROFILE)", profile_env);
    }
    if ((res = check_api(r, &profile)) != HT_OK) goto fail;
    ht_caps_apply_profile(&r->caps, &profile);
    ht_caps_hide_extensions(r->extensions, profile.hide_extensions);
    if ((res = check_es1(r)) != HT_OK) goto fail;
    /* The runtime itself must not call what the profile hides. */
    ht_gl_restrict(&r->gl, r->caps.has_3d_textures, r->caps.has_multitexture, r->caps.has_vbo,
                   r->caps.has_shaders);
    /* What the frame's baseline covers beyond the units (renderer.c). */
    GLint lights = HT_MAX_LIGHTS, attribs = 0;
    if (!ht_caps_es_programs(&r->caps)) r->gl.GetIntegerv(GL_MAX_LIGHTS, &lights);
    r->max_lights = clamp_int(lights, HT_MAX_LIGHTS, HT_RENDERER_MAX_LIGHTS);
    if (r->caps.has_shaders) r->gl.GetIntegerv(GL_MAX_VERTEX_ATTRIBS, &attribs);
    r->vertex_attribs = clamp_int(attribs, 0, HT_RENDERER_MAX_ATTRIBS);
    if (ht_caps_es1(&r->caps))
        ht_log_linef(r->log, r->log_user, "hairtier: device GL ES %d.%d (fixed function), %d texture units, %s%s",
                     r->caps.gl_major, r->caps.gl_minor, r->caps.texture_units, r->caps.renderer,
                     r->caps.has_combine ? "" : ", no combiners");
    else if (r->caps.es)
        ht_log_linef(r->log, r->log_user, "hairtier: device GL ES %d.%d, ESSL %d.%02d, fragment %s, %d texture units, %s",
                     r->caps.gl_major, r->caps.gl_minor, r->caps.glsl_major, r->caps.glsl_minor,
                     r->caps.fragment_highp ? "highp" : "mediump only", r->caps.texture_units, r->caps.renderer);
    else
        ht_log_linef(r->log, r->log_user, "hairtier: device GL %d.%d, GLSL %d.%02d, %d texture units, %s%s",
                     r->caps.gl_major, r->caps.gl_minor, r->caps.glsl_major, r->caps.glsl_minor, r->caps.texture_units,
                     r->caps.renderer, r->caps.has_vbo ? "" : ", no VBOs");

    if (has_dir || desc->bundle_memory) {
        res = has_dir ? ht_manifest_load(desc->bundle_dir, &r->bundle, err, sizeof err)
                      : ht_manifest_load_memory(desc->bundle_memory, &r->bundle, err, sizeof err);
        if (res != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
            goto fail;
        }
        r->have_bundle = true;
    }

    if (r->flat) {
        bool zero = desc->flat_color[0] == 0 && desc->flat_color[1] == 0 && desc->flat_color[2] == 0;
        for (int i = 0; i < 3; i++) {
            float c = zero ? 0.5f : desc->flat_color[i];
            r->flat_color[i] = isfinite(c) ? fminf(fmaxf(c, 0.0f), 1.0f) : 0.5f;
        }
        snprintf(r->reason, sizeof r->reason, "flat: geometry floor, one colour, no textures or shaders");
        ht_log_linef(r->log, r->log_user, "hairtier: %s", r->reason);
    } else {
        if (r->policy.kind == HT_POLICY_FRAME && r->time_tier && r->requested == HT_TIER_AUTO) time_tiers_by_hook(r);
        if ((res = create_backend(r)) != HT_OK) goto fail;
    }
    *out = r;
    return HT_OK;
fail:
    ht_renderer_destroy(r);
    return res;
}

ht_tier ht_renderer_tier(const ht_renderer *r) { return r ? r->tier : HT_TIER_COUNT; }
const char *ht_renderer_reason(const ht_renderer *r) { return r ? r->reason : ""; }
ht_variant ht_renderer_variant(const ht_renderer *r) {
    return r && r->backend && r->backend->device_variant && r->backend->device_variant(r->backend_state)
               ? HT_VARIANT_DEVICE
               : HT_VARIANT_EXACT;
}
const ht_trace *ht_renderer_trace(const ht_renderer *r) { return r ? &r->trace : NULL; }
const ht_caps *ht_renderer_caps(const ht_renderer *r) { return r ? &r->caps : NULL; }

ht_renderer_stats ht_renderer_get_stats(const ht_renderer *r) {
    ht_renderer_stats st = { 0 };
    if (!r) return st;
    st.frames = r->frames;
    if (r->backend && r->backend->cpu_vertices) st.cpu_vertices = r->backend->cpu_vertices(r->backend_state);
    return st;
}

void ht_renderer_destroy(ht_renderer *r) {
    if (!r) return;
    destroy_backends(r);
    ht_renderer_release_mesh(r);
    ht_renderer_release_opaque_es(r);
    free(r->extensions);
    free(r);
}

/* ---- the frame:MS policy's timing ---- */

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* Draws bundle tier i for HT_FRAME_TIMING_FRAMES frames after a warm-up
   (ht_timing_warmup_ms); 0 when its backend, the mesh upload or a draw
   fails (logged). */
static double time_tier_by_drawing(ht_renderer *r, int i, const ht_mesh *mesh, const ht_frame_desc *frame) {
    const ht_manifest_tier *t = &r->bundle.tiers[i];
    const ht_tier_backend *be = ht_tier_backend_find(t->tier);
    char err[1024];
    destroy_backends(r);
    char variant_reason[HT_SELECT_REASON];
    ht_variant variant;
    void *state = NULL;
    if (make_backend(r, i, be, &variant, variant_reason, sizeof variant_reason, &state, err, sizeof err) != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: timing %s: %s", t->name, err);
        return 0.0;
    }
    adopt_backend(r, i, be, state);
    if (ht_renderer_set_mesh(r, mesh) != HT_OK) return 0.0;
    const double warmup_ms = ht_timing_warmup_ms(r->caps.renderer);
    for (const double until = now_ms() + warmup_ms;;) {
        if (ht_renderer_draw(r, frame) != HT_OK) return 0.0;
        r->gl.Finish();
        if (now_ms() >= until) break;
    }
    double start = now_ms();
    for (int f = 0; f < HT_FRAME_TIMING_FRAMES; f++)
        if (ht_renderer_draw(r, frame) != HT_OK) return 0.0;
    r->gl.Finish();
    double ms = (now_ms() - start) / HT_FRAME_TIMING_FRAMES;
    ht_log_linef(r->log, r->log_user, "hairtier: timed %s: %.3f ms a frame (mean of %d, after %g ms of warm-up "
                 "frames, at least one)", t->name, ms, HT_FRAME_TIMING_FRAMES, warmup_ms);
    return ms > 0.0 ? ms : 1e-6;
}

ht_result ht_renderer_choose_by_frame_time(ht_renderer *r, const ht_mesh *mesh, const ht_frame_desc *frame,
                                           double budget_ms) {
    static const char what[] = "ht_renderer_choose_by_frame_time";
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (r->flat || !r->have_bundle) return ht_renderer_reject(r, what, "renderer", "flat: no tiers to choose from");
    if (!mesh) return ht_renderer_reject(r, what, "mesh", "NULL");
    if (!frame && !r->time_tier) return ht_renderer_reject(r, what, "frame", "NULL");
    double budget = budget_ms != 0.0 ? budget_ms : r->policy.kind == HT_POLICY_FRAME ? r->policy.value : 0.0;
    if (!(budget > 0.0) || !isfinite(budget))
        return ht_renderer_reject(r, what, "budget_ms", "%g: needs a budget > 0 ms, or the frame:MS policy", budget_ms);
    if (r->requested != HT_TIER_AUTO)
        ht_log_linef(r->log, r->log_user, "hairtier: %s: tier %s is forced; the timings do not change it", what,
                     ht_tier_name(r->requested));
    if (r->time_tier) {
        time_tiers_by_hook(r);
    } else {
        char why[HT_SELECT_REASON];
        for (int i = 0; i < r->bundle.tier_count; i++) {
            const ht_manifest_tier *t = &r->bundle.tiers[i];
            r->frame_ms[i] = 0.0;
            if (ht_tier_backend_find(t->tier) && ht_select_check_requirements(&r->caps, r->extensions, t, why, sizeof why))
                r->frame_ms[i] = time_tier_by_drawing(r, i, mesh, frame);
        }
    }
    destroy_backends(r);
    r->policy = (ht_policy){ HT_POLICY_FRAME, budget };
    ht_result res = create_backend(r);
    if (res == HT_OK) res = ht_renderer_set_mesh(r, mesh);
    return res;
}

/* ---- switching tiers ---- */

ht_result ht_renderer_set_tier(ht_renderer *r, ht_tier tier, const ht_mesh *mesh) {
    static const char what[] = "ht_renderer_set_tier";
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (r->flat || !r->have_bundle) return ht_renderer_reject(r, what, "renderer", "flat: no tiers to switch");
    int i = 0;
    while (i < r->bundle.tier_count && r->bundle.tiers[i].tier != tier) i++;
    if (i == r->bundle.tier_count) return ht_renderer_reject(r, what, "tier", "%s: not in the bundle", ht_tier_name(tier));
    const ht_tier_backend *be = r->made[i].backend ? r->made[i].backend : ht_tier_backend_find(tier);
    if (!be) return ht_renderer_reject(r, what, "tier", "%s: no backend in this runtime", ht_tier_name(tier));
    const bool per_vertex = be->set_mesh && r->has_mesh && r->made[i].mesh_serial != r->mesh_serial;
    if (per_vertex && (!mesh || mesh->vertex_count != r->vertex_count || mesh->index_count != r->index_count))
        return ht_renderer_reject(r, what, "mesh", "the %s tier makes per-vertex data of the mesh set last: "
                                  "give that mesh", ht_tier_name(tier));
    if (per_vertex && r->chunk_count) {
        ht_log_linef(r->log, r->log_user, "hairtier: %s: %s: the mesh is split into 16-bit chunks, which the "
                     "tier's own vertex arrays are not", what, ht_tier_name(tier));
        return HT_ERR_UNSUPPORTED;
    }
    if (!r->made[i].backend) {
        char why[HT_SELECT_REASON], err[1024], variant_reason[HT_SELECT_REASON];
        if (!ht_select_check_requirements(&r->caps, r->extensions, &r->bundle.tiers[i], why, sizeof why)) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s: %s: %s", what, ht_tier_name(tier), why);
            return HT_ERR_UNSUPPORTED;
        }
        ht_variant variant;
        void *state = NULL;
        ht_result res = make_backend(r, i, be, &variant, variant_reason, sizeof variant_reason, &state, err, sizeof err);
        if (res != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s: %s: %s", what, ht_tier_name(tier), err);
            return res;
        }
        r->made[i].backend = be;
        r->made[i].state = state;
        r->made[i].mesh_serial = 0;
        ht_log_linef(r->log, r->log_user, "hairtier: %s: made tier %s", what, ht_tier_name(tier));
    }
    if (per_vertex) {
        ht_result res = be->set_mesh(r->made[i].state, mesh);
        if (res != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s: %s tier: %s", what, ht_tier_name(tier),
                         ht_result_string(res));
            return res;
        }
        r->made[i].mesh_serial = r->mesh_serial;
    }
    r->backend = be;
    r->backend_state = r->made[i].state;
    r->backend_index = i;
    r->tier = tier;
    snprintf(r->reason, sizeof r->reason, "%s", what);
    return HT_OK;
}

/* ---- drawing ---- */

/* The frame proper, between saving and restoring the app's state. */
static ht_result draw_frame(ht_renderer *r, const ht_frame_desc *f, const ht_tier_frame *tf) {
    const ht_gl *gl = &r->gl;
    /* GL ES programs take projection x view as a uniform (glsl_program.c). */
    if (!ht_caps_es_programs(&r->caps)) {
        gl->MatrixMode(GL_PROJECTION);
        gl->LoadMatrixf(tf->projection);
        gl->MatrixMode(GL_MODELVIEW);
        gl->LoadMatrixf(tf->view);
    }
    gl->Enable(GL_DEPTH_TEST);

    if (f->opaque && ht_caps_es_programs(&r->caps)) ht_renderer_draw_opaque_es(r, f->opaque, tf);
    else if (f->opaque) ht_renderer_draw_opaque(r, f->opaque, tf);
    return ht_renderer_draw_passes(r, tf);
}


ht_result ht_renderer_draw(ht_renderer *r, const ht_frame_desc *f) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!f) return ht_renderer_reject(r, "ht_renderer_draw", "frame", "NULL");
    if (!r->flat && !r->backend)
        return ht_renderer_reject(r, "ht_renderer_draw", "renderer", "no tier (ht_renderer_choose_by_frame_time found none)");
    ht_tier_frame tf = { 0 };
    ht_result checked = ht_renderer_check_frame(r, f, &tf);
    if (checked != HT_OK) return checked;
    ht_light lights[HT_MAX_LIGHTS];
    tf.light_count = ht_renderer_plan_lights(r, f, lights);
    tf.lights = lights;
    tf.opacity_cut = r->opacity_cut;
    if (ht_renderer_width_rule_drawn(r)) {
        GLint vp[4] = { 0 };
        r->gl.GetIntegerv(GL_VIEWPORT, vp);
        /* the drawn width's world length at clip w = 1 (shader_interface.h) */
        if (vp[3] > 0 && tf.projection[5] > 0.0f)
            tf.width_rule = (float)HT_WIDTH_RULE_VERTEX_PX * 2.0f / (tf.projection[5] * (float)vp[3]);
    }
    ht_renderer_draw_vertices(r, &tf.first_vertex, &tf.vertex_count);
    while (r->gl.GetError() != GL_NO_ERROR) {}
    r->trace.count = 0;

    ht_gl_state saved;
    ht_result result;
    if (ht_caps_es1(&r->caps)) {
        ht_gl_state_save_es1(r, &saved);
        ht_gl_state_set_baseline_es1(r);
        result = draw_frame(r, f, &tf);
        ht_gl_state_restore_es1(r, &saved);
    } else if (r->caps.es) {
        ht_gl_state_save_es(r, &saved);
        ht_gl_state_set_baseline_es(r);
        result = draw_frame(r, f, &tf);
        ht_gl_state_restore_es(r, &saved);
    } else {
        if ((result = ht_gl_state_save(r, &saved)) != HT_OK) return result;
        ht_gl_state_set_baseline(r);
        result = draw_frame(r, f, &tf);
        ht_gl_state_restore(r, &saved);
    }
    if (result == HT_OK) r->frames++;
    return result;
}

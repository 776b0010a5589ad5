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

#include "caps.h"
#include "errfmt.h"
#include "renderer_internal.h"

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

static ht_result create_backend(ht_renderer *r, const ht_renderer_desc *desc) {
    char failed_text[HT_MANIFEST_MAX_TIERS][HT_SELECT_REASON];
    ht_select_desc sd = {
        .caps = &r->caps, .extensions = r->extensions, .bundle = &r->bundle, .requested = desc->tier,
        .env_tier = getenv("HAIRTIER_TIER"), .strict = desc->strict,
    };
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
        ht_tier_context ctx = { .gl = &r->gl, .caps = &r->caps, .bundle = &r->bundle,
                                .tier = &r->bundle.tiers[sel.index], .log = r->log, .log_user = r->log_user };
        void *state = NULL;
        while (r->gl.GetError() != GL_NO_ERROR) {}
        res = be->create(&ctx, &state, err, sizeof err);
        if (res == HT_OK) {
            r->backend = be;
            r->backend_state = state;
            r->tier = sel.tier;
            copy_text(r->reason, sizeof r->reason, sel.reason);
            ht_log_linef(r->log, r->log_user, "hairtier: tier %s (%s)", ht_tier_name(r->tier), r->reason);
            return HT_OK;
        }
        copy_text(failed_text[sel.index], sizeof failed_text[0], err);
        sd.failed[sel.index] = failed_text[sel.index];
        while (r->gl.GetError() != GL_NO_ERROR) {}
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
    if (!desc->flat && (!desc->bundle_dir || !desc->bundle_dir[0])) {
        log(log_user, "hairtier: ht_renderer_desc: bundle_dir: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_renderer *r = calloc(1, sizeof *r);
    if (!r) return HT_ERR_OUT_OF_MEMORY;
    r->log = log;
    r->log_user = log_user;
    r->record_trace = desc->record_trace;
    r->flat = desc->flat;
    r->tier = HT_TIER_COUNT;

    char err[1024];
    ht_result res = ht_gl_load(&r->gl, desc->getproc, err, sizeof err);
    if (res != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
        goto fail;
    }
    if ((res = ht_caps_probe_gl(&r->gl, &r->caps, &r->extensions)) != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: glGetString(GL_VERSION): no answer (is a GL context current?)");
        goto fail;
    }
    ht_caps_apply_profile(&r->caps, &desc->profile);
    ht_caps_hide_extensions(r->extensions, desc->profile.hide_extensions);
    /* The runtime itself must not call what the profile hides. */
    ht_gl_restrict(&r->gl, r->caps.has_3d_textures, r->caps.has_multitexture, r->caps.has_vbo,
                   r->caps.has_shaders);
    /* What the frame's baseline covers beyond the units (renderer.c). */
    GLint lights = HT_MAX_LIGHTS, attribs = 0;
    r->gl.GetIntegerv(GL_MAX_LIGHTS, &lights);
    r->max_lights = clamp_int(lights, HT_MAX_LIGHTS, HT_RENDERER_MAX_LIGHTS);
    if (r->caps.has_shaders) r->gl.GetIntegerv(GL_MAX_VERTEX_ATTRIBS, &attribs);
    r->vertex_attribs = clamp_int(attribs, 0, HT_RENDERER_MAX_ATTRIBS);
    ht_log_linef(r->log, r->log_user, "hairtier: device GL %d.%d, GLSL %d.%02d, %d texture units, %s%s",
                 r->caps.gl_major, r->caps.gl_minor, r->caps.glsl_major, r->caps.glsl_minor, r->caps.texture_units,
                 r->caps.renderer, r->caps.has_vbo ? "" : ", no VBOs");

    if (desc->bundle_dir && desc->bundle_dir[0]) {
        if ((res = ht_manifest_load(desc->bundle_dir, &r->bundle, err, sizeof err)) != HT_OK) {
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
    } else if ((res = create_backend(r, desc)) != HT_OK) {
        goto fail;
    }
    *out = r;
    return HT_OK;
fail:
    ht_renderer_destroy(r);
    return res;
}

ht_tier ht_renderer_tier(const ht_renderer *r) { return r ? r->tier : HT_TIER_COUNT; }
const char *ht_renderer_reason(const ht_renderer *r) { return r ? r->reason : ""; }
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
    if (r->backend && r->backend->destroy) r->backend->destroy(r->backend_state);
    ht_renderer_release_mesh(r);
    free(r->extensions);
    free(r);
}

/* ---- drawing ---- */

/* The frame proper, between saving and restoring the app's state. */
static ht_result draw_frame(ht_renderer *r, const ht_frame_desc *f, const ht_tier_frame *tf) {
    const ht_gl *gl = &r->gl;
    gl->MatrixMode(GL_PROJECTION);
    gl->LoadMatrixf(tf->projection);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadMatrixf(tf->view);
    gl->Enable(GL_DEPTH_TEST);

    if (f->opaque) ht_renderer_draw_opaque(r, f->opaque, tf);
    return ht_renderer_draw_passes(r, tf);
}


ht_result ht_renderer_draw(ht_renderer *r, const ht_frame_desc *f) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!f) return ht_renderer_reject(r, "ht_renderer_draw", "frame", "NULL");
    ht_tier_frame tf = { 0 };
    ht_result checked = ht_renderer_check_frame(r, f, &tf);
    if (checked != HT_OK) return checked;
    ht_light lights[HT_MAX_LIGHTS];
    tf.light_count = ht_renderer_plan_lights(r, f, lights);
    tf.lights = lights;
    while (r->gl.GetError() != GL_NO_ERROR) {}
    r->trace.count = 0;

    ht_gl_state saved;
    ht_result result = ht_gl_state_save(r, &saved);
    if (result != HT_OK) return result;
    ht_gl_state_set_baseline(r);
    result = draw_frame(r, f, &tf);
    ht_gl_state_restore(r, &saved);
    if (result == HT_OK) r->frames++;
    return result;
}

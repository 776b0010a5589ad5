/* tier_render.c — one tier of a bundle rendered offscreen, timed (tier_render.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/lod.h>

#include "offscreen.h"
#include "../timing.h"
#include "tier_render.h"

ht_result tier_scene_load(const char *path, tier_scene *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    ht_result r = ht_scene_load(path, &out->scene, err, err_size);
    if (r != HT_OK) return r;
    r = ht_scene_build_meshes(&out->scene, path, &out->hair, &out->head, err, err_size);
    if (r != HT_OK) tier_scene_free(out);
    return r;
}

void tier_scene_free(tier_scene *s) {
    ht_mesh_free(&s->hair);
    ht_mesh_free(&s->head);
}

/* How tier_render makes its contexts (tier_render_use_context). */
static offscreen_kind context_kind = OFFSCREEN_AUTO;
static int context_egl_device = -1;
static offscreen_api context_api = OFFSCREEN_API_GL;

void tier_render_use_context(offscreen_kind kind, int egl_device, offscreen_api api) {
    context_kind = kind;
    context_egl_device = egl_device;
    context_api = api;
}

/* The renderer's last log line: why a strict tier did not run. */
static char last_log[512];

static void log_line(void *user, const char *line) {
    (void)user;
    const char *prefix = "hairtier: ";
    snprintf(last_log, sizeof last_log, "%s", strncmp(line, prefix, strlen(prefix)) == 0 ? line + strlen(prefix) : line);
}

static void draw_frame(const offscreen *gl, const ht_scene *s, ht_renderer *r, const ht_frame_desc *f,
                       ht_result *res) {
    gl->gl.ClearColor(s->background[0], s->background[1], s->background[2], 1.0f);
    gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_result fr = ht_renderer_draw(r, f);
    if (fr != HT_OK && *res == HT_OK) *res = fr;
    gl->gl.Finish();
}

/* A fresh context per tier: no GL state leaks from one tier into the next. */
void tier_render(const char *bundle, const tier_scene *ts, ht_tier tier, int frames, tier_frame *out) {
    memset(out, 0, sizeof *out);
    const ht_scene *s = &ts->scene;
    ht_renderer *r = NULL;
    double *times = NULL;
    char err[512];
    offscreen *gl = offscreen_open(&(offscreen_desc){ .kind = context_kind, .width = s->width, .height = s->height,
                                                      .egl_device = context_egl_device, .api = context_api },
                                   err, sizeof err);
    if (!gl) {
        snprintf(out->reason, sizeof out->reason, "%s", err);
        goto done;
    }
    const char *driver = (const char *)gl->gl.GetString(GL_RENDERER);
    snprintf(out->driver, sizeof out->driver, "%s", driver ? driver : "");
    last_log[0] = '\0';
    ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle,
                                                            .tier = tier, .strict = true, .log = log_line },
                                       &r);
    if (res == HT_OK) {
        last_log[0] = '\0'; /* not the creation's "tier ..." line */
        res = ht_renderer_set_mesh(r, &ts->hair);
        if (res == HT_OK && ts->opacity > 0.0f) res = ht_renderer_set_opacity_scale(r, ts->opacity);
    }
    if (res != HT_OK) {
        snprintf(out->reason, sizeof out->reason, "%s", last_log[0] ? last_log : ht_result_string(res));
        goto done;
    }
    ht_frame_desc frame = { .camera = s->camera, .lights = s->lights, .light_count = s->light_count,
                            .aspect = (float)s->width / (float)s->height,
                            .opaque = ts->head.index_count ? &ts->head : NULL };
    times = malloc(sizeof *times * (size_t)frames);
    if (!times) {
        snprintf(out->reason, sizeof out->reason, "out of memory");
        goto done;
    }
    last_log[0] = '\0';
    draw_frame(gl, s, r, &frame, &res); /* warm-up: shader variants, texture uploads */
    for (int i = 0; i < frames; i++) {
        double t0 = now_ms();
        draw_frame(gl, s, r, &frame, &res);
        times[i] = now_ms() - t0;
    }
    if (res != HT_OK) {
        snprintf(out->reason, sizeof out->reason, "%s", last_log[0] ? last_log : ht_result_string(res));
        goto done;
    }
    size_t bytes = (size_t)s->width * (size_t)s->height * 4;
    if (!(out->rgba = malloc(bytes))) {
        snprintf(out->reason, sizeof out->reason, "out of memory");
        goto done;
    }
    memcpy(out->rgba, offscreen_read(gl), bytes);
    out->frame_ms = median(times, frames);
    snprintf(out->reason, sizeof out->reason, "%s", ht_renderer_reason(r));
    out->ran = true;
done:
    free(times);
    ht_renderer_destroy(r);
    offscreen_close(gl);
    if (!out->ran) {
        free(out->rgba);
        out->rgba = NULL;
    }
}

void tier_frame_free(tier_frame *f) {
    free(f->rgba);
    f->rgba = NULL;
}

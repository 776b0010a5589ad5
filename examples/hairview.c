/* hairview — renders a scene with a hairgen bundle offscreen (OSMesa or
   EGL) and writes a PNG.

   build/hairview --bundle DIR --scene SCENE.json [--tier auto|marschner|full|vertex|fixed4|fixed|gl11]
                  [--policy best|fastest|error:DB|error:flip:E|frame:MS] [--strict] [--flat] [--frames N]
                  [--context osmesa|egl] [--egl-device N] -o OUT.png

   --context picks how the GL context is made (examples/offscreen.h; default
   HAIRTIER_CONTEXT, else osmesa where libOSMesa loads, else egl);
   --egl-device N draws on EGL device N (EGL_EXT_platform_device) and implies
   --context egl. A context that cannot be made is one line and exit 1.

   Prints `tier=NAME reason=...` then `frame_ms=...` (the mean of N timed
   frames after one warm-up, each ended by glFinish) on stdout; every skipped
   tier's reason goes to stderr. On any failure: one line naming the file or
   field on stderr, exit status 1, and no PNG. HAIRTIER_TIER is honoured
   unless --tier is given, HAIRTIER_POLICY unless --policy is. With
   frame:MS the scene's mesh and frame are timed on every tier the device
   runs (ht_renderer_choose_by_frame_time) before the timed frames. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/scene.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "offscreen.h"
#include "view_args.h"
#include "timing.h"

typedef struct options {
    view_args view;       /* --bundle, --scene, -o, --frames, the context */
    ht_tier tier;
    const char *policy;   /* NULL → HAIRTIER_POLICY */
    bool strict, flat;
} options;

static char last_log[1024];

static void log_line(void *user, const char *line) {
    (void)user;
    fprintf(stderr, "%s\n", line);
    /* Kept without the library's prefix: it becomes hairview's error line. */
    const char *prefix = "hairtier: ";
    snprintf(last_log, sizeof last_log, "%s", strncmp(line, prefix, strlen(prefix)) == 0 ? line + strlen(prefix) : line);
}

static int usage(const char *why) {
    fprintf(stderr, "hairview: %s\nusage: hairview --bundle DIR --scene SCENE.json "
                    "[--tier auto|marschner|full|vertex|fixed4|fixed|gl11] [--policy best|fastest|error:DB|error:flip:E|frame:MS] [--strict] [--flat] [--frames N] "
                    "[--context osmesa|egl] [--egl-device N] -o OUT.png\n", why);
    return 2;
}

static int parse_args(int argc, char **argv, options *o) {
    *o = (options){ .view = view_args_defaults(10), .tier = HT_TIER_AUTO };
    const char *why = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        bool has_value = i + 1 < argc;
        int taken = view_args_option(argc, argv, &i, &o->view, 100000, &why);
        if (taken < 0) return usage(why);
        if (taken) continue;
        if (strcmp(a, "--tier") == 0 && has_value) {
            o->tier = ht_tier_from_name(argv[++i]);
            if (o->tier == HT_TIER_COUNT) return usage("--tier: expected auto, marschner, full, vertex, fixed4, fixed or gl11");
        } else if (strcmp(a, "--policy") == 0 && has_value) {
            o->policy = argv[++i];
            ht_policy p;
            char err[200], message[240];
            if (ht_policy_parse(o->policy, &p, err, sizeof err) != HT_OK) {
                snprintf(message, sizeof message, "--%s", err);
                return usage(message);
            }
        } else if (strcmp(a, "--strict") == 0) o->strict = true;
        else if (strcmp(a, "--flat") == 0) o->flat = true;
        else {
            char message[300];
            snprintf(message, sizeof message, "%s: unknown option or missing value", a);
            return usage(message);
        }
    }
    if ((why = view_args_check(&o->view, false))) return usage(why);
    if (!o->view.bundle && !o->flat) return usage("--bundle: required (unless --flat)");
    return 0;
}

typedef struct view {
    offscreen *gl;
    ht_mesh hair, head;
    ht_renderer *renderer;
} view;

static void view_free(view *v) {
    ht_renderer_destroy(v->renderer);
    ht_mesh_free(&v->hair);
    ht_mesh_free(&v->head);
    offscreen_close(v->gl);
}

static void draw_frame(const ht_scene *s, const view *v, const ht_frame_desc *frame, ht_result *r) {
    v->gl->gl.ClearColor(s->background[0], s->background[1], s->background[2], 1.0f);
    v->gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_result fr = ht_renderer_draw(v->renderer, frame);
    if (fr != HT_OK && *r == HT_OK) *r = fr;
    v->gl->gl.Finish();
}

static int run(const options *o, view *v) {
    char err[1024];
    ht_scene scene;
    if (ht_scene_load(o->view.scene, &scene, err, sizeof err) != HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    v->gl = offscreen_open(&(offscreen_desc){ .kind = o->view.context, .width = scene.width, .height = scene.height,
                                              .egl_device = o->view.egl_device }, err, sizeof err);
    if (!v->gl) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    fprintf(stderr, "hairview: context %s\n", v->gl->display);

    ht_result r = ht_scene_build_meshes(&scene, o->view.scene, &v->hair, &v->head, err, sizeof err);
    if (r != HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }

    /* The error line is the library's last line after the failing call, so
       none from an earlier call may stand in for it. */
    last_log[0] = '\0';
    r = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = o->view.bundle, .tier = o->tier,
                                                .strict = o->strict, .log = log_line, .flat = o->flat,
                                                .policy = o->policy },
                           &v->renderer);
    if (r != HT_OK) {
        fprintf(stderr, "hairview: %s\n", last_log[0] ? last_log : ht_result_string(r));
        return 1;
    }
    last_log[0] = '\0';
    if ((r = ht_renderer_set_mesh(v->renderer, &v->hair)) != HT_OK) {
        fprintf(stderr, "hairview: %s\n", last_log[0] ? last_log : ht_result_string(r));
        return 1;
    }

    ht_frame_desc frame = { .camera = scene.camera, .lights = scene.lights, .light_count = scene.light_count,
                            .aspect = (float)scene.width / (float)scene.height,
                            .opaque = v->head.index_count ? &v->head : NULL };
    const char *policy_text = o->policy ? o->policy : getenv("HAIRTIER_POLICY");
    ht_policy policy;
    if (!o->flat && ht_policy_parse(policy_text && policy_text[0] ? policy_text : NULL, &policy, err, sizeof err) == HT_OK &&
        policy.kind == HT_POLICY_FRAME) {
        last_log[0] = '\0';
        if ((r = ht_renderer_choose_by_frame_time(v->renderer, &v->hair, &frame, 0)) != HT_OK) {
            fprintf(stderr, "hairview: %s\n", last_log[0] ? last_log : ht_result_string(r));
            return 1;
        }
    }
    ht_result fr = HT_OK;
    last_log[0] = '\0';
    draw_frame(&scene, v, &frame, &fr); /* warm-up: shader variants, texture uploads */
    double t0 = now_ms();
    for (int i = 0; i < o->view.frames; i++) draw_frame(&scene, v, &frame, &fr);
    double ms = (now_ms() - t0) / o->view.frames;
    if (fr != HT_OK) {
        fprintf(stderr, "hairview: %s\n", last_log[0] ? last_log : ht_result_string(fr));
        return 1;
    }

    ht_image img;
    if (ht_image_alloc(&img, scene.width, scene.height, 3) != HT_OK) {
        fprintf(stderr, "hairview: %s: out of memory\n", o->view.out);
        return 1;
    }
    const unsigned char *rgba = offscreen_read(v->gl);
    for (int y = 0; y < scene.height; y++) {
        const unsigned char *src = offscreen_row(rgba, scene.width, scene.height, y);
        unsigned char *dst = img.pixels + (size_t)y * (size_t)scene.width * 3;
        for (int x = 0; x < scene.width; x++) memcpy(dst + 3 * x, src + 4 * x, 3);
    }
    r = ht_image_write_png(o->view.out, &img, err, sizeof err);
    ht_image_free(&img);
    if (r != HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    const char *tier = o->flat ? "flat" : ht_tier_name(ht_renderer_tier(v->renderer));
    printf("tier=%s reason=%s\n", tier, ht_renderer_reason(v->renderer));
    printf("frame_ms=%.3f\n", ms);
    return 0;
}

int main(int argc, char **argv) {
    options o;
    int rc = parse_args(argc, argv, &o);
    if (rc) return rc;
    view v = { 0 };
    rc = run(&o, &v);
    view_free(&v);
    return rc;
}

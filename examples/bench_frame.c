/* bench_frame — the frame cost of each tier against the geometry floor,
   measured side by side in one run on the same context:
   the fur ball of 10 000 hairs x 16 joints at 512 x 512 (--hairs, --size,
   --frames change that), dark-brown, the fur-ball scene's camera and
   lights. The floor is the same mesh drawn in the same four passes with a
   flat colour and no textures or shaders (ht_renderer_desc.flat). Prints
   the median frame time of each, the ratios tier / floor and tier / full,
   and the per-vertex CPU work per frame (ht_renderer_get_stats) with the
   camera still and with it orbiting; frames are taken round-robin.
   Run: make bench (which also runs it on GALLIUM_DRIVER=softpipe, the
   interpreter, a stand-in for a slow fragment unit). --context osmesa|egl
   and --egl-device N pick the GL context as hairview's do
   (examples/offscreen.h); --hairs goes to 1 000 000 (32 M vertices at 16
   joints, about 2 GB of mesh: a real GPU's size, not llvmpipe's). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairgen.h"
#include "hairtier.h"
#include "offscreen.h"
#include "tempdir.h"
#include "timing.h"

#define MAX_FRAMES 64

#define MAX_HAIRS 1000000

static int WIDTH = 512, HEIGHT = 512, FRAMES = 9, HAIRS = 10000;
static offscreen_kind CONTEXT = OFFSCREEN_AUTO;
static int EGL_DEVICE = -1;
static offscreen *gl;   /* the one context every contender draws in */

static void quiet(void *user, const char *line) { (void)user, (void)line; }

typedef struct contender {
    const char *name;
    ht_renderer *renderer;   /* NULL: the tier does not run here */
    double samples[MAX_FRAMES];
    uint64_t cpu_still, cpu_orbit;   /* per-vertex CPU work over the timed frames */
} contender;

static ht_renderer *create(const char *bundle, ht_tier tier, bool flat, const ht_mesh *mesh) {
    ht_renderer *r = NULL;
    if (ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle, .tier = tier,
                                                .strict = true, .flat = flat, .log = quiet }, &r) != HT_OK)
        return NULL;
    if (ht_renderer_set_mesh(r, mesh) != HT_OK) {
        ht_renderer_destroy(r);
        return NULL;
    }
    return r;
}

/* Frames are taken round-robin (floor, full, vertex, fixed, floor, ...), so
   a change in machine load during the run falls on every contender alike. */
static bool time_round_robin(contender *c, int count, const ht_scene *scene) {
    ht_frame_desc frame = { .camera = scene->camera, .lights = scene->lights,
                            .light_count = scene->light_count };
    uint64_t before[8] = { 0 };
    for (int i = -1; i < FRAMES; i++) { /* frame -1 warms up */
        for (int k = 0; k < count; k++) {
            if (!c[k].renderer) continue;
            if (i == 0) before[k] = ht_renderer_get_stats(c[k].renderer).cpu_vertices;
            gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            double t0 = now_ms();
            if (ht_renderer_draw(c[k].renderer, &frame) != HT_OK) return false;
            gl->gl.Finish();
            if (i >= 0) c[k].samples[i] = now_ms() - t0;
        }
    }
    for (int k = 0; k < count; k++)
        if (c[k].renderer) c[k].cpu_still = ht_renderer_get_stats(c[k].renderer).cpu_vertices - before[k];
    return true;
}

/* The camera orbiting the ball, one step per frame (untimed): what per-vertex
   CPU work a moving camera costs each tier. */
static void count_orbit(contender *c, int count, const ht_scene *scene) {
    for (int k = 0; k < count; k++) {
        if (!c[k].renderer) continue;
        uint64_t before = ht_renderer_get_stats(c[k].renderer).cpu_vertices;
        for (int i = 0; i < 4; i++) {
            ht_frame_desc frame = { .camera = scene->camera, .lights = scene->lights,
                                    .light_count = scene->light_count };
            float a = 0.2f * (float)(i + 1), x = frame.camera.eye[0], z = frame.camera.eye[2];
            frame.camera.eye[0] = x * cosf(a) - z * sinf(a);
            frame.camera.eye[2] = x * sinf(a) + z * cosf(a);
            gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            ht_renderer_draw(c[k].renderer, &frame);
        }
        c[k].cpu_orbit = ht_renderer_get_stats(c[k].renderer).cpu_vertices - before;
    }
}

/* Everything but the scratch directory, which main removes whatever this
   returns. */
static int run(const char *work) {
    char err[2048];
    char dir[128];
    snprintf(dir, sizeof dir, "%s/bundle", work);
    ht_scene scene;
    if (ht_scene_load("scenes/furball.json", &scene, err, sizeof err) != HT_OK ||
        ht_generate_bundle("materials/dark-brown.json", "scenes/furball.json", dir, NULL, err, sizeof err) != HT_OK) {
        fprintf(stderr, "bench_frame: %s\n", err);
        return 1;
    }

    gl = offscreen_open(&(offscreen_desc){ .kind = CONTEXT, .width = WIDTH, .height = HEIGHT,
                                           .egl_device = EGL_DEVICE }, err, sizeof err);
    if (!gl) {
        fprintf(stderr, "bench_frame: %s\n", err);
        return 1;
    }

    int status = 1;
    ht_furball_desc fur = scene.furball;
    fur.hairs = HAIRS;
    fur.joints = 16;
    ht_mesh mesh;
    if (ht_mesh_build_furball(&fur, &mesh) != HT_OK) {
        fprintf(stderr, "bench_frame: cannot build the fur ball\n");
        goto close_context;
    }
    ht_mesh_sort_inside_out(&mesh);

    printf("fur ball %d hairs x %d joints (%u triangles), %dx%d, %s (%s), median of %d frames\n", fur.hairs,
           fur.joints, mesh.index_count / 3, WIDTH, HEIGHT, (const char *)gl->gl.GetString(GL_RENDERER), gl->display,
           FRAMES);
    /* Best first, as the bundle lists them; a tier this build lacks is skipped. */
    const char *names[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    enum { TIERS = sizeof names / sizeof names[0] };
    contender c[TIERS + 1] = { { "geometry floor", create(dir, HT_TIER_AUTO, true, &mesh), { 0 }, 0, 0 } };
    for (int k = 0; k < TIERS; k++) {
        ht_tier t = ht_tier_from_name(names[k]);
        c[k + 1] = (contender){ names[k], t == HT_TIER_COUNT ? NULL : create(dir, t, false, &mesh), { 0 }, 0, 0 };
    }
    if (!c[0].renderer || !c[1].renderer || !time_round_robin(c, TIERS + 1, &scene)) {
        fprintf(stderr, "bench_frame: the geometry floor or the full tier did not render\n");
    } else {
        count_orbit(c, TIERS + 1, &scene);
        double floor_ms = median(c[0].samples, FRAMES), full_ms = median(c[1].samples, FRAMES);
        printf("  %-14s %9s %11s %10s %22s\n", "", "median", "/ floor", "/ full", "CPU vertices per frame");
        printf("  %-14s %9s %11s %10s %11s %10s\n", "", "", "", "", "still", "orbiting");
        for (int k = 0; k <= TIERS; k++) {
            if (!c[k].renderer) {
                printf("  %-14s       n/a (does not run here)\n", c[k].name);
                continue;
            }
            double ms = median(c[k].samples, FRAMES);
            printf("  %-14s %8.2f ms %10.2fx %9.2fx %11.0f %10.0f\n", c[k].name, ms, ms / floor_ms, ms / full_ms,
                   (double)c[k].cpu_still / FRAMES, (double)c[k].cpu_orbit / 4);
        }
        status = 0;
    }
    for (int k = 0; k <= TIERS; k++)
        if (c[k].renderer) ht_renderer_destroy(c[k].renderer);
    ht_mesh_free(&mesh);
close_context:
    offscreen_close(gl);
    gl = NULL;
    return status;
}

static bool option(int argc, char **argv, int *i, const char *name, int lo, int hi, int *out) {
    if (strcmp(argv[*i], name) != 0) return false;
    if (*i + 1 >= argc || (*out = atoi(argv[*i + 1])) < lo || *out > hi) {
        fprintf(stderr, "bench_frame: %s takes a number in [%d, %d]\n", name, lo, hi);
        exit(2);
    }
    (*i)++;
    return true;
}

int main(int argc, char **argv) {
    for (int i = 1; i < argc; i++) {
        if (option(argc, argv, &i, "--hairs", 1, MAX_HAIRS, &HAIRS) ||
            option(argc, argv, &i, "--frames", 1, MAX_FRAMES, &FRAMES) ||
            option(argc, argv, &i, "--egl-device", 0, 255, &EGL_DEVICE))
            continue;
        if (strcmp(argv[i], "--context") == 0) {
            if (i + 1 >= argc || !offscreen_kind_parse(argv[i + 1], &CONTEXT)) {
                fprintf(stderr, "bench_frame: --context takes osmesa or egl\n");
                return 2;
            }
            i++;
            continue;
        }
        int size = 0;
        if (option(argc, argv, &i, "--size", 16, 4096, &size)) {
            WIDTH = HEIGHT = size;
            continue;
        }
        fprintf(stderr, "usage: bench_frame [--hairs N] [--size S] [--frames F] [--context osmesa|egl] [--egl-device N]\n");
        return 2;
    }
    if (EGL_DEVICE >= 0 && CONTEXT == OFFSCREEN_OSMESA) {
        fprintf(stderr, "bench_frame: --egl-device needs --context egl\n");
        return 2;
    }
    if (EGL_DEVICE >= 0) CONTEXT = OFFSCREEN_EGL;
    char work[] = "/tmp/hairtier-bench-frame-XXXXXX";
    if (!mkdtemp(work)) {
        perror("mkdtemp");
        return 1;
    }
    int status = run(work);
    if (tempdir_remove(work) != 0) {
        fprintf(stderr, "bench_frame: cannot remove %s\n", work);
        status = 1;
    }
    return status;
}

/* bench_frame — the frame cost of each tier against the geometry floor,
   measured side by side in one run on the same context:
   the fur ball of 10 000 hairs x 16 joints at 512 x 512, dark-brown,
   the fur-ball scene's camera and lights. The floor is the same mesh drawn
   in the same four passes with a flat colour and no textures or shaders
   (ht_renderer_desc.flat). Prints the median frame time of each and the
   ratio tier / floor; frames are taken round-robin. Run: make bench (GALLIUM_DRIVER=softpipe for the
   interpreter, a stand-in for a slow fragment unit). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairgen.h"
#include "hairtier.h"
#include "offscreen.h"
#include "tempdir.h"
#include "timing.h"

#define WIDTH 512
#define HEIGHT 512
#define FRAMES 9

static void quiet(void *user, const char *line) { (void)user, (void)line; }

typedef struct contender {
    const char *name;
    ht_renderer *renderer;   /* NULL: the tier does not run here */
    double samples[FRAMES];
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
    for (int i = -1; i < FRAMES; i++) { /* frame -1 warms up */
        for (int k = 0; k < count; k++) {
            if (!c[k].renderer) continue;
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            double t0 = now_ms();
            if (ht_renderer_draw(c[k].renderer, &frame) != HT_OK) return false;
            glFinish();
            if (i >= 0) c[k].samples[i] = now_ms() - t0;
        }
    }
    return true;
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

    unsigned char *buffer = malloc((size_t)WIDTH * HEIGHT * 4);
    OSMesaContext ctx = offscreen_create(buffer, WIDTH, HEIGHT);
    if (!ctx) {
        fprintf(stderr, "bench_frame: cannot create a %dx%d OSMesa context\n", WIDTH, HEIGHT);
        free(buffer);
        return 1;
    }

    int status = 1;
    ht_furball_desc fur = scene.furball;
    fur.hairs = 10000;
    fur.joints = 16;
    ht_mesh mesh;
    if (ht_mesh_build_furball(&fur, &mesh) != HT_OK) {
        fprintf(stderr, "bench_frame: cannot build the fur ball\n");
        goto close_context;
    }
    ht_mesh_sort_inside_out(&mesh);

    printf("fur ball %d hairs x %d joints (%u triangles), %dx%d, %s, median of %d frames\n", fur.hairs,
           fur.joints, mesh.index_count / 3, WIDTH, HEIGHT, (const char *)glGetString(GL_RENDERER), FRAMES);
    contender c[4] = {
        { "geometry floor", create(dir, HT_TIER_AUTO, true, &mesh), { 0 } },
        { "full", create(dir, HT_TIER_FULL, false, &mesh), { 0 } },
        { "vertex", create(dir, HT_TIER_VERTEX, false, &mesh), { 0 } },
        { "fixed", create(dir, HT_TIER_FIXED, false, &mesh), { 0 } },
    };
    if (!c[0].renderer || !c[1].renderer || !time_round_robin(c, 4, &scene)) {
        fprintf(stderr, "bench_frame: the geometry floor or the full tier did not render\n");
    } else {
        double floor_ms = median(c[0].samples, FRAMES);
        printf("  %-14s %8.2f ms\n", c[0].name, floor_ms);
        for (int k = 1; k < 4; k++) {
            if (!c[k].renderer) {
                printf("  %-14s      n/a (does not run here)\n", c[k].name);
                continue;
            }
            double ms = median(c[k].samples, FRAMES);
            printf("  %-14s %8.2f ms   %.2fx the floor\n", c[k].name, ms, ms / floor_ms);
        }
        status = 0;
    }
    for (int k = 0; k < 4; k++)
        if (c[k].renderer) ht_renderer_destroy(c[k].renderer);
    ht_mesh_free(&mesh);
close_context:
    OSMesaDestroyContext(ctx);
    free(buffer);
    return status;
}

int main(void) {
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

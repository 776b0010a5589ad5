/* test_render_scenes — what `make demo` shows: every shipped scene rendered
   with each tier forced is hair, not a blank or garbage frame (the fur
   ball's bundle by build/hairgen and its best tier by build/hairview, as
   `make demo` runs them; every other frame by the same library calls in
   this process, which is what the programs run too): enough pixels differ from
   the background, the hair is not one flat colour, it has highlights well
   above its median, no pixel is the magenta of a failed shader,
   and the three tiers agree with each other within a measured bound.
   On softpipe (GALLIUM_DRIVER=softpipe, an interpreter) the scenes render
   at 256², the fur ball with 2000 of its 8000 hairs; llvmpipe keeps the
   shipped scenes. `make test`'s softpipe run (support_driver.h) draws the
   fur ball only, in this process, at HT_TEST_DRIVER_SIDE² with
   HT_TEST_DRIVER_HAIRS: every tier on the second driver, held to the same
   bounds; the other scenes differ in geometry and material, prepared on
   the CPU. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_driver.h"
#include "support_render.h"
#include "support_scene.h"
#include "support_scratch.h"

/* The tiers' mean difference from the full tier over hair pixels, in /255:
   what their documented drops cost on the demo scenes (docs/accuracy.md; one bound holds
   at 512² and 256²). */
#define MAX_MEAN_TIER_DIFFERENCE 14.0
/* The vertex tier looks its highlights up per pixel in fixed4's LUTs, so
   it holds a tighter bound. */
#define MAX_MEAN_VERTEX_DIFFERENCE 9.0
/* The softpipe run's side and fur-ball hairs (see the top): softpipe's
   vertex stage interprets, so a quarter of the hairs too. */
#define SOFTPIPE_SIZE 256
#define SOFTPIPE_HAIRS 2000

static char work[64];
/* The one context of the frames drawn in this process (ht_test_view_draw). */
static ht_test_gl gl;

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "scenes") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    if (gl.context) ht_test_gl_destroy(&gl);
    return ht_test_scratch_remove(work);
}

typedef struct frame_stats {
    int hair_pixels;
    double hair_fraction;
    double luminance_median, luminance_p99, luminance_stddev;
    int magenta;
} frame_stats;

static int by_value(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static bool is_hair(const uint8_t *p, const float background[3]) {
    for (int c = 0; c < 3; c++)
        if (abs(p[c] - (int)lroundf(background[c] * 255)) > 3) return true;
    return false;
}

static frame_stats measure(const ht_image *img, const float background[3]) {
    frame_stats s = { 0 };
    size_t n = (size_t)img->width * img->height;
    double *lum = malloc(n * sizeof *lum);
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = img->pixels + i * img->channels;
        if (p[0] > 240 && p[1] < 16 && p[2] > 240) s.magenta++;
        if (!is_hair(p, background)) continue;
        double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        lum[s.hair_pixels++] = y;
        sum += y;
        sum2 += y * y;
    }
    s.hair_fraction = (double)s.hair_pixels / (double)n;
    if (s.hair_pixels > 0) {
        qsort(lum, (size_t)s.hair_pixels, sizeof *lum, by_value);
        s.luminance_median = lum[s.hair_pixels / 2];
        s.luminance_p99 = lum[(size_t)(s.hair_pixels * 0.99)];
        double mean = sum / s.hair_pixels;
        s.luminance_stddev = sqrt(fmax(0.0, sum2 / s.hair_pixels - mean * mean));
    }
    free(lum);
    return s;
}

/* Mean absolute channel difference over pixels that are hair in either image. */
static double mean_difference(const ht_image *a, const ht_image *b, const float background[3]) {
    size_t n = (size_t)a->width * a->height, count = 0;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = a->pixels + i * a->channels, *q = b->pixels + i * b->channels;
        if (!is_hair(p, background) && !is_hair(q, background)) continue;
        for (int c = 0; c < 3; c++) sum += abs(p[c] - q[c]);
        count += 3;
    }
    return count ? sum / (double)count : 0;
}

static bool on_softpipe(void) {
    const char *d = getenv("GALLIUM_DRIVER");
    return d && strcmp(d, "softpipe") == 0;
}

/* The scene as shipped, or on softpipe a copy at SOFTPIPE_SIZE² with at
   most SOFTPIPE_HAIRS (less again in `make test`'s softpipe run) in the
   work directory (everything else unchanged). */
static const char *scene_for_driver(const char *scene_path, char *out, size_t out_size) {
    /* A copy made here is already at its size. */
    if (!on_softpipe() || strncmp(scene_path, work, strlen(work)) == 0) return scene_path;
    return ht_test_scene_copy(scene_path, work, "scene.json", ht_test_driver_side(SOFTPIPE_SIZE),
                              ht_test_driver_hairs(SOFTPIPE_HAIRS), false, out, out_size);
}

/* The bundle of material x scenes/SCENE.json (scene_path: it or a copy)
   and each tier's frame: through the programs when through_programs
   (build/hairgen into work/bundle; build/hairview --tier T --strict
   --frames 1 for the bundle's best tier, its PNG read back: what `make
   demo` draws), else, and for the other tiers, the same calls in this
   process (ht_test_bundle: make's fixture of the pair, the bundle of any
   copy of the scene; support_scene.h's ht_test_view_draw, one frame
   instead of hairview's warm-up and timed one, which is where hairview's
   time goes: its --tier only forces the tier those calls force). */
static int draw_tiers(const char *material, const char *scene, const char *scene_path, bool through_programs,
                      ht_image img[HT_TIER_COUNT], char names[HT_TIER_COUNT][16]) {
    char err[2048], bundle[256], cmd[4096], png[256];
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    if (through_programs) {
        snprintf(cmd, sizeof cmd, "%s/hairgen %s --scene %s -o %s >/dev/null", ht_test_build_dir(), material,
                 scene_path, bundle);
        ht_test_run_command(cmd);
    } else if (ht_test_bundle(material, scene, scene_path, bundle, sizeof bundle, err, sizeof err) != HT_OK) {
        fail_msg("hairgen %s --scene %s: %s", material, scene_path, err);
    }
    const int count = ht_test_bundle_tiers(bundle, names, "full");
    ht_test_view_scene view = { 0 };
    if (!through_programs || count > 1) ht_test_view_scene_load(scene_path, &view);
    for (int t = 0; t < count; t++) {
        if (!through_programs || t > 0) {
            ht_test_view_draw(&gl, bundle, &view, names[t], false, &img[t]);
            continue;
        }
        snprintf(png, sizeof png, "%s/%s.png", work, names[t]);
        snprintf(cmd, sizeof cmd, "%s/hairview --bundle %s --scene %s --tier %s --strict --frames 1 -o %s >/dev/null 2>&1",
                 ht_test_build_dir(), bundle, scene_path, names[t], png);
        ht_test_run_command(cmd);
        assert_int_equal(ht_image_read_png(png, &img[t], err, sizeof err), HT_OK);
    }
    ht_test_view_scene_free(&view);
    return count;
}

/* min_hair: the least fraction of the frame that is not background;
   compare_tiers: hold every tier to the bounds on its difference from full
   (the shipped demo frames). */
static void render_every_tier(const char *material, const char *scene_name, const char *shipped_scene,
                              double min_hair, bool compare_tiers, bool through_programs) {
    char err[2048], scene_copy[256];
    const char *scene_path = scene_for_driver(shipped_scene, scene_copy, sizeof scene_copy);
    ht_scene scene;
    assert_int_equal(ht_scene_load(scene_path, &scene, err, sizeof err), HT_OK);
    char names[HT_TIER_COUNT][16];
    ht_image img[HT_TIER_COUNT];
    const int count = draw_tiers(material, scene_name, scene_path, through_programs, img, names);
    for (int t = 0; t < count; t++) {
        assert_int_equal(img[t].width, scene.width);
        assert_int_equal(img[t].height, scene.height);

        frame_stats s = measure(&img[t], scene.background);
        printf("%s %dx%d %s %-6s: hair %.1f%% of pixels, luminance median %.1f, p99 %.1f, stddev %.1f\n",
               shipped_scene, scene.width, scene.height, material, names[t], 100 * s.hair_fraction, s.luminance_median, s.luminance_p99,
               s.luminance_stddev);
        assert_int_equal(s.magenta, 0);
        assert_true(s.hair_fraction > min_hair);           /* not blank */
        assert_true(s.luminance_stddev > 4.0);             /* not one flat colour */
        assert_true(s.luminance_p99 > s.luminance_median + 20.0); /* highlights */
    }
    for (int t = 1; t < count; t++) {
        double d = mean_difference(&img[0], &img[t], scene.background);
        printf("%s %dx%d %s %-6s: mean difference from full %.2f/255\n", shipped_scene, scene.width,
               scene.height, material, names[t], d);
        if (compare_tiers) assert_true(d < (t == 1 ? MAX_MEAN_VERTEX_DIFFERENCE : MAX_MEAN_TIER_DIFFERENCE));
    }
    for (int t = 0; t < count; t++) ht_image_free(&img[t]);
}

/* scenes/SCENE.json */
static void check_scene(const char *material, const char *scene, bool through_programs) {
    char shipped_scene[64];
    snprintf(shipped_scene, sizeof shipped_scene, "scenes/%s.json", scene);
    render_every_tier(material, scene, shipped_scene, 0.05, true, through_programs);
}

static void test_furball_scene_renders_hair_in_every_tier(void **state) {
    (void)state;
    /* The programs themselves on llvmpipe, as `make demo` runs them; the
       softpipe run draws in this process (the driver's part is the
       drawing, and it draws one frame where hairview draws two). */
    check_scene("materials/dark-brown.json", "furball", !on_softpipe());
}

static void test_patches_scene_renders_hair_in_every_tier(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    check_scene("materials/dark-brown.json", "patches", false);
}

static void test_blond_patches_render_hair_in_every_tier(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    check_scene("materials/blond.json", "patches", false);
}

static void test_ratboy_scene_renders_hair_in_every_tier(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    check_scene("materials/dark-brown.json", "ratboy", false);
}

/* The mohawk without its head: every pixel not background is hair, so the
   hair's own coverage is what is measured: 12.6% of the frame in every tier
   on llvmpipe at 512² (printed), held above 10%. The tiers' difference
   from full over these pixels is printed, not bounded (vertex 9.8/255: the
   bounds above are for the shipped frames, where the head is most of the
   pixels). */
static void test_ratboy_hair_alone_covers_the_crest_in_every_tier(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT();
    char path[256];
    render_every_tier("materials/dark-brown.json", "ratboy",
                      ht_test_scene_copy("scenes/ratboy.json", work, "ratboy-hair.json",
                                         on_softpipe() ? SOFTPIPE_SIZE : 0, 0, true, path, sizeof path),
                      0.10, false, false);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_furball_scene_renders_hair_in_every_tier),
        cmocka_unit_test(test_patches_scene_renders_hair_in_every_tier),
        cmocka_unit_test(test_blond_patches_render_hair_in_every_tier),
        cmocka_unit_test(test_ratboy_scene_renders_hair_in_every_tier),
        cmocka_unit_test(test_ratboy_hair_alone_covers_the_crest_in_every_tier),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

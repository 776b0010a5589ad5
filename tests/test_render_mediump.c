/* test_render_mediump — what fp16 costs a whole frame: each pair's full
   tier rendered as shipped (fp32 on llvmpipe) and again with full.frag
   replaced by the bundle's own full-es2-mediump.frag turned into desktop
   GLSL whose every step and input rounds to fp16 (ht_mp_desktop_emulation:
   the CPU mirror's rounding, run by the GPU over the same four passes,
   sort and blending). The PSNR of the fp16 frame against the fp32 one is
   what docs/accuracy.md reports; a 0.5 dB loss for a tier measured at R dB
   against a reference means an added error at R + 9.1 dB (MSEs add), so a
   pair at >= 50 dB loses <= 0.5 dB for any tier measured at up to ~41 dB.

   By default one pair at 128² (the highest exponent, backlit: the half
   vector near L = -V is where fp16 errs most); HT_MEDIUMP_ALL_PAIRS=1 measures every shipped material x
   scene at 256² with a 2000-hair fur ball (test_render_accuracy's sweep),
   HT_MEDIUMP_ALL_PAIRS=MATERIAL that material's pairs only. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include <hairtier/image.h>
#include "mediump_glsl.h"
#include "metrics.h"
#include "support_scene.h"
#include "support_scratch.h"

#define TARGET_DB 50.0

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "mediump") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static void render(const char *bundle, const char *scene, const char *png, ht_image *img) {
    char cmd[2048], err[512];
    snprintf(cmd, sizeof cmd, "%s/hairview --bundle %s --scene %s --tier full --strict -o %s >/dev/null 2>&1",
             ht_test_build_dir(), bundle, scene, png);
    ht_test_run_command(cmd);
    assert_int_equal(ht_image_read_png(png, img, err, sizeof err), HT_OK);
}

/* The fp16 frame's PSNR against the fp32 frame of one pair. */
static double measure(const char *material, const char *scene_file, int size, int hairs) {
    char path[128], bundle[128], fp16[128], cmd[4096], png[256];
    /* the scene at the measured size (and hair count, for a fur ball) */
    ht_test_scene_copy(scene_file, work, "scene.json", size, hairs, false, path, sizeof path);

    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    snprintf(fp16, sizeof fp16, "%s/bundle-fp16", work);
    snprintf(cmd, sizeof cmd, "rm -rf %s %s && %s/hairgen %s --scene %s -o %s >/dev/null && cp -r %s %s", bundle,
             fp16, ht_test_build_dir(), material, path, bundle, bundle, fp16);
    ht_test_run_command(cmd);
    snprintf(png, sizeof png, "%s/full-es2-mediump.frag", bundle);
    if (!ht_test_path_exists(png)) fail_msg("%s: no full-es2-mediump.frag", material);
    char *es = ht_test_read_all(png, NULL);
    assert_non_null(es);
    char *emulated = ht_mp_desktop_emulation(es);
    free(es);
    ht_test_write_file(fp16, "full.frag", emulated);
    free(emulated);

    ht_image a, b;
    snprintf(png, sizeof png, "%s/fp32.png", work);
    render(bundle, path, png, &a);
    snprintf(png, sizeof png, "%s/fp16.png", work);
    render(fp16, path, png, &b);
    const ht_metrics m = ht_test_whole_frame_metrics(&a, &b);
    ht_image_free(&a);
    ht_image_free(&b);
    return m.psnr_db;
}

static void test_fp16_frames_stay_within_the_target_of_fp32(void **state) {
    (void)state;
#ifdef __SANITIZE_ADDRESS__
    printf("mediump frames: measured in the plain build only\n");
    return;
#endif
    const char *d = getenv("GALLIUM_DRIVER");
    if (d && strcmp(d, "softpipe") == 0) {
        printf("mediump frames: measured on llvmpipe only\n");
        return;
    }
    static const char *const materials[] = { "blond", "brown-marschner", "dark-brown", "high-contrast", "kajiya-kay" };
    static const char *const scenes[] = { "backlit", "furball", "patches", "ratboy" };
    const char *pairs = getenv("HT_MEDIUMP_ALL_PAIRS");
    const bool all = pairs && pairs[0] && strcmp(pairs, "0") != 0;
    int below = 0;
    for (size_t mi = 0; mi < sizeof materials / sizeof materials[0]; mi++)
        for (size_t si = 0; si < sizeof scenes / sizeof scenes[0]; si++) {
            const bool sample = strcmp(materials[mi], "high-contrast") == 0 && strcmp(scenes[si], "backlit") == 0;
            if (!all && !sample) continue;
            if (all && strcmp(pairs, "1") != 0 && strcmp(pairs, materials[mi]) != 0) continue;
            char material[256], scene[256];
            snprintf(material, sizeof material, "materials/%s.json", materials[mi]);
            snprintf(scene, sizeof scene, "scenes/%s.json", scenes[si]);
            const double db = measure(material, scene, all ? 256 : 128, all ? 2000 : 500);
            printf("| %s × %s | %.1f |\n", materials[mi], scenes[si], db);
            /* identical frames would mean the rounding never ran */
            assert_true(isfinite(db));
            if (db < TARGET_DB) below++;
        }
    assert_int_equal(below, 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fp16_frames_stay_within_the_target_of_fp32),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

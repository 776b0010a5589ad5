/* test_report_program — build/haircompare end to end on llvmpipe, on a
   small scene: a report with every tier's image and heatmap, replaced
   whole by a second run; a Marschner bundle's report naming marschner as
   its reference, with each tier's 4x crop of marschner's brightest
   highlight; the bundle's measured numbers on the page, or a sentence
   saying it has none; and every bad input (no bundle, a bundle no tier
   can draw, a bad scene, an output it must not or cannot write, bad
   options) one line on stderr, a non-zero exit, and no report and no
   temporary directory left. The page in a browser is `make report-check`. */
#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cJSON.h>
#include <cmocka.h>

#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_render.h"
#include "support_scratch.h"

static char work[64], bundle[128], marschner_bundle[128], scene[128];

static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "haircompare")) return -1;
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    snprintf(scene, sizeof scene, "%s/scene.json", work);
    ht_test_write_file(work, "scene.json",
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [48, 40],\n"
        " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]},\n"
        "            {\"type\": \"directional\", \"direction\": [-0.7, 0.2, -0.6], \"color\": [0.3, 0.3, 0.3]}],\n"
        " \"background\": [0.1, 0.2, 0.3],\n"
        " \"geometry\": {\"type\": \"furball\", \"hairs\": 300, \"joints\": 6, \"length\": 0.1, \"width\": 0.02}}\n");
    char err[1024];
    snprintf(marschner_bundle, sizeof marschner_bundle, "%s/marschner-bundle", work);
    /* The Marschner bundle is the shared fixture (its bake and fit cost
       1.4 s), planned for the fur ball's two directional lights as this
       scene has; read only. */
    return ht_generate_bundle("materials/dark-brown.json", scene, bundle, NULL, err, sizeof err) == HT_OK &&
                   ht_test_bundle("materials/brown-marschner.json", "furball", "scenes/furball.json",
                                  marschner_bundle, sizeof marschner_bundle, err, sizeof err) == HT_OK
               ? 0
               : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* Runs build/haircompare ARGS; stdout and stderr into out/err. */
static int run(const char *args, char *out, size_t out_size, char *err, size_t err_size) {
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s/haircompare %s >%s/stdout.txt 2>%s/stderr.txt", build ? build : "build", args, work,
             work);
    int status = system(cmd);
    assert_true(WIFEXITED(status));
    snprintf(out, out_size, "%s", ht_test_read_file(work, "stdout.txt"));
    snprintf(err, err_size, "%s", ht_test_read_file(work, "stderr.txt"));
    return WEXITSTATUS(status);
}

static void assert_no_temporary(void) {
    DIR *d = opendir(work);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".tmp-")) fail_msg("%s/%s left behind", work, e->d_name);
    closedir(d);
}

static void expect_in(const char *text, const char *what) {
    if (!strstr(text, what)) fail_msg("\"%s\" not in:\n%.3000s", what, text);
}

static void test_report_has_every_tier_image_and_heatmap_and_is_replaced_whole(void **state) {
    (void)state;
    char args[1024], out[8192], err[8192], report[256], path[512];
    snprintf(report, sizeof report, "%s/report", work);
    /* a trailing slash names the same directory */
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s/'", bundle, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    expect_in(out, "haircompare: wrote");
    static const char *const tiers[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int t = 0; t < 5; t++)
        for (int heat = 0; heat < 2; heat++) {
            snprintf(path, sizeof path, "%s/%s%s.png", report, tiers[t], heat ? "-error" : "");
            if (t == 0 && heat) { /* full is the reference: no heatmap of itself */
                assert_false(ht_test_path_exists(path));
                continue;
            }
            ht_image img = { 0 };
            char e[512];
            if (ht_image_read_png(path, &img, e, sizeof e) != HT_OK) fail_msg("%s", e);
            assert_true(img.width == 48 && img.height == 40 && img.channels == 3);
            bool varied = false; /* the hair, or its errors, are there */
            for (size_t i = 3; i < (size_t)48 * 40 * 3 && !varied; i++) varied = img.pixels[i] != img.pixels[i % 3];
            if (!varied) fail_msg("%s is one colour", path);
            ht_image_free(&img);
        }
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "<img src=\"fixed-error.png\"");
    expect_in(html, "<tr><th scope=\"row\">gl11</th><td class=\"needs\">GL 1.1, 1 texture unit</td>");
    expect_in(html, "<td class=\"num\">&infin;</td>"); /* full against itself */
    expect_in(html, "light 2: dropped: diffuse"); /* dark-brown's fill: highlights only, no sub-pass */
    assert_no_temporary();

    /* Again into the same directory: replaced whole (a stray file goes). */
    ht_test_write_file(report, "stray.txt", "x");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bundle, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    snprintf(path, sizeof path, "%s/stray.txt", report);
    assert_false(ht_test_path_exists(path));
    snprintf(path, sizeof path, "%s/index.html", report);
    assert_true(ht_test_path_exists(path));
    assert_no_temporary();
}

static void read_png(const char *dir, const char *name, ht_image *img) {
    char path[512], e[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (ht_image_read_png(path, img, e, sizeof e) != HT_OK) fail_msg("%s", e);
}

/* A Marschner bundle is measured against its marschner tier, and the page
   says so everywhere; each tier's crop is marschner's brightest 32x32
   (as the page names it) of that tier's image, 4x, nearest neighbour. */
static void test_marschner_report_names_its_reference_and_crops_its_highlight(void **state) {
    (void)state;
    char args[1024], out[8192], err[8192], report[256];
    snprintf(report, sizeof report, "%s/marschner-report", work);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", marschner_bundle, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "reference: <b>marschner</b>");
    expect_in(html, "<h2>Measurements against marschner</h2>");
    expect_in(html, "the reference: marschner<br>no error to show");
    expect_in(html, "<img src=\"full-error.png\"");
    for (const char *const *w = (const char *const[]){ "against full", "against <b>full", "vs full", "full&#8217;s",
                                                       "reference (full)", NULL };
         *w; w++)
        if (strstr(html, *w)) fail_msg("\"%s\" in the report of a Marschner bundle", *w);
    /* hairgen without --measure: the page says the bundle has no measured numbers */
    expect_in(html, "The bundle has no measured numbers");

    int x, y, w, h;
    const char *at = strstr(html, "pixels at (");
    assert_non_null(at);
    assert_int_equal(sscanf(at, "pixels at (%d, %d)", &x, &y), 2);
    assert_int_equal(sscanf(strstr(html, "<p class=\"note\">The "), "<p class=\"note\">The %d&times;%d", &w, &h), 2);
    assert_true(w == 32 && h == 32 && x >= 0 && y >= 0 && x + w <= 48 && y + h <= 40);
    static const char *const tiers[] = { "marschner", "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int t = 0; t < 6; t++)
        for (int heat = 0; heat < 2; heat++) {
            char name[64], crop_name[64];
            snprintf(name, sizeof name, "%s%s.png", tiers[t], heat ? "-error" : "");
            snprintf(crop_name, sizeof crop_name, "%s%s-crop.png", tiers[t], heat ? "-error" : "");
            char path[512];
            snprintf(path, sizeof path, "%s/%s", report, crop_name);
            if (t == 0 && heat) { /* the reference has no heatmap, so no crop of one */
                assert_false(ht_test_path_exists(path));
                continue;
            }
            ht_image full_size = { 0 }, crop = { 0 };
            read_png(report, name, &full_size);
            read_png(report, crop_name, &crop);
            assert_true(crop.width == 128 && crop.height == 128 && crop.channels == 3);
            for (int cy = 0; cy < 128; cy++)
                for (int cx = 0; cx < 128; cx++)
                    if (memcmp(crop.pixels + 3 * ((size_t)cy * 128 + (size_t)cx),
                               full_size.pixels + 3 * ((size_t)(y + cy / 4) * 48 + (size_t)(x + cx / 4)), 3) != 0)
                        fail_msg("%s (%d, %d) is not %s (%d, %d)", crop_name, cx, cy, name, x + cx / 4, y + cy / 4);
            char tag[160];
            snprintf(tag, sizeof tag, "<img src=\"%s\" width=\"128\" height=\"128\"", crop_name);
            expect_in(html, tag);
            ht_image_free(&full_size);
            ht_image_free(&crop);
        }
    /* the window holds hair: marschner's crop is not one colour */
    ht_image ref = { 0 };
    read_png(report, "marschner-crop.png", &ref);
    bool varied = false;
    for (size_t i = 3; i < (size_t)128 * 128 * 3 && !varied; i++) varied = ref.pixels[i] != ref.pixels[i % 3];
    assert_true(varied);
    ht_image_free(&ref);
}

/* The manifest's measured numbers, as hairgen --measure writes them,
   shown beside the report's own and labelled. */
static void test_report_shows_the_bundles_measured_numbers(void **state) {
    (void)state;
    char measured[256], report[256], args[1024], out[8192], err[8192];
    snprintf(measured, sizeof measured, "%s/measured-bundle", work);
    snprintf(report, sizeof report, "%s/measured-report", work);
    ht_test_copy_dir(bundle, measured);
    cJSON *root = ht_test_read_json(measured, "manifest.json");
    cJSON *tier;
    int i = 0;
    cJSON_ArrayForEach(tier, cJSON_GetObjectItemCaseSensitive(root, "tiers")) {
        char object[256];
        snprintf(object, sizeof object, "{\"psnr_db\": %s, \"ssim\": 0.97%d1, \"delta_e00_mean\": 0.4%d3, "
                 "\"delta_e00_p95\": 2.8%d5, \"cost_ratio\": 0.6%d, \"scene\": \"elsewhere.json\", "
                 "\"driver\": \"a GPU\"}", i ? "41.23" : "null", i, i, i, i);
        cJSON_AddItemToObject(tier, "measured", cJSON_Parse(object));
        i++;
    }
    char *text = cJSON_Print(root);
    ht_test_write_file(measured, "manifest.json", text);
    free(text);
    cJSON_Delete(root);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", measured, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "the bundle&#8217;s <code>measured</code> (manifest.json, hairgen --measure)");
    expect_in(html, "on scene <code>elsewhere.json</code> and driver <code>a GPU</code>");
    /* gl11, the fifth tier: its own numbers, then the manifest's */
    const char *row = strstr(html, "<tr><th scope=\"row\">gl11</th>");
    assert_non_null(row);
    char want[512];
    snprintf(want, sizeof want, "<td class=\"num measured\">0.64&times;</td><td class=\"num measured\">41.23</td>"
             "<td class=\"num measured\">0.9741</td><td class=\"num measured\">0.443</td>"
             "<td class=\"num measured\">2.845</td><td class=\"num measured\">");
    if (strncmp(strstr(row, "<td class=\"num measured\">"), want, strlen(want)) != 0)
        fail_msg("gl11's measured cells are not %s in:\n%.1500s", want, row);
    expect_in(strstr(html, "<tr><th scope=\"row\">full</th>"), "<td class=\"num measured\">&infin;</td>");
    assert_null(strstr(html, "has no measured numbers"));
}

/* Exit status, one line on stderr starting "haircompare: " and naming
   `mentions`, and no report at `report`. */
static void expect_fails(const char *args, int status, const char *mentions, const char *report) {
    char out[8192], err[8192];
    int got = run(args, out, sizeof out, err, sizeof err);
    if (got != status) fail_msg("haircompare %s: exit %d, expected %d:\n%s", args, got, status, err);
    /* the progress lines name the tiers rendered; the failure is the last line */
    size_t n = strlen(err);
    while (n && err[n - 1] == '\n') err[--n] = '\0';
    const char *line = strrchr(err, '\n') ? strrchr(err, '\n') + 1 : err;
    if (status == 2) line = err; /* usage: the reason first, then the help */
    if (strncmp(line, "haircompare: ", 13) != 0 || !strstr(line, mentions))
        fail_msg("haircompare %s: \"%.300s\" does not name %s", args, line, mentions);
    if (report && ht_test_path_exists(report)) fail_msg("haircompare %s: %s written", args, report);
    assert_no_temporary();
}

static void test_bad_input_is_one_line_and_writes_nothing(void **state) {
    (void)state;
    char args[2048], report[256], path[512], bad[256];
    snprintf(report, sizeof report, "%s/report-bad", work);

    snprintf(args, sizeof args, "--bundle '%s/no-bundle' --scene '%s' -o '%s'", work, scene, report);
    expect_fails(args, 1, "no-bundle/manifest.json: cannot read", report);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s/no-scene.json' -o '%s'", bundle, work, report);
    expect_fails(args, 1, "no-scene.json", report);

    /* every tier needs the albedo: none draws, so no report */
    snprintf(bad, sizeof bad, "%s/bad-albedo", work);
    ht_test_copy_dir(bundle, bad);
    ht_test_write_file(bad, "albedo.png", "\x89PNG\r\n\x1a\n");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bad, scene, report);
    expect_fails(args, 1, "no tier ran: ", report);

    /* outputs it cannot or must not write */
    ht_test_write_file(work, "a-file", "x");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s/a-file/report'", bundle, scene, work);
    snprintf(path, sizeof path, "%s/a-file/report", work);
    expect_fails(args, 1, "a-file/report: cannot create a temporary directory beside it", NULL);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s/a-file'", bundle, scene, work);
    expect_fails(args, 1, "a-file: exists and is not a directory", NULL);
    snprintf(path, sizeof path, "%s/mine", work);
    assert_int_equal(mkdir(path, 0755), 0);
    ht_test_write_file(path, "notes.txt", "keep me");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bundle, scene, path);
    expect_fails(args, 1, "mine: exists and is not a haircompare report", NULL);
    assert_string_equal(ht_test_read_file(path, "notes.txt"), "keep me");

    /* the command line */
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 0 -o '%s'", bundle, scene, report);
    expect_fails(args, 2, "--frames: expected an integer in 1..1000", report);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s'", bundle, scene);
    expect_fails(args, 2, "-o: required", NULL);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' -o /", bundle, scene);
    expect_fails(args, 2, "-o: not a usable directory", NULL);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_report_has_every_tier_image_and_heatmap_and_is_replaced_whole),
        cmocka_unit_test(test_marschner_report_names_its_reference_and_crops_its_highlight),
        cmocka_unit_test(test_report_shows_the_bundles_measured_numbers),
        cmocka_unit_test(test_bad_input_is_one_line_and_writes_nothing),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

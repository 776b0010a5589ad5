/* test_report_program — build/haircompare end to end on llvmpipe, on a
   small scene: a report with every tier's image and heatmap, replaced
   whole by a second run; and every bad input (no bundle, a bundle no tier
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

#include <cmocka.h>

#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_scratch.h"

static char work[64], bundle[128], scene[128];

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
    return ht_generate_bundle("materials/dark-brown.json", scene, bundle, NULL, err, sizeof err) == HT_OK ? 0 : -1;
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
        cmocka_unit_test(test_bad_input_is_one_line_and_writes_nothing),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_programs.c — every program behaves like a tool (platform/cli.h):
   --help and -h print usage on stdout and exit 0 (a benchmark runs
   nothing), --version prints the version (hairgen also the bundle
   generator version), an unknown option or a missing value is one line and
   the usage on stderr, exit 2. And hairview refuses a bundle of another
   generator version with one line, printed once, as it prints every
   library error once. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "manifest.h"
#include "support_scratch.h"

static const char *const programs[] = { "hairgen", "hairview", "haircompare", "tier_sheet", "png_metrics",
                                        "bench_frame", "bench_hairgen", "bench_mesh", "bench_suite" };
#define PROGRAMS (int)(sizeof programs / sizeof programs[0])

static char work[64];
static char *out_text, *err_text;   /* the last run's stdout and stderr */

static char scene[128];   /* a small scene for hairview */

static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "programs")) return -1;
    snprintf(scene, sizeof scene, "%s/scene.json", work);
    FILE *f = fopen(scene, "w");
    if (!f) return -1;
    fputs("{\"format\": \"hairtier-scene/1\", \"resolution\": [32, 32],\n"
          " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
          " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]}],\n"
          " \"geometry\": {\"type\": \"furball\", \"hairs\": 50, \"joints\": 4, \"length\": 0.1, \"width\": 0.02}}\n", f);
    return fclose(f) == 0 ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    free(out_text);
    free(err_text);
    return ht_test_scratch_remove(work);
}

/* `env build/PROGRAM args`, stdout and stderr kept; the exit status. */
static int run(const char *env, const char *program, const char *args) {
    char cmd[8192], out[128], err[128];
    snprintf(out, sizeof out, "%s/out.txt", work);
    snprintf(err, sizeof err, "%s/err.txt", work);
    char build[4096];
    assert_non_null(realpath(ht_test_build_dir(), build));
    snprintf(cmd, sizeof cmd, "%s %s/%s %s >%s 2>%s </dev/null", env ? env : "", build, program, args, out, err);
    int status = system(cmd);
    free(out_text);
    free(err_text);
    out_text = ht_test_read_all(out, NULL);
    err_text = ht_test_read_all(err, NULL);
    assert_non_null(out_text);
    assert_non_null(err_text);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

static int count(const char *text, const char *what) {
    int n = 0;
    for (const char *p = text; (p = strstr(p, what)) != NULL; p += strlen(what)) n++;
    return n;
}

static void test_help_prints_usage_on_stdout_and_exits_0(void **state) {
    (void)state;
    static const char *const spellings[] = { "--help", "-h" };
    for (int i = 0; i < PROGRAMS; i++)
        for (int k = 0; k < 2; k++) {
            /* A benchmark that ran anyway would fail here (no materials, no
               programs beside it) or print figures (bench_mesh needs no file). */
            char env[128];
            snprintf(env, sizeof env, "cd %s && HAIRTIER_BUILD=/nonexistent", work);
            int rc = run(env, programs[i], spellings[k]);
            if (rc != 0) fail_msg("%s %s: exit %d\n%s", programs[i], spellings[k], rc, err_text);
            char want[64];
            snprintf(want, sizeof want, "usage: %s", programs[i]);
            if (strncmp(out_text, want, strlen(want)) != 0 || err_text[0])
                fail_msg("%s %s: stdout \"%.200s\", stderr \"%.200s\"", programs[i], spellings[k], out_text, err_text);
            if (strstr(out_text, "triangles  build"))
                fail_msg("%s %s ran:\n%s", programs[i], spellings[k], out_text);
        }
}

static void test_hairgen_help_lists_every_option(void **state) {
    (void)state;
    assert_int_equal(run(NULL, "hairgen", "--help"), 0);
    static const char *const options[] = { "--scene", "-o ", "--batch", "-j ", "--force", "-MD", "-MF", "-q ",
                                           "--measure", "--emit-header", "--header-symbol", "--version" };
    for (size_t i = 0; i < sizeof options / sizeof options[0]; i++)
        if (!strstr(strstr(out_text, "\n\n"), options[i])) fail_msg("hairgen --help: no %s", options[i]);
}

static void test_version_prints_the_version(void **state) {
    (void)state;
    for (int i = 0; i < PROGRAMS; i++) {
        assert_int_equal(run(NULL, programs[i], "--version"), 0);
        char want[64];
        snprintf(want, sizeof want, "%s (hairtier) ", programs[i]);
        if (strncmp(out_text, want, strlen(want)) != 0 || err_text[0])
            fail_msg("%s --version: \"%s\"", programs[i], out_text);
        /* one place for every program: the Makefile's VERSION */
        size_t line = strcspn(out_text, "\n");
        assert_int_equal(line, strlen(want) + strlen(HT_VERSION));
        assert_memory_equal(out_text + strlen(want), HT_VERSION, strlen(HT_VERSION));
        bool hairgen = strcmp(programs[i], "hairgen") == 0;
        if (!hairgen) assert_int_equal(out_text[line + 1], '\0');
        else assert_string_equal(out_text + line + 1, "bundles: generator version " HT_MANIFEST_GENERATOR "\n");
    }
}

static void test_unknown_option_or_missing_value_is_one_line_and_usage(void **state) {
    (void)state;
    for (int i = 0; i < PROGRAMS; i++) {
        assert_int_equal(run(NULL, programs[i], "--no-such-option"), 2);
        char want[128];
        snprintf(want, sizeof want, "%s: --no-such-option: unknown option\nusage: %s", programs[i], programs[i]);
        if (strncmp(err_text, want, strlen(want)) != 0 || out_text[0])
            fail_msg("%s --no-such-option: stderr \"%s\"", programs[i], err_text);
    }
    static const struct { const char *program, *args, *line; } missing[] = {
        { "hairgen", "materials/dark-brown.json -o", "hairgen: -o: missing value\n" },
        { "hairgen", "materials/dark-brown.json --scene", "hairgen: --scene: missing value\n" },
        { "hairgen", "-MF", "hairgen: -MF: missing value\n" },
        { "hairview", "--bundle b --scene", "hairview: --scene: missing value\n" },
        { "haircompare", "--frames", "haircompare: --frames: missing value\n" },
        { "tier_sheet", "-o", "tier_sheet: -o: missing value\n" },
        { "bench_frame", "--hairs", "bench_frame: --hairs: missing value\n" },
        { "bench_suite", "-o", "bench_suite: -o: missing value\n" },
        { "bench_mesh", "extra", "bench_mesh: extra: unexpected argument\n" },
        { "png_metrics", "a.png b.png c.png", "png_metrics: c.png: unexpected argument\n" },
        { "hairview", "-x", "hairview: -x: unknown option\n" },
    };
    for (size_t i = 0; i < sizeof missing / sizeof missing[0]; i++) {
        assert_int_equal(run(NULL, missing[i].program, missing[i].args), 2);
        size_t n = strlen(missing[i].line);
        if (strncmp(err_text, missing[i].line, n) != 0 || strncmp(err_text + n, "usage: ", 7) != 0)
            fail_msg("%s %s: stderr \"%s\", expected \"%s\" and the usage", missing[i].program, missing[i].args,
                     err_text, missing[i].line);
    }
}

/* The options keep their spellings: -jN as make spells it, -MD. */
static void test_hairgen_keeps_its_spellings(void **state) {
    (void)state;
    char args[512];
    snprintf(args, sizeof args, "-o %s/batch --batch -j1 -MD -q materials/kajiya-kay.json", work);
    if (run(NULL, "hairgen", args) != 0) fail_msg("hairgen %s: %s", args, err_text);
    char path[256];
    snprintf(path, sizeof path, "%s/batch/kajiya-kay.d", work);
    assert_true(ht_test_path_exists(path));
    snprintf(args, sizeof args, "-o %s/b1 -o %s/b2 materials/kajiya-kay.json", work, work);
    assert_int_equal(run(NULL, "hairgen", args), 2);
    assert_true(strncmp(err_text, "hairgen: -o: given twice\n", 25) == 0);
}

/* A bundle whose manifest records another generator: hairview refuses it
   with one line naming the manifest, its version and the one to
   regenerate with, printed once; no PNG. */
static void test_hairview_refuses_another_generator_version_once(void **state) {
    (void)state;
    char bundle[128], args[1024], png[128];
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    snprintf(png, sizeof png, "%s/view.png", work);
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s -o %s -q", scene, bundle);
    if (run(NULL, "hairgen", args) != 0) fail_msg("hairgen %s: %s", args, err_text);
    snprintf(args, sizeof args, "--bundle %s --scene %s --frames 1 -o %s", bundle, scene, png);
    if (run(NULL, "hairview", args) != 0) fail_msg("hairview %s: %s", args, err_text);
    assert_int_equal(remove(png), 0);

    static const char *const versions[] = { "hairgen 2", "hairgen 9" };
    for (int i = 0; i < 2; i++) {
        cJSON *m = ht_test_read_json(bundle, "manifest.json");
        cJSON_ReplaceItemInObjectCaseSensitive(m, "generator", cJSON_CreateString(versions[i]));
        char *text = cJSON_Print(m);
        ht_test_write_file(bundle, "manifest.json", text);
        cJSON_free(text);
        cJSON_Delete(m);
        assert_int_equal(run(NULL, "hairview", args), 1);
        char want[512];
        snprintf(want, sizeof want, "hairview: %s/manifest.json: generator: \"%s\", this runtime reads "
                 HT_MANIFEST_GENERATOR " bundles: regenerate with " HT_MANIFEST_GENERATOR "\n", bundle, versions[i]);
        const char *last = err_text + strlen(err_text) - strlen(want);
        if (last < err_text || strcmp(last, want) != 0) fail_msg("stderr:\n%s\nexpected to end:\n%s", err_text, want);
        if (count(err_text, "regenerate with") != 1) fail_msg("printed more than once:\n%s", err_text);
        assert_false(ht_test_path_exists(png));
    }
}

/* Any library error, not only that one: a corrupt texture of a forced tier. */
static void test_hairview_prints_a_library_error_once(void **state) {
    (void)state;
    char bundle[128], args[1024], png[128];
    snprintf(bundle, sizeof bundle, "%s/bad-albedo", work);
    snprintf(png, sizeof png, "%s/bad.png", work);
    snprintf(args, sizeof args, "materials/dark-brown.json -o %s -q", bundle);
    if (run(NULL, "hairgen", args) != 0) fail_msg("hairgen %s: %s", args, err_text);
    ht_test_write_file(bundle, "albedo.png", "\x89PNG\r\n\x1a\n");
    snprintf(args, sizeof args, "--bundle %s --scene %s --tier full --strict --frames 1 -o %s", bundle, scene, png);
    assert_int_equal(run(NULL, "hairview", args), 1);
    const char *line = strstr(err_text, "hairview: full: ");
    if (!line) fail_msg("stderr:\n%s", err_text);
    char error[512];
    snprintf(error, sizeof error, "%.*s", (int)strcspn(line + 10, "\n"), line + 10);
    if (count(err_text, error) != 1) fail_msg("\"%s\" printed more than once:\n%s", error, err_text);
    assert_false(ht_test_path_exists(png));
}

/* The PSNR column of bench_frame's row NAME in out_text (NAN: none). */
static double row_db(const char *name) {
    char key[48];
    snprintf(key, sizeof key, "\n  %s ", name);
    const char *row = strstr(out_text, key), *end = row ? strchr(row + 1, '\n') : NULL;
    if (!row || !end) return NAN;
    /* the second-last column: median, 2 ratios, 2 dashes, 2 counts, PSNR, FLIP */
    const char *p = end;
    int spaces = 0;
    while (p > row && spaces < 2)
        if (*--p == ' ' && p[-1] != ' ') spaces++;
    double db = NAN;
    return sscanf(p, "%lf", &db) == 1 ? db : NAN;
}

/* bench_frame --lods --truth: every pair against the 16x truth, full
   detail too (finite: the truth is not its own image), full-rule beside,
   the pops between adjacent levels, the pick's cost against both;
   --truth alone is refused. */
static void test_bench_frame_measures_pairs_against_the_truth(void **state) {
    (void)state;
    assert_int_equal(run(NULL, "bench_frame", "--truth --hairs 50 --size 32 --frames 1"), 2);
    if (!strstr(err_text, "bench_frame: --truth: with --lods")) fail_msg("stderr:\n%s", err_text);
    const char *args = "--lods --width-rule --truth --samples 2 --hairs 400 --size 48 --frames 1 --no-orbit";
    if (run(NULL, "bench_frame", args) != 0) fail_msg("bench_frame %s: %s", args, err_text);
    if (!strstr(out_text, "vs truth") || !strstr(out_text, "\n  full-rule ")) fail_msg("stdout:\n%s", out_text);
    for (const char *row = strstr(out_text, "\n  geometry floor"); row; row = strstr(row + 1, "\n  ")) {
        char name[32];
        assert_non_null(strstr(row, " ms "));
        snprintf(name, sizeof name, "%.*s", (int)(strchr(row + 3, ' ') - row - 3), row + 3);
        if (!strcmp(name, "geometry")) snprintf(name, sizeof name, "geometry floor");
        const double db = row_db(name);
        if (!(db > 10 && db < 99)) fail_msg("%s: %g dB against the truth\n%s", name, db, out_text);
    }
    if (!strstr(out_text, "pop dB (a level against the one before, level 1 against full-rule): full 1>0 ") ||
        !strstr(out_text, " gl11 2>1 ") || !strstr(out_text, "full-rule's, ") ||
        !strstr(out_text, " dB against the truth\n"))
        fail_msg("stdout:\n%s", out_text);
}

/* bench_frame --soft=F draws levels 1 and 2 soft by F: another factor,
   another picture; a factor outside (1, 16] is refused in one line. */
static void test_bench_frame_soft_takes_a_factor(void **state) {
    (void)state;
    static const char *const bad[] = { "1", "17", "x", "3,8" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char args[128];
        snprintf(args, sizeof args, "--lods --soft=%s --hairs 50 --size 32 --frames 1", bad[i]);
        assert_int_equal(run(NULL, "bench_frame", args), 2);
        if (!strstr(err_text, "bench_frame: --soft: expected a factor above 1, at most 16\n"))
            fail_msg("--soft=%s: stderr:\n%s", bad[i], err_text);
    }
    double db[2];
    static const char *const factors[] = { "--soft=2", "--soft=8" };
    for (int i = 0; i < 2; i++) {
        char args[160];
        snprintf(args, sizeof args, "--lods %s --hairs 400 --size 48 --frames 1 --no-orbit", factors[i]);
        if (run(NULL, "bench_frame", args) != 0) fail_msg("bench_frame %s: %s", args, err_text);
        db[i] = row_db("lod1-full");
        if (!(db[i] > 10 && db[i] < 99)) fail_msg("%s: lod1-full %g dB\n%s", factors[i], db[i], out_text);
    }
    if (fabs(db[0] - db[1]) < 0.05) fail_msg("soft by 2 and by 8 drew alike: %g / %g dB", db[0], db[1]);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_help_prints_usage_on_stdout_and_exits_0),
        cmocka_unit_test(test_hairgen_help_lists_every_option),
        cmocka_unit_test(test_version_prints_the_version),
        cmocka_unit_test(test_unknown_option_or_missing_value_is_one_line_and_usage),
        cmocka_unit_test(test_hairgen_keeps_its_spellings),
        cmocka_unit_test(test_hairview_refuses_another_generator_version_once),
        cmocka_unit_test(test_hairview_prints_a_library_error_once),
        cmocka_unit_test(test_bench_frame_measures_pairs_against_the_truth),
        cmocka_unit_test(test_bench_frame_soft_takes_a_factor),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

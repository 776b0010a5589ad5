/* test_depfile.c — hairgen's depfiles read back by the real make and ninja:
   every file name hairgen accepts under -MD is read by both exactly as
   hairgen read it (a change rebuilds, a deletion rebuilds instead of
   stopping), and a name the two cannot both read is refused with one line
   before anything is written. A failed run leaves the old depfile. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "support_scratch.h"

static char work[64];
static char hairgen[PATH_MAX];
static char repo[PATH_MAX];

static int setup(void **state) {
    (void)state;
    char rel[PATH_MAX];
    snprintf(rel, sizeof rel, "%s/hairgen", ht_test_build_dir());
    if (!realpath(rel, hairgen) || !getcwd(repo, sizeof repo)) return -1;
    return ht_test_scratch_create(work, sizeof work, "depfile") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* cmd run in the scratch directory (sh -c); its exit status. */
static int run_in_work(const char *cmd) {
    char full[8192];
    snprintf(full, sizeof full, "cd %s && %s", work, cmd);
    int status = system(full);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static bool tool_missing(const char *tool) {
    char cmd[128];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tool);
    return system(cmd) != 0;
}

static void set_mtime(const char *name, time_t t) {
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", work, name);
    struct timespec times[2] = { { t, 0 }, { t, 0 } };
    if (utimensat(AT_FDCWD, path, times, 0) != 0) fail_msg("%s: cannot set its time", path);
}

/* The shipped kajiya-kay material (no texture file) copied to name. */
static void write_material(const char *name) {
    char from[PATH_MAX + 64];
    snprintf(from, sizeof from, "%s/materials/kajiya-kay.json", repo);
    char *text = ht_test_read_all(from, NULL);
    assert_non_null(text);
    ht_test_write_file(work, name, text);
    free(text);
}

/* run.sh: hairgen on the material `name` (single-quoted: no name here
   holds a quote), -MD, so make and ninja need not quote it. */
static void write_run_script(const char *name) {
    char text[PATH_MAX + 512];
    snprintf(text, sizeof text, "exec %s '%s' -o bundle -MD -q 2>err.txt\n", hairgen, name);
    ht_test_write_file(work, "run.sh", text);
}

/* make: up to date after a build; rebuilds when the material is newer;
   rebuilds (not "No rule to make target") when it is deleted. */
static void check_make_reads(const char *name) {
    ht_test_write_file(work, "rules.mk", "bundle/manifest.json:\n\tsh run.sh\n-include bundle.d\n");
    if (run_in_work("make -s -f rules.mk >make.txt 2>&1") != 0)
        fail_msg("%s: make failed: %s", name, ht_test_read_file(work, "make.txt"));
    time_t now = time(NULL);
    set_mtime("bundle/manifest.json", now + 3600); /* newer than hairgen too */
    if (run_in_work("make -q -f rules.mk >make.txt 2>&1") != 0)
        fail_msg("%s: make: bundle not up to date after a build: %s", name, ht_test_read_file(work, "make.txt"));
    set_mtime(name, now + 7200);
    if (run_in_work("make -q -f rules.mk >make.txt 2>&1") != 1)
        fail_msg("%s: make does not see the material change: %s", name, ht_test_read_file(work, "make.txt"));
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s", work, name);
    char *keep = ht_test_read_all(path, NULL);
    assert_int_equal(unlink(path), 0);
    int deleted = run_in_work("make -q -f rules.mk >make.txt 2>&1");
    ht_test_write_file(work, name, keep);
    free(keep);
    if (deleted != 1) fail_msg("%s: make on a deleted input: status %d, %s", name, deleted,
                               ht_test_read_file(work, "make.txt"));
}

/* ninja records the depfile's names (deps = gcc): the material, exactly.
   The depfile is the one hairgen wrote for make (check_make_reads), put
   back by the rule's command: the same bytes, without a second run. */
static void check_ninja_reads(const char *name) {
    ht_test_write_file(work, "build.ninja", "rule gen\n  command = cp hairgen.d bundle.d\n  depfile = bundle.d\n"
                                            "  deps = gcc\nbuild bundle/manifest.json: gen\n");
    assert_int_equal(run_in_work("mv bundle.d hairgen.d && rm -rf bundle .ninja_deps .ninja_log"), 0);
    if (run_in_work("ninja >ninja.txt 2>&1") != 0)
        fail_msg("%s: ninja failed: %s", name, ht_test_read_file(work, "ninja.txt"));
    assert_int_equal(run_in_work("ninja -t deps bundle/manifest.json >deps.txt 2>&1"), 0);
    const char *deps = ht_test_read_file(work, "deps.txt");
    /* "bundle/manifest.json: #deps 2, ...\n    NAME\n    HAIRGEN\n\n" */
    char want[2 * PATH_MAX];
    snprintf(want, sizeof want, "\n    %s\n    %s\n", name, hairgen);
    if (!strstr(deps, want)) fail_msg("%s: ninja recorded:\n%s", name, deps);
}

/* Names make and ninja can both read, once escaped. */
static void test_depfile_escapes_colon_hash_dollar_space_for_make_and_ninja(void **state) {
    (void)state;
    if (tool_missing("make") || tool_missing("ninja")) skip();
    const char *names[] = { "a:b.json", "a#b.json", "a$b.json", "a b.json", "a\\ b.json", "a\\b.json",
                            "a(b)@[c],d.json" };
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        run_in_work("rm -rf bundle bundle.d .ninja_deps .ninja_log");
        write_material(names[i]);
        write_run_script(names[i]);
        check_make_reads(names[i]);
        check_ninja_reads(names[i]);
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", work, names[i]);
        unlink(path);
    }
}

/* Names with no spelling both read alike: one line, nothing written, the
   old depfile as it was. */
static void test_depfile_refuses_names_make_and_ninja_read_differently(void **state) {
    (void)state;
    const char *names[] = { "a;b.json", "a=b.json", "a%b.json", "a\tb.json", "a\rb.json", "a?b.json", "a*b.json",
                            "a|b.json", "a&b.json" };
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        run_in_work("rm -rf bundle");
        ht_test_write_file(work, "bundle.d", "old depfile\n");
        write_material(names[i]);
        write_run_script(names[i]);
        if (run_in_work("sh run.sh") != 1) fail_msg("%s: accepted", names[i]);
        const char *err = ht_test_read_file(work, "err.txt");
        if (!strstr(err, "cannot be listed in a depfile") || strchr(err, '\n') != err + strlen(err) - 1)
            fail_msg("%s: not one line: %s", names[i], err);
        char dir_path[128];
        snprintf(dir_path, sizeof dir_path, "%s/bundle", work);
        assert_false(ht_test_path_exists(dir_path));
        assert_string_equal(ht_test_read_file(work, "bundle.d"), "old depfile\n");
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", work, names[i]);
        unlink(path);
    }
}

/* A material whose base texture is tex.png. */
static void write_textured_material(const char *name) {
    ht_test_write_file(work, name,
                       "{ \"format\": \"hairtier-material/1\", \"name\": \"textured\", \"model\": \"scheuermann\",\n"
                       "  \"diffuse\": {\"color\": [0.4,0.3,0.2], \"wrap\": 0.25},\n"
                       "  \"primary\": {\"color\": [0.9,0.8,0.7], \"exponent\": 80, \"shift\": -0.1},\n"
                       "  \"secondary\": {\"color\": [0.5,0.4,0.3], \"exponent\": 20, \"shift\": 0.1},\n"
                       "  \"textures\": {\"base\": {\"file\": \"tex.png\"}} }\n");
}

/* The README's rule: a failed run (a broken texture) must not empty the
   depfile, or make keeps the stale bundle once the texture is fixed. */
static void test_failed_run_leaves_the_depfile_that_names_the_broken_input(void **state) {
    (void)state;
    if (tool_missing("make")) skip();
    write_textured_material("tex.json");
    /* a PNG from a bundle (any PNG serves) */
    char cmd[PATH_MAX + 128];
    snprintf(cmd, sizeof cmd, "%s materials/dark-brown.json -o %s/png-src -q >/dev/null", hairgen, work);
    assert_int_equal(system(cmd), 0);
    assert_int_equal(run_in_work("cp png-src/albedo.png tex.png"), 0);
    ht_test_write_file(work, "rules.mk",
                       "out/tex/manifest.json:\n\tmkdir -p out && sh run.sh\n-include out/tex.d\n");
    char script[PATH_MAX + 128];
    snprintf(script, sizeof script, "exec %s tex.json -o out/tex -MD -q\n", hairgen);
    ht_test_write_file(work, "run.sh", script);
    assert_int_equal(run_in_work("make -s -f rules.mk >make.txt 2>&1"), 0);
    char *before = ht_test_read_all(strcat(strcpy(cmd, work), "/out/tex.d"), NULL);
    assert_non_null(before);
    assert_non_null(strstr(before, "tex.png"));
    /* the texture broken: make runs hairgen, which fails */
    time_t now = time(NULL);
    set_mtime("out/tex/manifest.json", now + 3600);
    ht_test_write_file(work, "tex.png", "not a png");
    set_mtime("tex.png", now + 7200);
    assert_int_equal(run_in_work("make -s -f rules.mk >make.txt 2>&1"), 2);
    char *after = ht_test_read_all(cmd, NULL);
    assert_non_null(after);
    assert_string_equal(after, before);
    /* fixed: make rebuilds */
    assert_int_equal(run_in_work("cp png-src/albedo.png tex.png"), 0);
    set_mtime("tex.png", now + 7300);
    assert_int_equal(run_in_work("make -q -f rules.mk >make.txt 2>&1"), 1);
    free(before);
    free(after);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_depfile_escapes_colon_hash_dollar_space_for_make_and_ninja, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_depfile_refuses_names_make_and_ninja_read_differently, setup, teardown),
        cmocka_unit_test_setup_teardown(test_failed_run_leaves_the_depfile_that_names_the_broken_input, setup,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

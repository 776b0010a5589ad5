/* test_hostile_output.c — what hairtier writes is as guarded as what it
   reads: every writer refuses an output path that is a FIFO or a device
   node with one line, leaving it as it was (a rename over /dev/full once
   made it a PNG), and a reader of an output-side file (an old manifest, an
   old report) never waits on a FIFO. Device nodes are made with mknod in
   the scratch folder, which needs root: without it those checks are
   skipped, saying why; the FIFO checks always run. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include "compare/report_dir.h"
#include "file_atomic.h"
#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_scratch.h"

static char work[64];
static char hairgen[PATH_MAX];
static char repo[PATH_MAX];
static bool have_device; /* mknod worked: "dev" is a character device (1, 7: /dev/full) */

static int setup(void **state) {
    (void)state;
    char rel[PATH_MAX];
    snprintf(rel, sizeof rel, "%s/hairgen", ht_test_build_dir());
    if (!realpath(rel, hairgen) || !getcwd(repo, sizeof repo)) return -1;
    if (!ht_test_scratch_create(work, sizeof work, "output")) return -1;
    char path[128];
    snprintf(path, sizeof path, "%s/fifo", work);
    if (mkfifo(path, 0600) != 0) return -1;
    snprintf(path, sizeof path, "%s/dev", work);
    have_device = mknod(path, S_IFCHR | 0600, makedev(1, 7)) == 0;
    static bool said;
    if (!have_device && !said) {
        printf("test_hostile_output: device-node checks skipped: mknod: %s (needs root)\n", strerror(errno));
        said = true;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* The special files a writer is pointed at: the FIFO, and the device
   node when there is one. */
static int targets(const char *names[2]) {
    names[0] = "fifo";
    names[1] = "dev";
    return have_device ? 2 : 1;
}

/* WORK/name is still what setup made. */
static void assert_untouched(const char *name) {
    char path[128];
    snprintf(path, sizeof path, "%s/%s", work, name);
    struct stat st;
    assert_int_equal(lstat(path, &st), 0);
    if (strcmp(name, "fifo") == 0 ? !S_ISFIFO(st.st_mode) : !S_ISCHR(st.st_mode))
        fail_msg("%s was replaced (mode %o)", path, (unsigned)st.st_mode);
}

/* hairgen args in the scratch folder, under a time limit (a FIFO must
   not hang it: 124 is the limit's status); stderr in err.txt. */
static int run_hairgen(const char *args) {
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "cd %s && timeout 60 %s %s >out.txt 2>err.txt", work, hairgen, args);
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* err.txt is one line holding want. */
static void assert_one_line(const char *want) {
    const char *err = ht_test_read_file(work, "err.txt");
    const char *nl = strchr(err, '\n');
    if (!strstr(err, want) || !nl || nl[1]) fail_msg("wanted one line with \"%s\", got: %s", want, err);
}

/* A usage error: one line holding want, then only the synopsis. */
static void assert_one_line_then_usage(const char *want) {
    const char *err = ht_test_read_file(work, "err.txt");
    const char *nl = strchr(err, '\n');
    if (!nl || !strstr(err, want) || strstr(err, want) > nl || strncmp(nl + 1, "usage: ", 7) != 0)
        fail_msg("wanted one line with \"%s\" and the usage after it, got: %s", want, err);
}

static void copy_material(const char *name) {
    char from[PATH_MAX + 64];
    snprintf(from, sizeof from, "%s/materials/kajiya-kay.json", repo);
    char *text = ht_test_read_all(from, NULL);
    assert_non_null(text);
    ht_test_write_file(work, name, text);
    free(text);
}

/* hairgen with args (a printf format taking the target's name) exits 1
   with one line holding want, leaves the target as it was and, when
   no_bundle, writes no ./bundle either. */
static void expect_hairgen_refuses(const char *args_format, const char *name, const char *want, bool no_bundle) {
    char args[256];
    snprintf(args, sizeof args, args_format, name);
    assert_int_equal(run_hairgen(args), 1);
    assert_one_line(want);
    assert_untouched(name);
    if (!no_bundle) return;
    char bundle[128];
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    assert_false(ht_test_path_exists(bundle));
}

/* The atomic writer behind hairview -o and the benchmarks' files. */
static void test_png_writer_refuses_a_fifo_or_device_and_leaves_it(void **state) {
    (void)state;
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, 4, 4, 3), HT_OK);
    const char *names[2];
    for (int i = 0, n = targets(names); i < n; i++) {
        char path[128], err[512] = "";
        snprintf(path, sizeof path, "%s/%s", work, names[i]);
        assert_int_equal(ht_image_write_png(path, &img, err, sizeof err), HT_ERR_IO);
        if (!strstr(err, "exists and is not a regular file") || strchr(err, '\n')) fail_msg("%s", err);
        assert_untouched(names[i]);
    }
    ht_image_free(&img);
    /* no temporary left beside them */
    char cmd[256];
    snprintf(cmd, sizeof cmd, "ls %s | grep -q tmp-", work);
    assert_int_not_equal(system(cmd), 0);
}

static void test_hairgen_depfile_refuses_a_fifo_or_device_before_any_work(void **state) {
    (void)state;
    copy_material("kk.json");
    const char *names[2];
    for (int i = 0, n = targets(names); i < n; i++)
        expect_hairgen_refuses("kk.json -o bundle -MF %s", names[i], "exists and is not a regular file", true);
}

static void test_hairgen_per_bundle_depfile_refuses_a_fifo(void **state) {
    (void)state;
    copy_material("kk.json");
    char path[128];
    assert_int_equal(mkdir(strcat(strcpy(path, work), "/out"), 0755), 0);
    assert_int_equal(mkfifo(strcat(strcpy(path, work), "/out/kk.d"), 0600), 0);
    assert_int_equal(run_hairgen("--batch kk.json -o out -MD -q"), 1);
    assert_one_line("out/kk.d: exists and is not a regular file (a FIFO)");
    struct stat st;
    assert_int_equal(lstat(path, &st), 0);
    assert_true(S_ISFIFO(st.st_mode));
}

static void test_hairgen_emit_header_refuses_a_fifo_or_device(void **state) {
    (void)state;
    copy_material("kk.json");
    const char *names[2];
    for (int i = 0, n = targets(names); i < n; i++) {
        expect_hairgen_refuses("kk.json --emit-header %s", names[i], "exists and is not a regular file", false);
        /* with -o too: neither the bundle nor the header is written */
        expect_hairgen_refuses("kk.json -o bundle --emit-header %s", names[i], "exists and is not a regular file",
                               true);
    }
}

static void test_hairgen_bundle_refuses_a_fifo_or_device_as_its_folder(void **state) {
    (void)state;
    copy_material("kk.json");
    const char *names[2];
    for (int i = 0, n = targets(names); i < n; i++)
        expect_hairgen_refuses("kk.json -o %s", names[i], "exists and is not a directory", false);
}

/* Row 2: a FIFO where the old bundle's manifest would be. */
static void test_hairgen_does_not_wait_on_a_fifo_manifest_of_the_bundle_it_replaces(void **state) {
    (void)state;
    copy_material("kk.json");
    char path[128];
    assert_int_equal(mkdir(strcat(strcpy(path, work), "/bundle"), 0755), 0);
    assert_int_equal(mkfifo(strcat(strcpy(path, work), "/bundle/manifest.json"), 0600), 0);
    assert_int_equal(run_hairgen("kk.json -o bundle"), 1);
    assert_one_line("bundle: exists and is not a hairtier bundle");
    /* a batch's no-change check and its replacement alike */
    assert_int_equal(mkdir(strcat(strcpy(path, work), "/out"), 0755), 0);
    assert_int_equal(mkdir(strcat(strcpy(path, work), "/out/kk"), 0755), 0);
    assert_int_equal(mkfifo(strcat(strcpy(path, work), "/out/kk/manifest.json"), 0600), 0);
    assert_int_equal(run_hairgen("--batch kk.json -o out -q"), 1);
    const char *err = ht_test_read_file(work, "err.txt");
    if (!strstr(err, "out/kk: exists and is not a hairtier bundle")) fail_msg("%s", err);
}

/* Row 2: a FIFO where the old report's index.html would be. The check is
   made in a child, so a hang ends in the alarm, not in a stuck test. */
static int report_child(void) {
    alarm(20);
    char dir[128], tmp[256], err[512] = "";
    snprintf(dir, sizeof dir, "%s/report", work);
    if (report_dir_begin(dir, tmp, sizeof tmp, err, sizeof err) != HT_ERR_IO) return 1;
    if (!strstr(err, "exists and is not a haircompare report")) return 2;
    return 0;
}

static void test_haircompare_does_not_wait_on_a_fifo_index_of_the_report_it_replaces(void **state) {
    (void)state;
    char path[128];
    assert_int_equal(mkdir(strcat(strcpy(path, work), "/report"), 0755), 0);
    assert_int_equal(mkfifo(strcat(strcpy(path, work), "/report/index.html"), 0600), 0);
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) _exit(report_child());
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        fail_msg("report_dir_begin over a FIFO index.html: %s %d", WIFEXITED(status) ? "exit" : "signal",
                 WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
}

/* The report folder itself. */
static void test_haircompare_report_refuses_a_fifo_or_device_as_its_folder(void **state) {
    (void)state;
    const char *names[2];
    for (int i = 0, n = targets(names); i < n; i++) {
        char dir[128], tmp[256], err[512] = "";
        snprintf(dir, sizeof dir, "%s/%s", work, names[i]);
        assert_int_equal(report_dir_begin(dir, tmp, sizeof tmp, err, sizeof err), HT_ERR_IO);
        if (!strstr(err, "exists and is not a directory")) fail_msg("%s", err);
        assert_untouched(names[i]);
    }
}

/* Row 10: replacing a bundle folder that held a subfolder exited 0 and
   left the old bundle behind as DIR.tmp-XXXXXX. */
static int count_temporaries(void) {
    char cmd[256];
    snprintf(cmd, sizeof cmd, "ls -a %s | grep -c tmp- >%s/count.txt", work, work);
    (void)system(cmd);
    return atoi(ht_test_read_file(work, "count.txt"));
}

static void test_publish_refuses_a_bundle_folder_holding_a_folder_and_leaves_no_temporary(void **state) {
    (void)state;
    copy_material("kk.json");
    assert_int_equal(run_hairgen("kk.json -o bundle -q"), 0);
    char path[128];
    assert_int_equal(mkdir(strcat(strcpy(path, work), "/bundle/mine"), 0755), 0);
    ht_test_write_file(path, "notes.txt", "kept\n");
    assert_int_equal(run_hairgen("kk.json -o bundle -q"), 1);
    assert_one_line("bundle: holds a folder hairgen did not write (mine); refusing to replace it");
    assert_string_equal(ht_test_read_file(path, "notes.txt"), "kept\n");
    assert_int_equal(count_temporaries(), 0);
}

/* A step that makes a folder where publishing must clean up after it:
   inside the temporary bundle (then fails), or inside the bundle being
   replaced (made after the target was checked). */
static ht_result folder_step(void *user, const char *dir, const ht_scene *scene, char *err, size_t err_size) {
    (void)scene;
    const char *where = user;
    char path[512];
    snprintf(path, sizeof path, "%s/sub", where ? where : dir);
    if (mkdir(path, 0755) != 0) return HT_ERR_IO;
    ht_test_write_file(path, "f.txt", "x");
    if (where) return HT_OK;
    snprintf(err, err_size, "%s: step failed", dir);
    return HT_ERR_IO;
}

static void test_publish_leaves_no_temporary_folder_on_any_path(void **state) {
    (void)state;
    copy_material("kk.json");
    char material[128], bundle[128], err[1024];
    snprintf(material, sizeof material, "%s/kk.json", work);
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    /* a failed step that made a folder in the temporary bundle */
    assert_int_equal(ht_generate_bundle_then(material, NULL, bundle, NULL, folder_step, NULL, err, sizeof err),
                     HT_ERR_IO);
    assert_false(ht_test_path_exists(bundle));
    assert_int_equal(count_temporaries(), 0);
    /* a folder made in the old bundle after it was checked: the old bundle
       goes whole */
    assert_int_equal(ht_generate_bundle(material, NULL, bundle, NULL, err, sizeof err), HT_OK);
    if (ht_generate_bundle_then(material, NULL, bundle, NULL, folder_step, bundle, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    assert_int_equal(count_temporaries(), 0);
    assert_true(ht_test_path_exists(strcat(strcpy(err, bundle), "/manifest.json")));
}

/* Row 11: hairgen only hashed a strands scene's strand file, so it
   published bundles for files the runtime refuses. The runtime's reader
   now reads it first: one line naming the scene, the file and the field. */
static void write_strands_scene(const char *name, const char *strand_file) {
    char text[1024];
    snprintf(text, sizeof text,
             "{\"format\": \"hairtier-scene/1\", \"resolution\": [64, 64],\n"
             " \"camera\": {\"eye\": [0, 0, 3], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 40},\n"
             " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], \"color\": [1, 1, 1]}],\n"
             " \"geometry\": {\"type\": \"strands\", \"file\": \"%s\"}}\n", strand_file);
    ht_test_write_file(work, name, text);
}

static void test_hairgen_reads_a_strands_scene_file_with_the_runtime_reader(void **state) {
    (void)state;
    copy_material("kk.json");
    char cmd[2 * PATH_MAX];
    snprintf(cmd, sizeof cmd, "cp %s/tests/data/strands/three-strands.tfx %s/good.tfx && "
             "cp %s/good.tfx %s/good.bin && cp %s/good.tfx %s/v3.tfx && "
             "printf '\\000\\000\\100\\100' | dd of=%s/v3.tfx conv=notrunc status=none",
             repo, work, work, work, work, work, work);
    assert_int_equal(system(cmd), 0);
    write_strands_scene("good.json", "good.tfx");
    assert_int_equal(run_hairgen("kk.json --scene good.json -o ok -q"), 0);
    static const struct { const char *file, *want; } bad[] = {
        { "v3.tfx", "bad.json: geometry.file: " },
        { "good.bin", "good.bin: not a strand file" },
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        write_strands_scene("bad.json", bad[i].file);
        assert_int_equal(run_hairgen("kk.json --scene bad.json -o bundle -q"), 1);
        assert_one_line(bad[i].want);
        assert_int_equal(run_hairgen("--batch kk.json --scene bad.json -o out -q"), 1);
        assert_one_line(bad[i].want);
        char dir[128];
        snprintf(dir, sizeof dir, "%s/bundle", work);
        assert_false(ht_test_path_exists(dir));
        snprintf(dir, sizeof dir, "%s/out/kk", work);
        assert_false(ht_test_path_exists(dir));
    }
}

/* Row 8: hairgen's own lines (progress, summary, usage) echo names
   escaped, so a newline in a file name stays in one line. */
static void test_hairgen_lines_escape_a_newline_in_a_file_name(void **state) {
    (void)state;
    copy_material("a\nb.json");
    assert_int_equal(run_hairgen("--batch 'a\nb.json' -o out"), 0);
    const char *out = ht_test_read_file(work, "out.txt");
    if (!strstr(out, "hairgen: [1/1] a\\nb.json -> out/a\\nb: ")) fail_msg("%s", out);
    assert_int_equal(run_hairgen("'--x\ny'"), 2);
    assert_one_line_then_usage("hairgen: --x\\ny: unknown option");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_hairgen_lines_escape_a_newline_in_a_file_name, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_reads_a_strands_scene_file_with_the_runtime_reader, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_publish_refuses_a_bundle_folder_holding_a_folder_and_leaves_no_temporary,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_publish_leaves_no_temporary_folder_on_any_path, setup, teardown),
        cmocka_unit_test_setup_teardown(test_png_writer_refuses_a_fifo_or_device_and_leaves_it, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_depfile_refuses_a_fifo_or_device_before_any_work, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_per_bundle_depfile_refuses_a_fifo, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_emit_header_refuses_a_fifo_or_device, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_bundle_refuses_a_fifo_or_device_as_its_folder, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_does_not_wait_on_a_fifo_manifest_of_the_bundle_it_replaces,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_haircompare_does_not_wait_on_a_fifo_index_of_the_report_it_replaces,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_haircompare_report_refuses_a_fifo_or_device_as_its_folder, setup,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

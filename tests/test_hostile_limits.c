/* test_hostile_limits.c — hostile files and sizes at the generator and the
   manifest reader (rows of docs/robustness.md): a material texture that is /dev/zero or a FIFO
   (C2, C3), a bundle directory path longer than the manifest keeps (D), a
   scene too big for the machine (G), a version with extra parts, and the
   messages that named the wrong thing (the texture file without its
   material field, packing, a full disk). Each test failed before its fix;
   the ones that used to hang run under alarm(). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <hairtier/hairgen.h>
#include <hairtier/ht_limits.h>
#include "manifest.h"
#include <hairtier/scene.h>
#include "support_scratch.h"

static char work[64];
static char bundle[128];

static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "limits")) return -1;
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    char err[512];
    if (ht_generate_bundle("materials/dark-brown.json", "scenes/furball.json", bundle, NULL, err, sizeof err) != HT_OK) {
        fprintf(stderr, "setup: %s\n", err);
        return -1;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* A material whose base texture is the file at path (alpha procedural). */
static void write_material(const char *name, const char *path) {
    char text[1024];
    snprintf(text, sizeof text,
             "{\"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"scheuermann\",\n"
             " \"diffuse\": {\"color\": [0.2, 0.1, 0.1], \"wrap\": 0.25},\n"
             " \"primary\": {\"color\": [1, 1, 1], \"exponent\": 80, \"shift\": -0.1},\n"
             " \"secondary\": {\"color\": [0.5, 0.4, 0.3], \"exponent\": 24, \"shift\": 0.15},\n"
             " \"textures\": {\"base\": {\"file\": \"%s\"}}}\n", path);
    ht_test_write_file(work, name, text);
}

static ht_result generate(const char *material, char *err, size_t err_size) {
    char m[256], out[256];
    snprintf(m, sizeof m, "%s/%s", work, material);
    snprintf(out, sizeof out, "%s/out", work);
    alarm(60); /* a hang (the defects) fails the test instead of the run */
    ht_result r = ht_generate_bundle(m, NULL, out, NULL, err, err_size);
    alarm(0);
    return r;
}

/* C2: hashing /dev/zero never ended. */
static void test_material_texture_at_dev_zero_is_refused_naming_the_field(void **state) {
    (void)state;
    write_material("zero.json", "/dev/zero");
    char err[1024] = "";
    assert_int_equal(generate("zero.json", err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "zero.json: textures.base.file: /dev/zero: not a regular file (a character device)"));
}

/* C3: hashing a FIFO waited for a writer forever. */
static void test_material_texture_that_is_a_fifo_is_refused_naming_the_field(void **state) {
    (void)state;
    char fifo[128];
    snprintf(fifo, sizeof fifo, "%s/base.png", work);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    write_material("fifo.json", "base.png");
    char err[1024] = "";
    assert_int_equal(generate("fifo.json", err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "fifo.json: textures.base.file: "));
    assert_non_null(strstr(err, "base.png: not a regular file (a FIFO)"));
    unlink(fifo);
}

/* A texture file that is not a PNG: the line names the material and field
   as well as the file. */
static void test_broken_texture_file_names_the_material_and_field(void **state) {
    (void)state;
    ht_test_write_file(work, "junk.png", "this is not a png");
    write_material("junk.json", "junk.png");
    char err[1024] = "";
    assert_int_not_equal(generate("junk.json", err, sizeof err), HT_OK);
    assert_non_null(strstr(err, "junk.json: textures.base.file: "));
    assert_non_null(strstr(err, "junk.png: not a PNG file"));
}

/* Builds a directory path of exactly len bytes under work (nested
   directories of at most 200 bytes a component). */
static void deep_dir(char *out, size_t len) {
    snprintf(out, len + 1, "%s", work);
    size_t n = strlen(out);
    while (n < len) {
        size_t part = len - n - 1;
        if (part > 200) part = 200;
        if (len - n - 1 - part > 0 && len - n - 1 - part < 2) part -= 2; /* leave room for one more */
        out[n++] = '/';
        memset(out + n, 'd', part);
        n += part;
        out[n] = '\0';
        assert_true(mkdir(out, 0700) == 0 || errno == EEXIST);
    }
    assert_int_equal(strlen(out), len);
}

/* D: the manifest was read from the real path and the shaders from its
   1023-byte prefix (another directory's bundle). */
static void test_bundle_directory_longer_than_the_limit_is_refused(void **state) {
    (void)state;
    char dir[1100];
    deep_dir(dir, 1027);
    rmdir(dir);
    ht_test_copy_dir(bundle, dir);
    ht_manifest m;
    char err[512] = "";
    ht_result r = ht_manifest_load(dir, &m, err, sizeof err);
    if (r != HT_ERR_INVALID_ARGUMENT) fail_msg("%d %s", (int)r, err);
    assert_non_null(strstr(err, "bundle directory path is 1027 bytes, more than 1023"));
    /* At the limit it loads, and the directory is kept whole. */
    char ok[1100];
    deep_dir(ok, HT_LIMIT_DIR_PATH);
    rmdir(ok);
    ht_test_copy_dir(bundle, ok);
    r = ht_manifest_load(ok, &m, err, sizeof err);
    if (r != HT_OK) fail_msg("%s", err);
    assert_string_equal(m.dir, ok);
}

static void test_generator_refuses_an_output_path_the_runtime_would_refuse(void **state) {
    (void)state;
    char dir[1100];
    deep_dir(dir, 1027);
    char err[512] = "";
    assert_int_equal(ht_generate_bundle("materials/dark-brown.json", NULL, dir, NULL, err, sizeof err),
                     HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "output directory path is 1027 bytes; the runtime reads bundles at paths of at most 1023"));
}

static void test_manifest_version_with_extra_parts_is_refused(void **state) {
    (void)state;
    char dir[256];
    snprintf(dir, sizeof dir, "%s/version", work);
    static const char *const bad[] = { "2.1.9.9.9", "2.", "2.1 beta", " 2.1", "123.1" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ht_test_copy_dir(bundle, dir);
        char *text = strdup(ht_test_read_file(dir, "manifest.json"));
        char *gl = strstr(text, "\"gl\":\t\"");
        assert_non_null(gl);
        char *end = strchr(gl + 7, '"');
        char edited[65536];
        snprintf(edited, sizeof edited, "%.*s%s%s", (int)(gl + 7 - text), text, bad[i], end);
        free(text);
        ht_test_write_file(dir, "manifest.json", edited);
        ht_manifest m;
        char err[512] = "";
        assert_int_equal(ht_manifest_load(dir, &m, err, sizeof err), HT_ERR_PARSE);
        assert_non_null(strstr(err, "requires.gl: \""));
        assert_non_null(strstr(err, "is not a version like \"2.1\""));
    }
}

/* G: the documented maximum needed more than 9 GB and failed in GL. */
static void test_scene_over_the_memory_budget_is_refused_naming_hairs(void **state) {
    (void)state;
    static const char head[] =
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [64, 64],\n"
        " \"camera\": {\"eye\": [0, 0, 3], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 40, \"near\": 0.05, \"far\": 100},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], \"color\": [1, 1, 1]}],\n"
        " \"background\": [0, 0, 0],\n";
    char text[2048];
    snprintf(text, sizeof text, "%s \"geometry\": {\"type\": \"furball\", \"hairs\": 1000000, \"joints\": 64}}", head);
    ht_scene s;
    char err[512] = "";
    ht_result r = ht_scene_parse(text, "big.json", &s, err, sizeof err);
    if (r != HT_ERR_UNSUPPORTED) fail_msg("%s", err);
    assert_non_null(strstr(err, "big.json: geometry.hairs: needs about "));
    assert_non_null(strstr(err, " GB (1000000 hairs x 64 joints), more than the 4 GB a scene may use; at most "));
    /* The shipped scenes fit. */
    assert_int_equal(ht_scene_load("scenes/furball.json", &s, err, sizeof err), HT_OK);
    assert_true(ht_scene_memory_estimate(&s) < HT_LIMIT_SCENE_BYTES);
    assert_int_equal(ht_scene_load("scenes/patches.json", &s, err, sizeof err), HT_OK);
    /* The largest patches scene the reader accepts fits too. */
    snprintf(text, sizeof text, "%s \"geometry\": {\"type\": \"patches\", \"layers\": 8, \"strips\": 1024, "
             "\"segments\": 256}}", head);
    assert_int_equal(ht_scene_parse(text, "patches.json", &s, err, sizeof err), HT_OK);
}

/* A full disk: the message named the temporary directory, removed by the
   time anyone reads it. A file size limit stands in for the disk. */
static void test_write_failure_names_the_bundle_not_the_removed_temporary(void **state) {
    (void)state;
    int pipefd[2];
    assert_int_equal(pipe(pipefd), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(pipefd[0]);
        signal(SIGXFSZ, SIG_IGN);
        struct rlimit lim = { 4096, 4096 };
        setrlimit(RLIMIT_FSIZE, &lim);
        char out[256], err[1024] = "";
        snprintf(out, sizeof out, "%s/full", work);
        ht_result r = ht_generate_bundle("materials/dark-brown.json", NULL, out, NULL, err, sizeof err);
        dprintf(pipefd[1], "%d %s", (int)r, err);
        _exit(0);
    }
    close(pipefd[1]);
    char got[1200] = "";
    ssize_t n = read(pipefd[0], got, sizeof got - 1);
    close(pipefd[0]);
    waitpid(pid, NULL, 0);
    assert_true(n > 0);
    got[n] = '\0';
    char expect[256];
    snprintf(expect, sizeof expect, "%s/full/", work);
    if (!strstr(got, expect) || strstr(got, ".tmp-") || !strstr(got, "is as it was"))
        fail_msg("got: %s", got);
    struct stat st;
    snprintf(expect, sizeof expect, "%s/full", work);
    assert_int_not_equal(stat(expect, &st), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_material_texture_at_dev_zero_is_refused_naming_the_field),
        cmocka_unit_test(test_material_texture_that_is_a_fifo_is_refused_naming_the_field),
        cmocka_unit_test(test_broken_texture_file_names_the_material_and_field),
        cmocka_unit_test(test_bundle_directory_longer_than_the_limit_is_refused),
        cmocka_unit_test(test_generator_refuses_an_output_path_the_runtime_would_refuse),
        cmocka_unit_test(test_manifest_version_with_extra_parts_is_refused),
        cmocka_unit_test(test_scene_over_the_memory_budget_is_refused_naming_hairs),
        cmocka_unit_test(test_write_failure_names_the_bundle_not_the_removed_temporary),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

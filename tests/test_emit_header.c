/* test_emit_header.c — hairgen --emit-header on the command line: beside
   or instead of -o DIR; the header holds every bundle file under one entry;
   usage errors exit 2, a bad symbol or material exits 1 with one line and
   writes nothing, and a failed run leaves an existing header as it was;
   with -o the header comes from the directory's own generation (its
   measured manifest included).
   (Drawing from a header, and its bytes against the directory's, are
   test_render_bundle_memory's.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <hairtier/hairgen.h>
#include "support_scratch.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "emit-header") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* hairgen ARGS, stdout to work/stdout.txt, stderr to work/stderr.txt; the
   exit status. */
static int run_hairgen(const char *args) {
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s/hairgen %s >%s/stdout.txt 2>%s/stderr.txt", build && build[0] ? build : "build",
             args, work, work);
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* Files in work whose name holds ".tmp-": what a failed write leaves. */
static int count_temporaries(void) {
    DIR *d = opendir(work);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d))) n += strstr(e->d_name, ".tmp-") != NULL;
    closedir(d);
    return n;
}

/* stderr held exactly one line containing what. */
static void assert_one_line_error(const char *what) {
    char path[128];
    snprintf(path, sizeof path, "%s/stderr.txt", work);
    char *text = ht_test_read_all(path, NULL);
    assert_non_null(text);
    if (!strstr(text, what)) fail_msg("no \"%s\" in: %s", what, text);
    assert_ptr_equal(strchr(text, '\n'), text + strlen(text) - 1);
    free(text);
}

static void test_header_instead_of_a_directory_holds_every_file_under_one_entry(void **state) {
    (void)state;
    char args[512], header[128], dir[128];
    snprintf(header, sizeof header, "%s/kk.h", work);
    snprintf(args, sizeof args, "materials/kajiya-kay.json --emit-header %s", header);
    assert_int_equal(run_hairgen(args), 0);
    char *text = ht_test_read_all(header, NULL);
    assert_non_null(text);
    assert_non_null(strstr(text, "static const ht_bundle_memory kajiya_kay_bundle = { \"kajiya_kay_bundle\", "
                                 "kajiya_kay_bundle_files, "));
    assert_non_null(strstr(text, "#include <hairtier/hairtier.h>"));
    /* One array per file of the directory the same run writes with -o. */
    snprintf(dir, sizeof dir, "%s/kk-bundle", work);
    snprintf(args, sizeof args, "materials/kajiya-kay.json -o %s --emit-header %s/kk2.h --header-symbol kk", dir,
             work);
    assert_int_equal(run_hairgen(args), 0);
    DIR *d = opendir(dir);
    assert_non_null(d);
    int files = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char entry[320];
        snprintf(entry, sizeof entry, "    { \"%s\", kajiya_kay_bundle_f", e->d_name);
        if (!strstr(text, entry)) fail_msg("%s: not in the header", e->d_name);
        files++;
    }
    closedir(d);
    char count[64];
    snprintf(count, sizeof count, "kajiya_kay_bundle_files, %d };", files);
    assert_non_null(strstr(text, count));
    free(text);
    /* The named symbol, and the summary names the header. */
    snprintf(header, sizeof header, "%s/kk2.h", work);
    text = ht_test_read_all(header, NULL);
    assert_non_null(strstr(text, "static const ht_bundle_memory kk = { \"kk\", kk_files, "));
    free(text);
    snprintf(header, sizeof header, "%s/stdout.txt", work);
    text = ht_test_read_all(header, NULL);
    assert_non_null(strstr(text, "kk2.h"));
    free(text);
    assert_int_equal(count_temporaries(), 0);
}

static void test_usage_errors_exit_2(void **state) {
    (void)state;
    char args[512];
    assert_int_equal(run_hairgen("materials/dark-brown.json"), 2); /* neither -o nor --emit-header */
    snprintf(args, sizeof args, "materials/dark-brown.json -o %s/u --header-symbol x", work);
    assert_int_equal(run_hairgen(args), 2); /* a symbol without a header */
    assert_int_equal(run_hairgen("materials/dark-brown.json --emit-header ''"), 2);
    snprintf(args, sizeof args, "materials/dark-brown.json --emit-header %s/a.h --emit-header %s/b.h", work, work);
    assert_int_equal(run_hairgen(args), 2);
    assert_false(ht_test_path_exists("materials/a.h"));
}

static void test_bad_symbol_or_material_writes_nothing_and_keeps_the_old_header(void **state) {
    (void)state;
    char args[512], header[128];
    snprintf(header, sizeof header, "%s/keep.h", work);
    snprintf(args, sizeof args, "materials/dark-brown.json --emit-header %s --header-symbol 2fast", header);
    assert_int_equal(run_hairgen(args), 1);
    assert_one_line_error("hairgen: --header-symbol: \"2fast\": not a C identifier");
    assert_false(ht_test_path_exists(header));
    char dir[128];
    snprintf(dir, sizeof dir, "%s/not-written", work);
    snprintf(args, sizeof args, "materials/dark-brown.json -o %s --emit-header %s --header-symbol struct", dir,
             header);
    assert_int_equal(run_hairgen(args), 1);
    assert_one_line_error("\"struct\": a C or C++ keyword");
    assert_false(ht_test_path_exists(dir)); /* refused before the directory too */

    snprintf(args, sizeof args, "materials/dark-brown.json --emit-header %s", header);
    assert_int_equal(run_hairgen(args), 0);
    char *before = ht_test_read_all(header, NULL);
    assert_non_null(before);
    snprintf(args, sizeof args, "no-such-material.json --emit-header %s", header);
    assert_int_equal(run_hairgen(args), 1);
    assert_one_line_error("no-such-material.json");
    char *after = ht_test_read_all(header, NULL);
    assert_string_equal(before, after);
    free(before);
    free(after);
    /* A directory that does not exist: one line naming the header. */
    snprintf(args, sizeof args, "materials/dark-brown.json --emit-header %s/no/such/dir/x.h", work);
    assert_int_equal(run_hairgen(args), 1);
    assert_one_line_error("/no/such/dir/x.h: cannot create a temporary file beside it");
    assert_int_equal(count_temporaries(), 0);
}

/* Issue 19 row 6: identifiers the included headers define gave a header
   that does not compile, with exit 0. Each is refused with one line, and
   the default symbol of a material named like hairtier's own names passes. */
static void test_header_symbol_refuses_names_the_included_headers_define(void **state) {
    (void)state;
    static const char *const taken[] = { "size_t", "uint8_t", "NULL", "HT_OK", "ht_bundle_memory",
                                         "ht_renderer_create", "offsetof", "SIZE_MAX", "INT8_C", "ht", "Ht_x",
                                         "std", NULL };
    char args[512], header[128];
    snprintf(header, sizeof header, "%s/taken.h", work);
    for (int i = 0; taken[i]; i++) {
        snprintf(args, sizeof args, "materials/dark-brown.json --emit-header %s --header-symbol %s", header,
                 taken[i]);
        if (run_hairgen(args) != 1) fail_msg("--header-symbol %s: accepted", taken[i]);
        char want[96];
        snprintf(want, sizeof want, "--header-symbol: \"%s\": ", taken[i]);
        assert_one_line_error(want);
        assert_false(ht_test_path_exists(header));
    }
    char sym[HT_HEADER_SYMBOL_MAX + 1];
    ht_header_symbol_default("ht-renderer", sym);
    assert_string_equal(sym, "hair_ht_renderer_bundle");
    assert_int_equal(ht_header_symbol_check(sym, args, sizeof args), HT_OK);
    ht_header_symbol_default("HT_OK", sym);
    assert_int_equal(ht_header_symbol_check(sym, args, sizeof args), HT_OK);
}

/* The bytes of the array the header holds for file `name`, malloc'd. */
static unsigned char *header_file_bytes(const char *text, const char *name, size_t *size) {
    char marker[96];
    snprintf(marker, sizeof marker, "/* %s */\n", name);
    const char *at = strstr(text, marker);
    assert_non_null(at);
    at = strstr(at, "] = {");
    assert_non_null(at);
    at += 5;
    const char *end = strstr(at, "};");
    assert_non_null(end);
    unsigned char *bytes = malloc((size_t)(end - at));
    assert_non_null(bytes);
    size_t n = 0;
    while (at < end) {
        char *next;
        long v = strtol(at, &next, 10);
        if (next == at) {
            at++;
            continue;
        }
        assert_in_range(v, 0, 255);
        bytes[n++] = (unsigned char)v;
        at = next;
    }
    *size = n;
    return bytes;
}

/* -o, --emit-header and --measure in one run: one generation, and the
   header holds the manifest the measure step wrote into the directory (a
   second generation for the header would hold one without "measured").
   Measured on a small scene: what is measured is test_measure's. */
static void test_directory_and_header_from_one_run_hold_the_measured_manifest(void **state) {
    (void)state;
    char args[700], header[128], dir[128], manifest[160], scene[128];
    snprintf(header, sizeof header, "%s/measured.h", work);
    snprintf(dir, sizeof dir, "%s/measured", work);
    snprintf(scene, sizeof scene, "%s/small.json", work);
    ht_test_write_file(work, "small.json",
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [48, 40],\n"
        " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]}],\n"
        " \"background\": [0.1, 0.2, 0.3],\n"
        " \"geometry\": {\"type\": \"furball\", \"hairs\": 200, \"joints\": 6, \"length\": 0.1, \"width\": 0.02}}\n");
    snprintf(args, sizeof args, "materials/kajiya-kay.json --scene %s -o %s --emit-header %s --measure", scene, dir,
             header);
    assert_int_equal(run_hairgen(args), 0);
    snprintf(manifest, sizeof manifest, "%s/manifest.json", dir);
    size_t file_size, header_size;
    char *file = ht_test_read_all(manifest, &file_size);
    char *text = ht_test_read_all(header, NULL);
    assert_non_null(file);
    assert_non_null(text);
    assert_non_null(strstr(file, "\"measured\""));
    unsigned char *held = header_file_bytes(text, "manifest.json", &header_size);
    assert_int_equal(header_size, file_size);
    assert_memory_equal(held, file, file_size);
    free(held);
    free(file);
    free(text);
    assert_int_equal(count_temporaries(), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_header_instead_of_a_directory_holds_every_file_under_one_entry),
        cmocka_unit_test(test_usage_errors_exit_2),
        cmocka_unit_test(test_bad_symbol_or_material_writes_nothing_and_keeps_the_old_header),
        cmocka_unit_test(test_header_symbol_refuses_names_the_included_headers_define),
        cmocka_unit_test(test_directory_and_header_from_one_run_hold_the_measured_manifest),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_bundle.c — hairgen's bundle: every tier written, byte-identical
   across runs, atomic on failure, and the CLI's exit codes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_scratch.h"

static char work[64];

static int make_work_dir(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "bundle") ? 0 : -1;
}

static int remove_work_dir(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static void write_text(const char *path, const char *text) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static cJSON *load_manifest(const char *dir) { return ht_test_read_json(dir, "manifest.json"); }

static void generate(const char *material, const char *scene, const char *dir) {
    char err[2048] = "";
    ht_result r = ht_generate_bundle(material, scene, dir, NULL, err, sizeof err);
    if (r != HT_OK) fail_msg("ht_generate_bundle: %s", err);
}

static void test_bundle_lists_every_tier_best_first_with_existing_files(void **state) {
    (void)state;
    char dir[256];
    snprintf(dir, sizeof dir, "%s/dark", work);
    generate("materials/dark-brown.json", "scenes/furball.json", dir);
    cJSON *m = load_manifest(dir);
    assert_string_equal(cJSON_GetObjectItem(m, "format")->valuestring, "hairtier-bundle/1");
    cJSON *tiers = cJSON_GetObjectItem(m, "tiers");
    const char *expected[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    assert_int_equal(cJSON_GetArraySize(tiers), 5);
    for (int i = 0; i < 5; i++) {
        cJSON *t = cJSON_GetArrayItem(tiers, i);
        assert_string_equal(cJSON_GetObjectItem(t, "name")->valuestring, expected[i]);
        assert_non_null(cJSON_GetObjectItem(cJSON_GetObjectItem(t, "requires"), "texture_units"));
        cJSON *file;
        cJSON_ArrayForEach(file, cJSON_GetObjectItem(t, "files")) {
            char path[512];
            snprintf(path, sizeof path, "%s/%s", dir, file->valuestring);
            size_t size = 0;
            char *text = ht_test_read_all(path, &size);
            assert_non_null(text);
            const char *dot = strrchr(file->valuestring, '.');
            if (strcmp(dot, ".vert") == 0 || strcmp(dot, ".frag") == 0)
                assert_memory_equal(text, "#version ", 9);
            free(text);
        }
    }
    cJSON *tex;
    cJSON_ArrayForEach(tex, cJSON_GetObjectItem(m, "textures")) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, cJSON_GetObjectItem(tex, "file")->valuestring);
        assert_true(ht_test_path_exists(path));
    }
    cJSON_Delete(m);
}

/* Compares every file of two bundles byte for byte. */
static void assert_same_tree(const char *a, const char *b) {
    DIR *d = opendir(a);
    assert_non_null(d);
    struct dirent *e;
    int files = 0;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.') continue;
        char pa[512], pb[512];
        snprintf(pa, sizeof pa, "%s/%s", a, e->d_name);
        snprintf(pb, sizeof pb, "%s/%s", b, e->d_name);
        size_t na = 0, nb = 0;
        char *ta = ht_test_read_all(pa, &na), *tb = ht_test_read_all(pb, &nb);
        assert_non_null(tb);
        assert_int_equal(na, nb);
        assert_memory_equal(ta, tb, na);
        free(ta);
        free(tb);
        files++;
    }
    closedir(d);
    assert_true(files >= 8);
}

static void test_bundle_is_byte_identical_across_runs(void **state) {
    (void)state;
    char a[256], b[256];
    snprintf(a, sizeof a, "%s/run-a", work);
    snprintf(b, sizeof b, "%s/run-b", work);
    generate("materials/dark-brown.json", "scenes/furball.json", a);
    generate("materials/dark-brown.json", "scenes/furball.json", b);
    assert_same_tree(a, b);
    assert_same_tree(b, a);
}

static int count_temporaries(void) {
    DIR *d = opendir(work);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) n += strstr(e->d_name, ".tmp-") != NULL;
    closedir(d);
    return n;
}

static void test_bundle_failure_writes_nothing(void **state) {
    (void)state;
    char material[256], dir[256], err[2048] = "";
    snprintf(material, sizeof material, "%s/missing-texture.json", work);
    snprintf(dir, sizeof dir, "%s/never", work);
    write_text(material,
               "{ \"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"scheuermann\",\n"
               "  \"diffuse\": {\"color\": [0.2,0.1,0.1]},\n"
               "  \"primary\": {\"color\": [1,1,1], \"exponent\": 80},\n"
               "  \"secondary\": {\"color\": [0.5,0.5,0.5], \"exponent\": 20},\n"
               "  \"textures\": {\"base\": {\"file\": \"no-such-file.png\"}} }\n");
    ht_result r = ht_generate_bundle(material, NULL, dir, NULL, err, sizeof err);
    assert_int_not_equal(r, HT_OK);
    assert_non_null(strstr(err, "no-such-file.png"));
    assert_false(ht_test_path_exists(dir));
    assert_int_equal(count_temporaries(), 0);
}

static void test_bundle_failure_keeps_the_previous_bundle(void **state) {
    (void)state;
    char material[256], dir[256], err[2048] = "", manifest[300];
    snprintf(material, sizeof material, "%s/broken.json", work);
    snprintf(dir, sizeof dir, "%s/kept", work);
    snprintf(manifest, sizeof manifest, "%s/manifest.json", dir);
    generate("materials/kajiya-kay.json", NULL, dir);
    size_t before_size = 0, after_size = 0;
    char *before = ht_test_read_all(manifest, &before_size);
    write_text(material, "{ \"format\": \"hairtier-material/1\", \"name\": \"m\", ");
    assert_int_not_equal(ht_generate_bundle(material, NULL, dir, NULL, err, sizeof err), HT_OK);
    char *after = ht_test_read_all(manifest, &after_size);
    assert_non_null(after);
    assert_int_equal(before_size, after_size);
    assert_memory_equal(before, after, before_size);
    assert_int_equal(count_temporaries(), 0);
    free(before);
    free(after);
}

static void test_bundle_replaces_an_existing_bundle(void **state) {
    (void)state;
    char dir[256];
    snprintf(dir, sizeof dir, "%s/replaced", work);
    generate("materials/kajiya-kay.json", NULL, dir);
    generate("materials/dark-brown.json", NULL, dir);
    cJSON *m = load_manifest(dir);
    assert_string_equal(cJSON_GetObjectItem(m, "material")->valuestring, "dark-brown");
    cJSON_Delete(m);
    assert_int_equal(count_temporaries(), 0);
}

static void test_bundle_input_hash_follows_the_inputs(void **state) {
    (void)state;
    char a[256], b[256], c[256];
    snprintf(a, sizeof a, "%s/hash-a", work);
    snprintf(b, sizeof b, "%s/hash-b", work);
    snprintf(c, sizeof c, "%s/hash-c", work);
    generate("materials/dark-brown.json", "scenes/furball.json", a);
    generate("materials/dark-brown.json", "scenes/patches.json", b);
    generate("materials/kajiya-kay.json", "scenes/furball.json", c);
    cJSON *ma = load_manifest(a), *mb = load_manifest(b), *mc = load_manifest(c);
    const char *ha = cJSON_GetObjectItem(ma, "input_hash")->valuestring;
    assert_string_not_equal(ha, cJSON_GetObjectItem(mb, "input_hash")->valuestring);
    assert_string_not_equal(ha, cJSON_GetObjectItem(mc, "input_hash")->valuestring);
    cJSON_Delete(ma);
    cJSON_Delete(mb);
    cJSON_Delete(mc);
}

static void test_bundle_refuses_to_replace_a_directory_that_is_not_a_bundle(void **state) {
    (void)state;
    char dir[256], keep[300], err[2048] = "";
    snprintf(dir, sizeof dir, "%s/not-a-bundle", work);
    snprintf(keep, sizeof keep, "%s/precious.txt", dir);
    mkdir(dir, 0755);
    write_text(keep, "mine\n");
    assert_int_equal(ht_generate_bundle("materials/dark-brown.json", NULL, dir, NULL, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "not a hairtier bundle"));
    assert_true(ht_test_path_exists(keep));
    assert_int_equal(count_temporaries(), 0);
}

static void test_bundle_onto_a_file_fails_and_leaves_nothing(void **state) {
    (void)state;
    char file[256], err[2048] = "";
    snprintf(file, sizeof file, "%s/plain-file", work);
    write_text(file, "x");
    assert_int_equal(ht_generate_bundle("materials/dark-brown.json", NULL, file, NULL, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "not a directory"));
    assert_int_equal(count_temporaries(), 0);
}

static void test_bundle_path_with_trailing_slash_is_the_same_bundle(void **state) {
    (void)state;
    char dir[256], slashed[260];
    snprintf(dir, sizeof dir, "%s/slashed", work);
    snprintf(slashed, sizeof slashed, "%s//", dir);
    generate("materials/kajiya-kay.json", NULL, slashed);
    generate("materials/dark-brown.json", NULL, slashed); /* replaces, no temporary inside */
    cJSON *m = load_manifest(dir);
    assert_string_equal(cJSON_GetObjectItem(m, "material")->valuestring, "dark-brown");
    cJSON_Delete(m);
    DIR *d = opendir(dir);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) assert_null(strstr(e->d_name, ".tmp-"));
    closedir(d);
    assert_int_equal(count_temporaries(), 0);
}

static void test_bundle_is_readable_per_the_umask(void **state) {
    (void)state;
    char dir[256];
    snprintf(dir, sizeof dir, "%s/modes", work);
    mode_t old = umask(022);
    generate("materials/kajiya-kay.json", NULL, dir);
    umask(old);
    struct stat st;
    assert_int_equal(stat(dir, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0755);
}

static int run_hairgen(const char *args) {
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "%s/hairgen %s >/dev/null 2>%s/stderr.txt", build ? build : "build", args, work);
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void test_hairgen_cli_reports_errors_with_exit_codes(void **state) {
    (void)state;
    char args[512], path[300];
    assert_int_equal(run_hairgen("--help"), 0);
    assert_int_equal(run_hairgen(""), 2);
    assert_int_equal(run_hairgen("materials/dark-brown.json --bogus -o x"), 2);
    assert_int_equal(run_hairgen("materials/dark-brown.json -o a -o b"), 2);
    assert_int_equal(run_hairgen("materials/dark-brown.json -o ''"), 2);
    snprintf(args, sizeof args, "no-such-material.json -o %s/cli-missing", work);
    assert_int_equal(run_hairgen(args), 1);
    snprintf(path, sizeof path, "%s/stderr.txt", work);
    char *text = ht_test_read_all(path, NULL);
    assert_non_null(strstr(text, "no-such-material.json"));
    assert_non_null(strchr(text, '\n'));
    assert_ptr_equal(strchr(text, '\n'), text + strlen(text) - 1); /* one line */
    free(text);
    snprintf(args, sizeof args, "materials/dark-brown.json --scene scenes/patches.json -o %s/cli-ok", work);
    assert_int_equal(run_hairgen(args), 0);
}

static void write_png(const char *path, int width, int height) {
    ht_image img;
    char err[256];
    assert_int_equal(ht_image_alloc(&img, width, height, 3), HT_OK);
    memset(img.pixels, 200, (size_t)width * (size_t)height * 3);
    if (ht_image_write_png(path, &img, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_image_free(&img);
}

/* hairgen on `material` must exit 1 with one stderr line naming the material
   file and `field`, and write nothing. */
static void expect_hairgen_refuses(const char *material, const char *field, const char *dir) {
    char args[700], path[300];
    snprintf(args, sizeof args, "%s -o %s", material, dir);
    assert_int_equal(run_hairgen(args), 1);
    snprintf(path, sizeof path, "%s/stderr.txt", work);
    char *text = ht_test_read_all(path, NULL);
    assert_non_null(text);
    char want[600];
    snprintf(want, sizeof want, "hairgen: %s: %s: ", material, field);
    if (!strstr(text, want)) fail_msg("no \"%s\" in: %s", want, text);
    assert_ptr_equal(strchr(text, '\n'), text + strlen(text) - 1); /* one line */
    free(text);
    assert_false(ht_test_path_exists(dir));
    assert_int_equal(count_temporaries(), 0);
}

static void write_textured_material(const char *path, const char *textures) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "{ \"format\": \"hairtier-material/1\", \"name\": \"m\", \"model\": \"scheuermann\",\n"
               "  \"diffuse\": {\"color\": [0.2,0.1,0.1]},\n"
               "  \"primary\": {\"color\": [1,1,1], \"exponent\": 80},\n"
               "  \"secondary\": {\"color\": [0.5,0.5,0.5], \"exponent\": 20},\n"
               "  \"textures\": {%s} }\n", textures);
    fclose(f);
}

static void test_hairgen_refuses_a_texture_wider_than_the_runtime_reads(void **state) {
    (void)state;
    char png[300], material[300], dir[300];
    snprintf(png, sizeof png, "%s/wide.png", work);
    write_png(png, 65536, 1);
    snprintf(material, sizeof material, "%s/wide.json", work);
    write_textured_material(material, "\"base\": {\"file\": \"wide.png\"}");
    snprintf(dir, sizeof dir, "%s/wide-bundle", work);
    expect_hairgen_refuses(material, "textures.base", dir);
}

static void test_hairgen_refuses_a_packed_albedo_over_the_runtime_texel_limit(void **state) {
    (void)state;
    char png[300], material[300], dir[300];
    snprintf(png, sizeof png, "%s/row.png", work);
    write_png(png, 16384, 1);
    snprintf(png, sizeof png, "%s/column.png", work);
    write_png(png, 1, 16384);
    snprintf(material, sizeof material, "%s/huge.json", work);
    write_textured_material(material, "\"base\": {\"file\": \"row.png\"}, \"alpha\": {\"file\": \"column.png\"}");
    snprintf(dir, sizeof dir, "%s/huge-bundle", work);
    expect_hairgen_refuses(material, "textures.base, textures.alpha", dir);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bundle_lists_every_tier_best_first_with_existing_files),
        cmocka_unit_test(test_bundle_is_byte_identical_across_runs),
        cmocka_unit_test(test_bundle_failure_writes_nothing),
        cmocka_unit_test(test_bundle_failure_keeps_the_previous_bundle),
        cmocka_unit_test(test_bundle_replaces_an_existing_bundle),
        cmocka_unit_test(test_bundle_input_hash_follows_the_inputs),
        cmocka_unit_test(test_hairgen_cli_reports_errors_with_exit_codes),
        cmocka_unit_test(test_bundle_refuses_to_replace_a_directory_that_is_not_a_bundle),
        cmocka_unit_test(test_bundle_onto_a_file_fails_and_leaves_nothing),
        cmocka_unit_test(test_bundle_path_with_trailing_slash_is_the_same_bundle),
        cmocka_unit_test(test_bundle_is_readable_per_the_umask),
        cmocka_unit_test(test_hairgen_refuses_a_texture_wider_than_the_runtime_reads),
        cmocka_unit_test(test_hairgen_refuses_a_packed_albedo_over_the_runtime_texel_limit),
    };
    return cmocka_run_group_tests(tests, make_work_dir, remove_work_dir);
}

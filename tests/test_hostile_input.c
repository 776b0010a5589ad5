/* test_hostile_input.c — inputs a hostile user (or a fuzzer) found: each
   test here failed before its fix. Texts sit at the very end of a mapped
   page followed by an unmapped one, so reading one byte past the end
   crashes even without AddressSanitizer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "json_check.h"

/* text (with its NUL) copied to the end of a page whose next page is
   PROT_NONE. Returns the copy; *map and *map_size are for munmap. */
static const char *at_page_end(const char *text, void **map, size_t *map_size) {
    size_t page = (size_t)sysconf(_SC_PAGESIZE), n = strlen(text) + 1;
    size_t pages = (n + page - 1) / page + 1;
    char *m = mmap(NULL, pages * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    assert_true(m != MAP_FAILED);
    assert_int_equal(mprotect(m + (pages - 1) * page, page, PROT_NONE), 0);
    char *copy = m + (pages - 1) * page - n;
    memcpy(copy, text, n);
    *map = m;
    *map_size = pages * page;
    return copy;
}

static ht_result parse_guarded(const char *text, char *err, size_t err_size) {
    void *map;
    size_t map_size;
    const char *guarded = at_page_end(text, &map, &map_size);
    ht_jctx c = { .file = "hostile.json", .err = err, .err_size = err_size };
    cJSON *root = NULL;
    ht_result r = ht_json_parse_root(&c, guarded, &root);
    cJSON_Delete(root);
    munmap(map, map_size);
    return r;
}

/* Defect A: the strict-number check read past the NUL of a text ending in
   a digit (heap-buffer-overflow under ASan). */
static void test_text_ending_in_an_integer_is_read_within_bounds(void **state) {
    (void)state;
    char err[256] = "";
    assert_int_equal(parse_guarded("4", err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "hostile.json: (root): expected a JSON object"));
    assert_int_equal(parse_guarded("{\"a\": 5}\n-12", err, sizeof err), HT_ERR_PARSE);
    assert_int_equal(parse_guarded("[1, 2, 3.5e7", err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "truncated"));
    assert_int_equal(parse_guarded("{\"a\": 1e5}", err, sizeof err), HT_OK);
}

static void test_nesting_deeper_than_cjson_allows_says_so(void **state) {
    (void)state;
    size_t depth = CJSON_NESTING_LIMIT + 5;
    char *text = malloc(2 * depth + 16);
    assert_non_null(text);
    size_t n = 0;
    text[n++] = '{';
    memcpy(text + n, "\"a\":", 4);
    n += 4;
    for (size_t i = 0; i < depth; i++) text[n++] = '[';
    for (size_t i = 0; i < depth; i++) text[n++] = ']';
    text[n++] = '}';
    text[n] = '\0';
    char err[256] = "";
    assert_int_equal(parse_guarded(text, err, sizeof err), HT_ERR_PARSE);
    if (!strstr(err, "nested more than 1000 levels deep")) fail_msg("unexpected error: %s", err);
    free(text);
}

/* Defect C1: a JSON file (a bundle's manifest, a material) that is a FIFO
   blocked the reader forever; /dev/zero would never end. */
static void test_json_reader_refuses_fifos_and_devices(void **state) {
    (void)state;
    char dir[] = "/tmp/hairtier-test-hostile-XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    assert_int_equal(mkfifo(path, 0600), 0);
    char *text = NULL, err[256] = "";
    assert_int_equal(ht_json_read_file(path, &text, err, sizeof err), HT_ERR_IO);
    if (!strstr(err, "manifest.json: not a regular file (a FIFO)")) fail_msg("unexpected error: %s", err);
    assert_null(text);
    unlink(path);
    rmdir(dir);
    assert_int_equal(ht_json_read_file("/dev/zero", &text, err, sizeof err), HT_ERR_IO);
    if (!strstr(err, "/dev/zero: not a regular file (a character device)")) fail_msg("unexpected error: %s", err);
    assert_int_equal(ht_json_read_file("/tmp", &text, err, sizeof err), HT_ERR_IO);
    if (!strstr(err, "/tmp: not a regular file (a directory)")) fail_msg("unexpected error: %s", err);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_text_ending_in_an_integer_is_read_within_bounds),
        cmocka_unit_test(test_nesting_deeper_than_cjson_allows_says_so),
        cmocka_unit_test(test_json_reader_refuses_fifos_and_devices),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

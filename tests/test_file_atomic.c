/* test_file_atomic — ht_file_write_atomic (runtime/io/file_atomic.h): the
   file replaced whole, a failed writer leaving the old file and no
   temporary, the writer's own reason in the error, mode 0644. */
#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "file_atomic.h"
#include "support_scratch.h"

static char work[64];

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "file-atomic") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static bool write_hello(FILE *f, void *ctx, char *why, size_t why_size) {
    (void)why, (void)why_size;
    return fprintf(f, "hello %s\n", (const char *)ctx) > 0;
}

static bool write_half_then_fail(FILE *f, void *ctx, char *why, size_t why_size) {
    (void)ctx;
    (void)why, (void)why_size;
    fputs("half", f);
    return false;
}

/* Files in the scratch directory: a temporary left behind shows here. */
static int files_in_work(void) {
    DIR *d = opendir(work);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));)
        if (e->d_name[0] != '.') n++;
    closedir(d);
    return n;
}

static void test_atomic_write_replaces_the_file_whole(void **state) {
    (void)state;
    char path[128], err[256];
    snprintf(path, sizeof path, "%s/out.txt", work);
    ht_test_write_file(work, "out.txt", "old\n");
    assert_int_equal(HT_OK, ht_file_write_atomic(path, write_hello, "world", err, sizeof err));
    assert_string_equal(ht_test_read_file(work, "out.txt"), "hello world\n");
    assert_int_equal(files_in_work(), 1);
}

static void test_a_failed_write_leaves_the_old_file_and_no_temporary(void **state) {
    (void)state;
    char path[128], err[256] = "";
    snprintf(path, sizeof path, "%s/keep.txt", work);
    ht_test_write_file(work, "keep.txt", "old\n");
    int before = files_in_work();
    assert_int_equal(HT_ERR_IO, ht_file_write_atomic(path, write_half_then_fail, NULL, err, sizeof err));
    assert_string_equal(strstr(err, "keep.txt: "), "keep.txt: write failed"); /* no system error to name */
    assert_string_equal(ht_test_read_file(work, "keep.txt"), "old\n");
    assert_int_equal(files_in_work(), before);

    snprintf(path, sizeof path, "%s/no-such-dir/out.txt", work);
    assert_int_equal(HT_ERR_IO, ht_file_write_atomic(path, write_hello, "x", err, sizeof err));
    assert_non_null(strstr(err, "no-such-dir/out.txt: cannot create a temporary file beside it: "));
}


static bool write_then_refuse(FILE *f, void *ctx, char *why, size_t why_size) {
    (void)ctx;
    fputs("partial", f);
    snprintf(why, why_size, "the encoder refused");
    return false;
}

/* A writer's own reason is the error, after the path; mode 0644 like any
   file the caller creates (mkstemp's 0600 is not kept). */
static void test_a_writer_names_its_own_reason_and_files_are_world_readable(void **state) {
    (void)state;
    char path[128], err[256] = "";
    snprintf(path, sizeof path, "%s/own.txt", work);
    assert_int_equal(HT_ERR_IO, ht_file_write_atomic(path, write_then_refuse, NULL, err, sizeof err));
    assert_string_equal(strstr(err, "own.txt: "), "own.txt: the encoder refused");
    assert_false(ht_test_path_exists(path));
    assert_int_equal(files_in_work(), 0);
    assert_int_equal(HT_OK, ht_file_write_atomic(path, write_hello, "you", err, sizeof err));
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0644);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_atomic_write_replaces_the_file_whole, setup, teardown),
        cmocka_unit_test_setup_teardown(test_a_failed_write_leaves_the_old_file_and_no_temporary, setup, teardown),
        cmocka_unit_test_setup_teardown(test_a_writer_names_its_own_reason_and_files_are_world_readable, setup,
                                        teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

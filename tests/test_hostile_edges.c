/* test_hostile_edges.c — issue 19's edges that need no GL: a memory-bundle
   file with data NULL and size 0 is an empty file (memchr(NULL, 0, 0) was
   undefined behaviour, fatal under the project's UBSan flags), a file name
   with a control character is refused, and every message and log line
   stays one line whatever a name, policy or variable holds. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bundle_source.h"
#include "errfmt.h"
#include "file_open.h"
#include "json_check.h"

static void test_memory_file_with_null_data_and_size_0_reads_as_an_empty_file(void **state) {
    (void)state;
    static const ht_bundle_file files[] = { { "manifest.json", NULL, 0 }, { "full.vert", NULL, 0 } };
    const ht_bundle_memory m = { "mem", files, 2 };
    char err[256] = "";
    assert_int_equal(ht_bundle_memory_check(&m, err, sizeof err), HT_OK);
    ht_bundle_source src = { .label = "mem", .memory = &m };
    char *shader = ht_bundle_read_shader(src, "full.vert", err, sizeof err);
    assert_non_null(shader);
    assert_string_equal(shader, "");
    free(shader);
    char *json = NULL;
    assert_int_equal(ht_bundle_read_json(src, "manifest.json", &json, err, sizeof err), HT_OK);
    assert_string_equal(json, "");
    free(json);
    char *text = ht_text_from_bytes("x", NULL, 0, err, sizeof err);
    assert_non_null(text);
    free(text);
}

static void test_memory_file_name_with_a_control_character_is_refused_in_one_line(void **state) {
    (void)state;
    static const unsigned char byte = '{';
    const char *names[] = { "full\nvert", "a\rb", "tab\there", "del\x7f" };
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        const ht_bundle_file files[] = { { "manifest.json", &byte, 1 }, { names[i], &byte, 1 } };
        const ht_bundle_memory m = { "bundle\nname", files, 2 };
        char err[256] = "";
        assert_int_equal(ht_bundle_memory_check(&m, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        if (!strstr(err, "files[1].name: a control character") || strchr(err, '\n') || strchr(err, '\r'))
            fail_msg("%s", err);
        assert_non_null(strstr(err, "bundle\\nname"));
    }
}

static char logged[2048];
static int log_lines;
static void capture(void *user, const char *line) {
    (void)user;
    snprintf(logged, sizeof logged, "%s", line);
    log_lines++;
}

static void test_every_message_and_log_line_escapes_control_characters(void **state) {
    (void)state;
    log_lines = 0;
    ht_log_linef(capture, NULL, "hairtier: %s", "tier\nfull\r\t\x1b[31m");
    assert_int_equal(log_lines, 1);
    assert_string_equal(logged, "hairtier: tier\\nfull\\r\\t\\x1b[31m");
    char err[64];
    ht_set_error(err, sizeof err, "%s: bad", "a\nb");
    assert_string_equal(err, "a\\nb: bad");
    /* cut to the buffer, never half an escape */
    char small[6];
    ht_set_error(small, sizeof small, "ab\n\n");
    assert_string_equal(small, "ab\\n");
    /* a parser's message about a file named with a newline */
    char *json = NULL;
    assert_int_equal(ht_json_read_file("/nonexistent/a\nb.json", &json, err, sizeof err), HT_ERR_IO);
    assert_null(strchr(err, '\n'));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_memory_file_with_null_data_and_size_0_reads_as_an_empty_file),
        cmocka_unit_test(test_memory_file_name_with_a_control_character_is_refused_in_one_line),
        cmocka_unit_test(test_every_message_and_log_line_escapes_control_characters),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* support_scratch.c — see support_scratch.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cJSON.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "support_scratch.h"

bool ht_test_scratch_create(char *dir, size_t size, const char *name) {
    int n = snprintf(dir, size, "/tmp/hairtier-test-%s-XXXXXX", name);
    return n > 0 && (size_t)n < size && mkdtemp(dir) != NULL;
}

int ht_test_scratch_remove(const char *dir) {
    struct stat st;
    if (lstat(dir, &st) != 0) return -1;
    if (!S_ISDIR(st.st_mode)) return unlink(dir) == 0 ? 0 : -1;
    chmod(dir, 0700); /* a read-only directory can neither be listed nor emptied */
    DIR *d = opendir(dir);
    if (!d) return -1;
    int result = 0;
    struct dirent *e;
    char path[4096];
    while ((e = readdir(d))) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        int n = snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (n < 0 || (size_t)n >= sizeof path || ht_test_scratch_remove(path) != 0) result = -1;
    }
    closedir(d);
    return rmdir(dir) == 0 ? result : -1;
}

void ht_test_write_file(const char *dir, const char *name, const char *text) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

char *ht_test_read_file(const char *dir, const char *name) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char text[1 << 16];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = '\0';
    return text;
}

char *ht_test_read_all(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    assert_non_null(buf);
    size_t got = fread(buf, 1, (size_t)n, f);
    fclose(f);
    buf[got] = '\0';
    if (size) *size = got;
    return buf;
}

void ht_test_copy_dir(const char *from, const char *to) {
    char cmd[8192 + 64];
    snprintf(cmd, sizeof cmd, "rm -rf %s && cp -r %s %s", to, from, to);
    assert_int_equal(system(cmd), 0);
}

bool ht_test_path_exists(const char *path) {
    struct stat st;
    return lstat(path, &st) == 0;
}

const char *ht_test_build_dir(void) {
    const char *b = getenv("HAIRTIER_BUILD");
    return b ? b : "build";
}

int ht_test_run_program(const char *program, const char *args, char *out, size_t size) {
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s/%s' %s 2>&1", ht_test_build_dir(), program, args);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, size - 1, p);
    out[n] = '\0';
    int status = pclose(p);
    assert_true(WIFEXITED(status));
    return WEXITSTATUS(status);
}

struct cJSON *ht_test_read_json(const char *dir, const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    char *text = ht_test_read_all(path, NULL);
    if (!text) fail_msg("%s: cannot be read", path);
    cJSON *root = cJSON_Parse(text);
    free(text);
    if (!root) fail_msg("%s: not JSON", path);
    return root;
}

void ht_test_set_json_number(const char *dir, const char *name, const char *key, double value) {
    cJSON *root = ht_test_read_json(dir, name);
    cJSON_DeleteItemFromObjectCaseSensitive(root, key);
    assert_non_null(cJSON_AddNumberToObject(root, key, value));
    char *text = cJSON_Print(root);
    assert_non_null(text);
    ht_test_write_file(dir, name, text);
    free(text);
    cJSON_Delete(root);
}

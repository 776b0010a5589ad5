/* support_scene.c — see support_scene.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cJSON.h>
#include <cmocka.h>

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "support_scene.h"
#include "support_scratch.h"

void ht_test_run_command(const char *cmd) {
    int status = system(cmd);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail_msg("command failed: %s", cmd);
}

void ht_test_keep_strand_file(cJSON *root, const char *shipped_scene) {
    cJSON *file = cJSON_GetObjectItem(cJSON_GetObjectItem(root, "geometry"), "file");
    if (!cJSON_IsString(file) || file->valuestring[0] == '/') return;
    char joined[1024], resolved[PATH_MAX];
    const char *slash = strrchr(shipped_scene, '/');
    snprintf(joined, sizeof joined, "%.*s%s", slash ? (int)(slash - shipped_scene) + 1 : 0, shipped_scene,
             file->valuestring);
    assert_non_null(realpath(joined, resolved));
    cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetObjectItem(root, "geometry"), "file",
                                           cJSON_CreateString(resolved));
}

const char *ht_test_scene_copy(const char *shipped_scene, const char *dir, const char *name, int side, int hairs,
                               bool no_head, char *out, size_t out_size) {
    cJSON *root = cJSON_Parse(ht_test_read_file(".", shipped_scene));
    assert_non_null(root);
    if (side > 0)
        cJSON_ReplaceItemInObjectCaseSensitive(root, "resolution", cJSON_CreateIntArray((const int[]){ side, side }, 2));
    ht_test_keep_strand_file(root, shipped_scene);
    cJSON *geometry = cJSON_GetObjectItem(root, "geometry");
    if (hairs > 0 && cJSON_GetObjectItem(geometry, "hairs"))
        cJSON_ReplaceItemInObjectCaseSensitive(geometry, "hairs", cJSON_CreateNumber(hairs));
    if (no_head) cJSON_DeleteItemFromObjectCaseSensitive(geometry, "head");
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    ht_test_write_file(dir, name, text);
    cJSON_free(text);
    snprintf(out, out_size, "%s/%s", dir, name);
    return out;
}

int ht_test_bundle_tiers(const char *bundle, char names[HT_TIER_COUNT][16], const char *first) {
    cJSON *root = cJSON_Parse(ht_test_read_file(bundle, "manifest.json"));
    assert_non_null(root);
    int n = 0;
    const cJSON *t;
    cJSON_ArrayForEach(t, cJSON_GetObjectItem(root, "tiers")) {
        if (n == HT_TIER_COUNT) break;
        snprintf(names[n++], 16, "%s", cJSON_GetObjectItem(t, "name")->valuestring);
    }
    cJSON_Delete(root);
    assert_true(n >= 2);
    assert_string_equal(names[0], first);
    return n;
}

/* fuzz_scene.c — ht_scene_parse (and its memory budget) on arbitrary text. */
#include "fuzz_common.h"
#include <hairtier/scene.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    ht_scene s;
    char err[512];
    ht_scene_parse(text, "fuzz.json", &s, err, sizeof err);
    free(text);
    return 0;
}

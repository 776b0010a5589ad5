/* fuzz_material.c — ht_material_parse on arbitrary text. */
#include "fuzz_common.h"
#include <hairtier/hairgen.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    ht_material m;
    char err[512];
    ht_material_parse(text, "fuzz.json", &m, err, sizeof err);
    free(text);
    return 0;
}

/* fuzz_strands_hair.c — ht_strands_parse_hair (Cem Yuksel's .hair strand
   files) on arbitrary bytes; what it accepts is also built into ribbons. */
#include "fuzz_common.h"
#include <hairtier/strands.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    ht_strands s;
    char err[512];
    if (ht_strands_parse_hair(data, size, "fuzz.hair", &s, err, sizeof err) != HT_OK) return 0;
    ht_mesh m;
    const ht_strands_ribbon_desc d = { .scale = 1, .width = 0.01f, .tip_width = 0.25f, .ao = 0.3f };
    if (ht_mesh_build_strands(&s, &d, &m, err, sizeof err) == HT_OK) ht_mesh_free(&m);
    ht_strands_free(&s);
    return 0;
}

/* fuzz_lod_file.c — ht_lod_file_parse (the stored ladder, lods.bin) on
   arbitrary bytes; what it accepts is split into its levels and written
   back, which must give the same bytes. */
#include "fuzz_common.h"
#include <hairtier/lod.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    ht_lod_file f;
    char err[512];
    if (ht_lod_file_parse(data, size, "fuzz.bin", &f, err, sizeof err) != HT_OK) return 0;
    for (int l = 0; l < f.level_count; l++) {
        ht_mesh m;
        if (ht_lod_file_level_mesh(&f, l, &m) == HT_OK) ht_mesh_free(&m);
    }
    unsigned char *out;
    size_t out_size;
    if (ht_lod_file_encode(&f, &out, &out_size) != HT_OK || out_size != size || memcmp(out, data, size) != 0) abort();
    free(out);
    ht_lod_file_free(&f);
    return 0;
}

/* fuzz_manifest.c — ht_manifest_parse on arbitrary text, then the lookups
   the renderer makes on what it accepted. */
#include "fuzz_common.h"
#include "manifest.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    static ht_manifest m;
    char err[512];
    if (ht_manifest_parse(text, "bundle", "manifest.json", &m, err, sizeof err) == HT_OK) {
        for (int t = 0; t < HT_TIER_COUNT; t++) {
            const ht_manifest_tier *tier = ht_manifest_find_tier(&m, (ht_tier)t);
            const char *file = ht_manifest_tier_file(tier, "fragment");
            char path[HT_LIMIT_BUNDLE_FILE_PATH];
            if (file) ht_manifest_path(&m, file, path, sizeof path);
            ht_manifest_find_texture(&m, tier, "albedo");
        }
    }
    free(text);
    return 0;
}

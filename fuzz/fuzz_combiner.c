/* fuzz_combiner.c — ht_combiner_parse (the fixed tier's fixed.json) on
   arbitrary text. */
#include "combiner.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    ht_combiner_program p;
    char err[512];
    ht_combiner_parse(text, "fixed.json", &p, err, sizeof err);
    free(text);
    return 0;
}

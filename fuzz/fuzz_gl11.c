/* fuzz_gl11.c — ht_gl11_parse (the gl11 tier's gl11.json) on arbitrary
   text; what parses is written back. */
#include "fuzz_common.h"
#include "gl11_program.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    ht_gl11_program p;
    char err[512];
    if (ht_gl11_parse(text, "gl11.json", &p, err, sizeof err) == HT_OK) {
        char *again = NULL;
        if (ht_gl11_write(&p, &again, err, sizeof err) == HT_OK) free(again);
    }
    free(text);
    return 0;
}

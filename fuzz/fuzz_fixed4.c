/* fuzz_fixed4.c — ht_fixed4_parse (the fixed4 tier's fixed4.json) on
   arbitrary text; what parses is written back and baked, as the runtime
   would (one LUT per accepted program, white lights). */
#include "fixed4_program.h"
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    ht_fixed4_program p;
    char err[512];
    if (ht_fixed4_parse(text, "fixed4.json", &p, err, sizeof err) == HT_OK) {
        char *again = NULL;
        if (ht_fixed4_write(&p, &again, err, sizeof err) == HT_OK) free(again);
        const float white[2][3] = { { 1, 1, 1 }, { 1, 1, 1 } };
        ht_image img;
        if (ht_fixed4_bake_lut(&p, 0, white, ht_fixed4_scale(&p, white), &img) == HT_OK) ht_image_free(&img);
    }
    free(text);
    return 0;
}

/* fuzz_json.c — json_check's strict parser (the one every JSON reader
   goes through: line and column errors, nesting, numbers at the end). */
#include "fuzz_common.h"
#include "json_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *text = ht_fuzz_text(data, size);
    if (!text) return 0;
    ht_jctx c = { .file = "fuzz.json", .err = (char[512]){ 0 }, .err_size = 512 };
    cJSON *root = NULL;
    ht_json_parse_root(&c, text, &root);
    cJSON_Delete(root);
    free(text);
    return 0;
}

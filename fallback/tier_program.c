/* tier_program.c — see tier_program.h. */
#include "tier_program.h"

#include <stdio.h>

#include "manifest.h"

char *ht_tier_program_read(const ht_tier_context *ctx, char *path, size_t path_size, ht_result *result, char *err,
                           size_t err_size) {
    const ht_manifest *b = ctx->bundle;
    const char *file = ht_manifest_tier_file(ctx->tier, "program");
    if (!file) {
        snprintf(err, err_size, "%s/manifest.json: tiers.%s.files: needs \"program\"", b->dir, ctx->tier->name);
        *result = HT_ERR_PARSE;
        return NULL;
    }
    if (!ht_manifest_path(b, file, path, path_size)) {
        snprintf(err, err_size, "%s: path too long", file);
        *result = HT_ERR_IO;
        return NULL;
    }
    char *text = ht_manifest_read_text(b, file, err, err_size);
    *result = text ? HT_OK : HT_ERR_IO;
    return text;
}

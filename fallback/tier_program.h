/* tier_program.h — the one reader of a fixed-function tier's program file
   (the manifest entry's files.program: fixed.json, fixed4.json, gl11.json):
   where it is, its text, the same messages for every tier. Internal.

   Usage:
       char path[HT_LIMIT_BUNDLE_FILE_PATH];
       ht_result r;
       char *text = ht_tier_program_read(ctx, path, sizeof path, &r, err, sizeof err);
       if (!text) return r;
       r = ht_gl11_parse(text, path, &program, err, sizeof err);
       free(text); */
#ifndef HT_TIER_PROGRAM_H
#define HT_TIER_PROGRAM_H

#include <stddef.h>

#include "tier.h"

/* The program's text (malloc'd) and its path (for the parser's messages);
   NULL with *result set and one line in err when the entry names no
   program or the file cannot be read. */
char *ht_tier_program_read(const ht_tier_context *ctx, char *path, size_t path_size, ht_result *result, char *err,
                           size_t err_size);

#endif

/* bundle_sums.h — each bundle file's size and CRC-32, written into the
   manifest ("file_sums", docs/bundle.md), and the check a no-change re-run
   makes with them: a bundle is kept only when every file the manifest
   lists is there, a regular file, with its size and checksum (a deleted
   full.frag or a cut albedo.png is regenerated, not "up to date").
   Internal to libhairgen (generate.c).

   Usage:
       cJSON *sums = ht_bundle_sums_json(&generated);          // into the manifest
       if (ht_bundle_sums_match("out/bundle", manifest_text, len)) ... // keep it */
#ifndef HT_BUNDLE_SUMS_H
#define HT_BUNDLE_SUMS_H

#include <cJSON.h>
#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairgen.h>

#define HT_MANIFEST_KEY_FILE_SUMS "file_sums"

/* {"NAME": {"size": N, "crc32": "8 hex digits"}, ...} for every file of g
   but the manifest, or NULL (out of memory, an image no PNG can hold). */
cJSON *ht_bundle_sums_json(const ht_generated *g);

/* sums[name] = {"size", "crc32"} of data (replacing an entry of that
   name); false when out of memory. hairgen --cards's files use it too. */
bool ht_bundle_sums_set(cJSON *sums, const char *name, const void *data, size_t size);

/* Whether every file listed in the manifest text's file_sums (a non-empty
   object of plain file names) is in dir with that size and CRC-32. */
bool ht_bundle_sums_match(const char *dir, const char *manifest, size_t manifest_size);

#endif

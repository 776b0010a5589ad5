/* bundle_source.h — where a bundle's files come from: a directory written
   by hairgen, or an ht_bundle_memory (hairgen --emit-header). Every reader
   of a bundle file (the manifest, the tiers' programs, shaders and
   textures) goes through here, and each kind of file is checked by one
   validator whatever the source: the size cap of its kind, no NUL byte in
   a text, the PNG decoder with its limits, the manifest's texture sizes.
   So a memory bundle with a missing file, truncated or oversized bytes gets
   the directory's one-line message word for word, its name standing where
   the directory path would. Internal to libhairtier.

   Usage:
       ht_bundle_source src = { .label = "out/bundle" };        // or .memory = &m
       char *json;
       if (ht_bundle_read_json(src, "fixed.json", &json, err, sizeof err) != HT_OK) ...
       // err: "out/bundle/fixed.json: cannot read: No such file or directory" */
#ifndef HT_BUNDLE_SOURCE_H
#define HT_BUNDLE_SOURCE_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>

typedef struct ht_bundle_source {
    const char *label;               /* the directory, or the memory bundle's name */
    const ht_bundle_memory *memory;  /* NULL: the files are read from the directory `label` */
} ht_bundle_source;

/* The name a memory bundle's messages use: its name, or "memory". */
const char *ht_bundle_memory_label(const ht_bundle_memory *m);

/* Checks a memory bundle's table before any file is read: 1 to
   HT_BUNDLE_MEMORY_MAX_FILES files, each with a plain, unique file name of
   at most HT_LIMIT_BUNDLE_NAME bytes and data unless its size is 0.
   HT_ERR_INVALID_ARGUMENT with "NAME: files[3].name: ..." otherwise. */
ht_result ht_bundle_memory_check(const ht_bundle_memory *m, char *err, size_t err_size);

/* LABEL/FILE into path, what every message names; false when it does not fit. */
bool ht_bundle_path(ht_bundle_source s, const char *file, char *path, size_t path_size);

/* A JSON file of the bundle (manifest, tier programs), NUL-terminated in
   *text (free()); json_check.h's reader's cap and messages. */
ht_result ht_bundle_read_json(ht_bundle_source s, const char *file, char **text, char *err, size_t err_size);
/* A GLSL source (free()), or NULL with one line in err: at most
   HT_FILE_MAX_SHADER bytes, no NUL byte. */
char *ht_bundle_read_shader(ht_bundle_source s, const char *file, char *err, size_t err_size);
/* A PNG of the bundle held to width x height: the size its header declares
   is checked before decoding (a hostile header must not make us allocate
   what it claims), then the decoded size: "LABEL/FILE: 8x8, manifest says
   256x256". path receives LABEL/FILE for the caller's own messages. */
ht_result ht_bundle_read_png(ht_bundle_source s, const char *file, int width, int height, ht_image *img,
                             char *path, size_t path_size, char *err, size_t err_size);

#endif

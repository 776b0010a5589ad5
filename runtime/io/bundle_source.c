/* bundle_source.c — see bundle_source.h. Each reader finds the bytes (a
   regular file through file_open.h, or a memory bundle's entry) and hands
   them to the one validator of their kind; nothing is checked twice or in
   two ways. */
#include "bundle_source.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "file_open.h"
#include <hairtier/ht_limits.h>
#include "json_check.h"

const char *ht_bundle_memory_label(const ht_bundle_memory *m) {
    return m && m->name && m->name[0] ? m->name : "memory";
}

/* Plain file names only, as the manifest's own "file" fields: a memory
   bundle holds what a directory would. */
static const char *bad_name(const char *name) {
    if (!name) return "missing (NULL)";
    if (!name[0]) return "empty file name";
    if (strlen(name) > HT_LIMIT_BUNDLE_NAME) return "longer than a bundle file name may be";
    if (strchr(name, '/') || strchr(name, '\\') || strcmp(name, ".") == 0 || strcmp(name, "..") == 0)
        return "not a plain file name inside the bundle";
    return NULL;
}

ht_result ht_bundle_memory_check(const ht_bundle_memory *m, char *err, size_t err_size) {
    const char *label = ht_bundle_memory_label(m);
    if (!m) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "bundle: bundle_memory: NULL");
    if (strlen(label) > HT_LIMIT_DIR_PATH)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%.200s...: memory bundle name is %zu bytes, more "
                       "than %d", label, strlen(label), HT_LIMIT_DIR_PATH);
    if (m->file_count < 1 || m->file_count > HT_BUNDLE_MEMORY_MAX_FILES || !m->files)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: file_count: %d%s, expected 1..%d files", label,
                       m->file_count, m->files ? "" : " with files NULL", HT_BUNDLE_MEMORY_MAX_FILES);
    for (int i = 0; i < m->file_count; i++) {
        const ht_bundle_file *f = &m->files[i];
        const char *why = bad_name(f->name);
        if (why) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: files[%d].name: %s", label, i, why);
        if (!f->data && f->size)
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: files[%d].data: NULL with size %zu (%s)",
                           label, i, f->size, f->name);
        for (int k = 0; k < i; k++)
            if (strcmp(m->files[k].name, f->name) == 0)
                return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: files[%d].name: \"%s\" already "
                               "listed as files[%d]", label, i, f->name, k);
    }
    return HT_OK;
}

bool ht_bundle_path(ht_bundle_source s, const char *file, char *path, size_t path_size) {
    int n = snprintf(path, path_size, "%s/%s", s.label, file);
    return n >= 0 && (size_t)n < path_size;
}

/* The entry named `file`, or NULL with the directory's message for a
   missing file. */
static const ht_bundle_file *find(ht_bundle_source s, const char *file, const char *path, char *err,
                                  size_t err_size) {
    for (int i = 0; i < s.memory->file_count; i++)
        if (strcmp(s.memory->files[i].name, file) == 0) return &s.memory->files[i];
    ht_set_error(err, err_size, "%s: cannot read: %s", path, strerror(ENOENT));
    return NULL;
}

ht_result ht_bundle_read_json(ht_bundle_source s, const char *file, char **text, char *err, size_t err_size) {
    *text = NULL;
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    if (!ht_bundle_path(s, file, path, sizeof path))
        return ht_fail(err, err_size, HT_ERR_IO, "%s: path too long", file);
    if (!s.memory) return ht_json_read_file(path, text, err, err_size);
    const ht_bundle_file *f = find(s, file, path, err, err_size);
    if (!f) return HT_ERR_IO;
    return ht_json_text_from_bytes(path, f->data, f->size, text, err, err_size);
}

char *ht_bundle_read_shader(ht_bundle_source s, const char *file, char *err, size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    if (!ht_bundle_path(s, file, path, sizeof path)) {
        ht_set_error(err, err_size, "%s: path too long", file);
        return NULL;
    }
    if (!s.memory) return ht_file_read_text(path, HT_FILE_MAX_SHADER, err, err_size);
    const ht_bundle_file *f = find(s, file, path, err, err_size);
    if (!f || ht_file_check_size(path, f->size, HT_FILE_MAX_SHADER, err, err_size) != HT_OK) return NULL;
    return ht_text_from_bytes(path, f->data, f->size, err, err_size);
}

ht_result ht_bundle_read_png(ht_bundle_source s, const char *file, int width, int height, ht_image *img,
                             char *path, size_t path_size, char *err, size_t err_size) {
    *img = (ht_image){ 0 };
    if (!ht_bundle_path(s, file, path, path_size))
        return ht_fail(err, err_size, HT_ERR_IO, "%s: path too long", file);
    const ht_bundle_file *f = NULL;
    if (s.memory && !(f = find(s, file, path, err, err_size))) return HT_ERR_IO;
    uint32_t hw, hh;
    bool header = f ? ht_image_png_header_size_bytes(f->data, f->size, &hw, &hh)
                    : ht_image_png_header_size(path, &hw, &hh);
    if (header && (hw != (uint32_t)width || hh != (uint32_t)height))
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s: %ux%u, manifest says %dx%d", path, hw, hh, width, height);
    ht_result r = f ? ht_image_decode_png(path, f->data, f->size, img, err, err_size)
                    : ht_image_read_png(path, img, err, err_size);
    if (r != HT_OK) return r;
    if (img->width != width || img->height != height) {
        ht_set_error(err, err_size, "%s: %dx%d, manifest says %dx%d", path, img->width, img->height, width, height);
        ht_image_free(img);
        return HT_ERR_PARSE;
    }
    return HT_OK;
}

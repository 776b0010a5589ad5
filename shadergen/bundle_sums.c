#define _GNU_SOURCE /* memmem */
/* bundle_sums.c — see bundle_sums.h. CRC-32 (libdeflate's, which the PNG
   writer links already): it catches any cut or changed file, and at
   gigabytes a second it keeps a no-change re-run's check cheap. */
#include "bundle_sums.h"

#include <fcntl.h>
#include <libdeflate.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hairgen_internal.h"
#include "manifest.h"

static void crc_text(const void *data, size_t size, char out[9]) {
    snprintf(out, 9, "%08x", (unsigned)libdeflate_crc32(0, data, size));
}

bool ht_bundle_sums_set(cJSON *sums, const char *name, const void *data, size_t size) {
    char crc[9];
    crc_text(data, size, crc);
    cJSON_DeleteItemFromObjectCaseSensitive(sums, name);
    cJSON *entry = cJSON_AddObjectToObject(sums, name);
    return entry && cJSON_AddNumberToObject(entry, "size", (double)size) && cJSON_AddStringToObject(entry, "crc32", crc);
}

cJSON *ht_bundle_sums_json(const ht_generated *g) {
    cJSON *sums = cJSON_CreateObject();
    for (int i = 0; sums && i < g->file_count; i++) {
        const ht_generated_file *f = &g->files[i];
        if (strcmp(f->name, HT_MANIFEST_FILE) == 0) continue;
        unsigned char *bytes = f->text ? (unsigned char *)f->text : f->png;
        size_t size = f->text ? strlen(f->text) : f->png_size;
        char why[256];
        if (!bytes && ht_generated_file_bytes(f, &bytes, &size, why, sizeof why) != HT_OK) {
            cJSON_Delete(sums);
            return NULL;
        }
        const bool ok = ht_bundle_sums_set(sums, f->name, bytes, size);
        if (!f->text && bytes != f->png) free(bytes);
        if (!ok) {
            cJSON_Delete(sums);
            return NULL;
        }
    }
    return sums;
}

/* A name the check may open: a plain file of the bundle, never a path. */
static bool plain_name(const char *name) {
    return name[0] && !strchr(name, '/') && strcmp(name, ".") != 0 && strcmp(name, "..") != 0;
}

/* A growing buffer the files of one check are read into, one after another. */
typedef struct read_buf {
    unsigned char *data;
    size_t size;
} read_buf;

/* Whether dirfd's entry is a regular file of that size and CRC-32: three
   system calls a file (openat, read, close), one buffer for all. */
static bool file_matches(int dirfd, const cJSON *entry, read_buf *buf) {
    const cJSON *size = cJSON_GetObjectItemCaseSensitive(entry, "size");
    const cJSON *crc = cJSON_GetObjectItemCaseSensitive(entry, "crc32");
    if (!entry->string || !plain_name(entry->string) || !cJSON_IsNumber(size) || !cJSON_IsString(crc) ||
        size->valuedouble < 0 || size->valuedouble > HT_LIMIT_FILE_PNG)
        return false;
    size_t want = (size_t)size->valuedouble;
    /* O_NONBLOCK: a FIFO there is seen by fstat, not waited on (file_open.c). */
    int fd = openat(dirfd, entry->string, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return false;
    /* No fstat: a read of one byte more than the manifest says tells a
       file of another size, a FIFO (EAGAIN), a directory (EISDIR) or a
       device (its length is not the file's) from the file; only a file
       said to be empty is stat'ed, as /dev/null would read as one. */
    struct stat st;
    bool ok = want > 0 || (fstat(fd, &st) == 0 && S_ISREG(st.st_mode));
    if (ok && buf->size < want + 1) {
        unsigned char *grown = realloc(buf->data, want + 1);
        ok = grown != NULL;
        if (grown) *buf = (read_buf){ grown, want + 1 };
    }
    /* One byte more than the manifest says: a file that grew is not it. */
    ssize_t got = ok ? read(fd, buf->data, want + 1) : -1;
    close(fd);
    if (!ok || got != (ssize_t)want) return false;
    char have[9];
    crc_text(buf->data, want, have);
    return strcmp(have, crc->valuestring) == 0;
}

bool ht_bundle_sums_match(const char *dir, const char *manifest, size_t manifest_size) {
    /* Only the file_sums object is parsed: parsing whole manifests was half
       of a no-change batch's time (generate.c's bundle_has_hash). */
    static const char key[] = "\"" HT_MANIFEST_KEY_FILE_SUMS "\"";
    const char *p = memmem(manifest, manifest_size, key, sizeof key - 1);
    if (!p) return false;
    p += sizeof key - 1;
    p += strspn(p, " \t\r\n");
    if (*p++ != ':') return false;
    cJSON *sums = cJSON_ParseWithLengthOpts(p, manifest_size - (size_t)(p - manifest), NULL, false);
    int dirfd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    bool ok = cJSON_IsObject(sums) && sums->child && dirfd >= 0;
    read_buf buf = { NULL, 0 };
    for (const cJSON *e = sums ? sums->child : NULL; ok && e; e = e->next) ok = file_matches(dirfd, e, &buf);
    free(buf.data);
    if (dirfd >= 0) close(dirfd);
    cJSON_Delete(sums);
    return ok;
}

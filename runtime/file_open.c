/* file_open.c — see file_open.h. */
#include "file_open.h"

#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "errfmt.h"

static const char *kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

ht_result ht_file_check_size(const char *path, uint64_t size, uint64_t max_bytes, char *err, size_t err_size) {
    if (size <= max_bytes) return HT_OK;
    ht_set_error(err, err_size, "%s: file is %llu bytes, more than the %llu this kind of file may have", path,
                 (unsigned long long)size, (unsigned long long)max_bytes);
    return HT_ERR_IO;
}

char *ht_text_from_bytes(const char *path, const void *data, size_t size, char *err, size_t err_size) {
    if (memchr(data, '\0', size)) {
        ht_set_error(err, err_size, "%s: NUL byte in a text file", path);
        return NULL;
    }
    char *text = malloc(size + 1);
    if (!text) {
        ht_set_error(err, err_size, "%s: out of memory (%llu bytes)", path, (unsigned long long)size);
        return NULL;
    }
    if (size) memcpy(text, data, size);
    text[size] = '\0';
    return text;
}

ht_result ht_file_open_regular(const char *path, uint64_t max_bytes, FILE **out, uint64_t *size,
                               char *err, size_t err_size) {
    *out = NULL;
    if (size) *size = 0;
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a
       writer before fstat could tell what it is. Only a regular file is
       kept, where the flag has no effect (open(2)), so it is not cleared:
       two system calls less per file, a fifth of a no-change batch's. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        ht_set_error(err, err_size, "%s: cannot read: %s", path, strerror(errno));
        return HT_ERR_IO;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) {
        ht_set_error(err, err_size, "%s: cannot stat: %s", path, strerror(errno));
        close(fd);
        return HT_ERR_IO;
    }
    if (!S_ISREG(st.st_mode)) {
        ht_set_error(err, err_size, "%s: not a regular file (%s)", path, kind_of(st.st_mode));
        close(fd);
        return HT_ERR_IO;
    }
    if (ht_file_check_size(path, (uint64_t)st.st_size, max_bytes, err, err_size) != HT_OK) {
        close(fd);
        return HT_ERR_IO;
    }
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        ht_set_error(err, err_size, "%s: cannot read: %s", path, strerror(errno));
        close(fd);
        return HT_ERR_IO;
    }
    *out = f;
    if (size) *size = (uint64_t)st.st_size;
    return HT_OK;
}

void *ht_file_read_bytes(const char *path, uint64_t max_bytes, size_t *size, char *err, size_t err_size) {
    FILE *f;
    uint64_t file_size;
    if (ht_file_open_regular(path, max_bytes, &f, &file_size, err, err_size) != HT_OK) return NULL;
    /* One byte more than fstat saw, to notice a file that grew. */
    unsigned char *data = malloc((size_t)file_size + 1);
    if (!data) {
        fclose(f);
        ht_set_error(err, err_size, "%s: out of memory (%llu bytes)", path, (unsigned long long)file_size);
        return NULL;
    }
    size_t got = fread(data, 1, (size_t)file_size + 1, f);
    bool bad = ferror(f) != 0;
    int e = errno;
    fclose(f);
    if (bad || got != file_size) {
        free(data);
        if (bad) ht_set_error(err, err_size, "%s: cannot read: %s", path, strerror(e));
        else ht_set_error(err, err_size, "%s: changed size while being read", path);
        return NULL;
    }
    *size = got;
    return data;
}

char *ht_file_read_text(const char *path, uint64_t max_bytes, char *err, size_t err_size) {
    size_t size = 0;
    void *bytes = ht_file_read_bytes(path, max_bytes, &size, err, err_size);
    if (!bytes) return NULL;
    /* One check for files and memory bundles (bundle_source.c). */
    char *checked = ht_text_from_bytes(path, bytes, size, err, err_size);
    free(bytes);
    return checked;
}

/* file_open.c — see file_open.h. */
#include "file_open.h"

#include <errno.h>
#include <fcntl.h>
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

ht_result ht_file_open_regular(const char *path, uint64_t max_bytes, FILE **out, uint64_t *size,
                               char *err, size_t err_size) {
    *out = NULL;
    if (size) *size = 0;
    /* O_NONBLOCK: opening a FIFO for reading would otherwise wait for a
       writer before fstat could tell what it is. Cleared again below. */
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
    if ((uint64_t)st.st_size > max_bytes) {
        ht_set_error(err, err_size, "%s: file is %llu bytes, more than the %llu this kind of file may have",
                     path, (unsigned long long)st.st_size, (unsigned long long)max_bytes);
        close(fd);
        return HT_ERR_IO;
    }
    int flags = fcntl(fd, F_GETFL);
    if (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0) {
        ht_set_error(err, err_size, "%s: cannot read: %s", path, strerror(errno));
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

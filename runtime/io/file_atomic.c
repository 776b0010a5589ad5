/* file_atomic.c — see file_atomic.h. */
#include "file_atomic.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "errfmt.h"

ht_result ht_file_write_atomic(const char *path, ht_file_writer_fn fn, void *ctx, char *err, size_t err_size) {
    static const char suffix[] = ".tmp-XXXXXX";
    size_t len = strlen(path);
    char *temp = malloc(len + sizeof suffix);
    if (!temp) {
        ht_set_error(err, err_size, "%s: out of memory", path);
        return HT_ERR_OUT_OF_MEMORY;
    }
    memcpy(temp, path, len);
    memcpy(temp + len, suffix, sizeof suffix);

    char why[200] = "";
    FILE *f = NULL;
    int fd = mkstemp(temp);
    if (fd < 0) {
        snprintf(why, sizeof why, "cannot create a temporary file beside it: %s", strerror(errno));
        goto done;
    }
    /* mkstemp creates 0600; a file we write is as readable as any other. */
    if (fchmod(fd, 0644) != 0 || !(f = fdopen(fd, "wb"))) {
        snprintf(why, sizeof why, "cannot write: %s", strerror(errno));
        close(fd);
        goto done;
    }
    errno = 0; /* a writer that fails without a system error leaves 0: no reason invented */
    if (!fn(f, ctx, why, sizeof why) || ferror(f)) {
        if (!why[0]) snprintf(why, sizeof why, "write failed%s%s", errno ? ": " : "", errno ? strerror(errno) : "");
        goto done;
    }
    /* Durable before it becomes visible. */
    if (fflush(f) != 0 || fsync(fileno(f)) != 0) {
        snprintf(why, sizeof why, "write failed: %s", strerror(errno));
        goto done;
    }
    FILE *closing = f;
    f = NULL;
    if (fclose(closing) != 0) {
        snprintf(why, sizeof why, "write failed: %s", strerror(errno));
        goto done;
    }
    if (rename(temp, path) != 0) snprintf(why, sizeof why, "cannot rename the temporary file into place: %s",
                                          strerror(errno));
done:
    if (f) fclose(f);
    if (why[0] && fd >= 0) remove(temp);
    free(temp);
    if (!why[0]) return HT_OK;
    ht_set_error(err, err_size, "%s: %s", path, why);
    return HT_ERR_IO;
}

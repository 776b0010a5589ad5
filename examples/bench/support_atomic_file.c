/* support_atomic_file.c — temporary sibling, fsync, rename (see the header). */
#include "support_atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

bool bench_write_atomic(const char *path, bench_writer_fn fn, void *ctx, char *err, size_t err_size) {
    static const char suffix[] = ".tmp-XXXXXX";
    size_t len = strlen(path);
    char *temp = malloc(len + sizeof suffix);
    if (!temp) {
        snprintf(err, err_size, "%s: out of memory", path);
        return false;
    }
    memcpy(temp, path, len);
    memcpy(temp + len, suffix, sizeof suffix);

    const char *why = NULL;
    int saved = 0;
    FILE *f = NULL;
    int fd = mkstemp(temp);
    if (fd < 0) {
        saved = errno;
        why = "cannot create a temporary file beside it";
        goto done;
    }
    /* mkstemp creates 0600; a result file is as readable as any we write. */
    if (fchmod(fd, 0644) != 0 || !(f = fdopen(fd, "w"))) {
        saved = errno;
        why = "cannot write";
        close(fd);
        goto done;
    }
    errno = 0; /* a writer that fails without a system error leaves 0: no reason invented */
    if (!fn(f, ctx) || ferror(f)) {
        saved = errno;
        why = "write failed";
        goto done;
    }
    if (fflush(f) != 0 || fsync(fileno(f)) != 0) {
        saved = errno;
        why = "write failed";
        goto done;
    }
    FILE *closing = f;
    f = NULL;
    if (fclose(closing) != 0) {
        saved = errno;
        why = "write failed";
        goto done;
    }
    if (rename(temp, path) != 0) {
        saved = errno;
        why = "cannot rename the temporary file into place";
    }
done:
    if (f) fclose(f);
    if (why) {
        if (fd >= 0) remove(temp);
        if (saved) snprintf(err, err_size, "%s: %s: %s", path, why, strerror(saved));
        else snprintf(err, err_size, "%s: %s", path, why);
    }
    free(temp);
    return why == NULL;
}

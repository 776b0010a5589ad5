/* report_dir.c — a report directory written whole or not at all (report_dir.h). */
#define _GNU_SOURCE /* renameat2 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "file_open.h"
#include "report_dir.h"

static bool is_empty_dir(const char *dir, bool *empty) {
    DIR *d = opendir(dir);
    if (!d) return false;
    struct dirent *e;
    *empty = true;
    while (*empty && (e = readdir(d)) != NULL) *empty = strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0;
    closedir(d);
    return true;
}

static bool is_report(const char *dir) {
    char path[4200], head[2048];
    snprintf(path, sizeof path, "%s/index.html", dir);
    /* The regular-file opener: a FIFO there must not hang haircompare. */
    FILE *f;
    char why[256];
    if (ht_file_open_regular(path, HT_FILE_MAX_JSON, &f, NULL, why, sizeof why) != HT_OK) return false;
    size_t n = fread(head, 1, sizeof head - 1, f);
    fclose(f);
    head[n] = '\0';
    return strstr(head, REPORT_DIR_GENERATOR_MARK) != NULL;
}

ht_result report_dir_begin(const char *dir, char *tmp, size_t tmp_size, char *err, size_t err_size) {
    struct stat st;
    if (stat(dir, &st) == 0) {
        bool empty;
        if (!S_ISDIR(st.st_mode)) {
            snprintf(err, err_size, "%s: exists and is not a directory", dir);
            return HT_ERR_IO;
        }
        if (!is_empty_dir(dir, &empty)) {
            snprintf(err, err_size, "%s: cannot read: %s", dir, strerror(errno));
            return HT_ERR_IO;
        }
        if (!empty && !is_report(dir)) {
            snprintf(err, err_size, "%s: exists and is not a haircompare report (no index.html it wrote); "
                     "refusing to replace it", dir);
            return HT_ERR_IO;
        }
    }
    int n = snprintf(tmp, tmp_size, "%s.tmp-XXXXXX", dir);
    if (n < 0 || (size_t)n >= tmp_size) {
        snprintf(err, err_size, "%.200s...: path too long", dir);
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (!mkdtemp(tmp)) {
        snprintf(err, err_size, "%s: cannot create a temporary directory beside it: %s", dir, strerror(errno));
        return HT_ERR_IO;
    }
    /* mkdtemp makes it owner-only; a report is as readable as any file. */
    mode_t mask = umask(0);
    umask(mask);
    chmod(tmp, 0777 & ~mask);
    return HT_OK;
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw) {
    (void)st, (void)flag, (void)ftw;
    return remove(path) == 0 ? 0 : -1;
}

void report_dir_remove(const char *tmp) { nftw(tmp, remove_entry, 16, FTW_DEPTH | FTW_PHYS); }

ht_result report_dir_publish(const char *tmp, const char *dir, char *err, size_t err_size) {
    if (rename(tmp, dir) == 0) return HT_OK;
    if (errno != EEXIST && errno != ENOTEMPTY) {
        snprintf(err, err_size, "%s: cannot create: %s", dir, strerror(errno));
        return HT_ERR_IO;
    }
    /* An earlier report: swap the two in one step, then drop the old one. */
    if (renameat2(AT_FDCWD, tmp, AT_FDCWD, dir, RENAME_EXCHANGE) != 0) {
        snprintf(err, err_size, "%s: cannot replace: %s", dir, strerror(errno));
        return HT_ERR_IO;
    }
    report_dir_remove(tmp);
    return HT_OK;
}

/* report_dir.h — writing a report directory whole or not at all: files go
   into a temporary sibling (DIR.tmp-XXXXXX) that is renamed into place at
   the end, so a failure leaves DIR as it was and no half-written report.
   An existing DIR is replaced only when it is empty or an earlier report
   (its index.html names haircompare as generator); anything else is
   refused before any work, so a mistyped -o deletes nothing.

   Usage:
       char tmp[4096];
       if (report_dir_begin(dir, tmp, sizeof tmp, err, sizeof err) != HT_OK) fail;
       ... write files into tmp ...
       if (ok) r = report_dir_publish(tmp, dir, err, sizeof err);
       else report_dir_remove(tmp); */
#ifndef HT_EXAMPLES_REPORT_DIR_H
#define HT_EXAMPLES_REPORT_DIR_H

#include <stddef.h>

#include <hairtier/hairtier.h>

/* What index.html carries to say a directory is a report. */
#define REPORT_DIR_GENERATOR_MARK "<meta name=\"generator\" content=\"haircompare\">"

/* Checks dir may be written and makes the temporary sibling (given the
   modes the umask allows). One line naming dir in err on failure. */
ht_result report_dir_begin(const char *dir, char *tmp, size_t tmp_size, char *err, size_t err_size);
/* Renames tmp to dir, replacing an earlier report; tmp is gone either way
   on success, and left for report_dir_remove on failure. */
ht_result report_dir_publish(const char *tmp, const char *dir, char *err, size_t err_size);
/* Removes tmp and everything in it (nothing followed through links). */
void report_dir_remove(const char *tmp);

#endif

/* depfile.h — make/ninja depfiles of bundles (hairgen -MD / -MF), spelt so
   that GNU make and ninja both read back exactly the file names hairgen
   read. What neither can spell the same way is refused by name, before a
   bundle is made. Internal to libhairgen (batch.c, generate.c).

   Usage:
       if (ht_depfile_check_name(path, err, sizeof err) != HT_OK) ...  // one line
       ht_depfile_rule rules[] = { { "out/bundle", &report } };
       ht_depfile_write("out/bundle.d", rules, 1, err, sizeof err); */
#ifndef HT_DEPFILE_H
#define HT_DEPFILE_H

#include <stddef.h>

#include "hairgen_internal.h"

/* HT_OK when name has one spelling that make and ninja both read as name;
   HT_ERR_INVALID_ARGUMENT with "NAME: cannot be listed in a depfile
   (-MD, -MF): ';' (make and ninja do not read it alike)" otherwise. */
ht_result ht_depfile_check_name(const char *name, char *err, size_t err_size);

/* Every input of a bundle report and its directory checked as above. */
ht_result ht_depfile_check_report(const char *dir, const ht_bundle_report *rep, char *err, size_t err_size);

typedef struct ht_depfile_rule {
    const char *dir;                 /* the bundle: its target is DIR/manifest.json */
    const ht_bundle_report *report;  /* its inputs */
} ht_depfile_rule;

/* "DIR/manifest.json: INPUTS... HAIRGEN" per rule, then an empty rule per
   prerequisite (as GCC's -MP), written whole or not at all
   (ht_file_write_atomic: never over a device or a FIFO). HAIRGEN is the
   running program (/proc/self/exe), so a new hairgen rebuilds; left out
   where it cannot be read or spelt. */
ht_result ht_depfile_write(const char *path, const ht_depfile_rule *rules, int count, char *err, size_t err_size);

#endif

/* file_open.h — open a file for reading only when it is a regular file of
   bounded size. Every reader of user or bundle files goes through it, so a
   FIFO, a device (/dev/zero), a directory or a file larger than its kind's
   cap is refused with one line before a single byte is read (a FIFO would
   block forever, /dev/zero would never end). Internal to libhairtier.

   Usage:
       FILE *f; uint64_t size;
       if (ht_file_open_regular(path, HT_FILE_MAX_JSON, &f, &size, err, sizeof err) != HT_OK)
           return ...;  // err: "PATH: not a regular file (a FIFO)"
       ... fread ...; fclose(f);

   The caps by kind of file are below: each is far above what hairgen
   writes or a person edits, and low enough that reading one cannot exhaust
   a small machine. */
#ifndef HT_FILE_OPEN_H
#define HT_FILE_OPEN_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hairtier.h"

#define HT_FILE_MAX_JSON    (16u << 20)   /* materials, scenes, manifests, combiner programs */
#define HT_FILE_MAX_SHADER  (1u << 20)    /* one GLSL source */
#define HT_FILE_MAX_PNG     (512u << 20)  /* a PNG: 64 Mi RGBA pixels stored, with room for poor compression */

/* Opens path for reading ("rb"). Refuses (HT_ERR_IO, err "PATH: why") a
   missing or unreadable file, anything but a regular file (naming what it
   is), and a file larger than max_bytes. The size is the one fstat saw on
   the open descriptor, so a file swapped after the check is still the file
   that was checked. size may be NULL. */
ht_result ht_file_open_regular(const char *path, uint64_t max_bytes, FILE **out, uint64_t *size,
                               char *err, size_t err_size);

#endif

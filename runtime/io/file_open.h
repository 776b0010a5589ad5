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

#include <hairtier/hairtier.h>
#include <hairtier/ht_limits.h>

#define HT_FILE_MAX_JSON    HT_LIMIT_FILE_JSON
#define HT_FILE_MAX_SHADER  HT_LIMIT_FILE_SHADER
#define HT_FILE_MAX_PNG     HT_LIMIT_FILE_PNG

/* Opens path for reading ("rb"). Refuses (HT_ERR_IO, err "PATH: why") a
   missing or unreadable file, anything but a regular file (naming what it
   is), and a file larger than max_bytes. The size is the one fstat saw on
   the open descriptor, so a file swapped after the check is still the file
   that was checked. size may be NULL. */
ht_result ht_file_open_regular(const char *path, uint64_t max_bytes, FILE **out, uint64_t *size,
                               char *err, size_t err_size);

/* "PATH: file is N bytes, more than the M this kind of file may have"
   (HT_ERR_IO) when size > max_bytes: the cap ht_file_open_regular applies,
   for bytes that come from elsewhere (a bundle in memory). */
ht_result ht_file_check_size(const char *path, uint64_t size, uint64_t max_bytes, char *err, size_t err_size);

/* size bytes as a malloc'd NUL-terminated text, or NULL with "PATH: NUL
   byte in a text file" (or out of memory) in err. */
char *ht_text_from_bytes(const char *path, const void *data, size_t size, char *err, size_t err_size);

/* The whole of a regular file of at most max_bytes, malloc'd (free()),
   its length in *size, or NULL with "PATH: why" in err (what
   ht_file_open_regular refuses, a read error, a file that changed size
   while read, out of memory). The block has one byte more than *size, so
   a caller may end a text in place. Read with read(2), not stdio. */
void *ht_file_read_bytes(const char *path, uint64_t max_bytes, size_t *size, char *err, size_t err_size);
/* The whole of a regular text file of at most max_bytes, malloc'd and
   NUL-terminated, or NULL with "PATH: why" in err (what
   ht_file_open_regular refuses, a read error, a NUL byte, out of memory). */
char *ht_file_read_text(const char *path, uint64_t max_bytes, char *err, size_t err_size);

#endif

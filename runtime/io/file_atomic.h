/* file_atomic.h — write a file whole or not at all: into a temporary
   sibling (PATH.tmp-XXXXXX, mode 0644), flushed to disk, then renamed over
   PATH, so a reader (or a crash) sees the old file or the whole new one,
   never half. Internal to libhairtier; the PNG writer (image.c) and the
   benchmarks' result files (examples/bench) go through it.

   Usage:
       static bool write_rows(FILE *f, void *ctx, char *why, size_t why_size) {
           return fprintf(f, "...") >= 0;
       }
       if (ht_file_write_atomic("bench/results.csv", write_rows, &rows, err, sizeof err) != HT_OK) puts(err);

   A writer that fails says why in `why` (without the path), or leaves it
   empty for "write failed" and errno's reason. Errors are one line naming
   the file; on any failure the file is untouched and no temporary is left. */
#ifndef HT_FILE_ATOMIC_H
#define HT_FILE_ATOMIC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <hairtier/hairtier.h>

typedef bool (*ht_file_writer_fn)(FILE *f, void *ctx, char *why, size_t why_size);

/* HT_OK, or HT_ERR_IO (HT_ERR_OUT_OF_MEMORY when the temporary's name
   cannot be made) with "PATH: why" in err. */
ht_result ht_file_write_atomic(const char *path, ht_file_writer_fn fn, void *ctx, char *err, size_t err_size);

#endif

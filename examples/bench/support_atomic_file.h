/* support_atomic_file.h — how the benchmarks write a result file: into a
   temporary sibling, flushed to disk, then renamed over the final name, so a
   reader (or a crash) sees the old file or the whole new one, never half.

   Usage:
       static bool write_rows(FILE *f, void *ctx) { return fprintf(f, "...") >= 0; }
       char err[512];
       if (!bench_write_atomic("bench/results.csv", write_rows, &rows, err, sizeof err)) puts(err);

   Errors are one line naming the file. */
#ifndef HT_EXAMPLES_SUPPORT_ATOMIC_FILE_H
#define HT_EXAMPLES_SUPPORT_ATOMIC_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/* Writes what fn writes (fn returns false on its own failure) to path.
   On any failure: false, one line in err, path untouched, no temporary left. */
typedef bool (*bench_writer_fn)(FILE *f, void *ctx);
bool bench_write_atomic(const char *path, bench_writer_fn fn, void *ctx, char *err, size_t err_size);

#endif

/* support_scratch.h — scratch directories and small files for tests.

   Usage:
       static char work[64];
       setup:    return ht_test_scratch_create(work, sizeof work, "bundle") ? 0 : -1;
       teardown: return ht_test_scratch_remove(work);

   The file helpers fail the running cmocka test when a file cannot be
   written, read or copied. */
#ifndef HT_SUPPORT_SCRATCH_H
#define HT_SUPPORT_SCRATCH_H

#include <stdbool.h>
#include <stddef.h>

/* A fresh directory /tmp/hairtier-test-NAME-XXXXXX; false if it cannot be made. */
bool ht_test_scratch_create(char *dir, size_t size, const char *name);
/* dir and everything under it, read-only directories included (they are
   made writable first); links are removed, never followed. 0, or -1 when
   anything stays. */
int ht_test_scratch_remove(const char *dir);

/* DIR/NAME replaced by text. */
void ht_test_write_file(const char *dir, const char *name, const char *text);
/* DIR/NAME, at most 64 KiB, in a buffer the next call reuses. */
char *ht_test_read_file(const char *dir, const char *name);
/* The whole file at path, malloc'd and NUL-terminated (free()); its size
   in *size when size is not NULL; NULL when it cannot be opened. */
char *ht_test_read_all(const char *path, size_t *size);
/* Anything at path (a link is not followed: a dangling one exists). */
bool ht_test_path_exists(const char *path);
/* Where the programs under test were built: $HAIRTIER_BUILD, else "build". */
const char *ht_test_build_dir(void);
/* Runs build/PROGRAM ARGS (ARGS already quoted for the shell), stdout and
   stderr into out (NUL-terminated, truncated to size); fails the test
   unless it exits normally; returns its exit status. */
int ht_test_run_program(const char *program, const char *args, char *out, size_t size);
/* DIR/NAME parsed as JSON (cJSON_Delete), failing the test when it cannot be read or parsed. */
struct cJSON *ht_test_read_json(const char *dir, const char *name);
/* DIR/NAME, a JSON object, rewritten with its top-level key set to value. */
void ht_test_set_json_number(const char *dir, const char *name, const char *key, double value);
/* to replaced by a copy of the directory from. */
void ht_test_copy_dir(const char *from, const char *to);

#endif

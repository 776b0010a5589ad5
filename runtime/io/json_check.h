/* json_check.h — checked access to cJSON documents, shared by every file
   format hairtier reads (materials, scenes, the bundle manifest, the
   combiner program): every getter checks type, finiteness and range, fills a default
   when the field is absent and optional, and on failure writes one line
   "FILE: FIELD: what is wrong" where FIELD is the JSON path of the value
   ("primary.exponent", "lights[1].color[2]").

   Usage:
       ht_jctx c = { .file = "blond.json", .err = err, .err_size = sizeof err };
       cJSON *root;
       if ((r = ht_json_parse_root(&c, text, &root)) != HT_OK) return r;
       static const char *const keys[] = { "format", "exponent", NULL };
       double e;
       if ((r = ht_json_keys(&c, root, "", keys)) == HT_OK)
           r = ht_json_number(&c, root, "", "exponent", NULL,
                              HT_JRANGE(0, 10000), &e);   // NULL: required
       cJSON_Delete(root);

   A `def` pointer of NULL makes a field required; otherwise *def is used
   when the field is absent. Getters that take `path` expect the path of the
   parent object ("" at the root). Nothing here keeps state between calls. */
#ifndef HT_JSON_CHECK_H
#define HT_JSON_CHECK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <cJSON.h>

#include <hairtier/hairtier.h>

/* Longest JSON path we report; deeper paths are cut, never overflow. */
#define HT_JSON_PATH_MAX 256

typedef struct ht_jctx {
    const char *file;   /* FILE of error lines; NULL → "<input>" */
    char *err;          /* may be NULL */
    size_t err_size;
} ht_jctx;

/* A closed, open or half-open interval of accepted numbers. */
typedef struct ht_jrange {
    double lo, hi;
    bool lo_open, hi_open;
} ht_jrange;

#define HT_JRANGE(lo, hi) ((ht_jrange){ (lo), (hi), false, false })
#define HT_JRANGE_LO_OPEN(lo, hi) ((ht_jrange){ (lo), (hi), true, false })
#define HT_JRANGE_OPEN(lo, hi) ((ht_jrange){ (lo), (hi), true, true })

/* Writes "FILE: FIELD: message" and returns HT_ERR_PARSE. */
ht_result ht_json_fail(const ht_jctx *c, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* "parent.key" (or "key" at the root) and "parent[index]". */
void ht_json_path_key(char out[HT_JSON_PATH_MAX], const char *parent, const char *key);
void ht_json_path_index(char out[HT_JSON_PATH_MAX], const char *parent, int index);

/* Reads a whole file as a NUL-terminated string (free() it). A file that
   cannot be read gives HT_ERR_IO and "FILE: cannot read: <strerror>"; a NUL
   byte inside or a file over 16 MiB gives HT_ERR_PARSE. */
ht_result ht_json_read_file(const char *path, char **text, char *err, size_t err_size);
/* The same checks (size cap, NUL byte) and messages for bytes already in
   memory (a bundle compiled in), PATH naming them. */
ht_result ht_json_text_from_bytes(const char *path, const void *data, size_t size, char **text, char *err,
                                  size_t err_size);

/* Parses text whose root must be an object. Syntax errors name the line:
   "FILE: line 3: malformed JSON at column 7 near ..." */
ht_result ht_json_parse_root(const ht_jctx *c, const char *text, cJSON **root);

/* How every FORMAT_parse(text, file_name, out, err, err_size) and
   FORMAT_load(path, out, err, err_size) starts: a NULL text, path or out is
   HT_ERR_INVALID_ARGUMENT with "FILE: (call): no text or no output" (FILE
   is c->file) or "(null): (call): no path or no output"; then the root is
   parsed (ht_json_parse_root) or the file read (ht_json_read_file). */
ht_result ht_json_parse_entry(const ht_jctx *c, const char *text, const void *out, cJSON **root);
ht_result ht_json_load_entry(const char *path, const void *out, char **text, char *err, size_t err_size);

/* Checks that the root's "format" is exactly `format`. */
ht_result ht_json_format(const ht_jctx *c, const cJSON *root, const char *format,
                         const char *what);

/* `obj` (at `path`) must be an object whose keys are all in `known`
   (NULL-terminated) and appear once; an unknown key is reported with the
   nearest known one by edit distance. */
ht_result ht_json_keys(const ht_jctx *c, const cJSON *obj, const char *path,
                       const char *const known[]);

/* Fails with "FIELD: why" when `key` is present in obj. */
ht_result ht_json_forbid(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, const char *why);

/* Item checkers: `item` is the value at `path`. */
ht_result ht_json_number_item(const ht_jctx *c, const cJSON *item, const char *path,
                              ht_jrange r, double *out);
/* Also checks the range after rounding to float (1e-50 is not > 0 there). */
ht_result ht_json_float_item(const ht_jctx *c, const cJSON *item, const char *path,
                             ht_jrange r, float *out);
ht_result ht_json_int_item(const ht_jctx *c, const cJSON *item, const char *path,
                           int64_t lo, int64_t hi, int64_t *out);
/* One of `names` (NULL-terminated); *out is its index. */
ht_result ht_json_enum_item(const ht_jctx *c, const cJSON *item, const char *path,
                            const char *const names[], int *out);
/* An array of exactly n (1..8) numbers, each in r. */
ht_result ht_json_vec_item(const ht_jctx *c, const cJSON *item, const char *path,
                           int n, ht_jrange r, double *out);

/* Keyed getters: the field `key` of `obj`, whose path is `path`. */
ht_result ht_json_object(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, bool required, const cJSON **out);
/* An array of min..max elements; *out is NULL and *count 0 when absent. */
ht_result ht_json_array(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, bool required, int min, int max,
                        const cJSON **out, int *count);
ht_result ht_json_number(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, const double *def, ht_jrange r, double *out);
ht_result ht_json_float(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, const float *def, ht_jrange r, float *out);
ht_result ht_json_int(const ht_jctx *c, const cJSON *obj, const char *path,
                      const char *key, const int64_t *def, int64_t lo, int64_t hi,
                      int64_t *out);
/* n (1..8) numbers, each in r; def holds n values. */
ht_result ht_json_vec(const ht_jctx *c, const cJSON *obj, const char *path,
                      const char *key, const double *def, int n, ht_jrange r,
                      double *out);
ht_result ht_json_vec3f(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, const float *def, ht_jrange r, float out[3]);
/* ht_json_int into an int: lo..hi must fit an int; def NULL: required. */
ht_result ht_json_int32(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, const int *def, int lo, int hi, int *out);
/* One of `names` (NULL-terminated); *out is its index. def < 0: required. */
ht_result ht_json_enum(const ht_jctx *c, const cJSON *obj, const char *path,
                       const char *key, int def, const char *const names[], int *out);
/* true or false; required when def is NULL. */
ht_result ht_json_bool(const ht_jctx *c, const cJSON *obj, const char *path, const char *key, const bool *def,
                       bool *out);
/* A string of 1..out_size-1 bytes; required when def is NULL. */
ht_result ht_json_string(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, const char *def, char *out, size_t out_size);
/* An optional string: absent or null gives ""; present, as ht_json_string. */
ht_result ht_json_string_or_null(const ht_jctx *c, const cJSON *obj, const char *path,
                                 const char *key, char *out, size_t out_size);

/* Edit distance (optimal string alignment: a swap of neighbours costs 1). */
int ht_json_edit_distance(const char *a, const char *b);

#endif

/* json_check.c — checked field access shared by every JSON reader (see
   json_check.h). Over 500 lines but one job: the strict parse (syntax,
   nesting, RFC 8259 numbers and strings), the typed getters and their one
   error style belong together; split, each half would re-derive the
   other's paths and messages. */
#include "json_check.h"

#include "file_open.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"

/* Bigger inputs are not hand-edited files; refusing them keeps a stray
   multi-gigabyte path from being read into memory. */
#define MAX_FILE_BYTES HT_FILE_MAX_JSON
/* Longest user string echoed in a message. */
#define ECHO_MAX 40

/* ---- messages ---- */

/* Control characters (a newline in a key, a file name) would break the
   one-line promise, so they never reach the caller. */
static void one_line(char *s) {
    for (; *s; s++)
        if ((unsigned char)*s < 0x20 || *s == 0x7f) *s = '?';
}

ht_result ht_json_fail(const ht_jctx *c, const char *field, const char *fmt, ...) {
    if (!c->err || c->err_size == 0) return HT_ERR_PARSE;
    va_list ap;
    va_start(ap, fmt);
    ht_set_field_error_v(c->err, c->err_size, c->file ? c->file : "<input>", field, fmt, ap);
    va_end(ap);
    one_line(c->err);
    return HT_ERR_PARSE;
}

/* Shortest decimal that reads back as the same double, so a message never
   says "must be <= 0.98, got 0.98". */
static const char *num(char buf[40], double v) {
    for (int prec = 6; prec <= 17; prec++) {
        snprintf(buf, 40, "%.*g", prec, v);
        if (strtod(buf, NULL) == v) break;
    }
    return buf;
}

/* A user string in quotes, cut to ECHO_MAX bytes. */
static const char *quoted(char buf[ECHO_MAX + 8], const char *s) {
    size_t n = strlen(s), cut = n > ECHO_MAX ? ECHO_MAX : n;
    while (cut < n && cut > 0 && ((unsigned char)s[cut] & 0xC0) == 0x80) cut--;  /* whole UTF-8 characters */
    snprintf(buf, ECHO_MAX + 8, "\"%.*s%s\"", (int)cut, s, cut < n ? "..." : "");
    return buf;
}

/* "string \"abc\"", "number 5", "array", ... for "expected X, got Y". */
static const char *describe(char buf[ECHO_MAX + 48], const cJSON *item) {
    char q[ECHO_MAX + 8], n[40];
    if (cJSON_IsString(item)) snprintf(buf, ECHO_MAX + 48, "string %s", quoted(q, item->valuestring));
    else if (cJSON_IsNumber(item)) snprintf(buf, ECHO_MAX + 48, "number %s", num(n, item->valuedouble));
    else if (cJSON_IsArray(item)) snprintf(buf, ECHO_MAX + 48, "an array");
    else if (cJSON_IsObject(item)) snprintf(buf, ECHO_MAX + 48, "an object");
    else if (cJSON_IsTrue(item)) snprintf(buf, ECHO_MAX + 48, "true");
    else if (cJSON_IsFalse(item)) snprintf(buf, ECHO_MAX + 48, "false");
    else if (cJSON_IsNull(item)) snprintf(buf, ECHO_MAX + 48, "null");
    else snprintf(buf, ECHO_MAX + 48, "an invalid value");
    return buf;
}

static const char *range_text(char buf[96], ht_jrange r) {
    char lo[40], hi[40];
    snprintf(buf, 96, "%c%s, %s%c", r.lo_open ? '(' : '[', num(lo, r.lo), num(hi, r.hi),
             r.hi_open ? ')' : ']');
    return buf;
}

static bool in_range(double v, ht_jrange r) {
    return (r.lo_open ? v > r.lo : v >= r.lo) && (r.hi_open ? v < r.hi : v <= r.hi);
}

/* ---- paths ---- */

/* A path cut to fit ends in "..." so it is not mistaken for a real one. */
static void mark_cut(char out[HT_JSON_PATH_MAX], int n) {
    if (n >= HT_JSON_PATH_MAX) memcpy(out + HT_JSON_PATH_MAX - 4, "...", 4);
}

/* Copies what fits of s at out + *at, leaving room for the NUL. */
static void path_append(char out[HT_JSON_PATH_MAX], size_t *at, const char *s, size_t len) {
    size_t fit = HT_JSON_PATH_MAX - 1 - *at;
    if (len > fit) len = fit;
    memcpy(out + *at, s, len);
    *at += len;
}

/* parent.key, built without snprintf: every key of every document gets
   one, and snprintf made these a third of the instructions of a batch
   re-run with nothing to do (callgrind). */
void ht_json_path_key(char out[HT_JSON_PATH_MAX], const char *parent, const char *key) {
    size_t parent_len = parent ? strlen(parent) : 0, key_len = strlen(key), at = 0;
    if (parent_len) {
        path_append(out, &at, parent, parent_len);
        path_append(out, &at, ".", 1);
    }
    path_append(out, &at, key, key_len);
    out[at] = '\0';
    size_t full = parent_len ? parent_len + 1 + key_len : key_len;
    mark_cut(out, full > INT_MAX ? INT_MAX : (int)full);
}

void ht_json_path_index(char out[HT_JSON_PATH_MAX], const char *parent, int index) {
    mark_cut(out, snprintf(out, HT_JSON_PATH_MAX, "%s[%d]", parent ? parent : "", index));
}

/* ---- files and documents ---- */

/* A NUL byte inside a JSON text: "FILE: line N: NUL byte in a text file". */
static ht_result check_no_nul(const ht_jctx *c, const char *buf, size_t len) {
    const char *nul = memchr(buf, '\0', len);
    if (!nul) return HT_OK;
    int line = 1;
    for (const char *p = buf; p < nul; p++) line += *p == '\n';
    char field[32];
    snprintf(field, sizeof field, "line %d", line);
    return ht_json_fail(c, field, "NUL byte in a text file");
}

ht_result ht_json_text_from_bytes(const char *path, const void *data, size_t size, char **text, char *err,
                                  size_t err_size) {
    ht_jctx c = { path, err, err_size };
    *text = NULL;
    ht_result r = ht_file_check_size(path, size, MAX_FILE_BYTES, err, err_size);
    if (r != HT_OK) {
        if (err && err_size) one_line(err);
        return r;
    }
    if ((r = check_no_nul(&c, data, size)) != HT_OK) return r;
    char *buf = malloc(size + 1);
    if (!buf) {
        if (err && err_size) snprintf(err, err_size, "%s: out of memory", path);
        return HT_ERR_OUT_OF_MEMORY;
    }
    if (size) memcpy(buf, data, size);
    buf[size] = '\0';
    *text = buf;
    return HT_OK;
}

ht_result ht_json_read_file(const char *path, char **text, char *err, size_t err_size) {
    *text = NULL;
    size_t size = 0;
    void *bytes = ht_file_read_bytes(path, MAX_FILE_BYTES, &size, err, err_size);
    if (!bytes) {
        if (err && err_size) one_line(err);
        return HT_ERR_IO;
    }
    /* ht_file_read_bytes leaves a byte past the end: the text is made in
       place, not copied. */
    ht_result r = check_no_nul(&(ht_jctx){ path, err, err_size }, bytes, size);
    if (r != HT_OK) {
        free(bytes);
        return r;
    }
    ((char *)bytes)[size] = '\0';
    *text = bytes;
    return HT_OK;
}

static bool blank(const char *s) {
    if ((unsigned char)s[0] == 0xEF && (unsigned char)s[1] == 0xBB && (unsigned char)s[2] == 0xBF) s += 3;
    while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r') s++;
    return *s == '\0';
}

/* cJSON stops at the start of a string cut by the end of the file, so "the
   error is at the end" means: nothing but that line remains, and brackets
   or a string are still open at the end. */
static bool truncated(const char *text, const char *end) {
    if (*end == '\0') return true;
    const char *rest = end + strcspn(end, "\n");
    if (!blank(rest)) return false;
    int depth = 0;
    bool in_string = false;
    for (const char *p = text; *p; p++) {
        if (in_string) {
            if (*p == '\\' && p[1]) p++;
            else if (*p == '"') in_string = false;
        } else if (*p == '"') in_string = true;
        else if (*p == '{' || *p == '[') depth++;
        else if (*p == '}' || *p == ']') depth--;
    }
    return in_string || depth > 0;
}

/* Open brackets before `end`, outside strings: cJSON refuses a document
   deeper than CJSON_NESTING_LIMIT at the bracket that crosses it. */
static int nesting_at(const char *text, const char *end) {
    int depth = 0, deepest = 0;
    bool in_string = false;
    for (const char *p = text; *p && p <= end; p++) {
        if (in_string) {
            if (*p == '\\' && p[1]) p++;
            else if (*p == '"') in_string = false;
        } else if (*p == '"') in_string = true;
        else if (*p == '{' || *p == '[') { if (++depth > deepest) deepest = depth; }
        else if (*p == '}' || *p == ']') depth--;
    }
    return deepest;
}

/* What cJSON accepts but JSON (RFC 8259) does not, and which would slip
   through silently: a raw control character or an escaped NUL in a string
   (cJSON ends the C string there, so "ok\u0000bad" would read as "ok"), a
   number with a leading zero ("080") or a bare fraction point ("80.").
   Returns the offending position, or NULL when the text is clean. */
static const char *lax_json(const char *text, const char **why) {
    bool in_string = false;
    for (const char *p = text; *p; p++) {
        unsigned char ch = (unsigned char)*p;
        if (in_string) {
            if (ch < 0x20) {
                *why = "raw control character in a string (escape it)";
                return p;
            }
            if (ch == '\\') {
                if (strncmp(p + 1, "u0000", 5) == 0) {
                    *why = "\\u0000 (NUL) in a string";
                    return p;
                }
                if (p[1]) p++;
            } else if (ch == '"') {
                in_string = false;
            }
            continue;
        }
        if (ch == '"') {
            in_string = true;
        } else if (ch == '-' || (ch >= '0' && ch <= '9')) {
            const char *start = p;
            if (*p == '-') p++;
            if (p[0] == '0' && p[1] >= '0' && p[1] <= '9') {
                *why = "number with a leading zero";
                return start;
            }
            while (*p >= '0' && *p <= '9') p++;
            if (*p == '.' && !(p[1] >= '0' && p[1] <= '9')) {
                *why = "number with no digit after its '.'";
                return start;
            }
            /* p may sit on the terminating NUL (a text ending in "4"): step
               over the rest of the number without reading past it, then
               back one so the loop's p++ lands on what follows. */
            while (*p && strchr("0123456789.eE+-", *p)) p++;
            p--;
        }
    }
    return NULL;
}

static int line_of(const char *text, const char *at) {
    int line = 1;
    for (const char *p = text; p < at && *p; p++) line += *p == '\n';
    return line;
}

ht_result ht_json_parse_root(const ht_jctx *c, const char *text, cJSON **root) {
    *root = NULL;
    if (blank(text)) return ht_json_fail(c, "line 1", "empty file, expected a JSON object");
    const char *end = NULL;
    cJSON *doc = cJSON_ParseWithOpts(text, &end, true);
    if (!doc) {
        if (!end || end < text) end = text;
        int line = 1, column = 1;
        for (const char *p = text; p < end && *p; p++) {
            if (*p == '\n') { line++; column = 1; }
            else column++;
        }
        char field[32];
        snprintf(field, sizeof field, "line %d", line);
        if (nesting_at(text, end) > CJSON_NESTING_LIMIT)
            return ht_json_fail(c, field, "malformed JSON: nested more than %d levels deep", CJSON_NESTING_LIMIT);
        if (truncated(text, end))
            return ht_json_fail(c, field, "malformed JSON: unexpected end of file (truncated?)");
        size_t n = strcspn(end, "\r\n");
        if (n > 20) n = 20;
        return ht_json_fail(c, field, "malformed JSON at column %d near '%.*s'", column, (int)n, end);
    }
    const char *why = NULL, *lax = lax_json(text, &why);
    if (lax) {
        char field[32];
        snprintf(field, sizeof field, "line %d", line_of(text, lax));
        cJSON_Delete(doc);
        return ht_json_fail(c, field, "malformed JSON: %s", why);
    }
    if (!cJSON_IsObject(doc)) {
        char got[ECHO_MAX + 48];
        ht_result r = ht_json_fail(c, "(root)", "expected a JSON object, got %s", describe(got, doc));
        cJSON_Delete(doc);
        return r;
    }
    *root = doc;
    return HT_OK;
}

ht_result ht_json_parse_entry(const ht_jctx *c, const char *text, const void *out, cJSON **root) {
    *root = NULL;
    if (!text || !out) {
        ht_set_error(c->err, c->err_size, "%s: (call): no text or no output", c->file);
        return HT_ERR_INVALID_ARGUMENT;
    }
    return ht_json_parse_root(c, text, root);
}

ht_result ht_json_load_entry(const char *path, const void *out, char **text, char *err, size_t err_size) {
    *text = NULL;
    if (!path || !out) {
        ht_set_error(err, err_size, "(null): (call): no path or no output");
        return HT_ERR_INVALID_ARGUMENT;
    }
    return ht_json_read_file(path, text, err, err_size);
}

ht_result ht_json_format(const ht_jctx *c, const cJSON *root, const char *format,
                         const char *what) {
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(root, "format");
    char q[ECHO_MAX + 8], got[ECHO_MAX + 48];
    if (!f)
        return ht_json_fail(c, "format", "missing; a %s starts with \"format\": \"%s\"", what, format);
    if (!cJSON_IsString(f))
        return ht_json_fail(c, "format", "expected the string \"%s\", got %s", format, describe(got, f));
    if (strcmp(f->valuestring, format) != 0)
        return ht_json_fail(c, "format", "expected \"%s\" (a %s), got %s", format, what,
                            quoted(q, f->valuestring));
    return HT_OK;
}

/* ---- keys ---- */

int ht_json_edit_distance(const char *a, const char *b) {
    enum { MAXLEN = 64 };
    size_t n = strlen(a), m = strlen(b);
    if (n > MAXLEN || m > MAXLEN) return MAXLEN * 2;
    int d[MAXLEN + 1][MAXLEN + 1];
    for (size_t i = 0; i <= n; i++) d[i][0] = (int)i;
    for (size_t j = 0; j <= m; j++) d[0][j] = (int)j;
    for (size_t i = 1; i <= n; i++) {
        for (size_t j = 1; j <= m; j++) {
            int cost = a[i - 1] != b[j - 1];
            int best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
            if (d[i - 1][j - 1] + cost < best) best = d[i - 1][j - 1] + cost;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    }
    return d[n][m];
}

/* The known name closest to `s`, or NULL when none is close enough to be a
   plausible typo: a third of the name (at least one edit), or a shortening
   of it ("fov" for "fov_y"). */
static const char *nearest(const char *s, const char *const names[]) {
    const char *best = NULL;
    int best_d = 0;
    size_t n = strlen(s);
    for (int i = 0; names[i]; i++) {
        int d = ht_json_edit_distance(s, names[i]);
        int limit = (int)strlen(names[i]) / 3;
        if (limit < 1) limit = 1;
        bool prefix = n >= 2 && strncmp(s, names[i], n) == 0;
        if ((d <= limit || prefix) && (!best || d < best_d)) { best = names[i]; best_d = d; }
    }
    return best;
}

/* ", " separated list of quoted names, for "expected one of ...". */
static void name_list(char *buf, size_t size, const char *const names[]) {
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; names[i] && used < size; i++) {
        int n = snprintf(buf + used, size - used, "%s\"%s\"", i ? ", " : "", names[i]);
        if (n < 0) break;
        used += (size_t)n;
    }
}

ht_result ht_json_keys(const ht_jctx *c, const cJSON *obj, const char *path,
                       const char *const known[]) {
    char got[ECHO_MAX + 48];
    if (!cJSON_IsObject(obj))
        return ht_json_fail(c, path[0] ? path : "(root)", "expected an object, got %s", describe(got, obj));
    enum { MAX_KNOWN = 32 };
    bool seen[MAX_KNOWN] = { false };
    for (const cJSON *it = obj->child; it; it = it->next) {
        int k = 0;
        while (known[k] && strcmp(known[k], it->string) != 0) k++;
        char field[HT_JSON_PATH_MAX], q[ECHO_MAX + 8];
        ht_json_path_key(field, path, it->string);
        if (!known[k]) {
            const char *near = nearest(it->string, known);
            if (near)
                return ht_json_fail(c, field, "unknown key %s (did you mean \"%s\"?)",
                                    quoted(q, it->string), near);
            char list[512];
            name_list(list, sizeof list, known);
            return ht_json_fail(c, field, "unknown key %s (known keys: %s)", quoted(q, it->string), list);
        }
        if (k < MAX_KNOWN) {
            if (seen[k]) return ht_json_fail(c, field, "duplicate key %s", quoted(q, it->string));
            seen[k] = true;
        }
    }
    return HT_OK;
}

ht_result ht_json_forbid(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, const char *why) {
    if (!cJSON_GetObjectItemCaseSensitive(obj, key)) return HT_OK;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, key);
    return ht_json_fail(c, field, "%s", why);
}

/* ---- values ---- */

ht_result ht_json_number_item(const ht_jctx *c, const cJSON *item, const char *path,
                              ht_jrange r, double *out) {
    char got[ECHO_MAX + 48], rt[96];
    if (!cJSON_IsNumber(item))
        return ht_json_fail(c, path, "expected a number, got %s", describe(got, item));
    double v = item->valuedouble;
    if (!isfinite(v))
        return ht_json_fail(c, path, "number too large for a double (read as %s)",
                            v > 0 ? "infinity" : "-infinity");
    if (!in_range(v, r))
        return ht_json_fail(c, path, "must be in %s, got %s", range_text(rt, r), num(got, v));
    *out = v;
    return HT_OK;
}

ht_result ht_json_float_item(const ht_jctx *c, const cJSON *item, const char *path,
                             ht_jrange r, float *out) {
    double v;
    ht_result res = ht_json_number_item(c, item, path, r, &v);
    if (res != HT_OK) return res;
    float f = (float)v;
    /* The value as stored must still be in range (1e-50 must not become the
       0 that means "default"), judged against the bounds as floats too, so
       a bound written in the docs (0.0001) is accepted exactly. */
    ht_jrange as_float = { (float)r.lo, (float)r.hi, r.lo_open, r.hi_open };
    if (!isfinite(f) || !in_range((double)f, as_float)) {
        char rt[96], a[40], b[40];
        return ht_json_fail(c, path, "must be in %s, got %s (%s in 32-bit float)",
                            range_text(rt, r), num(a, v), num(b, (double)f));
    }
    *out = f;
    return HT_OK;
}

ht_result ht_json_int_item(const ht_jctx *c, const cJSON *item, const char *path,
                           int64_t lo, int64_t hi, int64_t *out) {
    char got[ECHO_MAX + 48];
    if (!cJSON_IsNumber(item))
        return ht_json_fail(c, path, "expected an integer, got %s", describe(got, item));
    double v = item->valuedouble;
    if (!isfinite(v))
        return ht_json_fail(c, path, "number too large for a double (read as %s)",
                            v > 0 ? "infinity" : "-infinity");
    if (v != floor(v))
        return ht_json_fail(c, path, "must be an integer, got %s", num(got, v));
    if (v < (double)lo || v > (double)hi)
        return ht_json_fail(c, path, "must be an integer in [%lld, %lld], got %s",
                            (long long)lo, (long long)hi, num(got, v));
    *out = (int64_t)v;
    return HT_OK;
}

ht_result ht_json_vec_item(const ht_jctx *c, const cJSON *item, const char *path,
                           int n, ht_jrange r, double *out) {
    char got[ECHO_MAX + 48];
    if (n < 1 || n > 8) return ht_json_fail(c, path, "internal: vectors hold 1 to 8 numbers, asked %d", n);
    if (!cJSON_IsArray(item))
        return ht_json_fail(c, path, "expected an array of %d numbers, got %s", n, describe(got, item));
    int count = cJSON_GetArraySize(item);
    if (count != n)
        return ht_json_fail(c, path, "expected an array of %d numbers, got %d element%s", n, count,
                            count == 1 ? "" : "s");
    double tmp[8];
    int i = 0;
    for (const cJSON *it = item->child; it && i < n && i < 8; it = it->next, i++) {
        char field[HT_JSON_PATH_MAX];
        ht_json_path_index(field, path, i);
        ht_result res = ht_json_number_item(c, it, field, r, &tmp[i]);
        if (res != HT_OK) return res;
    }
    memcpy(out, tmp, sizeof(double) * (size_t)i);
    return HT_OK;
}

/* The field `key` of obj, or NULL. Fails only when it is absent and required. */
static ht_result lookup(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                        bool required, const char *what, const cJSON **item,
                        char field[HT_JSON_PATH_MAX]) {
    ht_json_path_key(field, path, key);
    *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!*item && required) return ht_json_fail(c, field, "missing required %s", what);
    return HT_OK;
}

ht_result ht_json_object(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, bool required, const cJSON **out) {
    char field[HT_JSON_PATH_MAX], got[ECHO_MAX + 48];
    const cJSON *it;
    ht_result r = lookup(c, obj, path, key, required, "object", &it, field);
    *out = NULL;
    if (r != HT_OK || !it) return r;
    if (!cJSON_IsObject(it)) return ht_json_fail(c, field, "expected an object, got %s", describe(got, it));
    *out = it;
    return HT_OK;
}

ht_result ht_json_array(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, bool required, int min, int max,
                        const cJSON **out, int *count) {
    char field[HT_JSON_PATH_MAX], got[ECHO_MAX + 48];
    const cJSON *it;
    ht_result r = lookup(c, obj, path, key, required, "array", &it, field);
    *out = NULL;
    *count = 0;
    if (r != HT_OK || !it) return r;
    if (!cJSON_IsArray(it)) return ht_json_fail(c, field, "expected an array, got %s", describe(got, it));
    int n = cJSON_GetArraySize(it);
    if (n < min || n > max) {
        if (min == max) return ht_json_fail(c, field, "expected %d elements, got %d", min, n);
        return ht_json_fail(c, field, "expected %d to %d elements, got %d", min, max, n);
    }
    *out = it;
    *count = n;
    return HT_OK;
}

ht_result ht_json_number(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, const double *def, ht_jrange r, double *out) {
    char field[HT_JSON_PATH_MAX];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "number", &it, field);
    if (res != HT_OK) return res;
    if (!it) { *out = *def; return HT_OK; }
    return ht_json_number_item(c, it, field, r, out);
}

ht_result ht_json_float(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, const float *def, ht_jrange r, float *out) {
    char field[HT_JSON_PATH_MAX];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "number", &it, field);
    if (res != HT_OK) return res;
    if (!it) { *out = *def; return HT_OK; }
    return ht_json_float_item(c, it, field, r, out);
}

ht_result ht_json_int(const ht_jctx *c, const cJSON *obj, const char *path,
                      const char *key, const int64_t *def, int64_t lo, int64_t hi,
                      int64_t *out) {
    char field[HT_JSON_PATH_MAX];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "integer", &it, field);
    if (res != HT_OK) return res;
    if (!it) { *out = *def; return HT_OK; }
    return ht_json_int_item(c, it, field, lo, hi, out);
}

ht_result ht_json_vec(const ht_jctx *c, const cJSON *obj, const char *path,
                      const char *key, const double *def, int n, ht_jrange r,
                      double *out) {
    char field[HT_JSON_PATH_MAX];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "array", &it, field);
    if (res != HT_OK) return res;
    if (!it) { memcpy(out, def, sizeof(double) * (size_t)n); return HT_OK; }
    return ht_json_vec_item(c, it, field, n, r, out);
}

ht_result ht_json_vec3f(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, const float *def, ht_jrange r, float out[3]) {
    char field[HT_JSON_PATH_MAX], got[ECHO_MAX + 48];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "array", &it, field);
    if (res != HT_OK) return res;
    if (!it) { memcpy(out, def, sizeof(float) * 3); return HT_OK; }
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 3) {
        if (!cJSON_IsArray(it))
            return ht_json_fail(c, field, "expected an array of 3 numbers, got %s", describe(got, it));
        int count = cJSON_GetArraySize(it);
        return ht_json_fail(c, field, "expected an array of 3 numbers, got %d element%s", count,
                            count == 1 ? "" : "s");
    }
    float tmp[3];
    int i = 0;
    for (const cJSON *e = it->child; e && i < 3; e = e->next, i++) {
        char elem[HT_JSON_PATH_MAX];
        ht_json_path_index(elem, field, i);
        res = ht_json_float_item(c, e, elem, r, &tmp[i]);
        if (res != HT_OK) return res;
    }
    memcpy(out, tmp, sizeof tmp);
    return HT_OK;
}

ht_result ht_json_enum_item(const ht_jctx *c, const cJSON *item, const char *path,
                            const char *const names[], int *out) {
    char got[ECHO_MAX + 48], q[ECHO_MAX + 8], list[256];
    name_list(list, sizeof list, names);
    if (!cJSON_IsString(item))
        return ht_json_fail(c, path, "expected one of %s, got %s", list, describe(got, item));
    for (int i = 0; names[i]; i++)
        if (strcmp(names[i], item->valuestring) == 0) { *out = i; return HT_OK; }
    const char *near = nearest(item->valuestring, names);
    if (near)
        return ht_json_fail(c, path, "unknown value %s (did you mean \"%s\"?)", quoted(q, item->valuestring), near);
    return ht_json_fail(c, path, "unknown value %s (expected one of %s)", quoted(q, item->valuestring), list);
}

ht_result ht_json_enum(const ht_jctx *c, const cJSON *obj, const char *path,
                       const char *key, int def, const char *const names[], int *out) {
    char field[HT_JSON_PATH_MAX];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, def < 0, "string", &it, field);
    if (res != HT_OK) return res;
    if (!it) { *out = def; return HT_OK; }
    return ht_json_enum_item(c, it, field, names, out);
}

ht_result ht_json_bool(const ht_jctx *c, const cJSON *obj, const char *path, const char *key, const bool *def,
                       bool *out) {
    char field[HT_JSON_PATH_MAX], got[ECHO_MAX + 48];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "boolean", &it, field);
    if (res != HT_OK) return res;
    if (!it) {
        *out = *def;
        return HT_OK;
    }
    if (!cJSON_IsBool(it)) return ht_json_fail(c, field, "expected true or false, got %s", describe(got, it));
    *out = cJSON_IsTrue(it);
    return HT_OK;
}

ht_result ht_json_string(const ht_jctx *c, const cJSON *obj, const char *path,
                         const char *key, const char *def, char *out, size_t out_size) {
    char field[HT_JSON_PATH_MAX], got[ECHO_MAX + 48];
    const cJSON *it;
    ht_result res = lookup(c, obj, path, key, !def, "string", &it, field);
    if (res != HT_OK) return res;
    const char *s = def;
    if (it) {
        if (!cJSON_IsString(it)) return ht_json_fail(c, field, "expected a string, got %s", describe(got, it));
        s = it->valuestring;
    }
    size_t n = strlen(s);
    if (n == 0) return ht_json_fail(c, field, "empty string");
    if (n >= out_size) return ht_json_fail(c, field, "longer than %zu bytes", out_size - 1);
    memcpy(out, s, n + 1);
    return HT_OK;
}

ht_result ht_json_string_or_null(const ht_jctx *c, const cJSON *obj, const char *path,
                                 const char *key, char *out, size_t out_size) {
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!it || cJSON_IsNull(it)) {
        if (out_size) out[0] = '\0';
        return HT_OK;
    }
    return ht_json_string(c, obj, path, key, NULL, out, out_size);
}

ht_result ht_json_int32(const ht_jctx *c, const cJSON *obj, const char *path,
                        const char *key, const int *def, int lo, int hi, int *out) {
    int64_t v, d = def ? *def : 0;
    ht_result r = ht_json_int(c, obj, path, key, def ? &d : NULL, lo, hi, &v);
    if (r == HT_OK) *out = (int)v;
    return r;
}

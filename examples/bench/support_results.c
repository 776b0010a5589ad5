/* support_results.c — bench_row and its CSV form (see the header). One
   table of columns drives both the writer and the reader, so they cannot
   drift apart. */
#include "support_results.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef enum column_kind { TEXT, COUNT, NUMBER, FLAG } column_kind;

typedef struct column {
    const char *name;           /* the CSV header's */
    column_kind kind;
    size_t offset, size;        /* size: TEXT's buffer */
} column;

#define T(name, field) { name, TEXT, offsetof(bench_row, field), sizeof(((bench_row *)0)->field) }
#define C(name, field) { name, COUNT, offsetof(bench_row, field), 0 }
#define N(name, field) { name, NUMBER, offsetof(bench_row, field), 0 }
#define F(name, field) { name, FLAG, offsetof(bench_row, field), 0 }

/* In BENCH_CSV_HEADER's order (bench_csv_header checks it once). */
static const column columns[] = {
    T("series", series), T("scene", scene), T("driver", driver), T("renderer", renderer),
    C("hairs", hairs), C("triangles", triangles), C("width", width), C("height", height), C("frames", frames),
    T("tier", tier), F("ran", ran), N("median_ms", median_ms), N("per_floor", per_floor), N("per_full", per_full),
    N("orbit_ms", orbit_ms), N("orbit_per_full", orbit_per_full),
    N("psnr_db", whole.psnr_db), N("ssim", whole.ssim), N("de00_mean", whole.delta_e00_mean),
    N("de00_p95", whole.delta_e00_p95), N("hair_psnr_db", hair.psnr_db), N("hair_ssim", hair.ssim),
    N("hair_de00_mean", hair.delta_e00_mean), N("hair_de00_p95", hair.delta_e00_p95),
    N("flip_mean", flip_mean), N("flip_p95", flip_p95),
    N("cpu_vertices_still", cpu_still), N("cpu_vertices_orbit", cpu_orbit),
    T("figure", figure), N("value", value), T("unit", unit),
};
enum { COLUMNS = sizeof columns / sizeof columns[0] };

const char *bench_csv_header(void) {
    static char header[sizeof BENCH_CSV_HEADER];
    if (header[0]) return header;
    size_t n = 0;
    for (size_t i = 0; i < COLUMNS; i++) {
        size_t len = strlen(columns[i].name);
        if (n + len + 1 > sizeof header) return NULL;
        if (i) header[n++] = ',';
        memcpy(header + n, columns[i].name, len);
        n += len;
    }
    header[n] = '\0';
    return strcmp(header, BENCH_CSV_HEADER) == 0 ? header : NULL;
}

bench_row bench_row_blank(void) {
    bench_row r;
    memset(&r, 0, sizeof r);
    for (size_t i = 0; i < COLUMNS; i++) {
        char *p = (char *)&r + columns[i].offset;
        if (columns[i].kind == COUNT) *(long *)p = -1;
        if (columns[i].kind == NUMBER) *(double *)p = NAN;
    }
    r.whole.pixels = r.hair.pixels = -1;
    return r;
}

bench_row *bench_rows_add(bench_rows *rows) {
    if (rows->count == rows->capacity) {
        size_t capacity = rows->capacity ? 2 * rows->capacity : 16;
        bench_row *grown = realloc(rows->row, capacity * sizeof *grown);
        if (!grown) return NULL;
        rows->row = grown;
        rows->capacity = capacity;
    }
    bench_row *r = &rows->row[rows->count++];
    *r = bench_row_blank();
    return r;
}

void bench_rows_free(bench_rows *rows) {
    free(rows->row);
    *rows = (bench_rows){ 0 };
}

/* ---- writing ---- */

static bool write_text(FILE *f, const char *s) {
    if (!strpbrk(s, ",\"\r\n")) return fputs(s, f) >= 0;
    if (fputc('"', f) == EOF) return false;
    for (; *s; s++)
        if ((*s == '"' && fputc('"', f) == EOF) || fputc(*s, f) == EOF) return false;
    return fputc('"', f) != EOF;
}

static bool write_field(FILE *f, const bench_row *r, const column *c) {
    const char *p = (const char *)r + c->offset;
    switch (c->kind) {
    case TEXT: return write_text(f, p);
    case COUNT: return *(const long *)p < 0 ? true : fprintf(f, "%ld", *(const long *)p) >= 0;
    case FLAG: return fputc(*(const bool *)p ? '1' : '0', f) != EOF;
    case NUMBER: {
        double v = *(const double *)p;
        if (isnan(v)) return true;
        if (isinf(v)) return fputs(v > 0 ? "inf" : "-inf", f) >= 0;
        return fprintf(f, "%.10g", v) >= 0;
    }
    }
    return false;
}

bool bench_rows_write_csv(FILE *f, const bench_rows *rows) {
    if (!bench_csv_header() || fputs(BENCH_CSV_HEADER "\n", f) < 0) return false;
    for (size_t i = 0; i < rows->count; i++) {
        for (size_t k = 0; k < COLUMNS; k++)
            if ((k && fputc(',', f) == EOF) || !write_field(f, &rows->row[i], &columns[k])) return false;
        if (fputc('\n', f) == EOF) return false;
    }
    return true;
}

/* ---- reading ---- */

#define FIELD_MAX 512
#define FILE_MAX (16L << 20)

typedef struct record {
    char field[COLUMNS + 1][FIELD_MAX];   /* one spare: a field too many is seen */
    size_t count;
} record;

/* One record from *p (which it advances past the line end). NULL, or what is wrong. */
static const char *parse_record(const char **p, record *rec) {
    const char *s = *p;
    rec->count = 0;
    for (;;) {
        if (rec->count == COLUMNS + 1) return "wrong number of fields";
        char *out = rec->field[rec->count++];
        size_t n = 0;
        if (*s == '"') {
            for (s++;; s++) {
                if (!*s) return "unterminated quote";
                if (*s == '"' && s[1] != '"') break;
                if (*s == '"') s++;
                if (n + 1 == FIELD_MAX) return "field too long";
                out[n++] = *s;
            }
            s++;
            if (*s && *s != ',' && *s != '\n' && *s != '\r') return "text after a closing quote";
        } else {
            for (; *s && *s != ',' && *s != '\n' && *s != '\r'; s++) {
                if (*s == '"') return "quote inside an unquoted field";
                if (n + 1 == FIELD_MAX) return "field too long";
                out[n++] = *s;
            }
        }
        out[n] = '\0';
        if (*s != ',') break;
        s++;
    }
    if (*s == '\r') s++;
    if (*s == '\n') s++;
    *p = s;
    return NULL;
}

static const char *parse_field(const char *text, const column *c, bench_row *r) {
    char *p = (char *)r + c->offset;
    char *end;
    switch (c->kind) {
    case TEXT:
        if (strlen(text) >= c->size) return "text too long for its column";
        strcpy(p, text);
        return NULL;
    case COUNT: {
        if (!*text) {
            *(long *)p = -1;
            return NULL;
        }
        errno = 0;
        long v = strtol(text, &end, 10);
        if (*end || errno || v < 0) return "not a count";
        *(long *)p = v;
        return NULL;
    }
    case FLAG:
        if (strcmp(text, "0") && strcmp(text, "1")) return "not 0 or 1";
        *(bool *)p = text[0] == '1';
        return NULL;
    case NUMBER: {
        if (!*text) {
            *(double *)p = NAN;
            return NULL;
        }
        double v = strtod(text, &end);
        if (*end || isnan(v)) return "not a number";
        *(double *)p = v;
        return NULL;
    }
    }
    return "unknown column";
}

static char *read_all(const char *path, char *err, size_t err_size) {
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    char *text = malloc(FILE_MAX + 1);
    size_t n = text ? fread(text, 1, FILE_MAX + 1, f) : 0;
    bool failed = !text || ferror(f) || n > FILE_MAX || memchr(text, '\0', n);
    fclose(f);
    if (failed) {
        snprintf(err, err_size, "%s: %s", path, !text ? "out of memory" : n > FILE_MAX ? "larger than 16 MiB"
                                                                         : "cannot read it as text");
        free(text);
        return NULL;
    }
    text[n] = '\0';
    return text;
}

bool bench_rows_read_csv(const char *path, bench_rows *rows, char *err, size_t err_size) {
    char *text = read_all(path, err, err_size);
    if (!text) return false;
    record *rec = malloc(sizeof *rec);
    size_t before = rows->count;
    const char *p = text, *why = NULL, *column_name = NULL;
    long line = 1;
    if (!rec) why = "out of memory";
    else if (!bench_csv_header()) why = "this build's column table and BENCH_CSV_HEADER differ";
    else if (strncmp(p, BENCH_CSV_HEADER, strlen(BENCH_CSV_HEADER)) != 0 ||
             (p[strlen(BENCH_CSV_HEADER)] != '\n' && p[strlen(BENCH_CSV_HEADER)] != '\r'))
        why = "header: not the benchmark's columns (" BENCH_CSV_HEADER ")";
    else {
        p = strchr(p, '\n') + 1;
        line = 2;
    }
    for (; !why && *p; line++) {
        if ((why = parse_record(&p, rec))) break;
        if (rec->count != COLUMNS) {
            why = "wrong number of fields";
            break;
        }
        bench_row *r = bench_rows_add(rows);
        if (!r) {
            why = "out of memory";
            break;
        }
        for (size_t k = 0; k < COLUMNS && !why; k++)
            if ((why = parse_field(rec->field[k], &columns[k], r))) column_name = columns[k].name;
        if (why) break;
    }
    if (why) {
        if (line == 1) snprintf(err, err_size, "%s: %s", path, why);
        else if (column_name) snprintf(err, err_size, "%s: line %ld: %s: %s", path, line, column_name, why);
        else snprintf(err, err_size, "%s: line %ld: %s", path, line, why);
        rows->count = before;
    }
    free(rec);
    free(text);
    return why == NULL;
}

/* ---- views ---- */

/* matrix and scaling: desktop GL runs, the tiers the plots colour */
static bool desktop_frame(const bench_row *r) {
    return strcmp(r->series, "matrix") == 0 || strcmp(r->series, "scaling") == 0;
}

bool bench_row_is_es(const bench_row *r) {
    return strcmp(r->series, "gles2") == 0 || strcmp(r->series, "gles3") == 0;
}

bool bench_row_is_frame(const bench_row *r) { return desktop_frame(r) || bench_row_is_es(r); }

int bench_tier_index(const char *const tiers[], size_t count, const char *name) {
    for (size_t i = 0; i < count; i++)
        if (strcmp(tiers[i], name) == 0) return (int)i;
    return -1;
}

size_t bench_rows_tiers(const bench_rows *rows, const char *tiers[], size_t max) {
    size_t n = 0;
    for (size_t i = 0; i < rows->count && n < max; i++)
        if (desktop_frame(&rows->row[i]) && bench_tier_index(tiers, n, rows->row[i].tier) < 0)
            tiers[n++] = rows->row[i].tier;
    return n;
}

static bool same_place(const bench_row *a, const bench_row *b) {
    return strcmp(a->scene, b->scene) == 0 && strcmp(a->driver, b->driver) == 0 && a->width == b->width &&
           a->height == b->height;
}

bool bench_rows_same_run(const bench_row *a, const bench_row *b) {
    return strcmp(a->series, b->series) == 0 && same_place(a, b) && a->hairs == b->hairs;
}

size_t bench_rows_matrix_runs(const bench_rows *rows, size_t first[], size_t max) {
    return bench_rows_series_runs(rows, "matrix", first, max);
}

size_t bench_rows_series_runs(const bench_rows *rows, const char *series, size_t first[], size_t max) {
    size_t n = 0;
    for (size_t i = 0; i < rows->count && n < max; i++) {
        const bench_row *r = &rows->row[i];
        if (strcmp(r->series, series) != 0) continue;
        bool seen = false;
        for (size_t k = 0; k < n && !seen; k++) seen = bench_rows_same_run(&rows->row[first[k]], r);
        if (!seen) first[n++] = i;
    }
    return n;
}

size_t bench_rows_scaling_runs(const bench_rows *rows, size_t first[], size_t max) {
    const bench_row *key = NULL;
    for (size_t i = 0; i < rows->count && !key; i++)
        if (strcmp(rows->row[i].series, "scaling") == 0) key = &rows->row[i];
    if (!key) return 0;
    size_t n = 0;
    /* Scaling runs first, so a hair count the matrix shares is taken from them. */
    for (int pass = 0; pass < 2; pass++)
        for (size_t i = 0; i < rows->count && n < max; i++) {
            const bench_row *r = &rows->row[i];
            if (strcmp(r->series, pass == 0 ? "scaling" : "matrix") != 0 || !same_place(r, key)) continue;
            bool seen = false;
            for (size_t k = 0; k < n && !seen; k++) seen = rows->row[first[k]].hairs == r->hairs;
            if (!seen) first[n++] = i;
        }
    for (size_t i = 1; i < n; i++) /* insertion sort by hairs: a handful of runs */
        for (size_t k = i; k > 0 && rows->row[first[k - 1]].hairs > rows->row[first[k]].hairs; k--) {
            size_t t = first[k];
            first[k] = first[k - 1];
            first[k - 1] = t;
        }
    return n;
}

const bench_row *bench_rows_find(const bench_rows *rows, size_t first, const char *tier) {
    for (size_t i = first; i < rows->count && bench_rows_same_run(&rows->row[first], &rows->row[i]); i++)
        if (strcmp(rows->row[i].tier, tier) == 0) return &rows->row[i];
    return NULL;
}

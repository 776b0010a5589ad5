/* errfmt.c — see errfmt.h. */
#include "errfmt.h"

#include <stdio.h>
#include <string.h>

void ht_escape_controls(char *s, size_t size) {
    if (!s || size == 0) return;
    const char *p = s;
    while (*p && (unsigned char)*p >= 0x20 && *p != 0x7f) p++;
    if (!*p) return; /* the common case: nothing to escape, nothing copied */
    char copy[4096];
    snprintf(copy, sizeof copy, "%s", s);
    size_t n = 0;
    for (const char *c = copy; *c; c++) {
        unsigned char ch = (unsigned char)*c;
        char esc[5] = { (char)ch, 0 };
        if (ch == '\n') memcpy(esc, "\\n", 3);
        else if (ch == '\r') memcpy(esc, "\\r", 3);
        else if (ch == '\t') memcpy(esc, "\\t", 3);
        else if (ch < 0x20 || ch == 0x7f) snprintf(esc, sizeof esc, "\\x%02x", ch);
        size_t len = strlen(esc);
        if (n + len >= size) break; /* cut, never a half escape */
        memcpy(s + n, esc, len);
        n += len;
    }
    s[n] = '\0';
}

static void set_error_v(char *err, size_t size, const char *fmt, va_list ap) {
    if (!err || size == 0) return;
    vsnprintf(err, size, fmt, ap);
    ht_escape_controls(err, size);
}

void ht_set_error(char *err, size_t size, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    set_error_v(err, size, fmt, ap);
    va_end(ap);
}

ht_result ht_fail(char *err, size_t size, ht_result r, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    set_error_v(err, size, fmt, ap);
    va_end(ap);
    return r;
}

void ht_set_field_error_v(char *err, size_t size, const char *file, const char *field, const char *fmt,
                          va_list ap) {
    if (!err || size == 0) return;
    int n = snprintf(err, size, "%s: %s: ", file, field);
    if (n >= 0 && (size_t)n < size) vsnprintf(err + n, size - (size_t)n, fmt, ap);
    ht_escape_controls(err, size);
}

void ht_log_linef(ht_log_fn log, void *user, const char *fmt, ...) {
    char line[HT_LOG_LINE_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    ht_escape_controls(line, sizeof line);
    log(user, line);
}

void ht_print_line(FILE *f, const char *fmt, ...) {
    char line[HT_LOG_LINE_MAX * 4];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    ht_escape_controls(line, sizeof line);
    fputs(line, f);
    fputc('\n', f);
}

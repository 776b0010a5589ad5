/* errfmt.c — see errfmt.h. */
#include "errfmt.h"

#include <stdio.h>

static void set_error_v(char *err, size_t size, const char *fmt, va_list ap) {
    if (err && size > 0) vsnprintf(err, size, fmt, ap);
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
}

void ht_log_linef(ht_log_fn log, void *user, const char *fmt, ...) {
    char line[HT_LOG_LINE_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    log(user, line);
}

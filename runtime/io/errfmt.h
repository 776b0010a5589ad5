/* errfmt.h — the one formatter behind the libraries' messages (internal to
   libhairtier and libhairgen): a line written to a caller's err buffer,
   optionally prefixed "FILE: FIELD: ", and a formatted line handed to an
   ht_log_fn. A message longer than its buffer is cut, never overflows; a
   NULL err or a size of 0 writes nothing. */
#ifndef HT_ERRFMT_H
#define HT_ERRFMT_H

#include <stdarg.h>
#include <stddef.h>

#include <hairtier/hairtier.h>

/* Longest log line ht_log_linef hands on; longer ones are cut. */
#define HT_LOG_LINE_MAX 1024

void ht_set_error(char *err, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* ht_set_error, then r: `return ht_fail(err, err_size, HT_ERR_IO, ...);` */
ht_result ht_fail(char *err, size_t size, ht_result r, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
/* "FILE: FIELD: " followed by fmt; what parsers report. */
void ht_set_field_error_v(char *err, size_t size, const char *file, const char *field, const char *fmt,
                          va_list ap) __attribute__((format(printf, 5, 0)));
void ht_log_linef(ht_log_fn log, void *user, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif

/* errfmt.h — the one formatter behind the libraries' messages (internal to
   libhairtier and libhairgen): a line written to a caller's err buffer,
   optionally prefixed "FILE: FIELD: ", and a formatted line handed to an
   ht_log_fn. A message longer than its buffer is cut, never overflows; a
   NULL err or a size of 0 writes nothing. Control characters in a message
   (a newline in a file name, a policy or an environment variable) are
   escaped as \n, \r, \t or \xNN, so a message is always one line. */
#ifndef HT_ERRFMT_H
#define HT_ERRFMT_H

#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <hairtier/hairtier.h>

/* Longest log line ht_log_linef hands on; longer ones are cut. */
#define HT_LOG_LINE_MAX 1024

void ht_set_error(char *err, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* ht_set_error, then r: `return ht_fail(err, err_size, HT_ERR_IO, ...);` */
ht_result ht_fail(char *err, size_t size, ht_result r, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
/* "FILE: FIELD: " followed by fmt; what parsers report. */
void ht_set_field_error_v(char *err, size_t size, const char *file, const char *field, const char *fmt,
                          va_list ap) __attribute__((format(printf, 5, 0)));
/* s rewritten in place with its control characters escaped (\n, \xNN),
   cut to size bytes: the rule every message above follows. */
void ht_escape_controls(char *s, size_t size);
void ht_log_linef(ht_log_fn log, void *user, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* One line to f, escaped as above, then '\n': what the programs print
   about files and names ("hairgen: NAME -> DIR"). */
void ht_print_line(FILE *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif

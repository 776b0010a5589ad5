/* support_figures.c — "LABEL: VALUE UNIT NOTE" lines (see the header). */
#include "support_figures.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* s[0..n) without surrounding white space, into out (size bytes); false if it does not fit. */
static bool copy_trimmed(const char *s, size_t n, char *out, size_t size) {
    while (n && isspace((unsigned char)*s)) s++, n--;
    while (n && isspace((unsigned char)s[n - 1])) n--;
    if (n >= size) return false;
    memcpy(out, s, n);
    out[n] = '\0';
    return true;
}

bool bench_parse_figure(const char *line, const char *series, bench_row *out) {
    for (const char *colon = strchr(line, ':'); colon; colon = strchr(colon + 1, ':')) {
        const char *s = colon + 1;
        while (*s == ' ' || *s == '\t') s++;
        if (!isdigit((unsigned char)*s) && *s != '-' && *s != '+' && *s != '.') continue;
        char *end;
        double value = strtod(s, &end);
        if (end == s || !isfinite(value) || (*end && !isspace((unsigned char)*end))) continue;

        bench_row row = bench_row_blank();
        if (!copy_trimmed(line, (size_t)(colon - line), row.figure, sizeof row.figure) || !row.figure[0])
            return false;
        const char *unit = end;
        while (*unit == ' ' || *unit == '\t') unit++;
        const char *unit_end = unit;
        if (isalpha((unsigned char)*unit))
            while (*unit_end && !isspace((unsigned char)*unit_end)) unit_end++;
        if (!copy_trimmed(unit, (size_t)(unit_end - unit), row.unit, sizeof row.unit)) return false;
        char note[sizeof row.figure];
        if (!copy_trimmed(unit_end, strlen(unit_end), note, sizeof note)) return false;
        if (note[0]) {
            size_t n = strlen(row.figure);
            if (n + 1 + strlen(note) >= sizeof row.figure) return false;
            /* fits (checked above); appended by hand because GCC's -O1
               truncation check cannot see that bound */
            row.figure[n] = ' ';
            memcpy(row.figure + n + 1, note, strlen(note) + 1);
        }
        if (strlen(series) >= sizeof row.series) return false;
        strcpy(row.series, series);
        row.value = value;
        *out = row;
        return true;
    }
    return false;
}

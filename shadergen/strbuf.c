/* strbuf.c — growable strings and GLSL float literals for the emitters. */
#include "strbuf.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void ht_strbuf_init(ht_strbuf *sb) {
    sb->data = NULL;
    sb->len = sb->cap = 0;
    sb->failed = false;
}

static bool reserve(ht_strbuf *sb, size_t extra) {
    if (sb->failed) return false;
    if (sb->len + extra + 1 <= sb->cap) return true;
    size_t cap = sb->cap ? sb->cap : 256;
    while (cap < sb->len + extra + 1) cap *= 2;
    char *p = realloc(sb->data, cap);
    if (!p) {
        sb->failed = true;
        return false;
    }
    sb->data = p;
    sb->cap = cap;
    return true;
}

void ht_strbuf_add(ht_strbuf *sb, const char *s) {
    size_t n = strlen(s);
    if (!reserve(sb, n)) return;
    memcpy(sb->data + sb->len, s, n + 1);
    sb->len += n;
}

void ht_strbuf_addn(ht_strbuf *sb, const char *s, size_t n) {
    if (!reserve(sb, n)) return;
    memcpy(sb->data + sb->len, s, n);
    sb->len += n;
    sb->data[sb->len] = '\0';
}

void ht_strbuf_addf(ht_strbuf *sb, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0) {
        sb->failed = true;
        return;
    }
    if (!reserve(sb, (size_t)n)) return;
    va_start(ap, fmt);
    vsnprintf(sb->data + sb->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    sb->len += (size_t)n;
}

char *ht_strbuf_take(ht_strbuf *sb) {
    char *text = NULL;
    if (!sb->failed) {
        text = sb->data ? sb->data : calloc(1, 1);
        sb->data = NULL;
    }
    ht_strbuf_free(sb);
    return text;
}

void ht_strbuf_free(ht_strbuf *sb) {
    free(sb->data);
    ht_strbuf_init(sb);
}

/* %.*e of f split into its significant digits and decimal exponent, whatever
   the locale's decimal separator is. */
static void scientific(float f, int precision, char *digits, size_t digits_size, int *exponent, char *raw,
                       size_t raw_size) {
    snprintf(raw, raw_size, "%.*e", precision, (double)f);
    size_t d = 0;
    const char *p = raw;
    for (; *p && *p != 'e' && *p != 'E'; p++)
        if (*p >= '0' && *p <= '9' && d + 1 < digits_size) digits[d++] = *p;
    digits[d] = '\0';
    *exponent = *p ? atoi(p + 1) : 0;
}

const char *ht_glsl_float(double v, char out[HT_GLSL_FLOAT_SIZE]) {
    float f = isfinite(v) && fabs(v) <= 3.0e38 ? (float)v : 0.0f;
    if (f == 0.0f) {
        strcpy(out, "0.0");
        return out;
    }
    /* Fewest significant digits that read back as f (9 always do). strtof
       reads the locale's separator, which snprintf wrote, so the round trip
       itself is locale-proof. */
    char digits[16], raw[48];
    int exponent = 0;
    for (int precision = 0; precision <= 8; precision++) {
        scientific(f, precision, digits, sizeof digits, &exponent, raw, sizeof raw);
        if (strtof(raw, NULL) == f) break;
    }
    size_t n = strlen(digits);
    while (n > 1 && digits[n - 1] == '0') digits[--n] = '\0';

    char *o = out;
    if (f < 0) *o++ = '-';
    if (exponent >= -4 && exponent <= 8) {
        if (exponent < 0) {
            *o++ = '0';
            *o++ = '.';
            for (int i = -1; i > exponent; i--) *o++ = '0';
            memcpy(o, digits, n);
            o += n;
        } else {
            for (int i = 0; i <= exponent; i++) *o++ = (size_t)i < n ? digits[i] : '0';
            *o++ = '.';
            if ((size_t)exponent + 1 < n) {
                memcpy(o, digits + exponent + 1, n - (size_t)exponent - 1);
                o += n - (size_t)exponent - 1;
            } else {
                *o++ = '0';
            }
        }
        *o = '\0';
    } else {
        *o++ = digits[0];
        *o++ = '.';
        if (n > 1) {
            memcpy(o, digits + 1, n - 1);
            o += n - 1;
        } else {
            *o++ = '0';
        }
        snprintf(o, HT_GLSL_FLOAT_SIZE - (size_t)(o - out), "e%s%02d", exponent < 0 ? "-" : "+",
                 abs(exponent));
    }
    return out;
}

const char *ht_glsl_vec3(const double v[3], char out[HT_GLSL_VEC3_SIZE]) {
    char a[HT_GLSL_FLOAT_SIZE], b[HT_GLSL_FLOAT_SIZE], c[HT_GLSL_FLOAT_SIZE];
    snprintf(out, HT_GLSL_VEC3_SIZE, "vec3(%s, %s, %s)", ht_glsl_float(v[0], a), ht_glsl_float(v[1], b),
             ht_glsl_float(v[2], c));
    return out;
}

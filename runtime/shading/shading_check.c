/* shading_check.c — see shading_check.h. */
#include "shading_check.h"

#include <math.h>
#include <stdio.h>

#include <hairtier/ht_limits.h>
#include "errfmt.h"

static bool field_fail(const char *file, const char *field, char *err, size_t err_size, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
static bool field_fail(const char *file, const char *field, char *err, size_t err_size, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    ht_set_field_error_v(err, err_size, file, field, fmt, ap);
    va_end(ap);
    return false;
}

/* v finite and in [lo, hi]; %.17g names the value exactly. */
static bool number_ok(const char *file, const char *field, double v, double lo, double hi, char *err,
                      size_t err_size) {
    if (!isfinite(v)) return field_fail(file, field, err, err_size, "must be a finite number, got %g", v);
    if (v < lo || v > hi) return field_fail(file, field, err, err_size, "must be in [%g, %g], got %.17g", lo, hi, v);
    return true;
}

bool ht_shading_check_color(const double color[3], const char *file, const char *parent, char *err, size_t err_size) {
    for (int i = 0; i < 3; i++) {
        char field[64];
        snprintf(field, sizeof field, "%s.color[%d]", parent, i);
        if (!number_ok(file, field, color[i], 0, 1, err, err_size)) return false;
    }
    return true;
}

static bool lobe_ok(const char *file, const char *name, const ht_lobe *l, char *err, size_t err_size) {
    char field[64];
    if (!ht_shading_check_color(l->color, file, name, err, err_size)) return false;
    snprintf(field, sizeof field, "%s.exponent", name);
    if (!number_ok(file, field, l->exponent, 0, HT_LIMIT_EXPONENT, err, err_size)) return false;
    snprintf(field, sizeof field, "%s.shift", name);
    return number_ok(file, field, l->shift, -HT_LIMIT_SHIFT, HT_LIMIT_SHIFT, err, err_size);
}

/* A transmission lobe (model.h): Scheuermann's only, so any other model
   must leave it zero. */
static bool transmission_ok(const char *file, const ht_shading *s, char *err, size_t err_size) {
    const ht_transmission *t = &s->transmission;
    const bool none = t->color[0] == 0 && t->color[1] == 0 && t->color[2] == 0 && t->centre == 0 &&
                      t->sharpness == 0 && t->azimuth == 0;
    if (s->model != HT_MODEL_SCHEUERMANN && !none)
        return field_fail(file, "transmission", err, err_size, "only model \"scheuermann\" has a transmission lobe");
    for (int i = 0; i < 3; i++) {
        char field[64];
        snprintf(field, sizeof field, "transmission.color[%d]", i);
        if (!number_ok(file, field, t->color[i], 0, HT_LIMIT_TRANSMISSION, err, err_size)) return false;
    }
    return number_ok(file, "transmission.centre", t->centre, -1, 1, err, err_size) &&
           number_ok(file, "transmission.sharpness", t->sharpness, 0, HT_LIMIT_EXPONENT, err, err_size) &&
           number_ok(file, "transmission.azimuth", t->azimuth, 0, HT_LIMIT_EXPONENT, err, err_size);
}

bool ht_shading_check(const ht_shading *s, const char *file, char *err, size_t err_size) {
    if (s->model != HT_MODEL_SCHEUERMANN && s->model != HT_MODEL_KAJIYA_KAY)
        return field_fail(file, "model", err, err_size, "unknown model %d", (int)s->model);
    return ht_shading_check_color(s->diffuse_color, file, "diffuse", err, err_size) &&
           number_ok(file, "diffuse.wrap", s->wrap, 0, 1, err, err_size) &&
           lobe_ok(file, "primary", &s->primary, err, err_size) &&
           (s->model == HT_MODEL_KAJIYA_KAY || lobe_ok(file, "secondary", &s->secondary, err, err_size)) &&
           transmission_ok(file, s, err, err_size);
}

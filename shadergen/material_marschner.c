/* material_marschner.c — the "marschner" object of a material file. */
#include "material_marschner.h"

#include <math.h>
#include <stdio.h>

#include "errfmt.h"

#define DEG (HT_PI / 180)

ht_result ht_material_parse_marschner(const ht_jctx *c, const cJSON *root, ht_marschner *out) {
    static const char *const keys[] = { "absorption", "shift", "width", "eta", NULL };
    const cJSON *obj;
    double shift_deg, width_deg;
    ht_result r = ht_json_object(c, root, "", "marschner", true, &obj);
    if (r == HT_OK) r = ht_json_keys(c, obj, "marschner", keys);
    if (r == HT_OK)
        r = ht_json_vec(c, obj, "marschner", "absorption", NULL, 3,
                        HT_JRANGE(0, HT_MARSCHNER_ABSORPTION_MAX), out->absorption);
    if (r == HT_OK)
        r = ht_json_number(c, obj, "marschner", "shift", &(double){ HT_MARSCHNER_SHIFT_DEFAULT_DEG },
                           HT_JRANGE(-HT_MARSCHNER_SHIFT_MAX_DEG, HT_MARSCHNER_SHIFT_MAX_DEG), &shift_deg);
    if (r == HT_OK)
        r = ht_json_number(c, obj, "marschner", "width", &(double){ HT_MARSCHNER_WIDTH_DEFAULT_DEG },
                           HT_JRANGE(HT_MARSCHNER_WIDTH_MIN_DEG, HT_MARSCHNER_WIDTH_MAX_DEG), &width_deg);
    if (r == HT_OK)
        r = ht_json_number(c, obj, "marschner", "eta", &(double){ HT_MARSCHNER_ETA_DEFAULT },
                           HT_JRANGE(HT_MARSCHNER_ETA_MIN, HT_MARSCHNER_ETA_MAX), &out->eta);
    if (r != HT_OK) return r;
    out->shift_r = shift_deg * DEG;
    out->width_r = width_deg * DEG;
    return HT_OK;
}

static ht_result check(const char *file, const char *field, double v, double lo, double hi,
                       double scale, char *err, size_t err_size) {
    /* The message speaks the file's units: degrees for angles. */
    double shown = v / scale;
    if (!isfinite(v)) {
        ht_set_error(err, err_size, "%s: marschner.%s: must be a finite number, got %g", file, field, v);
        return HT_ERR_INVALID_ARGUMENT;
    }
    const double slack = 1e-12 * (1 + fabs(hi)); /* degrees -> radians -> degrees rounds */
    if (shown < lo - slack || shown > hi + slack) {
        ht_set_error(err, err_size, "%s: marschner.%s: must be in [%g, %g], got %.17g", file, field, lo, hi,
                     shown);
        return HT_ERR_INVALID_ARGUMENT;
    }
    return HT_OK;
}

ht_result ht_material_check_marschner(const char *file, const ht_marschner *m, char *err,
                                      size_t err_size) {
    ht_result r = HT_OK;
    for (int i = 0; i < 3 && r == HT_OK; i++) {
        char field[32];
        snprintf(field, sizeof field, "absorption[%d]", i);
        r = check(file, field, m->absorption[i], 0, HT_MARSCHNER_ABSORPTION_MAX, 1, err, err_size);
    }
    if (r == HT_OK)
        r = check(file, "shift", m->shift_r, -HT_MARSCHNER_SHIFT_MAX_DEG, HT_MARSCHNER_SHIFT_MAX_DEG, DEG, err,
                  err_size);
    if (r == HT_OK)
        r = check(file, "width", m->width_r, HT_MARSCHNER_WIDTH_MIN_DEG, HT_MARSCHNER_WIDTH_MAX_DEG, DEG, err,
                  err_size);
    if (r == HT_OK) r = check(file, "eta", m->eta, HT_MARSCHNER_ETA_MIN, HT_MARSCHNER_ETA_MAX, 1, err, err_size);
    return r;
}

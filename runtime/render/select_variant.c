/* select_variant.c — which variant of a tier runs (select.h): exact, with
   CPU coordinates where only the CPU is exact, or device-only, by the
   manifest's measured numbers and the policy. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "errfmt.h"
#include "select.h"

ht_result ht_variant_parse(const char *text, ht_variant *out, char *err, size_t err_size) {
    *out = HT_VARIANT_AUTO;
    if (!text || !text[0]) return HT_OK;
    if (strcmp(text, "exact") == 0) *out = HT_VARIANT_EXACT;
    else if (strcmp(text, "device") == 0) *out = HT_VARIANT_DEVICE;
    else return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "variant \"%s\": expected exact or device", text);
    return HT_OK;
}

static void db_text(double db, char *out, size_t size) {
    if (isinf(db)) snprintf(out, size, "identical to the top tier");
    else snprintf(out, size, "%.2f dB", db);
}

ht_variant ht_select_variant(const ht_manifest_tier *t, const ht_policy *p, ht_variant requested, char *reason,
                             size_t reason_size) {
    if (requested != HT_VARIANT_AUTO) {
        snprintf(reason, reason_size, "%s variant requested", requested == HT_VARIANT_DEVICE ? "device" : "exact");
        return requested;
    }
    const ht_manifest_measured *e = &t->measured, *d = &t->measured_device;
    if (!e->present || !d->present) {
        snprintf(reason, reason_size, "exact: no measured device variant (hairgen --measure)");
        return HT_VARIANT_EXACT;
    }
    char de[40], dd[40];
    db_text(e->psnr_db, de, sizeof de);
    db_text(d->psnr_db, dd, sizeof dd);
    bool device;
    switch (p->kind) {
    case HT_POLICY_FASTEST:
        device = d->cost_ratio < e->cost_ratio;
        snprintf(reason, reason_size, "%s: cost %.3gx against %.3gx (fastest)", device ? "device" : "exact",
                 d->cost_ratio, e->cost_ratio);
        return device ? HT_VARIANT_DEVICE : HT_VARIANT_EXACT;
    case HT_POLICY_ERROR:
        device = d->psnr_db >= p->value || (e->psnr_db < p->value && d->psnr_db >= e->psnr_db);
        snprintf(reason, reason_size, "%s: device %s, exact %s (error:%g)", device ? "device" : "exact", dd, de,
                 p->value);
        return device ? HT_VARIANT_DEVICE : HT_VARIANT_EXACT;
    default:
        device = d->psnr_db >= e->psnr_db - HT_VARIANT_DEVICE_DB;
        snprintf(reason, reason_size, "%s: device %s, exact %s: %s %g dB", device ? "device" : "exact", dd, de,
                 device ? "within" : "more than", HT_VARIANT_DEVICE_DB);
        return device ? HT_VARIANT_DEVICE : HT_VARIANT_EXACT;
    }
}

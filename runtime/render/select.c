/* select.c — which tier of a bundle runs on a device, and why the others
   do not. Pure: see select.h. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "select.h"
#include "errfmt.h"

/* A tier without GLSL: the fixed-function tiers (fixed4, fixed, gl11). */
static bool fixed_function(const ht_manifest_tier *t) { return t->glsl_major == 0 && t->es_count == 0; }

int ht_select_es_target(const ht_caps *c, const ht_manifest_tier *t, char *why, size_t why_size) {
    if (t->es_count == 0) {
        if (fixed_function(t))
            snprintf(why, why_size, "fixed function: GL ES 2.0 and later have none (desktop GL or GL ES 1.1 "
                     "runs it)");
        else
            snprintf(why, why_size, "no GL ES target in the bundle (this tier needs desktop GL %d.%d)", t->gl_major,
                     t->gl_minor);
        return -1;
    }
    bool precision_failed = false;
    for (int i = 0; i < t->es_count; i++) {
        const ht_manifest_es *e = &t->es[i];
        if (!ht_version_at_least(c->gl_major, c->gl_minor, e->es_major, e->es_minor)) {
            if (!precision_failed)
                snprintf(why, why_size, "needs GL ES %d.%d, have %d.%d", e->es_major, e->es_minor, c->gl_major,
                         c->gl_minor);
            continue;
        }
        if (!c->has_shaders || !ht_version_at_least(c->glsl_major, c->glsl_minor, e->essl_major, e->essl_minor)) {
            if (!precision_failed)
                snprintf(why, why_size, "needs ESSL %d.%02d, have %s", e->essl_major, e->essl_minor,
                         c->has_shaders ? "less" : "no shaders");
            continue;
        }
        if (!e->mediump && !c->fragment_highp) {
            /* The reason a mediump-only device reads, whatever else failed. */
            snprintf(why, why_size, "%s needs fragment highp, the device's fragment stage has none "
                     "(glGetShaderPrecisionFormat), and the bundle has no mediump variant", e->fragment);
            precision_failed = true;
            continue;
        }
        if (t->texture_units > c->texture_units) {
            snprintf(why, why_size, "needs %d texture units, have %d", t->texture_units, c->texture_units);
            return -1;
        }
        return i;
    }
    return -1;
}

/* The extensions and units a tier lists (ES 1.1 meets the desktop names
   it made core: caps.c). */
static bool check_extensions_and_units(const ht_caps *c, const char *extensions, const ht_manifest_tier *t,
                                       char *why, size_t why_size) {
    for (int i = 0; i < t->extension_count; i++)
        if (!ht_caps_satisfies_extension(c, extensions, t->extensions[i])) {
            snprintf(why, why_size, "needs %s", t->extensions[i]);
            return false;
        }
    if (t->texture_units > c->texture_units) {
        snprintf(why, why_size, "needs %d texture units, have %d", t->texture_units, c->texture_units);
        return false;
    }
    return true;
}

/* GL ES 1.1 runs the fixed-function tiers only; the desktop GL version a
   tier names is not compared (ES 1.1 is GL 1.5 without 3D textures and the
   crossbar, which the backends check themselves). */
static bool check_es1(const ht_caps *c, const char *extensions, const ht_manifest_tier *t, char *why,
                      size_t why_size) {
    if (!fixed_function(t)) {
        snprintf(why, why_size, "shaders: GL ES 1.x has none (desktop GL 2.0 or GL ES 2.0 runs it)");
        return false;
    }
    return check_extensions_and_units(c, extensions, t, why, why_size);
}

bool ht_select_check_requirements(const ht_caps *c, const char *extensions, const ht_manifest_tier *t,
                                  char *why, size_t why_size) {
    if (ht_caps_es1(c)) return check_es1(c, extensions, t, why, why_size);
    if (c->es) return ht_select_es_target(c, t, why, why_size) >= 0;
    if (!ht_version_at_least(c->gl_major, c->gl_minor, t->gl_major, t->gl_minor)) {
        snprintf(why, why_size, "needs GL %d.%d, have %d.%d", t->gl_major, t->gl_minor, c->gl_major, c->gl_minor);
        return false;
    }
    bool glsl = t->glsl_major > 0;
    if (glsl && ht_manifest_tier_file(t, "vertex") && !(c->has_shaders && c->has_vertex_shaders)) {
        snprintf(why, why_size, "needs vertex shaders (GLSL %d.%02d), have none", t->glsl_major, t->glsl_minor);
        return false;
    }
    if (glsl && ht_manifest_tier_file(t, "fragment") && !(c->has_shaders && c->has_fragment_shaders)) {
        snprintf(why, why_size, "needs fragment shaders (GLSL %d.%02d), have %s", t->glsl_major, t->glsl_minor,
                 c->has_shaders && c->has_vertex_shaders ? "vertex shaders only" : "none");
        return false;
    }
    if (glsl && !ht_version_at_least(c->glsl_major, c->glsl_minor, t->glsl_major, t->glsl_minor)) {
        snprintf(why, why_size, "needs GLSL %d.%02d, have %d.%02d", t->glsl_major, t->glsl_minor,
                 c->glsl_major, c->glsl_minor);
        return false;
    }
    return check_extensions_and_units(c, extensions, t, why, why_size);
}

/* Why bundle tier i cannot run, or false when it can. */
static bool tier_blocked(const ht_select_desc *d, int i, char *line, size_t size) {
    const ht_manifest_tier *t = &d->bundle->tiers[i];
    char why[HT_SELECT_REASON - 24];
    if (t->tier <= HT_TIER_AUTO || t->tier >= HT_TIER_COUNT) {
        snprintf(line, size, "%s: unknown to this runtime", t->name);
        return true;
    }
    if (!ht_select_check_requirements(d->caps, d->extensions, t, why, sizeof why)) {
        snprintf(line, size, "%s: %s", t->name, why);
        return true;
    }
    if (d->failed[i]) {
        snprintf(line, size, "%s: %s", t->name, d->failed[i]);
        return true;
    }
    return false;
}

/* "NAME: why". join: a tier the API cannot run at all joins the line
   before it when that says the same ("fixed4, fixed, gl11: fixed function:
   ..."): one line for what a whole API lacks, not one per tier. */
static void add_skip_joined(ht_selection *out, const char *line, bool join) {
    const char *why = strstr(line, ": ");
    if (join && out->skipped_count > 0 && why) {
        char *prev = out->skipped[out->skipped_count - 1];
        const char *prev_why = strstr(prev, ": ");
        const size_t name = (size_t)(why - line), prev_name = prev_why ? (size_t)(prev_why - prev) : 0;
        if (prev_why && strcmp(prev_why, why) == 0 && strlen(prev) + name + 2 < sizeof out->skipped[0]) {
            memmove(prev + prev_name + 2 + name, prev + prev_name, strlen(prev_why) + 1);
            memcpy(prev + prev_name, ", ", 2);
            memcpy(prev + prev_name + 2, line, name);
            return;
        }
    }
    if (out->skipped_count < HT_MANIFEST_MAX_TIERS)
        snprintf(out->skipped[out->skipped_count++], sizeof out->skipped[0], "%s", line);
}

static void add_skip(ht_selection *out, const char *line) { add_skip_joined(out, line, false); }

/* The context's API has nothing this tier is made of: shaders on GL ES 1.x,
   fixed function on GL ES 2.0 and later. */
static bool api_lacks(const ht_caps *c, const ht_manifest_tier *t) {
    return ht_caps_es1(c) ? !fixed_function(t) : ht_caps_es_programs(c) && fixed_function(t);
}

static void join_skips(const ht_selection *s, char *out, size_t size) {
    size_t used = strlen(out);
    for (int i = 0; i < s->skipped_count && used < size; i++) {
        snprintf(out + used, size - used, "%s%s", i ? "; " : "", s->skipped[i]);
        used = strlen(out);
    }
}

/* A policy's number as a person writes it: digits, optionally a point and
   more digits. No sign (-0), space, exponent, hex or inf that strtod would
   take as well. */
static bool plain_decimal(const char *s) {
    size_t digits = strspn(s, "0123456789");
    if (digits == 0) return false;
    s += digits;
    if (*s == '.') {
        size_t frac = strspn(s + 1, "0123456789");
        if (frac == 0) return false;
        s += 1 + frac;
    }
    return *s == '\0';
}

ht_result ht_policy_parse(const char *text, ht_policy *out, char *err, size_t err_size) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    *out = (ht_policy){ HT_POLICY_BEST, 0.0 };
    if (!text || strcmp(text, "best") == 0) return HT_OK;
    if (strcmp(text, "fastest") == 0) {
        out->kind = HT_POLICY_FASTEST;
        return HT_OK;
    }
    if (strncmp(text, "error:flip:", 11) == 0) {
        const char *num = text + 11;
        char *end;
        errno = 0;
        double v = strtod(num, &end);
        if (*num && *end == '\0' && errno == 0 && v >= 0.0 && v <= 1.0) {
            *out = (ht_policy){ HT_POLICY_ERROR_FLIP, v };
            return HT_OK;
        }
        snprintf(err, err_size, "policy: \"%.40s\": error:flip: needs a FLIP mean in [0, 1], like error:flip:0.05", text);
        return HT_ERR_INVALID_ARGUMENT;
    }
    bool error = strncmp(text, "error:", 6) == 0, frame = strncmp(text, "frame:", 6) == 0;
    if (error || frame) {
        const char *num = text + 6;
        char *end;
        errno = 0;
        double v = strtod(num, &end);
        bool ok = plain_decimal(num) && *end == '\0' && errno == 0 && isfinite(v) && (error ? v >= 0.0 : v > 0.0);
        if (ok) {
            *out = (ht_policy){ error ? HT_POLICY_ERROR : HT_POLICY_FRAME, v };
            return HT_OK;
        }
        ht_set_error(err, err_size, "policy: \"%.40s\": %s", text,
                 error ? "error: needs a number of dB >= 0, like error:30" : "frame: needs a number of ms > 0, like frame:16.7");
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_set_error(err, err_size, "policy: \"%.40s\" is not best, fastest, error:DB, error:flip:E or frame:MS", text);
    return HT_ERR_INVALID_ARGUMENT;
}

/* "cost 0.4x full" or "" when the tier has no measured cost. */
static void cost_text(const ht_manifest_tier *t, char *out, size_t size) {
    if (t->measured.present) snprintf(out, size, ", cost %.2gx full", t->measured.cost_ratio);
    else out[0] = '\0';
}

static void psnr_text(double db, char *out, size_t size) {
    if (isinf(db)) snprintf(out, size, "identical to full");
    else snprintf(out, size, "%.1f dB", db);
}

static bool has_flip(const ht_manifest_measured *m) { return m->present && !isnan(m->flip_mean); }

/* error:flip:E, as error:DB with the FLIP mean (lower is better). */
static ht_result pick_by_flip(const ht_select_desc *d, const bool ok[], ht_selection *out, char *err,
                              size_t err_size) {
    const ht_manifest *b = d->bundle;
    double e = d->policy.value;
    char line[HT_SELECT_REASON], cost[48];
    bool any = false;
    for (int i = 0; i < b->tier_count; i++) any = any || has_flip(&b->tiers[i].measured);
    if (!any) {
        snprintf(err, err_size, "%s/manifest.json: policy error:flip:%g: no tier has measured FLIP numbers (hairgen "
                 "--measure writes them)", b->dir, e);
        return HT_ERR_INVALID_ARGUMENT;
    }
    int pick = -1, most_accurate = -1;
    for (int i = 0; i < b->tier_count; i++) {
        if (!ok[i]) continue;
        const ht_manifest_measured *m = &b->tiers[i].measured;
        if (!has_flip(m)) {
            snprintf(line, sizeof line, "%s: no measured FLIP (policy error:flip:%g)", b->tiers[i].name, e);
            add_skip(out, line);
            continue;
        }
        if (most_accurate < 0 || m->flip_mean < b->tiers[most_accurate].measured.flip_mean) most_accurate = i;
        if (m->flip_mean <= e && (pick < 0 || m->cost_ratio < b->tiers[pick].measured.cost_ratio)) pick = i;
    }
    if (pick >= 0) {
        cost_text(&b->tiers[pick], cost, sizeof cost);
        snprintf(out->reason, sizeof out->reason, "error:flip:%g: FLIP %.4g <= %g%s, the cheapest that runs and "
                 "reaches it", e, b->tiers[pick].measured.flip_mean, e, cost);
    } else if (most_accurate >= 0) {
        pick = most_accurate;
        cost_text(&b->tiers[pick], cost, sizeof cost);
        snprintf(out->reason, sizeof out->reason, "error:flip:%g: no tier that runs is within %g; the most accurate: "
                 "FLIP %.4g%s", e, e, b->tiers[pick].measured.flip_mean, cost);
    } else {
        snprintf(err, err_size, "%s/manifest.json: policy error:flip:%g: no tier that runs here has measured FLIP "
                 "numbers", b->dir, e);
        return HT_ERR_INVALID_ARGUMENT;
    }
    out->index = pick;
    return HT_OK;
}

/* The policy's pick among the tiers that run (ok[i]); HT_OK with out->index
   and out->reason set. */
static ht_result pick_by_policy(const ht_select_desc *d, const bool ok[], ht_selection *out, char *err,
                                size_t err_size) {
    const ht_manifest *b = d->bundle;
    const ht_policy *p = &d->policy;
    char line[HT_SELECT_REASON], cost[48], db[32];
    int first = -1, last = -1;
    for (int i = 0; i < b->tier_count; i++)
        if (ok[i]) {
            if (first < 0) first = i;
            last = i;
        }
    switch (p->kind) {
    case HT_POLICY_FASTEST: {
        int pick = -1;
        bool all_measured = true;
        for (int i = 0; i < b->tier_count; i++)
            if (ok[i] && !b->tiers[i].measured.present) all_measured = false;
        if (all_measured) {
            for (int i = 0; i < b->tier_count; i++)
                if (ok[i] && (pick < 0 || b->tiers[i].measured.cost_ratio < b->tiers[pick].measured.cost_ratio))
                    pick = i;
            cost_text(&b->tiers[pick], cost, sizeof cost);
            snprintf(out->reason, sizeof out->reason, "fastest: the least measured cost of the tiers that run%s", cost);
        } else {
            pick = last;
            snprintf(out->reason, sizeof out->reason,
                     "fastest: the cheapest that runs, by the bundle's order (not every tier that runs is measured)");
        }
        out->index = pick;
        return HT_OK;
    }
    case HT_POLICY_ERROR: {
        bool any = false;
        for (int i = 0; i < b->tier_count; i++) any = any || b->tiers[i].measured.present;
        if (!any) {
            ht_set_error(err, err_size, "%s/manifest.json: policy error:%g: no tier has measured numbers (hairgen --measure writes them)",
                     b->dir, p->value);
            return HT_ERR_INVALID_ARGUMENT;
        }
        int pick = -1, most_accurate = -1;
        for (int i = 0; i < b->tier_count; i++) {
            if (!ok[i]) continue;
            const ht_manifest_measured *m = &b->tiers[i].measured;
            if (!m->present) {
                snprintf(line, sizeof line, "%s: no measured numbers (policy error:%g)", b->tiers[i].name, p->value);
                add_skip(out, line);
                continue;
            }
            if (most_accurate < 0 || m->psnr_db > b->tiers[most_accurate].measured.psnr_db) most_accurate = i;
            if (m->psnr_db >= p->value && (pick < 0 || m->cost_ratio < b->tiers[pick].measured.cost_ratio)) pick = i;
        }
        if (pick >= 0) {
            psnr_text(b->tiers[pick].measured.psnr_db, db, sizeof db);
            cost_text(&b->tiers[pick], cost, sizeof cost);
            snprintf(out->reason, sizeof out->reason, "error:%g: %s >= %g dB%s, the cheapest that runs and reaches it",
                     p->value, db, p->value, cost);
        } else if (most_accurate >= 0) {
            pick = most_accurate;
            psnr_text(b->tiers[pick].measured.psnr_db, db, sizeof db);
            cost_text(&b->tiers[pick], cost, sizeof cost);
            snprintf(out->reason, sizeof out->reason, "error:%g: no tier that runs reaches %g dB; the most accurate: %s%s",
                     p->value, p->value, db, cost);
        } else {
            ht_set_error(err, err_size, "%s/manifest.json: policy error:%g: no tier that runs here has measured numbers",
                     b->dir, p->value);
            return HT_ERR_INVALID_ARGUMENT;
        }
        out->index = pick;
        return HT_OK;
    }
    case HT_POLICY_ERROR_FLIP:
        return pick_by_flip(d, ok, out, err, err_size);
    case HT_POLICY_FRAME: {
        int pick = -1, fastest = -1;
        for (int i = 0; i < b->tier_count; i++) {
            double ms = d->frame_ms[i];
            if (!ok[i] || !(ms > 0.0) || !isfinite(ms)) continue;
            if (fastest < 0 || ms < d->frame_ms[fastest]) fastest = i;
            if (pick < 0 && ms <= p->value) pick = i;
        }
        if (pick >= 0) {
            snprintf(out->reason, sizeof out->reason, "frame:%g: %.2f ms <= %g ms, the best that runs within budget",
                     p->value, d->frame_ms[pick], p->value);
        } else if (fastest >= 0) {
            pick = fastest;
            snprintf(out->reason, sizeof out->reason, "frame:%g: no tier within %g ms; the fastest timed: %.2f ms",
                     p->value, p->value, d->frame_ms[pick]);
        } else {
            pick = first;
            snprintf(out->reason, sizeof out->reason,
                     "frame:%g: not timed yet, best supported (ht_renderer_choose_by_frame_time times the tiers)", p->value);
        }
        out->index = pick;
        return HT_OK;
    }
    case HT_POLICY_BEST:
    default:
        out->index = first;
        snprintf(out->reason, sizeof out->reason, "best supported");
        return HT_OK;
    }
}

ht_result ht_select_tier(const ht_select_desc *d, ht_selection *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->index = -1;
    out->tier = HT_TIER_COUNT;
    out->forced = HT_TIER_AUTO;
    if (!d || !d->caps || !d->bundle) {
        ht_set_error(err, err_size, "select: caps and bundle are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    const ht_manifest *b = d->bundle;
    const char *source = NULL;
    if (d->requested != HT_TIER_AUTO) {
        if (d->requested < 0 || d->requested >= HT_TIER_COUNT) {
            ht_set_error(err, err_size, "ht_renderer_desc: tier: %d is not a tier", (int)d->requested);
            return HT_ERR_INVALID_ARGUMENT;
        }
        out->forced = d->requested;
        source = "desc.tier";
    } else if (d->env_tier && d->env_tier[0]) {
        ht_tier t = ht_tier_from_name(d->env_tier);
        if (t == HT_TIER_COUNT) {
            ht_set_error(err, err_size, "HAIRTIER_TIER: \"%.40s\" is not auto, marschner, full, vertex, fixed4, fixed or gl11", d->env_tier);
            return HT_ERR_INVALID_ARGUMENT;
        }
        out->forced = t;
        if (t != HT_TIER_AUTO) source = "HAIRTIER_TIER";
    }

    int start = 0;
    char line[HT_SELECT_REASON];
    if (out->forced != HT_TIER_AUTO) {
        /* Start at the forced tier; when the bundle lacks it, at the first
           cheaper one (tiers rank in enum order). */
        start = b->tier_count;
        for (int i = 0; i < b->tier_count; i++)
            if (b->tiers[i].tier == out->forced) { start = i; break; }
        if (start == b->tier_count) {
            snprintf(line, sizeof line, "%s: not in this bundle", ht_tier_name(out->forced));
            add_skip(out, line);
            if (d->strict) {
                ht_set_error(err, err_size, "%s (forced by %s, strict)", line, source);
                return HT_ERR_UNSUPPORTED;
            }
            for (int i = 0; i < b->tier_count; i++)
                if (b->tiers[i].tier > out->forced && b->tiers[i].tier < HT_TIER_COUNT) { start = i; break; }
        }
    }

    if (out->forced == HT_TIER_AUTO) {
        bool ok[HT_MANIFEST_MAX_TIERS] = { false };
        bool any = false;
        for (int i = 0; i < b->tier_count; i++) {
            if (tier_blocked(d, i, line, sizeof line)) add_skip_joined(out, line, api_lacks(d->caps, &b->tiers[i]));
            else ok[i] = any = true;
        }
        if (any) {
            ht_result r = pick_by_policy(d, ok, out, err, err_size);
            if (r != HT_OK) {
                out->index = -1;
                return r;
            }
            out->tier = b->tiers[out->index].tier;
            if (out->skipped_count) {
                snprintf(out->reason + strlen(out->reason), sizeof out->reason - strlen(out->reason), "; skipped ");
                join_skips(out, out->reason, sizeof out->reason);
            }
            return HT_OK;
        }
        start = b->tier_count;
    }

    for (int i = start; i < b->tier_count; i++) {
        if (tier_blocked(d, i, line, sizeof line)) {
            add_skip(out, line);
            if (out->forced != HT_TIER_AUTO && d->strict) {
                ht_set_error(err, err_size, "%s (forced by %s, strict)", line, source);
                return HT_ERR_UNSUPPORTED;
            }
            continue;
        }
        out->index = i;
        out->tier = b->tiers[i].tier;
        if (out->tier == out->forced) {
            snprintf(out->reason, sizeof out->reason, "forced by %s", source);
        } else {
            snprintf(out->reason, sizeof out->reason, "%s forced by %s could not run, fell back; ",
                     ht_tier_name(out->forced), source);
            join_skips(out, out->reason, sizeof out->reason);
        }
        return HT_OK;
    }
    ht_set_error(err, err_size, "%s/manifest.json: tiers: none runs here: ", b->dir);
    join_skips(out, err, err_size);
    return HT_ERR_NO_TIER;
}

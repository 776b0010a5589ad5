/* select.c — which tier of a bundle runs on a device, and why the others
   do not. Pure: see select.h. */
#include <stdio.h>
#include <string.h>

#include "select.h"

bool ht_select_check_requirements(const ht_caps *c, const char *extensions, const ht_manifest_tier *t,
                                  char *why, size_t why_size) {
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

static void add_skip(ht_selection *out, const char *line) {
    if (out->skipped_count < HT_MANIFEST_MAX_TIERS)
        snprintf(out->skipped[out->skipped_count++], sizeof out->skipped[0], "%s", line);
}

static void join_skips(const ht_selection *s, char *out, size_t size) {
    size_t used = strlen(out);
    for (int i = 0; i < s->skipped_count && used < size; i++) {
        snprintf(out + used, size - used, "%s%s", i ? "; " : "", s->skipped[i]);
        used = strlen(out);
    }
}

ht_result ht_select_tier(const ht_select_desc *d, ht_selection *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->index = -1;
    out->tier = HT_TIER_COUNT;
    out->forced = HT_TIER_AUTO;
    if (!d || !d->caps || !d->bundle) {
        snprintf(err, err_size, "select: caps and bundle are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    const ht_manifest *b = d->bundle;
    const char *source = NULL;
    if (d->requested != HT_TIER_AUTO) {
        if (d->requested < 0 || d->requested >= HT_TIER_COUNT) {
            snprintf(err, err_size, "ht_renderer_desc: tier: %d is not a tier", (int)d->requested);
            return HT_ERR_INVALID_ARGUMENT;
        }
        out->forced = d->requested;
        source = "desc.tier";
    } else if (d->env_tier && d->env_tier[0]) {
        ht_tier t = ht_tier_from_name(d->env_tier);
        if (t == HT_TIER_COUNT) {
            snprintf(err, err_size, "HAIRTIER_TIER: \"%.40s\" is not auto, full, vertex, fixed4, fixed or gl11", d->env_tier);
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
                snprintf(err, err_size, "%s (forced by %s, strict)", line, source);
                return HT_ERR_UNSUPPORTED;
            }
            for (int i = 0; i < b->tier_count; i++)
                if (b->tiers[i].tier > out->forced && b->tiers[i].tier < HT_TIER_COUNT) { start = i; break; }
        }
    }

    for (int i = start; i < b->tier_count; i++) {
        if (tier_blocked(d, i, line, sizeof line)) {
            add_skip(out, line);
            if (out->forced != HT_TIER_AUTO && d->strict) {
                snprintf(err, err_size, "%s (forced by %s, strict)", line, source);
                return HT_ERR_UNSUPPORTED;
            }
            continue;
        }
        out->index = i;
        out->tier = b->tiers[i].tier;
        if (out->forced == HT_TIER_AUTO) {
            snprintf(out->reason, sizeof out->reason, "best supported");
            if (out->skipped_count) {
                snprintf(out->reason + strlen(out->reason), sizeof out->reason - strlen(out->reason), "; skipped ");
                join_skips(out, out->reason, sizeof out->reason);
            }
        } else if (out->tier == out->forced) {
            snprintf(out->reason, sizeof out->reason, "forced by %s", source);
        } else {
            snprintf(out->reason, sizeof out->reason, "%s forced by %s could not run, fell back; ",
                     ht_tier_name(out->forced), source);
            join_skips(out, out->reason, sizeof out->reason);
        }
        return HT_OK;
    }
    snprintf(err, err_size, "%s/manifest.json: tiers: none runs here: ", b->dir);
    join_skips(out, err, err_size);
    return HT_ERR_NO_TIER;
}

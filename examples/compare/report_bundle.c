/* report_bundle.c — what the report shows of a bundle's manifest: tier
   names, requirements and measured numbers (runtime/io/manifest.h reads
   and checks them), and
   the free-text lists the runtime does not keep, each tier's "dropped" and
   the root's "notes", read here through json_check.h. */
#include <stdlib.h>
#include <string.h>

#include "json_check.h"
#include "manifest.h"
#include "report.h"

static void describe_needs(const ht_manifest_tier *t, char *out, size_t size) {
    int n = snprintf(out, size, "GL %d.%d", t->gl_major, t->gl_minor);
    if (t->glsl_major && n < (int)size) n += snprintf(out + n, size - n, ", GLSL %d.%02d", t->glsl_major, t->glsl_minor);
    for (int e = 0; e < t->extension_count && n < (int)size; e++) n += snprintf(out + n, size - n, ", %s", t->extensions[e]);
    if (t->texture_units && n < (int)size)
        snprintf(out + n, size - n, ", %d texture unit%s", t->texture_units, t->texture_units == 1 ? "" : "s");
}

/* The strings of array `key` of obj (absent: none) into out, malloc'd. */
static ht_result read_strings(const ht_jctx *c, const cJSON *obj, const char *path, const char *key, int max,
                              char **out, int *count) {
    const cJSON *arr;
    int items;
    ht_result r = ht_json_array(c, obj, path, key, false, 0, max, &arr, &items);
    if (r != HT_OK || !arr) return r;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, key);
    for (const cJSON *s = arr->child; s; s = s->next) {
        char item[HT_JSON_PATH_MAX];
        ht_json_path_index(item, field, *count);
        if (!cJSON_IsString(s)) return ht_json_fail(c, item, "expected a string");
        if (!(out[*count] = strdup(s->valuestring))) return ht_json_fail(c, item, "out of memory");
        (*count)++;
    }
    return HT_OK;
}

ht_result report_read_bundle(report *r, const char *bundle, char *err, size_t err_size) {
    ht_manifest *m = malloc(sizeof *m);
    if (!m) {
        snprintf(err, err_size, "%s: out of memory reading the manifest", bundle);
        return HT_ERR_OUT_OF_MEMORY;
    }
    ht_result res = ht_manifest_load(bundle, m, err, err_size);
    if (res == HT_OK && m->tier_count > REPORT_MAX_TIERS) {
        snprintf(err, err_size, "%s/" HT_MANIFEST_FILE ": tiers: %d listed, a report shows at most %d", bundle,
                 m->tier_count, REPORT_MAX_TIERS);
        res = HT_ERR_UNSUPPORTED;
    }
    if (res != HT_OK) {
        free(m);
        return res;
    }
    snprintf(r->material, sizeof r->material, "%s", m->material);
    r->tier_count = m->tier_count;
    for (int t = 0; t < m->tier_count; t++) {
        report_tier *p = &r->tiers[t];
        snprintf(p->name, sizeof p->name, "%s", m->tiers[t].name);
        describe_needs(&m->tiers[t], p->needs, sizeof p->needs);
        p->tier = m->tiers[t].tier;
        p->known = p->tier != HT_TIER_COUNT;
        p->measured = m->tiers[t].measured;
    }
    r->measured_lods = m->lods;
    free(m);

    /* The manifest was read and checked above: only the lists are new here. */
    char path[HT_LIMIT_BUNDLE_FILE_PATH], *text = NULL;
    snprintf(path, sizeof path, "%s/" HT_MANIFEST_FILE, bundle);
    ht_jctx c = { .file = path, .err = err, .err_size = err_size };
    cJSON *root = NULL;
    if ((res = ht_json_read_file(path, &text, err, err_size)) != HT_OK ||
        (res = ht_json_parse_root(&c, text, &root)) != HT_OK ||
        (res = read_strings(&c, root, "", HT_MANIFEST_KEY_NOTES, REPORT_MAX_NOTES, r->notes, &r->note_count)) != HT_OK)
        goto done;
    const cJSON *tiers = cJSON_GetObjectItemCaseSensitive(root, HT_MANIFEST_KEY_TIERS);
    int t = 0;
    for (const cJSON *e = tiers ? tiers->child : NULL; e && t < r->tier_count; e = e->next, t++) {
        char base[HT_JSON_PATH_MAX];
        ht_json_path_index(base, HT_MANIFEST_KEY_TIERS, t);
        if ((res = read_strings(&c, e, base, HT_MANIFEST_KEY_DROPPED, REPORT_MAX_DROPPED, r->tiers[t].dropped,
                                &r->tiers[t].dropped_count)) != HT_OK)
            goto done;
    }
done:
    cJSON_Delete(root);
    free(text);
    return res;
}

/* manifest_lods.c — the manifest's optional "lods" object (manifest.h):
   every tier's measured cost and error at each geometry LOD and projected
   size against (LOD 0, the reference tier), which the error:DB and
   frame:MS rules for (LOD, tier) pairs read
   (include/hairtier/lod.h, ht_lod_pick_error). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include <cJSON.h>

#include <hairtier/lod.h>
#include "json_check.h"
#include "manifest.h"

#define K(name) HT_MANIFEST_KEY_##name

/* A PSNR: null is infinite (identical; no level before). */
static ht_result psnr(const ht_jctx *c, const cJSON *cell, const char *path, const char *key, double *out) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(cell, key);
    if (cJSON_IsNull(v)) {
        *out = INFINITY;
        return HT_OK;
    }
    return ht_json_number(c, cell, path, key, NULL, HT_JRANGE(0, HT_MANIFEST_MAX_PSNR_DB), out);
}

/* "soften" (optional): a strand level past 0 drawn soft (lod.h); level 0
   is full detail and cards are not soft. */
static ht_result soften(const ht_jctx *c, const cJSON *cell, const char *path, ht_manifest_lod_cell *out) {
    out->soften = 0.0f;
    if (!cJSON_GetObjectItemCaseSensitive(cell, K(SOFTEN))) return HT_OK;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, K(SOFTEN));
    ht_result r = ht_json_float(c, cell, path, K(SOFTEN), NULL, HT_JRANGE_LO_OPEN(1, HT_LOD_MAX_SOFTEN), &out->soften);
    if (r == HT_OK && out->level == 0) return ht_json_fail(c, field, "level 0 (full detail) is never soft");
    if (r == HT_OK && out->cards) return ht_json_fail(c, field, "a cards level is not soft");
    return r;
}

static ht_result parse_cell(const ht_jctx *c, const cJSON *cell, const char *path, const char *lods_tier,
                            ht_manifest_lod_cell *out) {
    static const char *const known[] = { K(LEVEL), K(LOD_TIER), K(STRANDS), K(SIZE), K(PSNR_DB), K(SSIM),
                                         K(DELTA_E00_MEAN), K(COST_RATIO), K(POP_PSNR_DB), K(LOD_KIND),
                                         K(SOFTEN), NULL };
    int64_t strands = 0;
    ht_result r = ht_json_keys(c, cell, path, known);
    if (r == HT_OK) r = ht_json_int32(c, cell, path, K(LEVEL), NULL, 0, HT_LOD_FILE_MAX_LEVELS - 1, &out->level);
    static const char *const kinds[] = { "strands", "cards", NULL };
    if (r == HT_OK) r = ht_json_enum(c, cell, path, K(LOD_KIND), 0, kinds, &out->cards);
    /* A cell of the one-tier format has no "tier": the lods' own. */
    const size_t n = strnlen(lods_tier, sizeof out->tier - 1);
    memcpy(out->tier, lods_tier, n);
    out->tier[n] = '\0';
    if (r == HT_OK && cJSON_GetObjectItemCaseSensitive(cell, K(LOD_TIER)))
        r = ht_json_string(c, cell, path, K(LOD_TIER), NULL, out->tier, sizeof out->tier);
    if (r == HT_OK) r = ht_json_int(c, cell, path, K(STRANDS), NULL, 1, UINT32_MAX, &strands);
    if (r == HT_OK) r = ht_json_number(c, cell, path, K(SIZE), NULL, HT_JRANGE_LO_OPEN(0, 4), &out->size);
    if (r == HT_OK) r = psnr(c, cell, path, K(PSNR_DB), &out->psnr_db);
    if (r == HT_OK) r = ht_json_number(c, cell, path, K(SSIM), NULL, HT_JRANGE(-1, 1), &out->ssim);
    if (r == HT_OK)
        r = ht_json_number(c, cell, path, K(DELTA_E00_MEAN), NULL, HT_JRANGE(0, HT_MANIFEST_MAX_DELTA_E),
                           &out->delta_e00_mean);
    if (r == HT_OK)
        r = ht_json_number(c, cell, path, K(COST_RATIO), NULL, HT_JRANGE_LO_OPEN(0, HT_MANIFEST_MAX_COST_RATIO),
                           &out->cost_ratio);
    if (r == HT_OK) r = psnr(c, cell, path, K(POP_PSNR_DB), &out->pop_psnr_db);
    if (r == HT_OK) r = soften(c, cell, path, out);
    out->strands = (uint32_t)strands;
    return r;
}

ht_result ht_manifest_parse_lods(const ht_jctx *c, const cJSON *root, ht_manifest_lods *out) {
    static const char *const known[] = { K(LOD_TIER), K(CELLS), K(SCENE), K(DRIVER), K(SAMPLES), K(LOD_REFERENCE), NULL };
    static const char *const references[] = HT_LOD_REFERENCE_NAMES;
    memset(out, 0, sizeof *out);
    const cJSON *lods, *cells;
    int count = 0;
    ht_result r = ht_json_object(c, root, "", K(LODS), false, &lods);
    if (r != HT_OK || !lods) return r;
    if ((r = ht_json_keys(c, lods, K(LODS), known)) != HT_OK ||
        (r = ht_json_string(c, lods, K(LODS), K(LOD_TIER), NULL, out->tier, sizeof out->tier)) != HT_OK ||
        (r = ht_json_array(c, lods, K(LODS), K(CELLS), true, 1, HT_MANIFEST_MAX_LOD_CELLS, &cells, &count)) != HT_OK)
        return r;
    if (cJSON_GetObjectItemCaseSensitive(lods, K(SAMPLES)) &&
        (r = ht_json_int32(c, lods, K(LODS), K(SAMPLES), NULL, 2, HT_MANIFEST_MAX_LOD_SAMPLES, &out->samples)) != HT_OK)
        return r;
    int reference = HT_LOD_REFERENCE_SAMPLES;
    if ((r = ht_json_enum(c, lods, K(LODS), K(LOD_REFERENCE), HT_LOD_REFERENCE_SAMPLES, references, &reference)) != HT_OK)
        return r;
    out->reference = (ht_lod_reference)reference;
    for (const cJSON *cell = cells->child; cell && r == HT_OK; cell = cell->next) {
        char path[HT_JSON_PATH_MAX];
        ht_json_path_index(path, K(LODS) "." K(CELLS), out->cell_count);
        r = parse_cell(c, cell, path, out->tier, &out->cells[out->cell_count]);
        if (r == HT_OK) out->cell_count++;
    }
    if (r != HT_OK) memset(out, 0, sizeof *out);
    return r;
}

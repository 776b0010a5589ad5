/* renderer_lod.c — the bundle's measured LOD cells (manifest "lods",
   hairgen --measure-lods) handed to the application as ht_lod_cell, for
   ht_lod_pick_error; the width rule's opacity scale (lod.h). */
#include <hairtier/lod.h>
#include "caps.h"
#include "renderer_internal.h"

int ht_renderer_lod_cells(const ht_renderer *r, ht_lod_cell *out, int max) {
    if (!r || !r->have_bundle || !out || max <= 0) return 0;
    const ht_manifest_lods *l = &r->bundle.lods;
    int n = 0;
    for (int i = 0; i < l->cell_count && n < max; i++) {
        const ht_tier tier = ht_tier_from_name(l->cells[i].tier);
        if (tier == HT_TIER_COUNT) continue; /* a tier this runtime does not know */
        out[n++] = (ht_lod_cell){ .lod = l->cells[i].level, .tier = tier, .size = l->cells[i].size,
                                  .psnr = l->cells[i].psnr_db, .cost = l->cells[i].cost_ratio,
                                  .soften = l->cells[i].soften };
    }
    return n;
}

bool ht_renderer_lod_cells_width_rule(const ht_renderer *r) {
    return r && r->have_bundle && r->bundle.lods.cell_count > 0 &&
           r->bundle.lods.reference == HT_LOD_REFERENCE_SUPERSAMPLE;
}

void ht_renderer_set_width_rule(ht_renderer *r, bool per_vertex) {
    if (r) r->width_vertex = per_vertex;
}

void ht_renderer_set_back_to_front(ht_renderer *r, bool on) {
    if (r) r->back_to_front = on;
}

bool ht_renderer_width_rule_per_vertex(const ht_renderer *r) { return r && ht_renderer_width_rule_active(r); }

int ht_renderer_samples(const ht_renderer *r) {
    if (!r || !(r->caps.es || ht_caps_gl_at_least(&r->caps, 1, 3))) return 1;
    GLint samples = 0;
    r->gl.GetIntegerv(GL_SAMPLES, &samples);
    return samples > 1 ? (int)samples : 1;
}

ht_result ht_renderer_set_opacity_scale(ht_renderer *r, float scale) {
    if (!r || !(scale > 0.0f && scale <= 1.0f)) return HT_ERR_INVALID_ARGUMENT;
    r->opacity_cut = 1.0f - scale;
    return HT_OK;
}

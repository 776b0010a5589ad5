/* select_lod.c — which geometry LOD (and, with measured cells, which
   (LOD, tier) pair) draws at a projected size: pure functions, lod.h says
   the rules. Hysteresis lives here and nowhere else. */
#include <math.h>
#include <stdbool.h>

#include <hairtier/lod.h>

double ht_projected_width_px(double width, double distance, double fov_y_deg, int viewport_h) {
    if (!(width > 0) || !(distance > 0) || !(fov_y_deg > 0 && fov_y_deg < 180) || viewport_h <= 0) return 0;
    return width * viewport_h / (2.0 * distance * tan(fov_y_deg * M_PI / 360.0));
}

double ht_mesh_projected_width_px(const ht_mesh *mesh, const ht_camera *camera, int viewport_h) {
    if (!mesh || !camera) return 0;
    double d = 0;
    for (int k = 0; k < 3; k++) d += ((double)camera->eye[k] - camera->target[k]) * (camera->eye[k] - camera->target[k]);
    return ht_projected_width_px(ht_mesh_mean_width(mesh), sqrt(d), camera->fov_y, viewport_h);
}

double ht_width_rule_widen(double strand_px) {
    if (!(strand_px > 0) || strand_px >= 1.0 || !isfinite(strand_px)) return 1.0;
    const double quarters = ceil(4.0 * -log2(strand_px) - 1e-9);
    return fmin(exp2(quarters / 4.0), HT_LOD_MAX_WIDEN);
}

bool ht_width_rule_applies(double strand_px, int samples) {
    return strand_px > 0 && strand_px * sqrt(sqrt(samples > 1 ? (double)samples : 1.0)) < HT_WIDTH_RULE_VERTEX_PX;
}

int ht_lod_pick_best(double strand_px, int current, int max_level) {
    if (max_level < 0) max_level = 0;
    /* The ideal level as a real number: log2 of how many times too thin. */
    const double ideal = strand_px > 0 && isfinite(strand_px) ? -log2(strand_px) : max_level;
    int target = (int)ceil(ideal - 1e-9);
    if (target < 0) target = 0;
    if (target > max_level) target = max_level;
    if (current < 0 || current > max_level) return target;
    /* Level c serves ideal in (c - 1, c] (level 0: any ideal <= 0, the last
       level: any above); it stays while ideal is within the band widened. */
    const double lo = current == 0 ? -INFINITY : current - 1 - HT_LOD_HYSTERESIS;
    const double hi = current == max_level ? INFINITY : current + HT_LOD_HYSTERESIS;
    return ideal > lo && ideal <= hi ? current : target;
}

bool ht_lod_cell_same_pair(const ht_lod_cell *a, const ht_lod_cell *b) {
    return a->lod == b->lod && a->tier == b->tier && (a->soften > 1.0f) == (b->soften > 1.0f) &&
           (a->soften <= 1.0f || a->soften == b->soften);
}

static double size_distance(double a, double b) { return fabs(log2(a) - log2(b)); }

/* The measured size nearest `size` (in log2): the rules compare cells there only. */
static double nearest_size(const ht_lod_cell *cells, int count, double size) {
    double nearest = cells[0].size;
    for (int i = 1; i < count; i++)
        if (cells[i].size > 0 && size_distance(cells[i].size, size) < size_distance(nearest, size)) nearest = cells[i].size;
    return nearest;
}

/* The cell at `size` holding the same pair as cells[current] (level, tier
   and soft or plain); -1: none. */
static int held_pair(const ht_lod_cell *cells, int count, double size, int current) {
    if (current < 0 || current >= count) return -1;
    for (int i = 0; i < count; i++)
        if (cells[i].size == size && ht_lod_cell_same_pair(&cells[i], &cells[current])) return i;
    return -1;
}

int ht_lod_pick_error(const ht_lod_cell *cells, int count, double size, double db, int current) {
    if (!cells || count <= 0 || !(size > 0)) return -1;
    const double nearest = nearest_size(cells, count, size);
    int best = -1, most_accurate = -1;
    const int held = held_pair(cells, count, nearest, current);
    for (int i = 0; i < count; i++) {
        if (cells[i].size != nearest) continue;
        if (most_accurate < 0 || cells[i].psnr > cells[most_accurate].psnr) most_accurate = i;
        if (cells[i].psnr >= db && (best < 0 || cells[i].cost < cells[best].cost)) best = i;
    }
    if (best < 0) return most_accurate;
    /* Hysteresis: the pair in use stays while it meets the budget and no
       cheaper pair meets it with a margin. */
    if (held >= 0 && cells[held].psnr >= db) {
        int cheaper = -1;
        for (int i = 0; i < count; i++)
            if (cells[i].size == nearest && cells[i].psnr >= db + HT_LOD_ERROR_HYSTERESIS_DB &&
                cells[i].cost < cells[held].cost && (cheaper < 0 || cells[i].cost < cells[cheaper].cost))
                cheaper = i;
        return cheaper >= 0 ? cheaper : held;
    }
    return best;
}

/* a more accurate than b; equal PSNR: the cheaper */
static bool better(const ht_lod_cell *a, const ht_lod_cell *b) {
    return a->psnr > b->psnr || (a->psnr == b->psnr && a->cost < b->cost);
}

double ht_lod_rule_reference_ms(const ht_lod_rule *rule, double size) {
    if (!rule) return 0;
    for (int i = 0; rule->reference_frames && i < rule->reference_frame_count; i++) {
        const ht_lod_reference_frame *f = &rule->reference_frames[i];
        if (f->size == size && f->ms > 0) return f->ms;
    }
    return rule->reference_ms;
}

int ht_lod_pick_frame(const ht_lod_cell *cells, int count, double size, double budget_ms, double reference_ms,
                      int current) {
    if (!cells || count <= 0 || !(size > 0) || !(reference_ms > 0) || !(budget_ms > 0)) return -1;
    const double nearest = nearest_size(cells, count, size);
    int best = -1, cheapest = -1;
    for (int i = 0; i < count; i++) {
        if (cells[i].size != nearest) continue;
        if (cheapest < 0 || cells[i].cost < cells[cheapest].cost) cheapest = i;
        if (cells[i].cost * reference_ms <= budget_ms && (best < 0 || better(&cells[i], &cells[best]))) best = i;
    }
    const int held = held_pair(cells, count, nearest, current);
    /* Hysteresis: the pair in use stays while it is near the budget and no
       pair within it is more accurate by the margin. */
    if (held >= 0 && cells[held].cost * reference_ms <= budget_ms * (1 + HT_LOD_FRAME_HYSTERESIS) &&
        (best < 0 || cells[best].psnr < cells[held].psnr + HT_LOD_ERROR_HYSTERESIS_DB))
        return held;
    return best >= 0 ? best : cheapest;
}

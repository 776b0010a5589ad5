/* support_lod_bound.c — lods.bin's quantization bounds (support_lod_bound.h). */
#include "support_lod_bound.h"

#include <float.h>
#include <math.h>
#include <stdio.h>

#include <hairtier/lod.h>

double ht_test_angle(const float a[3], const float b[3]) {
    const double c[3] = { (double)a[1] * b[2] - (double)a[2] * b[1], (double)a[2] * b[0] - (double)a[0] * b[2],
                          (double)a[0] * b[1] - (double)a[1] * b[0] };
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                 (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]);
}

static double unit_error(const float a[3]) {
    return fabs(sqrt((double)a[0] * a[0] + (double)a[1] * a[1] + (double)a[2] * a[2]) - 1);
}

static void axes(const ht_vertex *v, float out[6]) {
    const float x[6] = { v->position[0], v->position[1], v->position[2], v->uv[0], v->uv[1], v->ao };
    for (int k = 0; k < 6; k++) out[k] = x[k];
}

bool ht_test_lod_within_bound(const ht_vertex *got, const ht_vertex *want, uint32_t n, const ht_vertex *all,
                              uint32_t all_count, char *why, size_t why_size) {
    float lo[6], hi[6], x[6];
    for (int k = 0; k < 6; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t v = 0; v < all_count; v++) {
        axes(&all[v], x);
        for (int k = 0; k < 6; k++) lo[k] = fminf(lo[k], x[k]), hi[k] = fmaxf(hi[k], x[k]);
    }
    double worst_pos = 0, worst_tex = 0, worst_dir = 0, worst_unit = 0;
    for (uint32_t v = 0; v < n; v++) {
        float g[6], w[6];
        axes(&got[v], g);
        axes(&want[v], w);
        for (int k = 0; k < 6; k++) {
            const double extent = hi[k] > lo[k] ? hi[k] - lo[k] : 1;
            const double step = extent * (k < 3 ? HT_LOD_FILE_POSITION_ERROR : HT_LOD_FILE_ATTRIBUTE_ERROR);
            const double err = fabs((double)g[k] - w[k]), ulp = fabs(w[k]) * FLT_EPSILON;
            if (err > step * 1.0001 + ulp) {
                snprintf(why, why_size, "vertex %u axis %d: %g off, the bound is %g", v, k, err, step);
                return false;
            }
            if (k < 3) worst_pos = fmax(worst_pos, err / extent);
            else worst_tex = fmax(worst_tex, err / extent);
        }
        const double dir = fmax(ht_test_angle(got[v].normal, want[v].normal), ht_test_angle(got[v].tangent, want[v].tangent));
        const double unit = fmax(unit_error(got[v].normal), unit_error(got[v].tangent));
        if (dir > HT_LOD_FILE_DIRECTION_ERROR || unit > 4 * FLT_EPSILON) {
            snprintf(why, why_size, "vertex %u: normal or tangent %g rad off, |n| - 1 %g", v, dir, unit);
            return false;
        }
        worst_dir = fmax(worst_dir, dir);
        worst_unit = fmax(worst_unit, unit);
    }
    snprintf(why, why_size, "%u vertices: position %.3g, uv/ao %.3g of the box, directions %.3g rad, |n| - 1 %.2g", n,
             worst_pos, worst_tex, worst_dir, worst_unit);
    return true;
}

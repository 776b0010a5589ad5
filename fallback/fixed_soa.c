/* fixed_soa.c — see fixed_soa.h. */
#include "fixed_soa.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vecmath.h"

void ht_fixed_soa_free(ht_fixed_soa *s) {
    free(s->px);
    free(s->py);
    free(s->pz);
    for (int j = 0; j < 3; j++) {
        free(s->a[j]);
        free(s->b[j]);
        free(s->c[j]);
    }
    memset(s, 0, sizeof *s);
}

static void store(float *const dst[3], size_t i, const double v[3]) {
    for (int j = 0; j < 3; j++) dst[j][i] = (float)v[j];
}

ht_result ht_fixed_soa_make(const ht_combiner_program *p, const ht_vertex *v, size_t count, ht_fixed_soa *out) {
    memset(out, 0, sizeof *out);
    const size_t bytes = (count ? count : 1) * sizeof(float);
    float **all[] = { &out->px, &out->py, &out->pz, &out->a[0], &out->a[1], &out->a[2], &out->b[0],
                      &out->b[1], &out->b[2], &out->c[0], &out->c[1], &out->c[2] };
    for (size_t k = 0; k < sizeof all / sizeof all[0]; k++)
        if (!(*all[k] = malloc(bytes))) {
            ht_fixed_soa_free(out);
            return HT_ERR_OUT_OF_MEMORY;
        }
    const bool kajiya_kay = p->model == HT_MODEL_KAJIYA_KAY;
    for (size_t i = 0; i < count; i++) {
        double raw[3], T[3], N[3], t1[3], t2[3];
        ht_vec3_from_float(raw, v[i].tangent);
        bool has_t = ht_vec3_direction(T, raw);
        ht_vec3_from_float(raw, v[i].normal);
        ht_vec3_direction(N, raw);
        out->px[i] = v[i].position[0];
        out->py[i] = v[i].position[1];
        out->pz[i] = v[i].position[2];
        if (kajiya_kay) {
            store(out->a, i, T);
            store(out->b, i, T);
            ht_vec3_set(t2, 0, 0, 0);
            store(out->c, i, t2);
        } else {
            ht_vec3_shifted_tangent(t1, T, has_t, N, p->shift[0]);
            ht_vec3_shifted_tangent(t2, T, has_t, N, p->shift[1]);
            store(out->a, i, N);
            store(out->b, i, t1);
            store(out->c, i, t2);
        }
    }
    out->count = count;
    return HT_OK;
}

/* What ht_combiner_lut_coord does, as a multiply-add: d k + o for d in
   [-1, 1] on an axis of n texels. */
typedef struct axis_map {
    float k, o;
} axis_map;

static axis_map axis(int n) {
    const double lo = ht_combiner_lut_coord(-1.0, n), hi = ht_combiner_lut_coord(1.0, n);
    return (axis_map){ (float)(0.5 * (hi - lo)), (float)(0.5 * (hi + lo)) };
}

static inline float clamp_unit(float d) { return d > 1.0f ? 1.0f : (d < -1.0f ? -1.0f : d); }

/* Per vertex, L (directional: L, unit or zero; point: towards pl, made unit
   here), V = normalize(eye - position) and H = normalize(L + V) once, and the
   program's three dot products from them: d0 = a.L, d1 = b.H, d2 = c.H
   (zero where a direction is missing: the caller maps), has_l and has_h
   1 where L and H have a direction. One branch-free loop over plain float
   rows, so it vectorises. */
static void dot_products(const ht_fixed_soa *s, const float L[3], const float *pl, const float eye[3],
                         float *restrict d0, float *restrict d1, float *restrict d2, float *restrict has_l,
                         float *restrict has_h) {
    const size_t n = s->count;
    const float *restrict px = s->px, *restrict py = s->py, *restrict pz = s->pz;
    const float *restrict ax = s->a[0], *restrict ay = s->a[1], *restrict az = s->a[2];
    const float *restrict bx = s->b[0], *restrict by = s->b[1], *restrict bz = s->b[2];
    const float *restrict cx = s->c[0], *restrict cy = s->c[1], *restrict cz = s->c[2];
    const float wp = pl ? 1.0f : 0.0f, p0 = pl ? pl[0] : 0.0f, p1 = pl ? pl[1] : 0.0f, p2 = pl ? pl[2] : 0.0f;
    for (size_t i = 0; i < n; i++) {
        /* one formula for directional and point lights keeps the loop branch-free */
        float lx = L[0] + wp * (p0 - px[i]), ly = L[1] + wp * (p1 - py[i]), lz = L[2] + wp * (p2 - pz[i]);
        float l2 = lx * lx + ly * ly + lz * lz;
        float il = l2 > 1e-12f ? 1.0f / sqrtf(l2) : 0.0f;
        lx *= il;
        ly *= il;
        lz *= il;
        float vx = eye[0] - px[i], vy = eye[1] - py[i], vz = eye[2] - pz[i];
        float v2 = vx * vx + vy * vy + vz * vz;
        float iv = v2 > 1e-12f ? 1.0f / sqrtf(v2) : 0.0f;
        float hx = lx + vx * iv, hy = ly + vy * iv, hz = lz + vz * iv;
        float h2 = hx * hx + hy * hy + hz * hz;
        float ih = h2 > 1e-12f ? 1.0f / sqrtf(h2) : 0.0f;
        d0[i] = ax[i] * lx + ay[i] * ly + az[i] * lz;
        d1[i] = (bx[i] * hx + by[i] * hy + bz[i] * hz) * ih;
        d2[i] = (cx[i] * hx + cy[i] * hy + cz[i] * hz) * ih;
        has_l[i] = l2 > 1e-12f ? 1.0f : 0.0f;
        has_h[i] = h2 > 1e-12f ? 1.0f : 0.0f;
    }
}

static float length2(float *const v[3], size_t i) { return v[0][i] * v[0][i] + v[1][i] * v[1][i] + v[2][i] * v[2][i]; }

void ht_fixed_soa_coords(const ht_combiner_program *p, const ht_fixed_soa *s, const ht_light *light,
                         const float eye[3], float *coords) {
    const bool kajiya_kay = p->model == HT_MODEL_KAJIYA_KAY;
    const bool point = light && light->type == HT_LIGHT_POINT;
    float lv[3] = { 0, 0, 0 };
    if (light)
        for (int j = 0; j < 3; j++) lv[j] = isfinite(light->vector[j]) ? light->vector[j] : 0.0f;
    /* a directional light's L is the same for every vertex: normalize once */
    float dir_l[3] = { 0, 0, 0 };
    if (!point) {
        double raw[3] = { lv[0], lv[1], lv[2] }, L[3];
        ht_vec3_direction(L, raw);
        for (int j = 0; j < 3; j++) dir_l[j] = (float)L[j];
    }
    const float *pl = point ? lv : NULL; /* dir_l stays zero for a point light */
    const size_t n = s->count;
    /* the scratch rows: d0, d1, d2, and whether H has a direction */
    float *scratch = malloc((n ? n : 1) * 5 * sizeof(float));
    if (!scratch) {
        /* out of memory: read as unlit, inside the LUT (the model's answers without directions) */
        for (size_t i = 0; i < 3 * n; i++) coords[i] = ht_combiner_lut_coord(-1.0, p->lut_size[i % 3]);
        return;
    }
    float *d0 = scratch, *d1 = scratch + n, *d2 = scratch + 2 * n, *hh = scratch + 3 * n, *hl = scratch + 4 * n;
    dot_products(s, dir_l, pl, eye, d0, d1, d2, hl, hh);

    const axis_map m0 = axis(p->lut_size[0]), m1 = axis(p->lut_size[1]), m2 = axis(p->lut_size[2]);
    const float none_a = ht_combiner_lut_coord(kajiya_kay ? 1.0 : 0.0, p->lut_size[0]);
    const float none_h = ht_combiner_lut_coord(-1.0, p->lut_size[1]), none_h2 = ht_combiner_lut_coord(-1.0, p->lut_size[2]);
    const float third = kajiya_kay ? ht_combiner_lut_coord(0.0, p->lut_size[2]) : 0.0f;
    for (size_t i = 0; i < n; i++) {
        /* a vector stored as zero has no direction (no strand, no normal);
           a point light on the vertex has none either */
        bool a_ok = length2(s->a, i) > 0.5f, b_ok = length2(s->b, i) > 0.5f, c_ok = length2(s->c, i) > 0.5f;
        bool h_ok = hh[i] > 0.5f;
        float *out = coords + 3 * i;
        if (kajiya_kay) {
            out[0] = a_ok && hl[i] > 0.5f ? clamp_unit(d0[i]) * m0.k + m0.o : none_a;
            out[1] = b_ok && h_ok ? clamp_unit(d1[i]) * m1.k + m1.o : none_h;
            out[2] = third;
        } else {
            /* a zero N gives N.L = 0 (model.c) */
            out[0] = a_ok ? clamp_unit(d0[i]) * m0.k + m0.o : none_a;
            out[1] = b_ok && h_ok ? clamp_unit(d1[i]) * m1.k + m1.o : none_h;
            out[2] = c_ok && h_ok ? clamp_unit(d2[i]) * m2.k + m2.o : none_h2;
        }
    }
    free(scratch);
}

ht_fixed_soa ht_fixed_soa_range(const ht_fixed_soa *soa, size_t first, size_t count) {
    ht_fixed_soa v = *soa;
    float **all[] = { &v.px, &v.py, &v.pz, &v.a[0], &v.a[1], &v.a[2], &v.b[0], &v.b[1], &v.b[2],
                      &v.c[0], &v.c[1], &v.c[2] };
    for (size_t k = 0; k < sizeof all / sizeof all[0]; k++)
        if (*all[k]) *all[k] += first;
    v.count = count;
    return v;
}

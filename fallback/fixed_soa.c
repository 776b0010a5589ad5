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

/* The shifted tangent as model.c makes it: zero when T has none. */
static void shifted(const double T[3], bool has_t, const double N[3], double shift, double out[3]) {
    double raw[3];
    for (int j = 0; j < 3; j++) raw[j] = T[j] + shift * N[j];
    if (!has_t || !ht_vec3_direction(out, raw)) ht_vec3_set(out, 0, 0, 0);
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
            shifted(T, has_t, N, p->shift[0], t1);
            shifted(T, has_t, N, p->shift[1], t2);
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

void ht_fixed_soa_coords(const ht_combiner_program *p, const ht_fixed_soa *s, const ht_light *light,
                         const float eye[3], float *coords) {
    const bool kajiya_kay = p->model == HT_MODEL_KAJIYA_KAY;
    const bool point = light && light->type == HT_LIGHT_POINT;
    float lv[3] = { 0, 0, 0 };
    if (light)
        for (int j = 0; j < 3; j++) lv[j] = isfinite(light->vector[j]) ? light->vector[j] : 0.0f;
    /* a directional light's L is the same for every vertex: normalize once */
    float dir_l[3] = { 0, 0, 0 };
    bool dir_has_l = false;
    if (!point) {
        double raw[3] = { lv[0], lv[1], lv[2] }, L[3];
        dir_has_l = ht_vec3_direction(L, raw);
        for (int j = 0; j < 3; j++) dir_l[j] = (float)L[j];
    }
    const axis_map m0 = axis(p->lut_size[0]), m1 = axis(p->lut_size[1]), m2 = axis(p->lut_size[2]);
    const float none_a = ht_combiner_lut_coord(kajiya_kay ? 1.0 : 0.0, p->lut_size[0]);
    const float none_h = ht_combiner_lut_coord(-1.0, p->lut_size[1]), none_h2 = ht_combiner_lut_coord(-1.0, p->lut_size[2]);
    const float third = kajiya_kay ? ht_combiner_lut_coord(0.0, p->lut_size[2]) : 0.0f;
    const float tiny = 1e-12f;
    for (size_t i = 0; i < s->count; i++) {
        float lx = dir_l[0], ly = dir_l[1], lz = dir_l[2];
        bool has_l = dir_has_l;
        if (point) {
            lx = lv[0] - s->px[i];
            ly = lv[1] - s->py[i];
            lz = lv[2] - s->pz[i];
            float l2 = lx * lx + ly * ly + lz * lz;
            has_l = l2 > tiny;
            float il = has_l ? 1.0f / sqrtf(l2) : 0.0f;
            lx *= il;
            ly *= il;
            lz *= il;
        }
        float vx = eye[0] - s->px[i], vy = eye[1] - s->py[i], vz = eye[2] - s->pz[i];
        float v2 = vx * vx + vy * vy + vz * vz;
        float iv = v2 > tiny ? 1.0f / sqrtf(v2) : 0.0f;
        float hx = lx + vx * iv, hy = ly + vy * iv, hz = lz + vz * iv;
        float h2 = hx * hx + hy * hy + hz * hz;
        bool has_h = h2 > tiny;
        float ih = has_h ? 1.0f / sqrtf(h2) : 0.0f;
        hx *= ih;
        hy *= ih;
        hz *= ih;
        /* a vector stored as zero has no direction (no strand, no normal) */
        float a2 = s->a[0][i] * s->a[0][i] + s->a[1][i] * s->a[1][i] + s->a[2][i] * s->a[2][i];
        float b2 = s->b[0][i] * s->b[0][i] + s->b[1][i] * s->b[1][i] + s->b[2][i] * s->b[2][i];
        float c2 = s->c[0][i] * s->c[0][i] + s->c[1][i] * s->c[1][i] + s->c[2][i] * s->c[2][i];
        float da = clamp_unit(s->a[0][i] * lx + s->a[1][i] * ly + s->a[2][i] * lz);
        float db = clamp_unit(s->b[0][i] * hx + s->b[1][i] * hy + s->b[2][i] * hz);
        float dc = clamp_unit(s->c[0][i] * hx + s->c[1][i] * hy + s->c[2][i] * hz);
        float *out = coords + 3 * i;
        if (kajiya_kay) {
            out[0] = a2 > 0.5f && has_l ? da * m0.k + m0.o : none_a;
            out[1] = b2 > 0.5f && has_h ? db * m1.k + m1.o : none_h;
            out[2] = third;
        } else {
            /* a zero N gives N.L = 0 (model.c) */
            out[0] = a2 > 0.5f ? da * m0.k + m0.o : none_a;
            out[1] = b2 > 0.5f && has_h ? db * m1.k + m1.o : none_h;
            out[2] = c2 > 0.5f && has_h ? dc * m2.k + m2.o : none_h2;
        }
    }
}

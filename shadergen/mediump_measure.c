/* mediump_measure.c — see mediump_measure.h. */
#include "mediump_measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"

static int to_byte(double v) { return (int)lround(fmin(1.0, fmax(0.0, v)) * 255.0); }

static double half_length(const double L[3], const double V[3]) {
    const double l = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]), v = sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
    double h2 = 0;
    for (int k = 0; k < 3; k++) h2 += (L[k] / l + V[k] / v) * (L[k] / l + V[k] / v);
    return sqrt(h2);
}

void ht_mp_compare(const ht_mp_mirror *mm, const ht_mp_desc *d, const ht_mp_inputs *in, bool flush,
                   ht_mp_measurement *out) {
    ht_surface s = { .shift_tex = d->jitter ? in->shift_texel : 0.5,
                     .sparkle = d->sparkle ? in->sparkle : 1.0,
                     .ao = d->ao ? in->ao : 1.0 };
    ht_light_ray rays[HT_MAX_LIGHTS];
    for (int k = 0; k < 3; k++) {
        s.T[k] = in->tangent[k];
        s.N[k] = in->normal[k];
        s.V[k] = in->eye[k] - in->position[k];
        s.base[k] = d->base ? in->base[k] : 1.0;
        for (int i = 0; i < d->light_count; i++) {
            rays[i].L[k] = in->light[i][k] - (d->light_types[i] == HT_LIGHT_POINT ? in->position[k] : 0.0);
            rays[i].color[k] = in->colour[i][k];
        }
    }
    ht_mp_error *e = &out->regular;
    for (int i = 0; i < d->light_count; i++)
        if (half_length(rays[i].L, s.V) < HT_MP_OPPOSITE) e = &out->opposite;
    double want[3], got[3];
    ht_model_shade_d(&d->shading, &s, rays, d->light_count, want);
    ht_mp_mirror_shade(mm, in, flush, got, &e->stats);
    e->samples++;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(got[k])) {
            e->nonfinite++;
            continue;
        }
        const int diff = abs(to_byte(got[k]) - to_byte(want[k]));
        if (diff > e->max_byte) {
            e->max_byte = diff;
            e->worst = *in;
        }
    }
}

static void random_vector(ht_rng *r, double min_log2, double max_log2, double v[3]) {
    double len;
    do {
        for (int k = 0; k < 3; k++) v[k] = ht_rng_range(r, -1, 1);
        len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (len < 1e-3 || len > 1);
    const double scale = exp2(ht_rng_range(r, min_log2, max_log2)) / len;
    for (int k = 0; k < 3; k++) v[k] *= scale;
}

bool ht_mp_measure_random(const ht_mp_desc *d, long samples, uint64_t seed, bool flush,
                          const double (*colours)[3], ht_mp_measurement *out) {
    ht_mp_program *p = malloc(sizeof *p);
    if (!p) return false;
    ht_mp_build(d, p);
    char err[256];
    ht_mp_mirror *mm = ht_mp_mirror_new(p, err, sizeof err);
    free(p);
    if (!mm) return false;
    ht_rng r = ht_rng_seed(seed);
    for (long n = 0; n < samples; n++) {
        ht_mp_inputs in = { .shift_texel = ht_rng_unit(&r), .sparkle = ht_rng_unit(&r), .ao = ht_rng_unit(&r) };
        random_vector(&r, -4, 10, in.tangent);
        random_vector(&r, -4, 10, in.normal);
        random_vector(&r, -4, 1, in.position);
        double view[3];
        random_vector(&r, 1, 6, view);
        for (int k = 0; k < 3; k++) {
            in.eye[k] = in.position[k] + view[k];
            in.base[k] = ht_rng_unit(&r);
        }
        for (int i = 0; i < d->light_count; i++) {
            const bool point = d->light_types[i] == HT_LIGHT_POINT;
            random_vector(&r, point ? 1 : -4, point ? 6 : 10, in.light[i]);
            for (int k = 0; k < 3; k++) {
                if (point) in.light[i][k] += in.position[k];
                in.colour[i][k] = colours ? colours[i][k] : ht_rng_unit(&r);
            }
        }
        ht_mp_compare(mm, d, &in, flush, out);
    }
    ht_mp_mirror_free(mm);
    return true;
}

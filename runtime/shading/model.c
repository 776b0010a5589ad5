/* model.c — the shading model, written once over `real` and compiled twice:
   as double (the oracle, functions ending in _d) and as float (what 32-bit
   hardware computes, _f). <tgmath.h> makes sqrt/fabs/pow follow `real`.

   Documented answers at the model's undefined points (docs/DESIGN.md):
   - A vector shorter than sqrt(HT_MODEL_MIN_LENGTH2) has no direction and
     normalizes to the zero vector: a zero tangent (degenerate interpolation,
     or T = -k N exactly), H when L = -V, N, L or V of zero length.
   - S(t,e) = 0 when t or H has no direction: no highlight without a strand
     direction or a half vector. A zero T stays zero after the shift (t1 =
     t2 = 0, not N), so a zero tangent shades diffuse only. A zero N gives
     N.L = 0, so diff = wrap, and leaves T unshifted.
   - sin(t,x) = |t x x|, better conditioned than sqrt(1 - dot^2) near
     parallel vectors, clamped to [0,1]; dot(t,x) clamped to [-1,1].
   - sin^e with e = 0 is 1, also at sin = 0 (pow(0,0) := 1), so S = the
     smoothstep factor alone; sin = 0 with e > 0 gives 0.
   - smoothstep(-1,0,x) is 0 at x <= -1 and 1 at x >= 0.
   - Kajiya-Kay diffuse sin(T,L) is 0 when T or L has no direction.
   - The transmission lobe is 0 when T, L or V has no direction; L or V
     parallel to T has no azimuth and takes cos(phi) = 0. */
#ifndef HT_MODEL_PASS
#include <hairtier/model.h>

#include "model_terms.h"

#include <tgmath.h>

#define HT_MODEL_PASS 1
#define real double
#define FN(name) name##_d
#include "model.c"
#undef real
#undef FN

#undef HT_MODEL_PASS
#define HT_MODEL_PASS 2
#define real float
#define FN(name) name##_f
#include "model.c"
#undef real
#undef FN

/* Precision-independent entry points (double only). */
bool ht_model_has_transmission(const ht_shading *m) {
    const double *c = m->transmission.color;
    return m->model == HT_MODEL_SCHEUERMANN && (c[0] != 0 || c[1] != 0 || c[2] != 0);
}

double ht_model_transmission_d(const ht_transmission *t, const double T[3], const double L[3], const double V[3]) {
    double tn[3], ln[3], vn[3];
    normalize_or_zero_d(T, tn);
    normalize_or_zero_d(L, ln);
    normalize_or_zero_d(V, vn);
    return transmission_unit_d(t, tn, ln, vn);
}

void ht_model_light_terms_init(const ht_surface *s, const double L[3], ht_model_light_terms *g) {
    normalize_or_zero_d(s->T, g->T);
    normalize_or_zero_d(s->N, g->N);
    double V[3], h_raw[3];
    normalize_or_zero_d(s->V, V);
    normalize_or_zero_d(L, g->L);
    for (int i = 0; i < 3; i++) h_raw[i] = g->L[i] + V[i];
    normalize_or_zero_d(h_raw, g->H);
    g->n_dot_l = dot3_d(g->N, g->L);
    g->has_transmission = transmission_geometry_d(g->T, g->L, V, &g->mean_angle, &g->transmission_base);
}

double ht_model_light_highlight(const ht_model_light_terms *g, double shift, double exponent) {
    double t[3];
    shifted_tangent_d(g->T, g->N, shift, t);
    return highlight_unit_d(t, g->H, exponent);
}

double ht_model_light_transmission(const ht_model_light_terms *g, const ht_transmission *t) {
    return g->has_transmission ? transmission_of_d(t, g->mean_angle, g->transmission_base) : 0;
}

double ht_model_highlight_of_cos_d(double c, double exponent) {
    if (c > 1.0) c = 1.0;
    if (c < -1.0) c = -1.0;
    double sine = sqrt(fmax(0.0, 1.0 - c * c));
    return smoothstep_to_zero_d(c) * power_d(sine, exponent);
}

double ht_model_wrap_diffuse_d(double n_dot_l, double wrap) {
    return saturate_d(wrap + (1.0 - wrap) * n_dot_l);
}

double ht_model_dot_factor_d(const ht_shading *m, int axis, double value) {
    const bool kajiya_kay = m->model == HT_MODEL_KAJIYA_KAY;
    switch (axis) {
    case 0:
        if (kajiya_kay) { /* sin(T,L) from T.L */
            double c = fmin(1.0, fmax(-1.0, value));
            return sqrt(fmax(0.0, 1.0 - c * c));
        }
        return ht_model_wrap_diffuse_d(value, m->wrap);
    case 1: return ht_model_highlight_of_cos_d(value, m->primary.exponent);
    default: return kajiya_kay ? 0.0 : ht_model_highlight_of_cos_d(value, m->secondary.exponent);
    }
}

void ht_model_dot_combine_d(const ht_shading *m, const double f[3], double rgb[3]) {
    for (int i = 0; i < 3; i++)
        rgb[i] = m->diffuse_color[i] * f[0] + m->primary.color[i] * f[1] + m->secondary.color[i] * f[2];
}

void ht_model_dot_terms_d(const ht_shading *m, double a, double b, double c, double rgb[3]) {
    const double factors[3] = { ht_model_dot_factor_d(m, 0, a), ht_model_dot_factor_d(m, 1, b),
                                ht_model_dot_factor_d(m, 2, c) };
    ht_model_dot_combine_d(m, factors, rgb);
}

double ht_model_dot_terms_max(const ht_shading *m) {
    double most = 0.0;
    for (int i = 0; i < 3; i++) {
        double sum = m->diffuse_color[i] + m->primary.color[i];
        if (m->model != HT_MODEL_KAJIYA_KAY) sum += m->secondary.color[i];
        if (sum > most) most = sum;
    }
    return most;
}

#else /* HT_MODEL_PASS: the model body, once per precision */

static real FN(saturate)(real x) { return x < 0 ? (real)0 : (x > 1 ? (real)1 : x); }

static real FN(dot3)(const real a[3], const real b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Unit vector along v, or the zero vector when v has no direction. */
static void FN(normalize_or_zero)(const real v[3], real out[3]) {
    real len2 = FN(dot3)(v, v);
    if (!(len2 > (real)HT_MODEL_MIN_LENGTH2)) {
        out[0] = out[1] = out[2] = 0;
        return;
    }
    real inv = 1 / sqrt(len2);
    for (int i = 0; i < 3; i++) out[i] = v[i] * inv;
}

static bool FN(has_direction)(const real v[3]) { return FN(dot3)(v, v) > 0; }

/* sin of the angle between unit vectors, |a x b| clamped to [0,1]. */
static real FN(sine)(const real a[3], const real b[3]) {
    real c[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0] };
    real s = sqrt(FN(dot3)(c, c));
    return s > 1 ? (real)1 : s;
}

/* smoothstep(-1, 0, x) */
static real FN(smoothstep_to_zero)(real x) {
    real u = FN(saturate)(x + 1);
    return u * u * (3 - 2 * u);
}

/* x^e for x in [0,1], e >= 0, with 0^0 = 1. */
static real FN(power)(real x, real e) {
    if (e == 0) return 1;
    if (x <= 0) return 0;
    return pow(x, e);
}

/* S(t,e) on unit-or-zero vectors t and h. */
static real FN(highlight_unit)(const real t[3], const real h[3], real e) {
    if (!FN(has_direction)(t) || !FN(has_direction)(h)) return 0;
    real c = FN(dot3)(t, h);
    if (c > 1) c = 1;
    if (c < -1) c = -1;
    return FN(smoothstep_to_zero)(c) * FN(power)(FN(sine)(t, h), e);
}

real FN(ht_model_highlight)(const real t[3], const real h[3], real e) {
    real tn[3], hn[3];
    FN(normalize_or_zero)(t, tn);
    FN(normalize_or_zero)(h, hn);
    return FN(highlight_unit)(tn, hn, e);
}

/* t = normalize(T + amount * N). A strand without a direction has none
   after the shift either: T + amount * N alone would turn a zero T into N. */
static void FN(shifted_tangent)(const real T[3], const real N[3], real amount, real out[3]) {
    if (!FN(has_direction)(T)) {
        out[0] = out[1] = out[2] = 0;
        return;
    }
    real v[3];
    for (int i = 0; i < 3; i++) v[i] = T[i] + amount * N[i];
    FN(normalize_or_zero)(v, out);
}

static real FN(clamp1)(real x) { return x < -1 ? (real)-1 : (x > 1 ? (real)1 : x); }

/* What ht_transmission's tt takes from unit-or-zero T, L, V: the mean
   longitudinal angle and the azimuth term's base; false when T, L or V
   has no direction (tt = 0). */
static bool FN(transmission_geometry)(const real T[3], const real L[3], const real V[3], real *mean_angle,
                                      real *a) {
    if (!FN(has_direction)(T) || !FN(has_direction)(L) || !FN(has_direction)(V)) return false;
    const real tl = FN(dot3)(T, L), tv = FN(dot3)(T, V);
    real lp[3], vp[3], lr[3], vr[3];
    for (int i = 0; i < 3; i++) lr[i] = L[i] - tl * T[i], vr[i] = V[i] - tv * T[i];
    FN(normalize_or_zero)(lr, lp);
    FN(normalize_or_zero)(vr, vp);
    *mean_angle = (asin(FN(clamp1)(tl)) + asin(FN(clamp1)(tv))) / 2;
    *a = FN(saturate)((1 - FN(dot3)(lp, vp)) / 2);
    return true;
}

static real FN(transmission_of)(const ht_transmission *t, real mean_angle, real a) {
    const real u = mean_angle - (real)t->centre;
    return exp2(-(real)t->sharpness * u * u) * FN(power)(a, (real)t->azimuth);
}

/* ht_transmission's tt on unit-or-zero T, L, V. */
static real FN(transmission_unit)(const ht_transmission *t, const real T[3], const real L[3], const real V[3]) {
    real mean_angle, a;
    return FN(transmission_geometry)(T, L, V, &mean_angle, &a) ? FN(transmission_of)(t, mean_angle, a) : 0;
}

static void FN(to_real)(const double in[3], real out[3]) {
    for (int i = 0; i < 3; i++) out[i] = (real)in[i];
}

void FN(ht_model_shade)(const ht_shading *m, const ht_surface *s,
                        const ht_light_ray *lights, int light_count, double rgb[3]) {
    real T[3], N[3], V[3], t_raw[3], n_raw[3], v_raw[3];
    FN(to_real)(s->T, t_raw);
    FN(to_real)(s->N, n_raw);
    FN(to_real)(s->V, v_raw);
    FN(normalize_or_zero)(t_raw, T);
    FN(normalize_or_zero)(n_raw, N);
    FN(normalize_or_zero)(v_raw, V);

    const bool marschner = m->model == HT_MODEL_MARSCHNER;
    const bool transmission = ht_model_has_transmission(m);
    const bool kajiya_kay = m->model == HT_MODEL_KAJIYA_KAY || marschner;
    const real jitter = kajiya_kay ? 0 : (real)s->shift_tex - (real)0.5;
    real t1[3], t2[3];
    if (kajiya_kay) {
        for (int i = 0; i < 3; i++) t1[i] = t2[i] = T[i];
    } else {
        FN(shifted_tangent)(T, N, (real)m->primary.shift + jitter, t1);
        FN(shifted_tangent)(T, N, (real)m->secondary.shift + jitter, t2);
    }

    real sum[3] = { 0, 0, 0 };
    for (int li = 0; li < light_count; li++) {
        real L[3], l_raw[3], H[3], h_raw[3];
        FN(to_real)(lights[li].L, l_raw);
        FN(normalize_or_zero)(l_raw, L);
        for (int i = 0; i < 3; i++) h_raw[i] = L[i] + V[i];
        FN(normalize_or_zero)(h_raw, H);

        real diffuse, s1, s2 = 0;
        if (marschner) {
            double td[3], ld[3], vd[3], fibre[3];
            for (int i = 0; i < 3; i++) td[i] = T[i], ld[i] = L[i], vd[i] = V[i];
            ht_marschner_fibre_vectors(&m->marschner, td, ld, vd, fibre);
            diffuse = FN(has_direction)(T) && FN(has_direction)(L) ? FN(sine)(T, L) : 0;
            for (int i = 0; i < 3; i++) {
                real lit = diffuse * (real)m->diffuse_color[i] + (real)fibre[i];
                sum[i] += lit * (real)s->base[i] * (real)lights[li].color[i] * (real)s->ao;
            }
            continue;
        }
        if (kajiya_kay) {
            diffuse = FN(has_direction)(T) && FN(has_direction)(L) ? FN(sine)(T, L) : 0;
            s1 = FN(highlight_unit)(T, H, (real)m->primary.exponent);
        } else {
            diffuse = FN(saturate)((real)m->wrap + (1 - (real)m->wrap) * FN(dot3)(N, L));
            s1 = FN(highlight_unit)(t1, H, (real)m->primary.exponent);
            s2 = FN(highlight_unit)(t2, H, (real)m->secondary.exponent) * (real)s->sparkle;
        }
        /* Left out entirely without a lobe: the sum stays bit for bit. */
        const real tt = transmission ? FN(transmission_unit)(&m->transmission, T, L, V) : 0;
        for (int i = 0; i < 3; i++) {
            real lit = diffuse * (real)m->diffuse_color[i] + s1 * (real)m->primary.color[i]
                     + s2 * (real)m->secondary.color[i];
            if (transmission) lit += tt * (real)m->transmission.color[i];
            sum[i] += lit * (real)s->base[i] * (real)lights[li].color[i] * (real)s->ao;
        }
    }
    for (int i = 0; i < 3; i++) rgb[i] = (double)sum[i];
}

#endif /* HT_MODEL_PASS */

/* test_model.c — the shading model at its extremes and over a million random
   points: every documented answer of model.c's header comment, no NaN or
   Inf in either precision, outputs within the bound model.h promises, and
   float within a measured tolerance of double.

   Expected values come from the documented rules, computed here on their
   own (ref_* below follow docs/DESIGN.md line by line), or from identities
   the rules imply: no highlight means the result equals the same material
   with its highlight colours set to black. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/hairtier.h>
#include <hairtier/model.h>
#include "model_terms.h"
#include "rng.h"

/* ---- the documented rules, written out independently of model.c ---- */

static double ref_dot(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Shorter than sqrt(HT_MODEL_MIN_LENGTH2): no direction, the zero vector. */
static void ref_normalize(const double v[3], double out[3]) {
    double len2 = ref_dot(v, v);
    double inv = len2 > HT_MODEL_MIN_LENGTH2 ? 1 / sqrt(len2) : 0;
    for (int i = 0; i < 3; i++) out[i] = v[i] * inv;
}

static double ref_smoothstep(double x) { /* smoothstep(-1, 0, x) */
    double u = fmin(1, fmax(0, x + 1));
    return u * u * (3 - 2 * u);
}

/* sin = |t x h| of unit vectors, clamped to [0,1] */
static double ref_sine(const double t[3], const double h[3]) {
    double c[3] = { t[1] * h[2] - t[2] * h[1], t[2] * h[0] - t[0] * h[2], t[0] * h[1] - t[1] * h[0] };
    return fmin(1, sqrt(ref_dot(c, c)));
}

/* S(t,e) of unit-or-zero vectors: 0 without a direction, sin^0 = 1. */
static double ref_highlight(const double t[3], const double h[3], double e) {
    if (ref_dot(t, t) == 0 || ref_dot(h, h) == 0) return 0;
    double c = fmin(1, fmax(-1, ref_dot(t, h)));
    return ref_smoothstep(c) * (e == 0 ? 1 : pow(ref_sine(t, h), e));
}

/* One light of the Scheuermann model, straight from docs/DESIGN.md. */
static void ref_shade_scheuermann(const ht_shading *m, const ht_surface *s,
                                  const ht_light_ray *light, double rgb[3]) {
    double T[3], N[3], V[3], L[3], H[3], t1[3], t2[3], v[3];
    ref_normalize(s->T, T);
    ref_normalize(s->N, N);
    ref_normalize(s->V, V);
    ref_normalize(light->L, L);
    for (int i = 0; i < 3; i++) v[i] = L[i] + V[i];
    ref_normalize(v, H);
    double jitter = s->shift_tex - 0.5;
    bool strand = ref_dot(T, T) > 0; /* a zero T stays zero after the shift */
    for (int i = 0; i < 3; i++) v[i] = strand ? T[i] + (m->primary.shift + jitter) * N[i] : 0;
    ref_normalize(v, t1);
    for (int i = 0; i < 3; i++) v[i] = strand ? T[i] + (m->secondary.shift + jitter) * N[i] : 0;
    ref_normalize(v, t2);
    double diffuse = fmin(1, fmax(0, m->wrap + (1 - m->wrap) * ref_dot(N, L)));
    double s1 = ref_highlight(t1, H, m->primary.exponent);
    double s2 = ref_highlight(t2, H, m->secondary.exponent) * s->sparkle;
    for (int i = 0; i < 3; i++)
        rgb[i] = (diffuse * m->diffuse_color[i] + s1 * m->primary.color[i] +
                  s2 * m->secondary.color[i]) * s->base[i] * light->color[i] * s->ao;
}

/* ---- fixtures ---- */

static ht_shading scheuermann(double e1, double shift1, double e2, double shift2) {
    return (ht_shading){
        .model = HT_MODEL_SCHEUERMANN,
        .diffuse_color = { 0.30, 0.20, 0.10 },
        .wrap = 0.25,
        .primary = { .color = { 0.50, 0.45, 0.40 }, .exponent = e1, .shift = shift1 },
        .secondary = { .color = { 0.35, 0.30, 0.20 }, .exponent = e2, .shift = shift2 },
    };
}

static ht_shading without_highlights(ht_shading m) {
    memset(m.primary.color, 0, sizeof m.primary.color);
    memset(m.secondary.color, 0, sizeof m.secondary.color);
    return m;
}

static ht_surface surface(double tx, double ty, double tz, double nx, double ny, double nz,
                          double vx, double vy, double vz) {
    return (ht_surface){ .T = { tx, ty, tz }, .N = { nx, ny, nz }, .V = { vx, vy, vz },
                         .base = { 0.9, 0.8, 0.7 }, .shift_tex = 0.5, .sparkle = 0.75, .ao = 0.8 };
}

static ht_light_ray light(double x, double y, double z) {
    return (ht_light_ray){ .L = { x, y, z }, .color = { 1.0, 0.9, 1.2 } };
}

typedef void (*shade_fn)(const ht_shading *, const ht_surface *, const ht_light_ray *, int, double[3]);

static const shade_fn shade_fns[2] = { ht_model_shade_d, ht_model_shade_f };
static const char *const precision_names[2] = { "double", "float" };
/* How close each precision must come to the double reference on the
   well-conditioned fixtures of the extreme tests (unit vectors, exponents
   at most 100): float rounds inputs and every operation to 24 bits. */
static const double fixture_tolerance[2] = { 1e-12, 2e-5 };

static void assert_rgb_near(const double got[3], const double want[3], double tolerance,
                            const char *what) {
    for (int i = 0; i < 3; i++) {
        if (!isfinite(got[i]) || fabs(got[i] - want[i]) > tolerance)
            fail_msg("%s: channel %d is %.17g, expected %.17g (tolerance %g)", what, i, got[i],
                     want[i], tolerance);
    }
}

/* The model in both precisions against the reference, one light. */
static void assert_matches_reference(const ht_shading *m, const ht_surface *s,
                                     const ht_light_ray *l, const char *what) {
    double want[3], got[3];
    ref_shade_scheuermann(m, s, l, want);
    for (int p = 0; p < 2; p++) {
        char label[160];
        snprintf(label, sizeof label, "%s (%s)", what, precision_names[p]);
        shade_fns[p](m, s, l, 1, got);
        assert_rgb_near(got, want, fixture_tolerance[p], label);
    }
}

/* No highlight anywhere: the result equals the material without highlight
   colours, bit for bit (S = 0 multiplies to the same 0 either way). */
static void assert_diffuse_only(const ht_shading *m, const ht_surface *s, const ht_light_ray *l,
                                int light_count, const char *what) {
    ht_shading plain = without_highlights(*m);
    for (int p = 0; p < 2; p++) {
        double got[3], want[3];
        shade_fns[p](m, s, l, light_count, got);
        shade_fns[p](&plain, s, l, light_count, want);
        char label[160];
        snprintf(label, sizeof label, "%s (%s)", what, precision_names[p]);
        assert_rgb_near(got, want, 0, label);
    }
}

/* The wrapped diffuse term alone, per the rule, for a given N.L. */
static void wrapped_diffuse(const ht_shading *m, const ht_surface *s, const ht_light_ray *l,
                            double n_dot_l, double rgb[3]) {
    double d = fmin(1, fmax(0, m->wrap + (1 - m->wrap) * n_dot_l));
    for (int i = 0; i < 3; i++)
        rgb[i] = d * m->diffuse_color[i] * s->base[i] * l->color[i] * s->ao;
}

/* ---- |dot| above 1 under the square root ---- */

/* A float unit vector whose float self-dot is 1.00000012. */
static const float tricky[3] = { -0.586155176f, 0.174946457f, -0.791085303f };

static void test_parallel_vectors_whose_float_dot_exceeds_one_give_finite_highlights(void **state) {
    (void)state;
    /* the trap is real: without the clamp, sqrt(1 - c*c) is sqrt of a negative */
    float self = tricky[0] * tricky[0] + tricky[1] * tricky[1] + tricky[2] * tricky[2];
    assert_true(self > 1.0f);
    const double exponents[] = { 0, 0.5, 1, 80, 10000 };
    double t[3] = { tricky[0], tricky[1], tricky[2] };
    for (int i = 0; i < 5; i++) {
        double e = exponents[i];
        /* parallel: sin = 0, and smoothstep(dot = 1) = 1; sin^0 = 1 */
        double want = e == 0 ? 1 : 0;
        assert_true(ht_model_highlight_f(tricky, tricky, (float)e) == (float)want);
        assert_true(ht_model_highlight_d(t, t, e) == want);
        assert_true(ht_model_highlight_of_cos_d(1.0 + 1e-7, e) == want);
        assert_true(ht_model_highlight_of_cos_d(-1.0 - 1e-7, e) == 0);
    }
}

static void test_light_and_view_along_the_tangent_shade_diffuse_only(void **state) {
    (void)state;
    /* T = L = V = H: both unshifted highlights see sin = 0 */
    ht_shading m = scheuermann(80, 0, 20, 0);
    const double n[3] = { tricky[1], -tricky[0], 0 }; /* N.T = 0 exactly */
    ht_surface s = surface(tricky[0], tricky[1], tricky[2], n[0], n[1], n[2],
                           tricky[0], tricky[1], tricky[2]);
    ht_light_ray l = light(tricky[0], tricky[1], tricky[2]);
    assert_diffuse_only(&m, &s, &l, 1, "T = L = V");
    double got[3], want[3];
    ht_model_shade_d(&m, &s, &l, 1, got);
    wrapped_diffuse(&m, &s, &l, 0, want); /* N.L = 0: diffuse = wrap */
    assert_rgb_near(got, want, 1e-12, "T = L = V diffuse");
}

static void test_near_parallel_vectors_keep_their_sine_in_float(void **state) {
    (void)state;
    /* 1e-4 rad apart: dot = 1 - 5e-9 rounds to 1 in float, so
       sqrt(1 - dot^2) would be 0; |t x h| keeps the sine. */
    const double angle = 1e-4;
    float t[3] = { 1, 0, 0 }, h[3] = { (float)cos(angle), (float)sin(angle), 0 };
    double td[3] = { 1, 0, 0 }, hd[3] = { cos(angle), sin(angle), 0 };
    assert_true(fabs(ht_model_highlight_f(t, h, 1) - sin(angle)) < 1e-3 * sin(angle));
    assert_true(fabs(ht_model_highlight_d(td, hd, 1) - sin(angle)) < 1e-12 * sin(angle));
}

/* ---- exponents: 0, pow(0,0), up to 10000 ---- */

/* t = x axis, h at angle acos(c) from it in the xy plane */
static void unit_pair(double c, double t[3], double h[3]) {
    t[0] = 1; t[1] = 0; t[2] = 0;
    h[0] = c; h[1] = sqrt(fmax(0, 1 - c * c)); h[2] = 0;
}

static void test_exponent_zero_leaves_the_smoothstep_factor(void **state) {
    (void)state;
    const double cosines[] = { -1, -0.999, -0.75, -0.5, -0.1, 0, 0.3, 0.999999, 1 };
    for (int i = 0; i < 9; i++) {
        double c = cosines[i], t[3], h[3];
        unit_pair(c, t, h);
        float tf[3] = { (float)t[0], (float)t[1], (float)t[2] };
        float hf[3] = { (float)h[0], (float)h[1], (float)h[2] };
        double want = ref_smoothstep(c); /* including c = 1: pow(0, 0) := 1 */
        assert_true(fabs(ht_model_highlight_d(t, h, 0) - want) < 1e-12);
        assert_true(fabs(ht_model_highlight_of_cos_d(c, 0) - want) < 1e-12);
        assert_true(fabs(ht_model_highlight_f(tf, hf, 0) - want) < 1e-6);
    }
    double t[3], h[3];
    unit_pair(1, t, h);
    assert_true(ht_model_highlight_d(t, h, 0) == 1);     /* sin = 0, e = 0 */
    assert_true(ht_model_highlight_d(t, h, 1e-9) == 0);  /* sin = 0, e > 0 */
}

static void test_smoothstep_edges(void **state) {
    (void)state;
    const double exponents[] = { 0, 1, 100, 10000 };
    for (int i = 0; i < 4; i++) {
        double e = exponents[i], t[3], h[3];
        unit_pair(-1, t, h);
        assert_true(ht_model_highlight_d(t, h, e) == 0);           /* dot = -1: factor 0 */
        assert_true(ht_model_highlight_of_cos_d(-1, e) == 0);
        unit_pair(0, t, h);
        assert_true(fabs(ht_model_highlight_d(t, h, e) - 1) < 1e-12); /* dot = 0: 1 * 1^e */
        assert_true(ht_model_highlight_of_cos_d(0, e) == 1);
        float tf[3] = { 1, 0, 0 }, hf[3] = { 0, 1, 0 };
        assert_true(ht_model_highlight_f(tf, hf, (float)e) == 1.0f);
    }
    assert_true(ht_model_highlight_of_cos_d(-0.5, 0) == 0.5);
}

static void test_exponents_up_to_ten_thousand_stay_finite_and_ordered(void **state) {
    (void)state;
    const double cosines[] = { -0.9, -0.3, -0.01, 0, 0.001, 0.01, 0.1, 0.5, 0.99 };
    for (int i = 0; i < 9; i++) {
        double c = cosines[i], t[3], h[3], previous = 2;
        unit_pair(c, t, h);
        for (double e = 0; e <= 10000; e = e < 1 ? e + 0.25 : e * 1.5) {
            double got = ht_model_highlight_d(t, h, e);
            double want = ref_smoothstep(c) * (e == 0 ? 1 : pow(sqrt(1 - c * c), e));
            assert_true(isfinite(got) && got >= 0 && got <= 1);
            assert_true(fabs(got - want) <= 1e-12 * (1 + e) * want + 1e-300);
            assert_true(fabs(ht_model_highlight_of_cos_d(c, e) - want) <= 1e-12 * (1 + e) * want);
            assert_true(got <= previous);  /* a higher exponent never widens the lobe */
            previous = got;
            float tf[3] = { (float)t[0], (float)t[1], (float)t[2] };
            float hf[3] = { (float)h[0], (float)h[1], (float)h[2] };
            float f = ht_model_highlight_f(tf, hf, (float)e);
            assert_true(isfinite(f) && f >= 0 && f <= 1);
        }
        if (c == 0) assert_true(ht_model_highlight_d(t, h, 10000) == 1); /* sin = 1 */
    }
}

static void test_perpendicular_float_vectors_never_exceed_one(void **state) {
    (void)state;
    /* At the peak sin = 1; rounded up to 1 + 6e-8 it would give
       sin^10000 = 1.0006 unless clamped. */
    ht_rng r = ht_rng_seed(7);
    int above_one = 0;
    for (int n = 0; n < 20000; n++) {
        double a[3], b[3], h[3];
        for (int i = 0; i < 3; i++) a[i] = ht_rng_range(&r, -1, 1), b[i] = ht_rng_range(&r, -1, 1);
        h[0] = a[1] * b[2] - a[2] * b[1];
        h[1] = a[2] * b[0] - a[0] * b[2];
        h[2] = a[0] * b[1] - a[1] * b[0];
        float tf[3], hf[3];
        double tl = sqrt(ref_dot(a, a)), hl = sqrt(ref_dot(h, h));
        if (tl < 1e-3 || hl < 1e-3) continue;
        for (int i = 0; i < 3; i++) tf[i] = (float)(a[i] / tl), hf[i] = (float)(h[i] / hl);
        float cross_x = tf[1] * hf[2] - tf[2] * hf[1], cross_y = tf[2] * hf[0] - tf[0] * hf[2];
        float cross_z = tf[0] * hf[1] - tf[1] * hf[0];
        above_one += cross_x * cross_x + cross_y * cross_y + cross_z * cross_z > 1.0f;
        float f = ht_model_highlight_f(tf, hf, 10000);
        assert_true(f >= 0 && f <= 1);
    }
    assert_true(above_one > 0); /* the trap was met */
}

/* ---- shifts, and tangents the shift turns to nothing ---- */

static void test_shifts_of_a_hundred_turn_the_tangent_to_the_normal(void **state) {
    (void)state;
    const double shifts[] = { -100, -3, 3, 100 };
    for (int i = 0; i < 4; i++) {
        ht_shading m = scheuermann(60, shifts[i], 8, -shifts[i]);
        ht_surface s = surface(0, 1, 0, 0.6, 0, 0.8, 0, 0.28, 0.96);
        ht_light_ray l = light(0.36, 0.48, 0.8);
        char what[64];
        snprintf(what, sizeof what, "shift %g", shifts[i]);
        assert_matches_reference(&m, &s, &l, what);
    }
    /* T + 100 N with T perpendicular to N is 1/100 rad from N:
       seen from H = N, sin = 1/sqrt(1 + 100^2) */
    double tn[3] = { 0, 1, 0 }, nn[3] = { 0.6, 0, 0.8 };
    double t1[3] = { tn[0] + 100 * nn[0], tn[1] + 100 * nn[1], tn[2] + 100 * nn[2] };
    assert_true(fabs(ht_model_highlight_d(t1, nn, 1) - 1 / sqrt(10001)) < 1e-12);
}

static void test_tangent_along_the_normal_stays_finite(void **state) {
    (void)state;
    const double shifts[] = { -2, -0.5, 0, 0.5, 7 };
    for (int i = 0; i < 5; i++) {
        /* T = N: the shifted tangent is (1 + shift) N, a direction unless shift = -1 */
        ht_shading m = scheuermann(40, shifts[i], 4, 0.1);
        ht_surface s = surface(0, 0, 2, 0, 0, 1, 0.6, 0, 0.8);
        ht_light_ray l = light(-0.6, 0, 0.8);
        char what[64];
        snprintf(what, sizeof what, "T = N, shift %g", shifts[i]);
        assert_matches_reference(&m, &s, &l, what);
    }
}

static void test_tangent_cancelled_by_the_shift_has_no_highlight(void **state) {
    (void)state;
    /* unit T + 1 * N = 0 exactly when T = -k N: the primary lobe vanishes,
       the secondary (shifted differently) does not */
    const double n[3] = { 1 / sqrt(14.0), 2 / sqrt(14.0), 3 / sqrt(14.0) };
    const double ks[] = { 0.3, 1, 7 };
    for (int i = 0; i < 3; i++) {
        double k = ks[i];
        /* primary.shift 0.75 + (shift_tex 0.75 - 0.5) = 1 */
        ht_shading m = scheuermann(30, 0.75, 30, -0.2);
        /* L = V = H perpendicular to N: the secondary lobe (t2 = -N) peaks */
        const double w[3] = { 2 / sqrt(5.0), -1 / sqrt(5.0), 0 };
        ht_surface s = surface(-k * n[0], -k * n[1], -k * n[2], n[0], n[1], n[2], w[0], w[1], w[2]);
        s.shift_tex = 0.75;
        ht_light_ray l = light(w[0], w[1], w[2]);
        ht_shading no_primary = m;
        memset(no_primary.primary.color, 0, sizeof no_primary.primary.color);
        double got[3], want[3];
        for (int p = 0; p < 2; p++) {
            shade_fns[p](&m, &s, &l, 1, got);
            shade_fns[p](&no_primary, &s, &l, 1, want);
            assert_rgb_near(got, want, 0, precision_names[p]);
        }
        /* and the secondary highlight is really there */
        ht_shading plain = without_highlights(m);
        ht_model_shade_d(&plain, &s, &l, 1, want);
        assert_true(got[0] > want[0] + 1e-3);
        assert_matches_reference(&m, &s, &l, "T = -kN");
    }
}

/* ---- zero-length vectors ---- */

static void test_zero_tangent_shades_diffuse_only(void **state) {
    (void)state;
    ht_shading m = scheuermann(20, 0.1, 5, -0.1);
    ht_light_ray l = light(0.36, 0.48, 0.8);
    ht_surface zero = surface(0, 0, 0, 0, 0, 1, 0, 0.6, 0.8);
    assert_diffuse_only(&m, &zero, &l, 1, "zero T");
    assert_matches_reference(&m, &zero, &l, "zero T");
    /* below the length threshold is the same as zero */
    ht_surface tiny = surface(1e-7, 0, 0, 0, 0, 1, 0, 0.6, 0.8);
    assert_diffuse_only(&m, &tiny, &l, 1, "tiny T");
    double got[3], want[3];
    ht_model_shade_d(&m, &zero, &l, 1, got);
    wrapped_diffuse(&m, &zero, &l, 0.8, want);
    assert_rgb_near(got, want, 1e-12, "zero T diffuse");
    /* Kajiya-Kay: no tangent, no sin(T,L), no highlight: black */
    m.model = HT_MODEL_KAJIYA_KAY;
    for (int p = 0; p < 2; p++) {
        shade_fns[p](&m, &zero, &l, 1, got);
        assert_rgb_near(got, (double[3]){ 0, 0, 0 }, 0, "Kajiya-Kay zero T");
    }
}

static void test_short_vectors_above_the_threshold_keep_their_direction(void **state) {
    (void)state;
    ht_shading m = scheuermann(20, 0.1, 5, -0.1);
    ht_light_ray l = light(0.36, 0.48, 0.8), l_short = light(0.36e-5, 0.48e-5, 0.8e-5);
    ht_surface s = surface(0.8, 0.6, 0, -0.6, 0.8, 0, 0, 0, 1);
    ht_surface s_short = surface(0.8e-5, 0.6e-5, 0, -0.6e-5, 0.8e-5, 0, 0, 0, 1e-5);
    for (int p = 0; p < 2; p++) {
        double got[3], want[3];
        shade_fns[p](&m, &s_short, &l_short, 1, got);
        shade_fns[p](&m, &s, &l, 1, want);
        assert_rgb_near(got, want, fixture_tolerance[p], "length 1e-5");
    }
}

static void test_zero_normal_light_or_view_follow_the_documented_rules(void **state) {
    (void)state;
    ht_shading m = scheuermann(20, 0.3, 5, -0.2);
    /* N = 0: N.L = 0 so diff = wrap; the shift moves T nowhere */
    ht_surface s = surface(0.8, 0.6, 0, 0, 0, 0, 0, 0, 1);
    ht_light_ray l = light(0.36, 0.48, 0.8);
    assert_matches_reference(&m, &s, &l, "zero N");
    ht_shading plain = without_highlights(m);
    double got[3], want[3];
    ht_model_shade_d(&plain, &s, &l, 1, got);
    wrapped_diffuse(&m, &s, &l, 0, want);
    assert_rgb_near(got, want, 1e-12, "zero N diffuse");

    /* L = 0: N.L = 0 and H = V */
    s = surface(0.8, 0.6, 0, -0.6, 0.8, 0, 0, 0.6, 0.8);
    l = light(0, 0, 0);
    assert_matches_reference(&m, &s, &l, "zero L");
    ht_model_shade_d(&plain, &s, &l, 1, got);
    wrapped_diffuse(&m, &s, &l, 0, want);
    assert_rgb_near(got, want, 1e-12, "zero L diffuse");

    /* V = 0: H = L */
    s = surface(0.8, 0.6, 0, -0.6, 0.8, 0, 0, 0, 0);
    l = light(0, 0.6, 0.8);
    assert_matches_reference(&m, &s, &l, "zero V");

    /* everything zero: diff = wrap, no highlight */
    s = surface(0, 0, 0, 0, 0, 0, 0, 0, 0);
    l = light(0, 0, 0);
    assert_diffuse_only(&m, &s, &l, 1, "all zero");
}

static void test_light_opposite_the_view_has_no_highlight(void **state) {
    (void)state;
    /* L = -V: H = normalize(0) has no direction */
    ht_shading m = scheuermann(1, 0.1, 1, -0.1);
    ht_surface s = surface(0.8, 0.6, 0, -0.6, 0.8, 0, 0.36, 0.48, 0.8);
    ht_light_ray l = light(-0.36 * 3, -0.48 * 3, -0.8 * 3);
    assert_diffuse_only(&m, &s, &l, 1, "L = -V");
    double got[3], want[3];
    ht_model_shade_d(&m, &s, &l, 1, got);
    wrapped_diffuse(&m, &s, &l, -(-0.6 * 0.36 + 0.8 * 0.48), want); /* N.L = -N.V */
    assert_rgb_near(got, want, 1e-12, "L = -V diffuse");
}

/* ---- lights ---- */

static void test_lights_add_up(void **state) {
    (void)state;
    ht_shading m = scheuermann(50, 0.1, 12, -0.15);
    ht_surface s = surface(0.8, 0.6, 0, -0.6, 0.8, 0, 0.2, 0.1, 1);
    ht_light_ray lights[4] = { light(0.36, 0.48, 0.8), light(-1, 0.2, 0.3),
                               light(0, -5, 1), light(0.1, 0.1, -1) };
    lights[3].color[1] = 4;
    for (int n = 1; n <= HT_MAX_LIGHTS; n++) {
        for (int p = 0; p < 2; p++) {
            double got[3], sum[3] = { 0, 0, 0 }, one[3];
            shade_fns[p](&m, &s, lights, n, got);
            for (int i = 0; i < n; i++) {
                shade_fns[p](&m, &s, &lights[i], 1, one);
                for (int c = 0; c < 3; c++) sum[c] += one[c];
            }
            assert_rgb_near(got, sum, fixture_tolerance[p] * n, "sum of lights");
        }
        double want[3] = { 0, 0, 0 }, one[3];
        for (int i = 0; i < n; i++) {
            ref_shade_scheuermann(&m, &s, &lights[i], one);
            for (int c = 0; c < 3; c++) want[c] += one[c];
        }
        double got[3];
        ht_model_shade_d(&m, &s, lights, n, got);
        assert_rgb_near(got, want, 1e-12, "lights against the reference");
    }
    double none[3] = { 1, 1, 1 };
    ht_model_shade_d(&m, &s, lights, 0, none);
    assert_rgb_near(none, (double[3]){ 0, 0, 0 }, 0, "no light");
}

/* ---- a million random points ---- */

/* Float against double, per channel:
       |f - d| <= (FLOAT_ABS_TOLERANCE + FLOAT_EXP_TOLERANCE * e) * bound
   where bound is the channel's bound of model.h and e the larger exponent.
   Why this shape: float rounds the inputs and the sine to ~6e-8 absolute,
   and sin^e multiplies a sine error by e (d(sin^e) = e sin^(e-1) d sin), so
   the error of a narrow highlight grows with its exponent; the rest stays
   near float epsilon times the output's scale. Measured over 4e6 samples
   of this generator, worst error / bound by exponent: e < 1: 1.7e-6,
   [1,10): 5.2e-6, [10,100): 7.3e-6, [100,1000): 5.7e-5, [1000,10000]:
   5.1e-4, i.e. about max(7e-6, 5e-8 e). The constants are twice that.
   At e = 10000 that is 1e-3 of full scale, a quarter of an 8-bit step: the
   price of evaluating a lobe that narrow in 32 bits, not a flaw to fix
   (the GLSL tiers compute it the same way).
   Points where the geometry itself is ill-conditioned (T nearly cancelled
   by the shift, L nearly opposite V, sin = 0 with 0 < e < 1) are checked
   for finiteness and bounds only: there a 1e-7 rounding of the inputs
   turns a direction by up to 1e-4 rad or moves sin^e by O(1) (measured up
   to 0.24 of the bound), in exact arithmetic as much as in float. */
#define FLOAT_ABS_TOLERANCE 1.5e-5
#define FLOAT_EXP_TOLERANCE 1e-7
#define RANDOM_SAMPLES 1000000

static void random_unit(ht_rng *r, double v[3]) {
    double len2;
    do {
        for (int i = 0; i < 3; i++) v[i] = ht_rng_range(r, -1, 1);
        len2 = ref_dot(v, v);
    } while (len2 > 1 || len2 < 1e-6);
    double inv = 1 / sqrt(len2);
    for (int i = 0; i < 3; i++) v[i] *= inv;
}

/* Mostly unit, often scaled over six decades, sometimes zero or shorter
   than the threshold. Lengths stay clear of the threshold itself, where
   float and double may rightly disagree about having a direction. */
static void random_vector(ht_rng *r, double v[3]) {
    random_unit(r, v);
    double u = ht_rng_unit(r), scale = 1;
    if (u < 0.03) scale = 0;
    else if (u < 0.05) scale = 1e-8;
    else if (u < 0.35) scale = pow(10, ht_rng_range(r, -3, 3));
    for (int i = 0; i < 3; i++) v[i] *= scale;
}

static double random_exponent(ht_rng *r) {
    double u = ht_rng_unit(r);
    if (u < 0.1) return 0;
    if (u < 0.2) return ht_rng_unit(r);
    return pow(10, ht_rng_range(r, 0, 4));
}

static double random_shift(ht_rng *r) {
    return ht_rng_unit(r) < 0.8 ? ht_rng_range(r, -1, 1) : ht_rng_range(r, -100, 100);
}

typedef struct sample {
    ht_shading m;
    ht_surface s;
    ht_light_ray lights[HT_MAX_LIGHTS];
    int light_count;
    bool ill_conditioned;
} sample;

static void random_sample(ht_rng *r, sample *x) {
    memset(x, 0, sizeof *x);
    ht_shading *m = &x->m;
    m->model = ht_rng_unit(r) < 0.15 ? HT_MODEL_KAJIYA_KAY : HT_MODEL_SCHEUERMANN;
    for (int i = 0; i < 3; i++) {
        m->diffuse_color[i] = ht_rng_unit(r);
        m->primary.color[i] = ht_rng_unit(r);
        m->secondary.color[i] = ht_rng_unit(r);
        x->s.base[i] = ht_rng_unit(r);
    }
    m->wrap = ht_rng_unit(r);
    m->primary.exponent = random_exponent(r);
    m->secondary.exponent = random_exponent(r);
    m->primary.shift = random_shift(r);
    m->secondary.shift = random_shift(r);
    x->s.shift_tex = ht_rng_unit(r);
    x->s.sparkle = ht_rng_unit(r);
    x->s.ao = ht_rng_unit(r);
    random_vector(r, x->s.T);
    random_vector(r, x->s.N);
    random_vector(r, x->s.V);
    x->light_count = 1 + (int)(ht_rng_next(r) % HT_MAX_LIGHTS);
    for (int li = 0; li < x->light_count; li++) {
        random_vector(r, x->lights[li].L);
        for (int i = 0; i < 3; i++) x->lights[li].color[i] = ht_rng_range(r, 0, 4);
    }

    /* a few constructed degeneracies, exact and nearly so */
    double u = ht_rng_unit(r), noise = ht_rng_unit(r) < 0.5 ? 1e-9 : 1e-3;
    if (u < 0.02) { /* L = -V (+ noise) */
        for (int i = 0; i < 3; i++)
            x->lights[0].L[i] = -2.5 * x->s.V[i] + noise * ht_rng_range(r, -1, 1);
        x->ill_conditioned = true;
    } else if (u < 0.04 && m->model == HT_MODEL_SCHEUERMANN) { /* T + shift N = 0 (+ noise) */
        m->primary.shift = 1 - (x->s.shift_tex - 0.5);
        double n[3];
        ref_normalize(x->s.N, n);
        for (int i = 0; i < 3; i++) x->s.T[i] = -3 * n[i] + noise * ht_rng_range(r, -1, 1);
        x->ill_conditioned = true;
    } else if (u < 0.06) { /* T = L = V: sin = 0, where sin^e with 0 < e < 1 has an
                              infinite slope and a 1e-7 float sine is not 0 */
        for (int i = 0; i < 3; i++) x->lights[0].L[i] = x->s.V[i] = x->s.T[i];
        x->ill_conditioned = (m->primary.exponent > 0 && m->primary.exponent < 1) ||
                             (m->secondary.exponent > 0 && m->secondary.exponent < 1);
    }
}

typedef struct worst {
    double error, allowed_ratio;
    long sample;
    int channel;
    double exponent, value;
} worst;

static void test_a_million_random_points_are_finite_bounded_and_agree(void **state) {
    (void)state;
    ht_rng r = ht_rng_seed(20240611);
    worst abs_worst = { 0 }, ratio_worst = { 0 };
    long ill = 0;
    for (long n = 0; n < RANDOM_SAMPLES; n++) {
        sample x;
        random_sample(&r, &x);
        double d[3], f[3];
        ht_model_shade_d(&x.m, &x.s, x.lights, x.light_count, d);
        ht_model_shade_f(&x.m, &x.s, x.lights, x.light_count, f);
        double e = fmax(x.m.primary.exponent,
                        x.m.model == HT_MODEL_KAJIYA_KAY ? 0 : x.m.secondary.exponent);
        ill += x.ill_conditioned;
        for (int c = 0; c < 3; c++) {
            double bound = 0;
            for (int li = 0; li < x.light_count; li++)
                bound += x.lights[li].color[c] *
                         (x.m.diffuse_color[c] + x.m.primary.color[c] + x.m.secondary.color[c]);
            /* 1 + a few roundings: the bound and the sum add in different orders */
            if (!isfinite(d[c]) || d[c] < 0 || d[c] > bound * (1 + 1e-12))
                fail_msg("sample %ld channel %d: double %.17g outside [0, %.17g]", n, c, d[c], bound);
            if (!isfinite(f[c]) || f[c] < 0 || f[c] > bound * (1 + 1e-6))
                fail_msg("sample %ld channel %d: float %.17g outside [0, %.17g]", n, c, f[c], bound);
            if (x.ill_conditioned) continue;
            double error = fabs(f[c] - d[c]);
            double allowed = (FLOAT_ABS_TOLERANCE + FLOAT_EXP_TOLERANCE * e) * bound;
            if (error > abs_worst.error)
                abs_worst = (worst){ error, allowed > 0 ? error / allowed : 0, n, c, e, d[c] };
            if (allowed > 0 && error / allowed > ratio_worst.allowed_ratio)
                ratio_worst = (worst){ error, error / allowed, n, c, e, d[c] };
            if (error > allowed)
                fail_msg("sample %ld channel %d: float %.9g, double %.9g, error %.3g > %.3g "
                         "(exponent %g, bound %g)", n, c, f[c], d[c], error, allowed, e, bound);
        }
    }
    print_message("%d samples (%ld ill-conditioned, bounds only): worst |float - double| "
                  "%.3g at sample %ld channel %d (exponent %g, value %g); closest to the "
                  "tolerance: %.0f%% of it at sample %ld (exponent %g, error %.3g)\n",
                  RANDOM_SAMPLES, ill, abs_worst.error, abs_worst.sample, abs_worst.channel,
                  abs_worst.exponent, abs_worst.value, 100 * ratio_worst.allowed_ratio,
                  ratio_worst.sample, ratio_worst.exponent, ratio_worst.error);
}

/* The fit's terms (model_terms.h) are what ht_model_shade_d adds, bit for
   bit: each factor alone with its colour 1 on one channel, for a white
   light with base, ao and sparkle 1 and no shift texture, over random
   vectors of any length (zero ones included), shifts and exponents. */
static void test_light_terms_are_shade_d_bit_for_bit(void **state) {
    (void)state;
    ht_rng r = ht_rng_seed(11);
    for (int n = 0; n < 20000; n++) {
        ht_shading m = { .model = HT_MODEL_SCHEUERMANN, .wrap = ht_rng_unit(&r),
                         .diffuse_color = { 1, 0, 0 }, .primary = { .color = { 0, 1, 0 } },
                         .secondary = { .color = { 0, 0, 1 } } };
        m.primary.exponent = random_exponent(&r), m.primary.shift = random_shift(&r);
        m.secondary.exponent = random_exponent(&r), m.secondary.shift = random_shift(&r);
        ht_transmission t = { .centre = ht_rng_range(&r, -0.5, 0.5), .sharpness = exp2(ht_rng_range(&r, 0, 13)) - 1,
                              .azimuth = random_exponent(&r) };
        ht_surface s = { .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = 1 };
        ht_light_ray light = { .color = { 1, 1, 1 } };
        random_vector(&r, s.T), random_vector(&r, s.N), random_vector(&r, s.V), random_vector(&r, light.L);
        double want[3];
        ht_model_shade_d(&m, &s, &light, 1, want);
        ht_model_light_terms g;
        ht_model_light_terms_init(&s, light.L, &g);
        const double got[3] = { ht_model_wrap_diffuse_d(g.n_dot_l, m.wrap),
                                ht_model_light_highlight(&g, m.primary.shift, m.primary.exponent),
                                ht_model_light_highlight(&g, m.secondary.shift, m.secondary.exponent) };
        assert_memory_equal(got, want, sizeof want);
        double tt = ht_model_transmission_d(&t, s.T, light.L, s.V), tt_got = ht_model_light_transmission(&g, &t);
        assert_memory_equal(&tt_got, &tt, sizeof tt);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parallel_vectors_whose_float_dot_exceeds_one_give_finite_highlights),
        cmocka_unit_test(test_light_and_view_along_the_tangent_shade_diffuse_only),
        cmocka_unit_test(test_near_parallel_vectors_keep_their_sine_in_float),
        cmocka_unit_test(test_exponent_zero_leaves_the_smoothstep_factor),
        cmocka_unit_test(test_smoothstep_edges),
        cmocka_unit_test(test_exponents_up_to_ten_thousand_stay_finite_and_ordered),
        cmocka_unit_test(test_perpendicular_float_vectors_never_exceed_one),
        cmocka_unit_test(test_shifts_of_a_hundred_turn_the_tangent_to_the_normal),
        cmocka_unit_test(test_tangent_along_the_normal_stays_finite),
        cmocka_unit_test(test_tangent_cancelled_by_the_shift_has_no_highlight),
        cmocka_unit_test(test_zero_tangent_shades_diffuse_only),
        cmocka_unit_test(test_short_vectors_above_the_threshold_keep_their_direction),
        cmocka_unit_test(test_zero_normal_light_or_view_follow_the_documented_rules),
        cmocka_unit_test(test_light_opposite_the_view_has_no_highlight),
        cmocka_unit_test(test_lights_add_up),
        cmocka_unit_test(test_a_million_random_points_are_finite_bounded_and_agree),
        cmocka_unit_test(test_light_terms_are_shade_d_bit_for_bit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

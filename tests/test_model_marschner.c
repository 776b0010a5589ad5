/* test_model_marschner.c — the Marschner oracle (runtime/shading/model_marschner.c)
   against published behaviour, not against itself:
   - the white furnace (pbrt-v4's hair test in spirit): with sigma_a = 0 the
     integral over the sphere of the scattering times cos(theta_i), i.e. of
     fibre() under model_marschner.h's normalisation, is within [0.95, 1.05]
     for beta_R from 0.1 to 0.9 radians and several viewing angles;
   - d'Eon 2011: the integral of M times cos(theta_i) over theta_i is 1;
   - Marschner 2003: the lobes peak at theta_h = alpha_p; A_R at h = 0,
     theta_d = 0 is the normal-incidence Fresnel ((eta-1)/(eta+1))^2, and
     N_R at phi = 0 is that over |2 dphi/dh| = 4; N_TT at phi = pi is
     (1-F0)^2 exp(-2 sigma_a) / (2 |6c/pi - 2|); the integral of N_p over
     phi is the mean of A_p over h (the change of variables the cubic's
     roots must honour, and TRT's spread caustic must keep);
   - no NaN or Inf at the extremes and over 10^5 random samples (1000
     materials; the oracle integrates TRT and the rest adaptively, so more
     would cost seconds);
   - an independent reference (tests/data/marschner_reference.h, mpmath,
     tools/marschner_reference.py): each lobe's M_p, A_p, N_p across theta_i,
     theta_r to 89.99 degrees, phi, eta and absorption to 1e-6 (or 1e-9
     absolute), each lobe's share of the white furnace, the caustic's width
     (N_TRT's Fourier coefficients) and the absorption path's length. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include <hairtier/model.h>
#include <hairtier/model_marschner.h>
#include "data/marschner_reference.h"
#include "rng.h"

#define DEG (HT_PI / 180)

#define assert_double_equal(got, want, tolerance)                                               \
    do {                                                                                        \
        double got_ = (got), want_ = (want);                                                    \
        if (!(fabs(got_ - want_) <= (tolerance))) fail_msg("%s = %.17g, want %.17g", #got, got_, want_); \
    } while (0)

static ht_marschner default_fibre(void) {
    return (ht_marschner){ .absorption = { 0, 0, 0 }, .shift_r = -7 * DEG, .width_r = 7 * DEG, .eta = 1.55 };
}

/* Midpoint rule over theta in [-pi/2, pi/2]. */
static double integrate_cos_m(double v, double theta_r, int steps) {
    double sum = 0, d = HT_PI / steps;
    for (int k = 0; k < steps; k++) {
        double t = -HT_PI / 2 + (k + 0.5) * d;
        sum += ht_marschner_longitudinal_v(v, sin(t), sin(theta_r)) * cos(t) * d;
    }
    return sum;
}

static void longitudinal_is_normalised(void **state) {
    (void)state;
    const double widths[] = { 0.02, 0.1, 0.3, 0.9, 1.8 };
    const double thetas[] = { -1.5, -0.7, 0, 0.4, 1.2, HT_PI / 2 };
    for (size_t w = 0; w < sizeof widths / sizeof *widths; w++)
        for (size_t t = 0; t < sizeof thetas / sizeof *thetas; t++) {
            double v = widths[w] * widths[w];
            double integral = integrate_cos_m(v, thetas[t], 20000);
            if (fabs(integral - 1) > 2e-3)
                fail_msg("beta %g theta_r %g: integral of M cos = %.6f", widths[w], thetas[t], integral);
        }
}

/* The whole fibre() integrated over the sphere of light directions
   (midpoint rule in theta_i and phi; fibre is even in phi). */
/* The fibre is sum_p M_p(theta_i) N_p(phi) (model_marschner.h), so the
   sphere's midpoint sum of fibre() is the sum over p of a sum over theta_i
   times a sum over phi; that fibre() is that sum of products is checked on
   one row of the grid per theta_r (a product per point costs 120 times the
   integrals). */
static void white_furnace(void **state) {
    (void)state;
    const double thetas_r[] = { -60 * DEG, 0, 35 * DEG, 75 * DEG };
    double lowest = 2, highest = 0;
    for (double beta = 0.1; beta <= 0.9 + 1e-9; beta += 0.4) {
        ht_marschner m = default_fibre();
        m.width_r = beta;
        for (size_t r = 0; r < sizeof thetas_r / sizeof *thetas_r; r++) {
            enum { THETAS = 120, PHIS = 90 };
            const double dt = HT_PI / THETAS, dp = HT_PI / PHIS, sin_r = sin(thetas_r[r]);
            double n[HT_LOBE_COUNT][PHIS][3], energy = 0;
            for (int p = 0; p < HT_LOBE_COUNT; p++)
                for (int j = 0; j < PHIS; j++)
                    ht_marschner_azimuthal(&m, (ht_marschner_lobe)p, cos(thetas_r[r]), (j + 0.5) * dp, n[p][j]);
            for (int p = 0; p < HT_LOBE_COUNT; p++) {
                double m_sum = 0, n_sum = 0;
                for (int k = 0; k < THETAS; k++) {
                    double theta_i = -HT_PI / 2 + (k + 0.5) * dt;
                    m_sum += ht_marschner_longitudinal(&m, (ht_marschner_lobe)p, sin(theta_i), sin_r) * cos(theta_i) * dt;
                }
                for (int j = 0; j < PHIS; j++) n_sum += n[p][j][0] * dp;
                energy += 2 * m_sum * n_sum;
            }
            const double theta_i = 20 * DEG; /* the row where fibre() itself is summed */
            for (int j = 0; j < PHIS; j++) {
                double rgb[3], want = 0;
                ht_marschner_fibre(&m, sin(theta_i), sin_r, cos((j + 0.5) * dp), rgb);
                for (int p = 0; p < HT_LOBE_COUNT; p++)
                    want += ht_marschner_longitudinal(&m, (ht_marschner_lobe)p, sin(theta_i), sin_r) * n[p][j][0];
                assert_double_equal(rgb[0], want, 1e-12 * want);
            }
            print_message("furnace beta %.1f theta_r %+.0f deg: %.4f\n", beta, thetas_r[r] / DEG, energy);
            if (energy < lowest) lowest = energy;
            if (energy > highest) highest = energy;
            assert_true(energy >= 0.95 && energy <= 1.05);
        }
    }
    print_message("furnace over beta 0.1..0.9 rad: [%.4f, %.4f]\n", lowest, highest);
}

static void azimuthal_integral_is_mean_attenuation(void **state) {
    (void)state;
    ht_marschner m = default_fibre();
    m.absorption[0] = 0.3, m.absorption[1] = 1, m.absorption[2] = 4;
    const double cos_ds[] = { 1, 0.9, 0.6, 0.2 };
    for (size_t c = 0; c < sizeof cos_ds / sizeof *cos_ds; c++)
        for (int p = 0; p < HT_LOBE_COUNT; p++) {
            double n_int[3] = { 0 }, a_mean[3] = { 0 };
            const int steps = p >= HT_LOBE_TRT ? 2000 : 50000; /* N_TRT is smooth, the rest constant */
            for (int k = 0; k < steps; k++) {
                double phi = -HT_PI + (k + 0.5) * 2 * HT_PI / steps, n[3];
                ht_marschner_azimuthal(&m, (ht_marschner_lobe)p, cos_ds[c], phi, n);
                for (int i = 0; i < 3; i++) n_int[i] += n[i] * 2 * HT_PI / steps;
            }
            const int hs = 20000;
            for (int k = 0; k < hs; k++) {
                double h = -1 + (k + 0.5) * 2.0 / hs, a[3];
                ht_marschner_attenuation(&m, (ht_marschner_lobe)p, cos_ds[c], h, a);
                for (int i = 0; i < 3; i++) a_mean[i] += a[i] / hs;
            }
            double below = 2e-3, above = below;
            for (int i = 0; i < 3; i++)
                if (n_int[i] < a_mean[i] * (1 - below) - 1e-6 || n_int[i] > a_mean[i] * (1 + above) + 1e-6)
                    fail_msg("lobe %d cos_d %g ch %d: integral of N %.6f, mean A %.6f", p, cos_ds[c], i,
                             n_int[i], a_mean[i]);
        }
}

static void lobes_peak_at_their_shift(void **state) {
    (void)state;
    const double shifts[] = { -7 * DEG, -10 * DEG, -5 * DEG, 4 * DEG };
    for (size_t s = 0; s < sizeof shifts / sizeof *shifts; s++) {
        ht_marschner m = default_fibre();
        m.shift_r = shifts[s];
        for (int p = 0; p < HT_LOBE_COUNT; p++) {
            /* theta_d = 0: theta_i = theta_r = theta_h */
            double best = -1, best_h = 0;
            for (double th = -40 * DEG; th <= 40 * DEG; th += 0.005 * DEG) {
                double v = ht_marschner_longitudinal(&m, (ht_marschner_lobe)p, sin(th), sin(th));
                if (v > best) best = v, best_h = th;
            }
            double alpha = ht_marschner_shift(&m, (ht_marschner_lobe)p);
            if (fabs(best_h - alpha) > 0.05 * DEG)
                fail_msg("lobe %d alpha_R %g deg: peak at %.3f deg, alpha_p %.3f deg", p, shifts[s] / DEG,
                         best_h / DEG, alpha / DEG);
        }
    }
    ht_marschner m = default_fibre();
    assert_double_equal(ht_marschner_shift(&m, HT_LOBE_TT), 3.5 * DEG, 1e-12);
    assert_double_equal(ht_marschner_shift(&m, HT_LOBE_TRT), 10.5 * DEG, 1e-12);
    assert_double_equal(ht_marschner_width(&m, HT_LOBE_TT), 3.5 * DEG, 1e-12);
    assert_double_equal(ht_marschner_width(&m, HT_LOBE_TRT), 14 * DEG, 1e-12);
}

static void reflection_at_normal_incidence_is_fresnel(void **state) {
    (void)state;
    const double etas[] = { 1.1, 1.33, 1.55, 2.0, 3.0 };
    for (size_t e = 0; e < sizeof etas / sizeof *etas; e++) {
        ht_marschner m = default_fibre();
        m.eta = etas[e];
        double f0 = (m.eta - 1) / (m.eta + 1);
        f0 *= f0;
        double a[3], n[3];
        ht_marschner_attenuation(&m, HT_LOBE_R, 1, 0, a);
        assert_double_equal(a[0], f0, 1e-12);
        ht_marschner_azimuthal(&m, HT_LOBE_R, 1, 0, n);
        assert_double_equal(n[0], f0 / 4, 1e-12);
        /* grazing rays reflect entirely */
        ht_marschner_attenuation(&m, HT_LOBE_R, 1, 1, a);
        assert_double_equal(a[0], 1, 1e-12);
    }
}

static void transmission_through_the_centre(void **state) {
    (void)state;
    ht_marschner m = default_fibre();
    m.absorption[0] = 0, m.absorption[1] = 0.5, m.absorption[2] = 2;
    double f0 = (m.eta - 1) / (m.eta + 1);
    f0 *= f0;
    double c = asin(1 / m.eta), n[3];
    ht_marschner_azimuthal(&m, HT_LOBE_TT, 1, HT_PI, n);
    for (int i = 0; i < 3; i++) {
        double want = (1 - f0) * (1 - f0) * exp(-2 * m.absorption[i]) / (2 * fabs(6 * c / HT_PI - 2));
        assert_double_equal(n[i], want, 1e-9 * want + 1e-15);
    }
}

static void assert_finite_rgb(const double rgb[3], const char *what) {
    for (int i = 0; i < 3; i++)
        if (!isfinite(rgb[i]) || rgb[i] < 0) fail_msg("%s: channel %d is %g", what, i, rgb[i]);
}

static void extremes_are_finite(void **state) {
    (void)state;
    const double absorptions[] = { 0, 50 };
    const double shifts[] = { -20 * DEG, 0, 20 * DEG };
    const double widths[] = { 1 * DEG, 60 * DEG };
    const double etas[] = { 1.1, 3 };
    const double sines[] = { -1, -0.999999, -0.5, 0, 1e-12, 0.5, 0.999999, 1 };
    const double cos_phis[] = { -1, -0.999999, 0, 0.999999, 1 };
    for (size_t a = 0; a < 2; a++)
        for (size_t s = 0; s < 3; s++)
            for (size_t w = 0; w < 2; w++)
                for (size_t e = 0; e < 2; e++) {
                    ht_marschner m = { { absorptions[a], absorptions[a], 0 }, shifts[s], widths[w], etas[e] };
                    for (size_t i = 0; i < 8; i++)
                        for (size_t r = 0; r < 8; r++)
                            for (size_t f = 0; f < 5; f++) {
                                double rgb[3];
                                ht_marschner_fibre(&m, sines[i], sines[r], cos_phis[f], rgb);
                                assert_finite_rgb(rgb, "fibre at an extreme");
                            }
                    /* N_REST is uniform in phi (model_marschner.h): one azimuth */
                    for (int p = 0; p < HT_LOBE_COUNT; p++)
                        for (double cd = 0; cd <= 1; cd += 0.125)
                            for (double phi = -7; phi <= 7; phi += p == HT_LOBE_REST ? 15 : p == HT_LOBE_TRT ? 0.25 : 0.01) {
                                double n[3];
                                ht_marschner_azimuthal(&m, (ht_marschner_lobe)p, cd, phi, n);
                                assert_finite_rgb(n, "N_p");
                            }
                }
    /* degenerate vectors: no tangent, L or V along it, L = -V, zero L */
    ht_marschner m = default_fibre();
    const double zero[3] = { 0, 0, 0 }, t[3] = { 0, 1, 0 }, l[3] = { 0, 0, 1 }, minus_l[3] = { 0, 0, -1 };
    double rgb[3];
    ht_marschner_fibre_vectors(&m, zero, l, l, rgb);
    assert_true(rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0);
    ht_marschner_fibre_vectors(&m, t, zero, l, rgb);
    assert_true(rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0);
    ht_marschner_fibre_vectors(&m, t, t, l, rgb);
    assert_finite_rgb(rgb, "L along T");
    ht_marschner_fibre_vectors(&m, t, l, t, rgb);
    assert_finite_rgb(rgb, "V along T");
    ht_marschner_fibre_vectors(&m, t, l, minus_l, rgb);
    assert_finite_rgb(rgb, "L = -V");
    assert_true(rgb[0] > 0); /* TT glows straight through */
}

static void random_vec(ht_rng *r, double out[3], double scale) {
    for (int i = 0; i < 3; i++) out[i] = (ht_rng_unit(r) * 2 - 1) * scale;
}

static void random_samples_are_finite(void **state) {
    (void)state;
    ht_rng rng = ht_rng_seed(12);
    ht_shading s = { .model = HT_MODEL_MARSCHNER };
    double most = 0;
    for (int n = 0; n < 100000; n++) {
        if (n % 100 == 0) {
            for (int i = 0; i < 3; i++) {
                s.diffuse_color[i] = ht_rng_unit(&rng);
                s.marschner.absorption[i] = 50 * ht_rng_unit(&rng);
            }
            s.marschner.shift_r = (ht_rng_unit(&rng) * 40 - 20) * DEG;
            s.marschner.width_r = (1 + 59 * ht_rng_unit(&rng)) * DEG;
            s.marschner.eta = 1.1 + 1.9 * ht_rng_unit(&rng);
        }
        ht_surface surf = { .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = 1 };
        random_vec(&rng, surf.T, n % 7 == 0 ? 1e-7 : 1);
        random_vec(&rng, surf.N, 1);
        random_vec(&rng, surf.V, 1);
        ht_light_ray light = { .color = { 1, 1, 1 } };
        random_vec(&rng, light.L, 1);
        double rgb[3];
        ht_model_shade_d(&s, &surf, &light, 1, rgb);
        assert_finite_rgb(rgb, "random sample");
        for (int i = 0; i < 3; i++) most = fmax(most, rgb[i]);
    }
    print_message("largest channel over 10^5 random samples: %.3f\n", most);
}

/* The oracle's shade is diffuse * sin(T,L) plus the fibre, scaled by base,
   light colour and ao, summed over lights. */
static void shade_combines_diffuse_and_fibre(void **state) {
    (void)state;
    ht_shading s = { .model = HT_MODEL_MARSCHNER, .diffuse_color = { 0.2, 0.1, 0.05 },
                     .marschner = default_fibre() };
    s.marschner.absorption[0] = 0.2, s.marschner.absorption[1] = 0.6, s.marschner.absorption[2] = 1.4;
    ht_surface surf = { .T = { 0, 2, 0 }, .N = { 0, 0, 1 }, .V = { 0, 0.3, 1 },
                        .base = { 0.5, 1, 0.25 }, .shift_tex = 0.5, .sparkle = 1, .ao = 0.8 };
    ht_light_ray lights[2] = { { .L = { 0.5, -0.2, 1 }, .color = { 1, 2, 0.5 } },
                               { .L = { 0, 0.1, -1 }, .color = { 0.3, 0.3, 0.3 } } };
    double rgb[3], want[3] = { 0, 0, 0 };
    ht_model_shade_d(&s, &surf, lights, 2, rgb);
    double T[3] = { 0, 1, 0 }, V[3];
    double vl = sqrt(0.09 + 1);
    V[0] = 0, V[1] = 0.3 / vl, V[2] = 1 / vl;
    for (int li = 0; li < 2; li++) {
        double L[3], len = 0, fibre[3];
        for (int i = 0; i < 3; i++) len += lights[li].L[i] * lights[li].L[i];
        for (int i = 0; i < 3; i++) L[i] = lights[li].L[i] / sqrt(len);
        ht_marschner_fibre_vectors(&s.marschner, T, L, V, fibre);
        double sin_tl = sqrt(1 - L[1] * L[1]);
        for (int i = 0; i < 3; i++)
            want[i] += (sin_tl * s.diffuse_color[i] + fibre[i]) * surf.base[i] * lights[li].color[i] * surf.ao;
    }
    for (int i = 0; i < 3; i++) assert_double_equal(rgb[i], want[i], 1e-12);
    double rgb_f[3];
    ht_model_shade_f(&s, &surf, lights, 2, rgb_f);
    for (int i = 0; i < 3; i++) assert_double_equal(rgb_f[i], want[i], 1e-5 * (1 + want[i]));
}

/* The reference table (tests/data/marschner_reference.h, made by
   tools/marschner_reference.py in mpmath from the header's equations):
   every value within 1e-6 of itself or 1e-9 absolute, the oracle's stated
   precision. The worst errors seen are printed (docs/accuracy.md). */
typedef struct worst {
    double rel, abs;
} worst;

static void check_value(worst *w, int row, int ch, double got, double want) {
    double err = fabs(got - want);
    if (fabs(want) >= 1e-9) w->rel = fmax(w->rel, err / fabs(want));
    w->abs = fmax(w->abs, err);
    if (!(err <= 1e-6 * fabs(want) + 1e-9)) {
        const struct ht_marschner_reference *r = &ht_marschner_reference[row];
        fail_msg("reference row %d ('%c' lobe %d, in %g %g %g %g %g %g) channel %d: oracle %.12g, reference %.12g",
                 row, r->kind, r->lobe, r->in[0], r->in[1], r->in[2], r->in[3], r->in[4], r->in[5], ch, got, want);
    }
}

/* A fibre of index in[0] and absorption in[1..3] (the A, N and F rows). */
static ht_marschner reference_fibre(const double in[6]) {
    return (ht_marschner){ .absorption = { in[1], in[2], in[3] }, .shift_r = -7 * DEG, .width_r = 7 * DEG,
                           .eta = in[0] };
}

/* The oracle's value of one row, RGB (M: grey). */
static void evaluate_row(const struct ht_marschner_reference *r, double out[3]) {
    ht_marschner m = reference_fibre(r->in);
    ht_marschner_lobe p = (ht_marschner_lobe)r->lobe;
    switch (r->kind) {
    case 'M':
        m.shift_r = r->in[0] * DEG, m.width_r = r->in[1] * DEG;
        out[0] = out[1] = out[2] = ht_marschner_longitudinal(&m, p, sin(r->in[2] * DEG), sin(r->in[3] * DEG));
        break;
    case 'A': ht_marschner_attenuation(&m, p, cos(r->in[4] * DEG), r->in[5], out); break;
    default: ht_marschner_azimuthal(&m, p, cos(r->in[4] * DEG), r->in[5] * DEG, out); break;
    }
}

static void check_reference(char kind, int lobe, const char *what) {
    worst w = { 0, 0 };
    int rows = 0;
    for (int i = 0; i < HT_MARSCHNER_REFERENCE_ROWS; i++) {
        const struct ht_marschner_reference *r = &ht_marschner_reference[i];
        if (r->kind != kind || (lobe >= 0 && r->lobe != lobe)) continue;
        double got[3];
        evaluate_row(r, got);
        for (int c = 0; c < (kind == 'M' ? 1 : 3); c++) check_value(&w, i, c, got[c], r->out[c]);
        rows++;
    }
    assert_true(rows > 0);
    print_message("%s against the mpmath reference, %d rows: worst relative %.2e, absolute %.2e\n", what, rows, w.rel,
                  w.abs);
}

static void reference_longitudinal(void **state) {
    (void)state;
    check_reference('M', -1, "M_p");
}

static void reference_attenuation(void **state) {
    (void)state;
    check_reference('A', -1, "A_p");
}

static void reference_azimuthal_r(void **state) {
    (void)state;
    check_reference('N', HT_LOBE_R, "N_R");
}

static void reference_azimuthal_tt(void **state) {
    (void)state;
    check_reference('N', HT_LOBE_TT, "N_TT");
}

static void reference_azimuthal_trt(void **state) {
    (void)state;
    check_reference('N', HT_LOBE_TRT, "N_TRT");
}

static void reference_rest(void **state) {
    (void)state;
    check_reference('N', HT_LOBE_REST, "N_rest");
}

/* Per lobe, without absorption: the integral of M_p N_p cos(theta_i) over
   the sphere of light directions is the lobe's share of the energy, the
   mean of A_p over h (reference 'E' rows). The sum is blind to how Fresnel
   splits the light; each share is not. M_p N_p is a product of a function
   of theta_i and one of phi, so the sphere's integral is a product of two. */
static void furnace_per_lobe(void **state) {
    (void)state;
    worst w = { 0, 0 };
    for (int i = 0; i < HT_MARSCHNER_REFERENCE_ROWS; i++) {
        const struct ht_marschner_reference *r = &ht_marschner_reference[i];
        if (r->kind != 'E') continue;
        ht_marschner m = { .absorption = { 0, 0, 0 }, .shift_r = -7 * DEG, .width_r = 0.2, .eta = r->in[0] };
        ht_marschner_lobe p = (ht_marschner_lobe)r->lobe;
        double theta_r = r->in[1] * DEG, m_int = 0, n_int = 0, n[3];
        /* midpoint rules; N_p is even in phi; N_R and N_TT near theta_r = 90 degrees
           have a kink and a narrow dip (the parallel polarisation's critical angle) */
        const int thetas = 4000, phis = p <= HT_LOBE_TT ? 65536 : 1024;
        for (int k = 0; k < thetas; k++) {
            double t = -HT_PI / 2 + (k + 0.5) * HT_PI / thetas;
            m_int += ht_marschner_longitudinal(&m, p, sin(t), sin(theta_r)) * cos(t) * HT_PI / thetas;
        }
        for (int j = 0; j < phis; j++) {
            ht_marschner_azimuthal(&m, p, cos(theta_r), (j + 0.5) * HT_PI / phis, n);
            n_int += 2 * n[0] * HT_PI / phis;
        }
        double err = fabs(m_int * n_int - r->out[0]);
        w.abs = fmax(w.abs, err);
        if (err > 1e-4)
            fail_msg("lobe %d eta %g theta_r %g deg: energy %.6f, reference %.6f", r->lobe, r->in[0], r->in[1],
                     m_int * n_int, r->out[0]);
    }
    print_message("energy per lobe against the reference: worst %.2e\n", w.abs);
}

/* The caustic's width: N_TRT is the smooth fibre's TRT convolved with a
   Gaussian of sigma 15 degrees, so its k-th Fourier coefficient is the
   smooth fibre's times exp(-k^2 sigma^2 / 2) (reference 'F' rows: 0.87 of
   it at k = 2; 0.98 for a 5 degree caustic). The trapezoid rule on the
   periodic, smooth N_TRT converges geometrically. */
static void caustic_width(void **state) {
    (void)state;
    worst w = { 0, 0 };
    for (int i = 0; i < HT_MARSCHNER_REFERENCE_ROWS; i++) {
        const struct ht_marschner_reference *r = &ht_marschner_reference[i];
        if (r->kind != 'F') continue;
        ht_marschner m = reference_fibre(r->in);
        double sum[3] = { 0, 0, 0 }, n[3];
        const int phis = 360;
        for (int j = 0; j < phis; j++) {
            double phi = -HT_PI + j * 2 * HT_PI / phis;
            ht_marschner_azimuthal(&m, HT_LOBE_TRT, cos(r->in[4] * DEG), phi, n);
            for (int c = 0; c < 3; c++) sum[c] += n[c] * cos(r->lobe * phi) * 2 * HT_PI / phis;
        }
        for (int c = 0; c < 3; c++) check_value(&w, i, c, sum[c], r->out[c]);
    }
    print_message("N_TRT's Fourier coefficients against the reference: worst relative %.2e, absolute %.2e\n", w.rel,
                  w.abs);
}

/* The internal path of a ray entering at h, in fibre radii: 2 cos(gamma_t)
   across the cross-section, stretched by 1 / cos(theta_t) along the fibre
   (sin(gamma_t) = h / eta', sin(theta_t) = sin(theta_r) / eta). */
static void absorption_path(void **state) {
    (void)state;
    const double etas[] = { 1.33, 1.55, 2.0 }, thetas[] = { 0, 30, -60, 80, 89 }, hs[] = { 0, 0.3, -0.7, 0.95 };
    for (size_t e = 0; e < 3; e++)
        for (size_t t = 0; t < 5; t++)
            for (size_t k = 0; k < 4; k++) {
                ht_marschner clear = { .absorption = { 0, 0, 0 }, .eta = etas[e] };
                ht_marschner dyed = { .absorption = { 0.3, 1, 3 }, .eta = etas[e] };
                double s = sin(thetas[t] * DEG), c = cos(thetas[t] * DEG);
                double eta_perp = sqrt(etas[e] * etas[e] - s * s) / c;
                double cos_gt = sqrt(1 - hs[k] * hs[k] / (eta_perp * eta_perp));
                double cos_tt = sqrt(1 - s * s / (etas[e] * etas[e]));
                double a0[3], a[3];
                ht_marschner_attenuation(&clear, HT_LOBE_TT, c, hs[k], a0);
                ht_marschner_attenuation(&dyed, HT_LOBE_TT, c, hs[k], a);
                for (int i = 0; i < 3; i++) {
                    double want = a0[i] * exp(-2 * dyed.absorption[i] * cos_gt / cos_tt);
                    if (fabs(a[i] - want) > 1e-12 * want + 1e-300)
                        fail_msg("eta %g theta_r %g h %g channel %d: A_TT %.15g, path says %.15g", etas[e], thetas[t],
                                 hs[k], i, a[i], want);
                }
            }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(longitudinal_is_normalised),
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(azimuthal_integral_is_mean_attenuation),
        cmocka_unit_test(lobes_peak_at_their_shift),
        cmocka_unit_test(reflection_at_normal_incidence_is_fresnel),
        cmocka_unit_test(transmission_through_the_centre),
        cmocka_unit_test(extremes_are_finite),
        cmocka_unit_test(random_samples_are_finite),
        cmocka_unit_test(shade_combines_diffuse_and_fibre),
        cmocka_unit_test(reference_longitudinal),
        cmocka_unit_test(reference_attenuation),
        cmocka_unit_test(reference_azimuthal_r),
        cmocka_unit_test(reference_azimuthal_tt),
        cmocka_unit_test(reference_azimuthal_trt),
        cmocka_unit_test(reference_rest),
        cmocka_unit_test(furnace_per_lobe),
        cmocka_unit_test(caustic_width),
        cmocka_unit_test(absorption_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

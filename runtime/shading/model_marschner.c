/* model_marschner.c — Marschner's fibre model, the equations of
   model_marschner.h in double precision. The tier that draws it reads M,
   the rest and N_TRT from lookup textures baked from these functions and
   evaluates N_R and N_TT itself, in float, from the same equations written
   in GLSL (shadergen/emit_marschner.c: the Fresnel below and the cubic's
   roots as cubic_roots finds them); the marschner probe holds the two
   together (tests/test_render_marschner.c). */
#include <hairtier/model_marschner.h>

#include <math.h>


static double clamp1(double x) { return x < -1 ? -1 : (x > 1 ? 1 : x); }

double ht_marschner_shift(const ht_marschner *m, ht_marschner_lobe p) {
    switch (p) {
    case HT_LOBE_R: return m->shift_r;
    case HT_LOBE_TT: return -m->shift_r / 2;
    case HT_LOBE_TRT: return -3 * m->shift_r / 2;
    default: return 0; /* the rest is spread out: no shift (pbrt-v4) */
    }
}

double ht_marschner_width(const ht_marschner *m, ht_marschner_lobe p) {
    switch (p) {
    case HT_LOBE_R: return m->width_r;
    case HT_LOBE_TT: return m->width_r / 2;
    default: return 2 * m->width_r; /* TRT, and the rest as TRT */
    }
}

/* log I0(x), x >= 0: the power series below 30 (it converges to full
   precision there), the asymptotic expansion above (error < 1e-8). */
static double log_bessel_i0(double x) {
    if (x < 30) {
        double q = x * x / 4, term = 1, sum = 1;
        for (int k = 1; k < 200 && term > 1e-17 * sum; k++) {
            term *= q / ((double)k * k);
            sum += term;
        }
        return log(sum);
    }
    double r = 1 / x;
    double series = 1 + r * (1.0 / 8 + r * (9.0 / 128 + r * (225.0 / 3072 + r * 11025.0 / 98304)));
    return x - 0.5 * log(2 * HT_PI * x) + log(series);
}

double ht_marschner_longitudinal_v(double v, double sin_i, double sin_r) {
    sin_i = clamp1(sin_i);
    sin_r = clamp1(sin_r);
    double cos_i = sqrt(1 - sin_i * sin_i), cos_r = sqrt(1 - sin_r * sin_r);
    /* log(2 v sinh(1/v)) without overflowing sinh for narrow lobes */
    double log_norm = log(v) + 1 / v + log1p(-exp(-2 / v));
    return exp(log_bessel_i0(cos_i * cos_r / v) - sin_i * sin_r / v - log_norm);
}

double ht_marschner_longitudinal(const ht_marschner *m, ht_marschner_lobe p,
                                 double sin_i, double sin_r) {
    /* Rotating theta_r by -2 alpha centres the lobe on theta_h = alpha; a
       rotation past a pole folds back (|cos|), which keeps the integral 1. */
    double two_alpha = 2 * ht_marschner_shift(m, p);
    sin_r = clamp1(sin_r);
    double cos_r = sqrt(1 - sin_r * sin_r);
    double sin_rot = clamp1(sin_r * cos(two_alpha) - cos_r * sin(two_alpha));
    double beta = ht_marschner_width(m, p);
    return ht_marschner_longitudinal_v(beta * beta, sin_i, sin_rot);
}

/* Bravais' indices of the fibre's cross-section seen at theta_r. */
static void bravais(double eta, double cos_theta_r, double *eta_perp, double *eta_par) {
    double c = fmax(fmin(cos_theta_r, 1), 1e-9);
    double root = sqrt(eta * eta - (1 - c * c));
    *eta_perp = root / c;
    *eta_par = eta * eta * c / root;
}

/* Dielectric reflectance for one polarisation; `parallel` picks which. */
static double fresnel_one(double n, double cos_i, double sin_i, bool parallel) {
    double sin_t = sin_i / n;
    if (sin_t >= 1) return 1; /* total internal reflection (n < 1) */
    double cos_t = sqrt(1 - sin_t * sin_t);
    double num = parallel ? n * cos_i - cos_t : cos_i - n * cos_t;
    double den = parallel ? n * cos_i + cos_t : cos_i + n * cos_t;
    if (!(den > 0)) return 1;
    double r = num / den;
    return r * r;
}

double ht_marschner_fresnel(double eta, double cos_theta_r, double h) {
    double sin_g = fabs(clamp1(h));
    double cos_g = sqrt(1 - sin_g * sin_g);
    if (cos_g <= 0) return 1; /* grazing */
    double eta_perp, eta_par;
    bravais(eta, cos_theta_r, &eta_perp, &eta_par);
    return 0.5 * (fresnel_one(eta_perp, cos_g, sin_g, false) + fresnel_one(eta_par, cos_g, sin_g, true));
}

void ht_marschner_attenuation(const ht_marschner *m, ht_marschner_lobe p,
                              double cos_theta_r, double h, double out[3]) {
    h = clamp1(h);
    double f = ht_marschner_fresnel(m->eta, cos_theta_r, h);
    if (p == HT_LOBE_R) {
        out[0] = out[1] = out[2] = f;
        return;
    }
    double eta_perp, eta_par;
    bravais(m->eta, cos_theta_r, &eta_perp, &eta_par);
    double sin_gt = h / eta_perp;
    double cos_gt = sqrt(1 - sin_gt * sin_gt);
    double c = fmax(fmin(cos_theta_r, 1), 0);
    double sin_tt = sqrt(1 - c * c) / m->eta;
    double cos_tt = sqrt(1 - sin_tt * sin_tt);
    /* The internal reflections have the entry's reflectance: a dielectric
       interface reflects the same both ways. */
    double through = (1 - f) * (1 - f);
    for (int i = 0; i < 3; i++) {
        double t = exp(-2 * m->absorption[i] * cos_gt / cos_tt);
        if (p == HT_LOBE_TT) out[i] = through * t;
        else if (p == HT_LOBE_TRT) out[i] = through * f * t * t;
        else /* the rest of the series: (1-F)^2 F^2 T^3 / (1 - F T); 0 in the limit F T -> 1 */
            out[i] = 1 - f * t > 1e-12 ? through * f * f * t * t * t / (1 - f * t) : 0;
    }
}

/* Real roots of x^3 + P x + Q = 0, polished by Newton's method. */
static int cubic_roots(double P, double Q, double roots[3]) {
    int n;
    double d = Q * Q / 4 + P * P * P / 27;
    if (d > 0) {
        double s = sqrt(d);
        roots[0] = cbrt(-Q / 2 + s) + cbrt(-Q / 2 - s);
        n = 1;
    } else if (P == 0) {
        roots[0] = 0;
        n = 1;
    } else {
        double r = 2 * sqrt(-P / 3);
        double angle = acos(clamp1(3 * Q / (P * r))) / 3;
        for (int k = 0; k < 3; k++) roots[k] = r * cos(angle - 2 * HT_PI * k / 3);
        n = 3;
    }
    for (int i = 0; i < n; i++)
        for (int it = 0; it < 2; it++) {
            double x = roots[i], slope = 3 * x * x + P;
            if (fabs(slope) > 1e-12) roots[i] = x - (x * x * x + P * x + Q) / slope;
        }
    return n;
}

void ht_marschner_azimuthal(const ht_marschner *m, ht_marschner_lobe p,
                            double cos_theta_r, double phi, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    if (p == HT_LOBE_REST) { /* uniform in phi: the mean of A over h, over 2 pi */
        const int steps = 64;
        for (int k = 0; k < steps; k++) {
            double g = -HT_PI / 2 + (k + 0.5) * HT_PI / steps, a[3];
            ht_marschner_attenuation(m, p, cos_theta_r, sin(g), a);
            /* dh = cos(gamma) dgamma; the mean over h in [-1, 1] halves it */
            for (int i = 0; i < 3; i++) out[i] += a[i] * cos(g) * (HT_PI / steps) / (2 * 2 * HT_PI);
        }
        return;
    }
    double phi_w = remainder(phi, 2 * HT_PI); /* [-pi, pi] */
    if (!isfinite(phi_w)) phi_w = 0;
    double eta_perp, eta_par;
    bravais(m->eta, cos_theta_r, &eta_perp, &eta_par);
    double c = asin(1 / eta_perp);
    /* phi(gamma) = a1 gamma + a3 gamma^3 + p pi (Marschner 2003, eq. 10) */
    const double k_p = (double)p; /* the lobe's number of internal paths */
    double a1 = 6 * k_p * c / HT_PI - 2, a3 = -8 * k_p * c / (HT_PI * HT_PI * HT_PI);
    if (p == HT_LOBE_TRT) { /* the caustic, spread: the integral over h */
        const int steps = 64;
        const double dg = HT_PI / steps, w = HT_MARSCHNER_CAUSTIC_WIDTH;
        for (int k = 0; k < steps; k++) {
            double g = -HT_PI / 2 + (k + 0.5) * dg, a[3];
            double d = remainder(phi_w - (a1 * g + a3 * g * g * g + k_p * HT_PI), 2 * HT_PI), spread = 0;
            for (int j = -1; j <= 1; j++) spread += exp(-(d + 2 * HT_PI * j) * (d + 2 * HT_PI * j) / (2 * w * w));
            spread /= sqrt(2 * HT_PI) * w;
            ht_marschner_attenuation(m, p, cos_theta_r, sin(g), a);
            /* A(h) / 2 dh, dh = cos(gamma) dgamma */
            for (int ch = 0; ch < 3; ch++) out[ch] += a[ch] * cos(g) * dg / 2 * spread;
        }
        return;
    }
    double gammas[16];
    int count = 0;
    if (p == HT_LOBE_R) {
        gammas[count++] = -phi_w / 2;
    } else {
        for (int k = -2; k <= 2; k++) {
            double roots[3];
            int n = cubic_roots(a1 / a3, (k_p * HT_PI - phi_w - 2 * HT_PI * k) / a3, roots);
            for (int i = 0; i < n; i++)
                if (fabs(roots[i]) <= HT_PI / 2 + 1e-9) gammas[count++] = fmax(-HT_PI / 2, fmin(HT_PI / 2, roots[i]));
        }
    }
    for (int i = 0; i < count; i++) {
        double g = gammas[i];
        /* R: |dphi/dgamma| = 2; TT: >= 2 - 6c/pi > 0 for eta' > 1.155 (c < pi/3); below, near
           theta_r = 0, TT has a fold where it reaches 0 (model_marschner.h) */
        double slope = fabs(a1 + 3 * a3 * g * g);
        double a[3];
        ht_marschner_attenuation(m, p, cos_theta_r, sin(g), a);
        /* 1 / |2 dphi/dh| = cos(gamma) / (2 |dphi/dgamma|) */
        for (int ch = 0; ch < 3; ch++) out[ch] += a[ch] * cos(g) / (2 * slope);
    }
}

void ht_marschner_fibre(const ht_marschner *m, double sin_i, double sin_r, double cos_phi,
                        double rgb[3]) {
    sin_r = clamp1(sin_r);
    double cos_r = sqrt(1 - sin_r * sin_r);
    double phi = acos(clamp1(cos_phi));
    rgb[0] = rgb[1] = rgb[2] = 0;
    for (int p = 0; p < HT_LOBE_COUNT; p++) {
        double n[3];
        double mp = ht_marschner_longitudinal(m, (ht_marschner_lobe)p, sin_i, sin_r);
        ht_marschner_azimuthal(m, (ht_marschner_lobe)p, cos_r, phi, n);
        for (int i = 0; i < 3; i++) rgb[i] += mp * n[i];
    }
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void ht_marschner_fibre_vectors(const ht_marschner *m, const double T[3], const double L[3],
                                const double V[3], double rgb[3]) {
    rgb[0] = rgb[1] = rgb[2] = 0;
    if (dot3(T, T) == 0 || dot3(L, L) == 0 || dot3(V, V) == 0) return;
    double sin_i = clamp1(dot3(T, L)), sin_r = clamp1(dot3(T, V));
    double lp[3], vp[3];
    for (int i = 0; i < 3; i++) {
        lp[i] = L[i] - sin_i * T[i];
        vp[i] = V[i] - sin_r * T[i];
    }
    double ll = dot3(lp, lp), vv = dot3(vp, vp);
    double cos_phi = 1; /* no azimuth along the fibre */
    if (ll > HT_MODEL_MIN_LENGTH2 && vv > HT_MODEL_MIN_LENGTH2) cos_phi = clamp1(dot3(lp, vp) / sqrt(ll * vv));
    ht_marschner_fibre(m, sin_i, sin_r, cos_phi, rgb);
}

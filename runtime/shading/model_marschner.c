/* model_marschner.c — Marschner's fibre model, the equations of
   model_marschner.h in double precision. The tier that draws it reads M,
   the rest and N_TRT from lookup textures baked from these functions and
   evaluates N_R and N_TT itself, in float, from the same equations written
   in GLSL (shadergen/emit_marschner.c: the Fresnel below and the cubic's
   roots as cubic_roots finds them); the marschner probe holds the two
   together (tests/test_render_marschner.c). */
#include <hairtier/model_marschner.h>

#include "model_marschner_bake.h"

#include <math.h>
#include <stdlib.h>


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

/* What M_p shares over every pair of angles: the variance, the
   normalisation's logarithm and the rotation by -2 alpha_p. */
ht_marschner_m_lobe ht_marschner_m_lobe_of(double v, double two_alpha) {
    /* log(2 v sinh(1/v)) without overflowing sinh for narrow lobes */
    return (ht_marschner_m_lobe){ .v = v, .log_norm = log(v) + 1 / v + log1p(-exp(-2 / v)),
                                  .cos_2a = cos(two_alpha), .sin_2a = sin(two_alpha) };
}

/* M for clamped sines and their cosines. */
static double longitudinal_of(const ht_marschner_m_lobe *l, double sin_i, double cos_i, double sin_r, double cos_r) {
    return exp(log_bessel_i0(cos_i * cos_r / l->v) - sin_i * sin_r / l->v - l->log_norm);
}

static double cos_of(double clamped_sin) { return sqrt(1 - clamped_sin * clamped_sin); }

static double longitudinal_unrotated(const ht_marschner_m_lobe *l, double sin_i, double sin_r) {
    sin_i = clamp1(sin_i);
    sin_r = clamp1(sin_r);
    return longitudinal_of(l, sin_i, cos_of(sin_i), sin_r, cos_of(sin_r));
}

/* sin_r rotated by -2 alpha: centres the lobe on theta_h = alpha; a
   rotation past a pole folds back (|cos|), which keeps the integral 1. */
static double rotated(const ht_marschner_m_lobe *l, double sin_r) {
    sin_r = clamp1(sin_r);
    return clamp1(sin_r * l->cos_2a - cos_of(sin_r) * l->sin_2a);
}

void ht_marschner_m_lobe_row(const ht_marschner_m_lobe *l, double sin_r, const double *sin_i, int count,
                             double *out) {
    const double sin_rot = rotated(l, sin_r), cos_rot = cos_of(sin_rot);
    for (int x = 0; x < count; x++) {
        double si = clamp1(sin_i[x]);
        out[x] = longitudinal_of(l, si, cos_of(si), sin_rot, cos_rot);
    }
}

double ht_marschner_longitudinal_v(double v, double sin_i, double sin_r) {
    ht_marschner_m_lobe l = ht_marschner_m_lobe_of(v, 0);
    return longitudinal_unrotated(&l, sin_i, sin_r);
}

ht_marschner_m_lobe ht_marschner_m_lobe_for(const ht_marschner *m, ht_marschner_lobe p) {
    double beta = ht_marschner_width(m, p);
    return ht_marschner_m_lobe_of(beta * beta, 2 * ht_marschner_shift(m, p));
}

double ht_marschner_longitudinal(const ht_marschner *m, ht_marschner_lobe p,
                                 double sin_i, double sin_r) {
    ht_marschner_m_lobe l = ht_marschner_m_lobe_for(m, p);
    return longitudinal_unrotated(&l, sin_i, rotated(&l, sin_r));
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

/* What every ray through one cross-section shares: the Bravais indices and
   the longitudinal part of the internal path. */
typedef struct section {
    double eta_perp, eta_par, cos_tt;
    double absorption[3];
} section;

static section section_of(const ht_marschner *m, double cos_theta_r) {
    section s;
    bravais(m->eta, cos_theta_r, &s.eta_perp, &s.eta_par);
    double c = fmax(fmin(cos_theta_r, 1), 0);
    double sin_tt = sqrt(1 - c * c) / m->eta;
    s.cos_tt = sqrt(1 - sin_tt * sin_tt);
    for (int i = 0; i < 3; i++) s.absorption[i] = m->absorption[i];
    return s;
}

/* Fresnel at the in-plane incidence gamma (sin_g = |h| >= 0, cos_g). */
static double section_fresnel(const section *s, double sin_g, double cos_g) {
    if (cos_g <= 0) return 1; /* grazing */
    return 0.5 * (fresnel_one(s->eta_perp, cos_g, sin_g, false) + fresnel_one(s->eta_par, cos_g, sin_g, true));
}

double ht_marschner_fresnel(double eta, double cos_theta_r, double h) {
    double sin_g = fabs(clamp1(h));
    double eta_perp, eta_par;
    bravais(eta, cos_theta_r, &eta_perp, &eta_par);
    section s = { .eta_perp = eta_perp, .eta_par = eta_par };
    return section_fresnel(&s, sin_g, sqrt(1 - sin_g * sin_g));
}

/* A_p for |h| = sin_g (cos_g given, so that callers integrating in gamma
   keep it exact near grazing). */
static void attenuation_at(const section *s, ht_marschner_lobe p, double sin_g, double cos_g, double out[3]) {
    double f = section_fresnel(s, sin_g, cos_g);
    if (p == HT_LOBE_R) {
        out[0] = out[1] = out[2] = f;
        return;
    }
    double sin_gt = sin_g / s->eta_perp;
    double cos_gt = sqrt(1 - sin_gt * sin_gt);
    /* The internal reflections have the entry's reflectance: a dielectric
       interface reflects the same both ways. */
    double through = (1 - f) * (1 - f);
    for (int i = 0; i < 3; i++) {
        double t = exp(-2 * s->absorption[i] * cos_gt / s->cos_tt);
        if (p == HT_LOBE_TT) out[i] = through * t;
        else if (p == HT_LOBE_TRT) out[i] = through * f * t * t;
        else /* the rest of the series: (1-F)^2 F^2 T^3 / (1 - F T); 0 in the limit F T -> 1 */
            out[i] = 1 - f * t > 1e-12 ? through * f * f * t * t * t / (1 - f * t) : 0;
    }
}

void ht_marschner_attenuation(const ht_marschner *m, ht_marschner_lobe p,
                              double cos_theta_r, double h, double out[3]) {
    double sin_g = fabs(clamp1(h));
    section s = section_of(m, cos_theta_r);
    attenuation_at(&s, p, sin_g, sqrt(1 - sin_g * sin_g), out);
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

/* The integrals over h of TRT (times the caustic's Gaussian) and of the
   rest. A(h) has two kinks: at |h| = 1 (cos(gamma) = sqrt(1 - h^2))
   and, where eta'' < 1, at |h| = eta'' (the parallel polarisation's
   critical angle: Fresnel jumps to 1 with an infinite slope). Each panel is
   integrated in a variable that makes its ends smooth: gamma outside
   (h = sin gamma), u inside (h = eta'' sin u), by adaptive Gauss-Kronrod. */
typedef struct panel_memo panel_memo;
typedef struct integrand {
    const section *s;
    ht_marschner_lobe p;
    double phi, a1, a3; /* TRT: the azimuth and its exit-azimuth cubic */
    bool inner;         /* the variable: u (h = eta'' sin u) or gamma */
    panel_memo *memo;   /* NULL, or the azimuth-free node values of one theta_r */
} integrand;

/* What a node x shares with every azimuth: dh/dx, A(h) and the exit
   azimuth phi(2, gamma) (TRT's cubic plus p pi). */
typedef struct node_value {
    double dh, exit, a[3];
} node_value;

static void node_at(const integrand *f, double x, node_value *v) {
    double h, cos_g, g;
    if (f->inner) {
        h = f->s->eta_par * sin(x);
        cos_g = sqrt(1 - h * h);
        v->dh = f->s->eta_par * cos(x);
        g = asin(h);
    } else {
        h = sin(x);
        cos_g = cos(x);
        v->dh = cos_g;
        g = x;
    }
    attenuation_at(f->s, f->p, fabs(h), cos_g, v->a);
    v->exit = f->a1 * g + f->a3 * g * g * g + 2 * HT_PI; /* p pi, p = 2 */
}

/* remainder(x, 2 pi), bit for bit, without the division where |x| < 3 pi
   (x -+ 2 pi is exact there: Sterbenz). */
static double wrap_azimuth(double x) {
    if (x >= -HT_PI && x <= HT_PI) return x;
    if (x > -3 * HT_PI && x < -HT_PI) return x + 2 * HT_PI;
    if (x < 3 * HT_PI && x > HT_PI) return x - 2 * HT_PI;
    return remainder(x, 2 * HT_PI);
}

/* f(h) dh/dx at a node, RGB. */
static void integrand_of(const integrand *f, const node_value *v, double out[3]) {
    double w = v->dh;
    if (f->p == HT_LOBE_TRT) { /* A / 2 times the Gaussian; other images weigh < 1e-31 */
        const double sigma = HT_MARSCHNER_CAUSTIC_WIDTH;
        double d = wrap_azimuth(f->phi - v->exit);
        w *= 0.5 * exp(-d * d / (2 * sigma * sigma)) / (sqrt(2 * HT_PI) * sigma);
    }
    for (int i = 0; i < 3; i++) out[i] = v->a[i] * w;
}

/* Gauss-Kronrod 7-15 (QUADPACK's qk15): the nodes on [0, 1] (each also
   negated), the Kronrod and the Gauss weights. Node n of a panel is
   gk_x[n / 2], negated when n is odd (gk_node). */
#define GK_NODES 15
static const double gk_x[8] = { 0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                                0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                                0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                                0.207784955007898467600689403773245, 0 };
static const double gk_wk[8] = { 0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                                 0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                                 0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                                 0.204432940075298892414161999234649, 0.209482141084727828012999174891714 };
static const double gk_wg[4] = { 0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                 0.381830050505118944950369775488975, 0.417959183673469387755102040816327 };

static double gk_node(double a, double b, int n) {
    double mid = (a + b) / 2, half = (b - a) / 2;
    return mid + (n % 2 ? -1 : 1) * half * gk_x[n / 2];
}

/* The azimuth-free values of the panels adaptive() visits for one theta_r,
   a binary tree grown as azimuths need it: every azimuth of a column
   bisects the same panels at the same points, so each node is computed
   once. Indices, not pointers: the array grows. */
typedef struct memo_panel {
    node_value v[GK_NODES];
    int child[2]; /* -1: not yet made */
} memo_panel;

struct panel_memo {
    memo_panel *panels;
    int count, capacity;
    int root[3];
    bool failed; /* out of memory: evaluate directly (the same numbers) */
};

/* The panel (a, b) in slot `side` of `parent` (-1: root `side`), made on first use; -1 when out of memory. */
static int memo_panel_at(const integrand *f, int parent, int side, double a, double b) {
    panel_memo *m = f->memo;
    int *slot = parent < 0 ? &m->root[side] : &m->panels[parent].child[side];
    if (*slot >= 0) return *slot;
    if (m->count == m->capacity) {
        int capacity = m->capacity ? 2 * m->capacity : 256;
        memo_panel *grown = realloc(m->panels, sizeof *grown * (size_t)capacity);
        if (!grown) {
            m->failed = true;
            return -1;
        }
        m->panels = grown;
        m->capacity = capacity;
        slot = parent < 0 ? &m->root[side] : &m->panels[parent].child[side];
    }
    int at = m->count++;
    memo_panel *p = &m->panels[at];
    p->child[0] = p->child[1] = -1;
    for (int n = 0; n < GK_NODES; n++) node_at(f, gk_node(a, b, n), &p->v[n]);
    *slot = at;
    return at;
}

/* Gauss-Kronrod 7-15 (QUADPACK's qk15) on [a, b], RGB, with QUADPACK's
   error estimate per channel (|Kronrod - Gauss| scaled by how smooth the
   panel is); `panel` the memo's panel of [a, b] or -1. err is exact only
   where it decides converged() at tol. */
static void gauss_kronrod(const integrand *f, double a, double b, int panel, double tol, double out[3],
                          double err[3]) {
    double half = (b - a) / 2, kron[3] = { 0, 0, 0 }, gauss[3] = { 0, 0, 0 }, v[GK_NODES][3];
    for (int n = 0; n < GK_NODES; n++) {
        int k = n / 2;
        if (panel >= 0) {
            integrand_of(f, &f->memo->panels[panel].v[n], v[n]);
        } else {
            node_value nv;
            node_at(f, gk_node(a, b, n), &nv);
            integrand_of(f, &nv, v[n]);
        }
        for (int i = 0; i < 3; i++) {
            kron[i] += gk_wk[k] * v[n][i];
            if (k % 2 == 1) gauss[i] += gk_wg[k / 2] * v[n][i];
        }
    }
    for (int i = 0; i < 3; i++) {
        double spread = 0, mean = kron[i] / 2; /* the integral of |f - mean|, as qk15's resasc */
        for (int n = 0; n < GK_NODES; n++) spread += gk_wk[n / 2] * fabs(v[n][i] - mean);
        double e = fabs(kron[i] - gauss[i]) * half;
        spread *= fabs(half);
        out[i] = kron[i] * half;
        if (spread > 0 && e > 0) {
            /* spread min(1, r^1.5); r sqrt(r) is within a few ulps of pow's, so
               pow is called only where that could change converged()'s answer */
            double r = 200 * e / spread, cheap = spread * fmin(1, r * sqrt(r));
            const double near = 1e-9;
            bool close = fabs(cheap - tol) <= near * tol || fabs(cheap - 1e-10 * fabs(out[i])) <= near * cheap;
            e = close || !isfinite(cheap) ? spread * fmin(1, pow(r, 1.5)) : cheap;
        }
        err[i] = e;
    }
}

/* Whether every channel's error estimate is below tol or below 1e-10 of
   the channel's value; a NaN estimate counts as converged: no endless split. */
static bool converged(const double out[3], const double err[3], double tol) {
    for (int i = 0; i < 3; i++)
        if (err[i] > tol && err[i] > 1e-10 * fabs(out[i])) return false;
    return true;
}

/* Bisects until converged(), tol (absolute) halved with each split. With a
   memo, [a, b] is slot `side` of panel `parent` (-1: a root). */
static void adaptive(const integrand *f, double a, double b, double tol, int depth, int parent, int side,
                     double out[3]) {
    double err[3];
    int panel = f->memo && !f->memo->failed ? memo_panel_at(f, parent, side, a, b) : -1;
    gauss_kronrod(f, a, b, panel, tol, out, err);
    if (converged(out, err, tol) || depth >= 24) return;
    double left[3], right[3], mid = (a + b) / 2;
    adaptive(f, a, mid, tol / 2, depth + 1, panel, 0, left);
    adaptive(f, mid, b, tol / 2, depth + 1, panel, 1, right);
    for (int i = 0; i < 3; i++) out[i] = left[i] + right[i];
}

/* The integral of f over h in [-1, 1] (both_sides) or [0, 1], split at
   eta''. The tolerance is a thousandth of the 1e-9 the header promises. */
static void integrate_h(integrand *f, bool both_sides, double out[3]) {
    const double tol = 1e-12;
    double part[3], eta_par = f->s->eta_par;
    out[0] = out[1] = out[2] = 0;
    double edge = eta_par < 1 ? asin(eta_par) : 0; /* where the outer panels begin, in gamma */
    if (eta_par < 1) {
        f->inner = true;
        adaptive(f, both_sides ? -HT_PI / 2 : 0, HT_PI / 2, tol, 0, -1, 0, part);
        for (int i = 0; i < 3; i++) out[i] += part[i];
    }
    f->inner = false;
    adaptive(f, edge, HT_PI / 2, tol, 0, -1, 1, part);
    for (int i = 0; i < 3; i++) out[i] += part[i];
    if (both_sides) {
        adaptive(f, -HT_PI / 2, -edge, tol, 0, -1, 2, part);
        for (int i = 0; i < 3; i++) out[i] += part[i];
    }
}

/* phi in [-pi, pi] (0 for a non-finite phi). */
static double wrapped_phi(double phi) {
    double phi_w = remainder(phi, 2 * HT_PI);
    return isfinite(phi_w) ? phi_w : 0;
}

/* phi(gamma) = a1 gamma + a3 gamma^3 + p pi (Marschner 2003, eq. 10). */
static void exit_cubic(const section *s, ht_marschner_lobe p, double *a1, double *a3) {
    double c = asin(1 / s->eta_perp);
    const double k_p = (double)p; /* the lobe's number of internal paths */
    *a1 = 6 * k_p * c / HT_PI - 2;
    *a3 = -8 * k_p * c / (HT_PI * HT_PI * HT_PI);
}

void ht_marschner_azimuthal(const ht_marschner *m, ht_marschner_lobe p,
                            double cos_theta_r, double phi, double out[3]) {
    out[0] = out[1] = out[2] = 0;
    section s = section_of(m, cos_theta_r);
    if (p == HT_LOBE_REST) { /* uniform in phi: the mean of A over h (even in h), over 2 pi */
        integrand f = { .s = &s, .p = p };
        integrate_h(&f, false, out);
        for (int i = 0; i < 3; i++) out[i] /= 2 * HT_PI;
        return;
    }
    double phi_w = wrapped_phi(phi);
    const double k_p = (double)p; /* the lobe's number of internal paths */
    double a1, a3;
    exit_cubic(&s, p, &a1, &a3);
    if (p == HT_LOBE_TRT) { /* the caustic, spread: the integral over h */
        integrand f = { .s = &s, .p = p, .phi = phi_w, .a1 = a1, .a3 = a3 };
        integrate_h(&f, true, out);
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
        attenuation_at(&s, p, fabs(sin(g)), cos(g), a);
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

void ht_marschner_trt_column(const ht_marschner *m, double cos_theta_r, const double *phi, int count,
                             double (*out)[3]) {
    section s = section_of(m, cos_theta_r);
    panel_memo memo = { .root = { -1, -1, -1 } };
    integrand f = { .s = &s, .p = HT_LOBE_TRT, .memo = &memo };
    exit_cubic(&s, HT_LOBE_TRT, &f.a1, &f.a3);
    for (int i = 0; i < count; i++) {
        f.phi = wrapped_phi(phi[i]);
        integrate_h(&f, true, out[i]);
    }
    free(memo.panels);
}

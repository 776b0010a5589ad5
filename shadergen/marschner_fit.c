/* marschner_fit.c — Scheuermann constants fitted to a Marschner material
   (marschner_fit.h says how and why). */
#include "marschner_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"

typedef struct sample {
    ht_surface s;
    ht_light_ray light;
    double target[3];
} sample;

static void random_unit(ht_rng *r, double v[3]) {
    double len2;
    do {
        for (int i = 0; i < 3; i++) v[i] = ht_rng_range(r, -1, 1);
        len2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (len2 > 1 || len2 < 1e-6);
    for (int i = 0; i < 3; i++) v[i] /= sqrt(len2);
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void make_samples(const ht_shading *m, sample *out) {
    ht_rng rng = ht_rng_seed(2016);
    for (int n = 0; n < HT_MARSCHNER_FIT_SAMPLES; n++) {
        sample *p = &out[n];
        memset(p, 0, sizeof *p);
        double T[3], N[3], L[3], V[3];
        random_unit(&rng, T);
        do { /* N perpendicular to T, as on a ribbon */
            random_unit(&rng, N);
            double d = dot3(N, T);
            for (int i = 0; i < 3; i++) N[i] -= d * T[i];
        } while (dot3(N, N) < 1e-3);
        double len = sqrt(dot3(N, N));
        for (int i = 0; i < 3; i++) N[i] /= len;
        do random_unit(&rng, L); while (dot3(N, L) < -0.25);
        do random_unit(&rng, V); while (dot3(N, V) <= 0);
        memcpy(p->s.T, T, sizeof T);
        memcpy(p->s.N, N, sizeof N);
        memcpy(p->s.V, V, sizeof V);
        p->s.base[0] = p->s.base[1] = p->s.base[2] = 1;
        p->s.shift_tex = 0.5;
        p->s.sparkle = 1;
        p->s.ao = 1;
        memcpy(p->light.L, L, sizeof L);
        p->light.color[0] = p->light.color[1] = p->light.color[2] = 1;
        ht_model_shade_d(m, &p->s, &p->light, 1, p->target);
        for (int c = 0; c < 3; c++) p->target[c] = fmin(p->target[c], 1);
    }
}

/* The nonlinear parameters, in the order the search visits them. */
enum { WRAP, E1, S1, E2, S2, PARAMS };
static const double lo[PARAMS] = { 0, 0, -1, 0, -1 }, hi[PARAMS] = { 1, 8, 1, 8, 1 }; /* exponents as log(1 + e) */

static void to_shading(const double x[PARAMS], ht_shading *s) {
    memset(s, 0, sizeof *s);
    s->model = HT_MODEL_SCHEUERMANN;
    s->wrap = x[WRAP];
    s->primary.exponent = expm1(x[E1]);
    s->primary.shift = x[S1];
    s->secondary.exponent = expm1(x[E2]);
    s->secondary.shift = x[S2];
}

/* For fixed wrap, exponents and shifts: the three factors per sample
   (colours at 1; the model treats the channels alike and is linear in the
   colours, so one call with each colour on a channel of its own gives all
   three, bit for bit), then per channel the colours in [0, 1] that minimise the
   squared error (normal equations; a colour outside [0, 1] is pinned to
   its bound and the rest solved again). Returns the sum of squares. */
static double solve_colours(const sample *ps, const double x[PARAMS], ht_shading *out, double *f_buf) {
    ht_shading s;
    to_shading(x, &s);
    ht_shading split = s;
    memcpy(split.diffuse_color, (const double[3]){ 1, 0, 0 }, sizeof split.diffuse_color);
    memcpy(split.primary.color, (const double[3]){ 0, 1, 0 }, sizeof split.primary.color);
    memcpy(split.secondary.color, (const double[3]){ 0, 0, 1 }, sizeof split.secondary.color);
    for (int n = 0; n < HT_MARSCHNER_FIT_SAMPLES; n++)
        ht_model_shade_d(&split, &ps[n].s, &ps[n].light, 1, &f_buf[n * 3]);
    double total = 0;
    for (int c = 0; c < 3; c++) {
        double coef[3] = { 0, 0, 0 };
        bool pinned[3] = { false, false, false };
        for (int round = 0; round < 4; round++) {
            double a[3][3] = { { 0 } }, b[3] = { 0 };
            for (int n = 0; n < HT_MARSCHNER_FIT_SAMPLES; n++) {
                const double *f = &f_buf[n * 3];
                double y = ps[n].target[c];
                for (int i = 0; i < 3; i++)
                    if (pinned[i]) y -= coef[i] * f[i];
                for (int i = 0; i < 3; i++) {
                    if (pinned[i]) continue;
                    b[i] += f[i] * y;
                    for (int j = 0; j < 3; j++)
                        if (!pinned[j]) a[i][j] += f[i] * f[j];
                }
            }
            for (int i = 0; i < 3; i++)
                if (pinned[i]) a[i][i] = 1, b[i] = coef[i];
            /* Gaussian elimination with a ridge against singular systems */
            for (int i = 0; i < 3; i++) a[i][i] += 1e-9;
            for (int i = 0; i < 3; i++)
                for (int j = i + 1; j < 3; j++) {
                    double r = a[j][i] / a[i][i];
                    for (int k = i; k < 3; k++) a[j][k] -= r * a[i][k];
                    b[j] -= r * b[i];
                }
            for (int i = 2; i >= 0; i--) {
                double v = b[i];
                for (int k = i + 1; k < 3; k++) v -= a[i][k] * coef[k];
                coef[i] = v / a[i][i];
            }
            bool again = false;
            for (int i = 0; i < 3; i++)
                if (!pinned[i] && (coef[i] < 0 || coef[i] > 1)) {
                    coef[i] = coef[i] < 0 ? 0 : 1;
                    pinned[i] = again = true;
                }
            if (!again) break;
        }
        for (int i = 0; i < 3; i++) coef[i] = fmin(1, fmax(0, coef[i]));
        s.diffuse_color[c] = coef[0];
        s.primary.color[c] = coef[1];
        s.secondary.color[c] = coef[2];
        for (int n = 0; n < HT_MARSCHNER_FIT_SAMPLES; n++) {
            const double *f = &f_buf[n * 3];
            double e = coef[0] * f[0] + coef[1] * f[1] + coef[2] * f[2] - ps[n].target[c];
            total += e * e;
        }
    }
    if (out) *out = s;
    return total;
}

ht_result ht_marschner_fit_scheuermann(const ht_shading *m, ht_marschner_fit *out) {
    memset(out, 0, sizeof *out);
    if (m->model != HT_MODEL_MARSCHNER) return HT_ERR_INVALID_ARGUMENT;
    sample *ps = malloc(sizeof *ps * HT_MARSCHNER_FIT_SAMPLES);
    double *f = malloc(sizeof *f * HT_MARSCHNER_FIT_SAMPLES * 3);
    if (!ps || !f) {
        free(ps);
        free(f);
        return HT_ERR_OUT_OF_MEMORY;
    }
    make_samples(m, ps);
    /* A coarse grid over the exponents and shifts, wrap 0.25. */
    double best[PARAMS] = { 0.25, log1p(80), -0.1, log1p(20), 0.1 }, best_err = solve_colours(ps, best, NULL, f);
    const double exps[] = { 10, 40, 160, 640 }, shifts[] = { -0.3, -0.1, 0.1, 0.3 };
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            for (int c = 0; c < 4; c++)
                for (int d = 0; d < 4; d++) {
                    double x[PARAMS] = { 0.25, log1p(exps[a]), shifts[b], log1p(exps[c]), shifts[d] };
                    double e = solve_colours(ps, x, NULL, f);
                    if (e < best_err) best_err = e, memcpy(best, x, sizeof best);
                }
    /* Coordinate search: golden section on each parameter in turn. */
    const double g = (sqrt(5) - 1) / 2;
    for (int round = 0; round < 3; round++)
        for (int p = 0; p < PARAMS; p++) {
            double a = lo[p], b = hi[p], x[PARAMS];
            memcpy(x, best, sizeof x);
            for (int it = 0; it < 18; it++) {
                double c = b - g * (b - a), d = a + g * (b - a);
                x[p] = c;
                double ec = solve_colours(ps, x, NULL, f);
                x[p] = d;
                double ed = solve_colours(ps, x, NULL, f);
                if (ec < ed) b = d;
                else a = c;
            }
            x[p] = (a + b) / 2;
            double e = solve_colours(ps, x, NULL, f);
            if (e < best_err) best_err = e, memcpy(best, x, sizeof best);
        }
    solve_colours(ps, best, &out->shading, f);
    out->rms = sqrt(best_err / (3.0 * HT_MARSCHNER_FIT_SAMPLES));
    for (int n = 0; n < HT_MARSCHNER_FIT_SAMPLES; n++) {
        double rgb[3];
        ht_model_shade_d(&out->shading, &ps[n].s, &ps[n].light, 1, rgb);
        for (int c = 0; c < 3; c++) out->max_error = fmax(out->max_error, fabs(rgb[c] - ps[n].target[c]));
    }
    free(ps);
    free(f);
    return HT_OK;
}

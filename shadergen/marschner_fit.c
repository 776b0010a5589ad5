/* marschner_fit.c — Scheuermann constants with a transmission lobe fitted
   to a Marschner material (marschner_fit.h says how and why). */
#include "marschner_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/ht_limits.h>

#include "model_terms.h"
#include "rng.h"

#define SAMPLES HT_MARSCHNER_FIT_SAMPLES
#define FACTORS 4 /* diffuse, primary, secondary, transmission */

typedef struct sample {
    ht_surface s;
    ht_light_ray lights[HT_MAX_LIGHTS]; /* the scene's, its colours */
    int light_count;
    double target[3];    /* the whole fibre under every light, clamped to [0, 1] */
    double tt_target[3]; /* its M_TT N_TT alone, clamped likewise */
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

/* M_TT N_TT of the fibre for unit T, L, V (model_marschner.h's angles). */
static void tt_lobe(const ht_marschner *m, const double T[3], const double L[3], const double V[3], double out[3]) {
    double sin_i = dot3(T, L), sin_r = dot3(T, V), lp[3], vp[3];
    for (int i = 0; i < 3; i++) lp[i] = L[i] - sin_i * T[i], vp[i] = V[i] - sin_r * T[i];
    double nl = sqrt(dot3(lp, lp)), nv = sqrt(dot3(vp, vp));
    double cos_phi = nl > 1e-9 && nv > 1e-9 ? fmin(1, fmax(-1, dot3(lp, vp) / (nl * nv))) : 1;
    double n[3];
    ht_marschner_azimuthal(m, HT_LOBE_TT, sqrt(fmax(0, 1 - sin_r * sin_r)), acos(cos_phi), n);
    double mp = ht_marschner_longitudinal(m, HT_LOBE_TT, sin_i, sin_r);
    for (int c = 0; c < 3; c++) out[c] = mp * n[c];
}

static void normalized(const double v[3], double out[3]) {
    double len = sqrt(dot3(v, v));
    for (int i = 0; i < 3; i++) out[i] = len > 0 ? v[i] / len : 0;
}

static void cross3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* A direction towards the eye from a pixel of the scene's frame: the
   camera's ray through a random point of its (square) field of view. */
static void view_direction(ht_rng *r, const ht_camera *cam, double V[3]) {
    double fwd[3], up[3], right[3], upv[3], d[3];
    for (int i = 0; i < 3; i++) fwd[i] = (double)cam->target[i] - cam->eye[i], up[i] = cam->up[i];
    normalized(fwd, fwd);
    cross3(fwd, up, right);
    normalized(right, right);
    cross3(right, fwd, upv);
    double k = tan((double)cam->fov_y * HT_PI / 360), x = ht_rng_range(r, -k, k), y = ht_rng_range(r, -k, k);
    for (int i = 0; i < 3; i++) d[i] = -(fwd[i] + x * right[i] + y * upv[i]);
    normalized(d, V);
}

/* Samples of the scene's light layout: its camera's view directions, its
   lights (directions and colours; a point light seen from the camera's
   target), strands in every direction with their ribbon normal towards the
   viewer. The lights fall on the front and the back of the hair alike:
   backlit.json's key is behind it, every scene's fill too. */
static void make_samples(const ht_shading *m, const ht_scene *scene, sample *out) {
    ht_rng rng = ht_rng_seed(2016);
    for (int n = 0; n < SAMPLES; n++) {
        sample *p = &out[n];
        memset(p, 0, sizeof *p);
        double T[3], N[3], V[3];
        random_unit(&rng, T);
        view_direction(&rng, &scene->camera, V);
        do { /* N perpendicular to T, as on a ribbon, facing the viewer */
            random_unit(&rng, N);
            double d = dot3(N, T);
            for (int i = 0; i < 3; i++) N[i] -= d * T[i];
        } while (dot3(N, N) < 1e-3 || dot3(N, V) <= 0);
        normalized(N, N);
        memcpy(p->s.T, T, sizeof T);
        memcpy(p->s.N, N, sizeof N);
        memcpy(p->s.V, V, sizeof V);
        p->s.base[0] = p->s.base[1] = p->s.base[2] = 1;
        p->s.shift_tex = 0.5;
        p->s.sparkle = 1;
        p->s.ao = 1;
        p->light_count = scene->light_count;
        for (int l = 0; l < scene->light_count; l++) {
            const ht_light *sl = &scene->lights[l];
            double L[3], tt[3];
            for (int i = 0; i < 3; i++)
                L[i] = sl->type == HT_LIGHT_POINT ? (double)sl->vector[i] - scene->camera.target[i] : sl->vector[i];
            normalized(L, L);
            memcpy(p->lights[l].L, L, sizeof L);
            for (int c = 0; c < 3; c++) p->lights[l].color[c] = sl->color[c];
            tt_lobe(&m->marschner, T, L, V, tt);
            for (int c = 0; c < 3; c++) p->tt_target[c] += sl->color[c] * tt[c];
        }
        ht_model_shade_d(m, &p->s, p->lights, p->light_count, p->target);
        for (int c = 0; c < 3; c++) p->target[c] = fmin(p->target[c], 1), p->tt_target[c] = fmin(p->tt_target[c], 1);
    }
}

/* The nonlinear parameters, in the order the search visits them: wrap,
   the highlights' exponents (as log(1 + e)) and shifts, the transmission's
   centre, sharpness (log2(1 + k)) and azimuth exponent (log(1 + e)). */
enum { WRAP, E1, S1, E2, S2, TC, TK, TA, PARAMS };
static const double lo[PARAMS] = { 0, 0, -1, 0, -1, -0.5, 0, 0 }, hi[PARAMS] = { 1, 8, 1, 8, 1, 0.5, 13, 8 };

static void to_shading(const double x[PARAMS], ht_shading *s) {
    memset(s, 0, sizeof *s);
    s->model = HT_MODEL_SCHEUERMANN;
    s->wrap = x[WRAP];
    s->primary.exponent = expm1(x[E1]);
    s->primary.shift = x[S1];
    s->secondary.exponent = expm1(x[E2]);
    s->secondary.shift = x[S2];
    s->transmission.centre = x[TC];
    s->transmission.sharpness = exp2(x[TK]) - 1;
    s->transmission.azimuth = expm1(x[TA]);
}

/* Each factor's colour bound: a highlight's 1, the transmission's more. */
static const double colour_max[FACTORS] = { 1, 1, 1, HT_LIMIT_TRANSMISSION };

/* Least squares for k colours in [0, colour_max] (per channel): minimises the sum
   over samples of (sum_i coef_i f_i - y)^2 by the normal equations; a
   colour outside [0, 1] is pinned to its bound and the rest solved again.
   f holds FACTORS per sample and channel, y 3 per sample; both read at
   channel c. Samples with skip[n] set are left out. */
/* Factor i's bound; a fit of one factor is the transmission's alone. */
static double hi_of(int k, int i) { return k == 1 ? colour_max[3] : colour_max[i]; }

static void least_squares(const double *f, int k, const double *y, int c, const bool *skip, double coef[FACTORS]) {
    bool pinned[FACTORS] = { false };
    for (int i = 0; i < k; i++) coef[i] = 0;
    for (int round = 0; round < 2 * FACTORS; round++) {
        double a[FACTORS][FACTORS] = { { 0 } }, b[FACTORS] = { 0 };
        int free[FACTORS], free_count = 0, fixed[FACTORS], fixed_count = 0; /* the unpinned and pinned factors */
        for (int i = 0; i < k; i++) {
            if (pinned[i]) fixed[fixed_count++] = i;
            else free[free_count++] = i;
        }
        /* a is symmetric: its upper triangle summed, the lower copied (the same products) */
        if (free_count == FACTORS) /* the common case, unrolled: the same sums in the same order */
            for (int n = 0; n < SAMPLES; n++) {
                if (skip[n]) continue;
                const double *fn = &f[(n * 3 + c) * FACTORS];
                const double yn = y[n * 3 + c], f0 = fn[0], f1 = fn[1], f2 = fn[2], f3 = fn[3];
                b[0] += f0 * yn, b[1] += f1 * yn, b[2] += f2 * yn, b[3] += f3 * yn;
                a[0][0] += f0 * f0, a[0][1] += f0 * f1, a[0][2] += f0 * f2, a[0][3] += f0 * f3;
                a[1][1] += f1 * f1, a[1][2] += f1 * f2, a[1][3] += f1 * f3;
                a[2][2] += f2 * f2, a[2][3] += f2 * f3;
                a[3][3] += f3 * f3;
            }
        else
        for (int n = 0; n < SAMPLES; n++) {
            if (skip[n]) continue;
            const double *fn = &f[(n * 3 + c) * FACTORS];
            double yn = y[n * 3 + c];
            for (int p = 0; p < fixed_count; p++) yn -= coef[fixed[p]] * fn[fixed[p]];
            for (int p = 0; p < free_count; p++) {
                const int i = free[p];
                b[i] += fn[i] * yn;
                for (int q = p; q < free_count; q++) a[i][free[q]] += fn[i] * fn[free[q]];
            }
        }
        for (int p = 0; p < free_count; p++)
            for (int q = p + 1; q < free_count; q++) a[free[q]][free[p]] = a[free[p]][free[q]];
        for (int i = 0; i < k; i++)
            if (pinned[i]) a[i][i] = 1, b[i] = coef[i];
        /* Gaussian elimination with a ridge against singular systems */
        for (int i = 0; i < k; i++) a[i][i] += 1e-9;
        for (int i = 0; i < k; i++)
            for (int j = i + 1; j < k; j++) {
                double r = a[j][i] / a[i][i];
                for (int l = i; l < k; l++) a[j][l] -= r * a[i][l];
                b[j] -= r * b[i];
            }
        for (int i = k - 1; i >= 0; i--) {
            double v = b[i];
            for (int l = i + 1; l < k; l++) v -= a[i][l] * coef[l];
            coef[i] = v / a[i][i];
        }
        bool again = false;
        for (int i = 0; i < k; i++)
            if (!pinned[i] && (coef[i] < 0 || coef[i] > hi_of(k, i))) {
                coef[i] = coef[i] < 0 ? 0 : hi_of(k, i);
                pinned[i] = again = true;
            }
        if (!again) break;
    }
    for (int i = 0; i < k; i++) coef[i] = fmin(hi_of(k, i), fmax(0, coef[i]));
}

static double predict(const double *f, int k, int n, int c, const double coef[FACTORS]) {
    double v = 0;
    for (int i = 0; i < k; i++) v += coef[i] * f[(n * 3 + c) * FACTORS + i];
    return v;
}

/* least_squares as a framebuffer sees it: both sides clamp at 1, so a
   sample whose target is 1 and whose fit reaches 1 has no error. Such
   samples are left out and the fit solved again, until the set holds
   (at most 4 times). Returns the sum of squares of the clamped errors. */
static double clamped_least_squares(const double *f, int k, const double *y, int c, double coef[FACTORS]) {
    bool skip[SAMPLES] = { false };
    double fitted[SAMPLES]; /* the last pass's predictions: the final coef's */
    for (int pass = 0; pass < 4; pass++) {
        least_squares(f, k, y, c, skip, coef);
        bool changed = false;
        for (int n = 0; n < SAMPLES; n++) {
            fitted[n] = predict(f, k, n, c, coef);
            bool s = fitted[n] >= 1;
            changed |= s != skip[n];
            skip[n] = s;
        }
        if (!changed) break;
    }
    double total = 0;
    for (int n = 0; n < SAMPLES; n++) {
        double e = fmin(fitted[n], 1) - y[n * 3 + c];
        total += e * e;
    }
    return total;
}

/* The factors per sample and channel (FACTORS each), and the parameters
   they were made for: each column is remade only when its own parameters
   change, which a coordinate search does one at a time. */
typedef struct factor_cache {
    double *f;
    double x[PARAMS];
    bool valid[FACTORS]; /* column i made for x */
    /* what they are made of, in order (sample n's lights at n * light_count), kept compact */
    ht_model_light_terms *terms;
    int light_count;
    double colour[HT_MAX_LIGHTS][3];
} factor_cache;

/* The samples' light terms and the lights' colours (every sample's lights are the scene's). */
static void factor_inputs(const sample *ps, factor_cache *fc) {
    fc->light_count = ps[0].light_count;
    for (int n = 0; n < SAMPLES; n++)
        for (int l = 0; l < fc->light_count; l++)
            ht_model_light_terms_init(&ps[n].s, ps[n].lights[l].L, &fc->terms[n * fc->light_count + l]);
    for (int l = 0; l < fc->light_count; l++) memcpy(fc->colour[l], ps[0].lights[l].color, sizeof fc->colour[l]);
}

/* Column i's parameters, x[first] to x[last]. */
static const int column_first[FACTORS] = { WRAP, E1, E2, TC }, column_last[FACTORS] = { WRAP, S1, S2, TA };

/* Each light's terms (ht_model_shade_d's diffuse, highlights and
   transmission for a white light, base, ao and sparkle 1) times the
   light's colour, summed over the lights. */
static const double *factors(const double x[PARAMS], factor_cache *fc) {
    bool stale[FACTORS], any = false;
    for (int i = 0; i < FACTORS; i++) {
        size_t size = sizeof *x * (size_t)(column_last[i] - column_first[i] + 1);
        stale[i] = !fc->valid[i] || memcmp(x + column_first[i], fc->x + column_first[i], size) != 0;
        any |= stale[i];
    }
    if (!any) return fc->f;
    ht_shading s;
    to_shading(x, &s);
    for (int n = 0; n < SAMPLES; n++) {
        double *fn = &fc->f[n * 3 * FACTORS];
        for (int c = 0; c < 3; c++)
            for (int i = 0; i < FACTORS; i++)
                if (stale[i]) fn[c * FACTORS + i] = 0;
        for (int l = 0; l < fc->light_count; l++) {
            const ht_model_light_terms *t = &fc->terms[n * fc->light_count + l];
            double g[FACTORS] = { 0 };
            if (stale[0]) g[0] = ht_model_wrap_diffuse_d(t->n_dot_l, s.wrap);
            if (stale[1]) g[1] = ht_model_light_highlight(t, s.primary.shift, s.primary.exponent);
            if (stale[2]) g[2] = ht_model_light_highlight(t, s.secondary.shift, s.secondary.exponent);
            if (stale[3]) g[3] = ht_model_light_transmission(t, &s.transmission);
            for (int c = 0; c < 3; c++)
                for (int i = 0; i < FACTORS; i++)
                    if (stale[i]) fn[c * FACTORS + i] += fc->colour[l][c] * g[i];
        }
    }
    memcpy(fc->x, x, sizeof fc->x);
    for (int i = 0; i < FACTORS; i++) fc->valid[i] = true;
    return fc->f;
}

/* For fixed nonlinear parameters: the colours that fit best, the sum of
   squares over every sample and channel. y is the targets, stride 3. */
static double solve_colours(const double *y, const double x[PARAMS], ht_shading *out, factor_cache *fc) {
    ht_shading s;
    to_shading(x, &s);
    const double *f = factors(x, fc);
    double total = 0;
    double *colours[FACTORS] = { s.diffuse_color, s.primary.color, s.secondary.color, s.transmission.color };
    for (int c = 0; c < 3; c++) {
        double coef[FACTORS];
        total += clamped_least_squares(f, FACTORS, y, c, coef);
        for (int i = 0; i < FACTORS; i++) colours[i][c] = coef[i];
    }
    if (out) *out = s;
    return total;
}

/* The transmission's shape alone against M_TT N_TT: its colour per
   channel by least squares (the other factors out). */
static double tt_error(const double *y, const double x[PARAMS], factor_cache *fc) {
    const double *tt = factors(x, fc) + 3; /* column 3 read as a fit of one factor */
    double total = 0;
    for (int c = 0; c < 3; c++) {
        double coef[FACTORS];
        total += clamped_least_squares(tt, 1, y, c, coef);
    }
    return total;
}

typedef double (*objective)(const double *y, const double x[PARAMS], factor_cache *fc);

static double whole_error(const double *y, const double x[PARAMS], factor_cache *fc) {
    return solve_colours(y, x, NULL, fc);
}

/* The last points a search evaluated and their errors: a golden section's
   new point is often its previous one to the bit (about a quarter of
   them), and an objective is a function of x alone. */
enum { RECENT = 4 };
typedef struct recent_points {
    double x[RECENT][PARAMS], err[RECENT];
    int count;
} recent_points;

static double error_at(objective err_of, const double *y, const double x[PARAMS], factor_cache *f,
                       recent_points *r) {
    for (int i = 0; i < r->count && i < RECENT; i++)
        if (memcmp(r->x[i], x, sizeof r->x[i]) == 0) return r->err[i];
    const int slot = r->count++ % RECENT;
    memcpy(r->x[slot], x, sizeof r->x[slot]);
    return r->err[slot] = err_of(y, x, f);
}

/* Golden section on each parameter of [first, last] in turn, from best. */
static double coordinate_search(objective err_of, const double *y, int first, int last, int rounds, double best[PARAMS],
                                double best_err, factor_cache *f) {
    const double g = (sqrt(5) - 1) / 2;
    recent_points recent = { .count = 0 };
    for (int round = 0; round < rounds; round++)
        for (int p = first; p <= last; p++) {
            double a = lo[p], b = hi[p], x[PARAMS];
            memcpy(x, best, sizeof x);
            for (int it = 0; it < 12; it++) { /* the bracket shrinks to 0.3 % */
                double c = b - g * (b - a), d = a + g * (b - a);
                x[p] = c;
                double ec = error_at(err_of, y, x, f, &recent);
                x[p] = d;
                double ed = error_at(err_of, y, x, f, &recent);
                if (ec < ed) b = d;
                else a = c;
            }
            x[p] = (a + b) / 2;
            double e = error_at(err_of, y, x, f, &recent);
            if (e < best_err) best_err = e, memcpy(best, x, sizeof x);
        }
    return best_err;
}

ht_result ht_marschner_fit_scheuermann(const ht_shading *m, const ht_scene *scene, ht_marschner_fit *out) {
    memset(out, 0, sizeof *out);
    if (m->model != HT_MODEL_MARSCHNER) return HT_ERR_INVALID_ARGUMENT;
    sample *ps = malloc(sizeof *ps * SAMPLES);
    factor_cache fc = { .f = malloc(sizeof *fc.f * SAMPLES * 3 * FACTORS),
                        .terms = malloc(sizeof *fc.terms * SAMPLES * HT_MAX_LIGHTS) };
    double *y = malloc(sizeof *y * SAMPLES * 3), *y_tt = malloc(sizeof *y_tt * SAMPLES * 3);
    if (!ps || !fc.f || !fc.terms || !y || !y_tt) {
        free(ps);
        free(fc.f);
        free(fc.terms);
        free(y);
        free(y_tt);
        return HT_ERR_OUT_OF_MEMORY;
    }
    make_samples(m, scene, ps);
    factor_inputs(ps, &fc);
    for (int n = 0; n < SAMPLES; n++)
        for (int c = 0; c < 3; c++) y[n * 3 + c] = ps[n].target[c], y_tt[n * 3 + c] = ps[n].tt_target[c];
    /* The transmission's shape first, against TT alone: a grid, then golden
       sections. */
    double best[PARAMS] = { 0.25, log1p(80), -0.1, log1p(20), 0.1, 0, 7, log1p(4) };
    double tt_best = tt_error(y_tt, best, &fc);
    const double centres[] = { -0.1, 0, 0.1 }, sharps[] = { 4, 7, 10 }, azimuths[] = { 0.5, 1.5, 3 };
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 3; c++) {
                double x[PARAMS];
                memcpy(x, best, sizeof x);
                x[TC] = centres[a], x[TK] = sharps[b], x[TA] = azimuths[c];
                double e = tt_error(y_tt, x, &fc);
                if (e < tt_best) tt_best = e, memcpy(best, x, sizeof best);
            }
    tt_best = coordinate_search(tt_error, y_tt, TC, TA, 2, best, tt_best, &fc);
    out->tt_rms = sqrt(tt_best / (3.0 * SAMPLES));
    /* Then the highlights on a coarse grid, wrap 0.25, with every colour
       solved jointly, and golden sections over all of it. */
    double best_err = solve_colours(y, best, NULL, &fc);
    const double exps[] = { 10, 80, 640 }, shifts[] = { -0.2, 0, 0.2 };
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            for (int c = 0; c < 3; c++)
                for (int d = 0; d < 3; d++) {
                    double x[PARAMS];
                    memcpy(x, best, sizeof x);
                    x[E1] = log1p(exps[a]), x[S1] = shifts[b], x[E2] = log1p(exps[c]), x[S2] = shifts[d];
                    double e = solve_colours(y, x, NULL, &fc);
                    if (e < best_err) best_err = e, memcpy(best, x, sizeof best);
                }
    best_err = coordinate_search(whole_error, y, WRAP, TA, 3, best, best_err, &fc);
    solve_colours(y, best, &out->shading, &fc);
    /* Both sides as a framebuffer keeps them, clamped to [0, 1]. */
    double sum = 0;
    for (int n = 0; n < SAMPLES; n++) {
        double rgb[3];
        ht_model_shade_d(&out->shading, &ps[n].s, ps[n].lights, ps[n].light_count, rgb);
        for (int c = 0; c < 3; c++) {
            double e = fabs(fmin(rgb[c], 1) - ps[n].target[c]);
            sum += e * e;
            out->max_error = fmax(out->max_error, e);
        }
    }
    out->rms = sqrt(sum / (3.0 * SAMPLES));
    free(ps);
    free(fc.f);
    free(fc.terms);
    free(y);
    free(y_tt);
    return HT_OK;
}

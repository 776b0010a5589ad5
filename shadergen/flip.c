/* flip.c — LDR-FLIP between two RGBA8 frames (flip.h has the pipeline
   and the paper's constants). Double precision throughout; every
   convolution is separable and clamps at the border. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "flip.h"

#define PI 3.14159265358979323846

/* Colour pipeline. */
#define Q_C 0.7
#define P_C 0.4
#define P_T 0.95
/* Feature pipeline: the detectors' width in degrees, and the exponent. */
#define FEATURE_W 0.082
#define Q_F 0.5

/* The CSF's sum of (at most two) Gaussians per YyCxCz channel: a, b pairs. */
static const double csf[3][2][2] = {
    { { 1.0, 0.0047 }, { 0.0, 1e-5 } },    /* achromatic */
    { { 1.0, 0.0053 }, { 0.0, 1e-5 } },    /* red-green */
    { { 34.1, 0.04 }, { 13.5, 0.025 } },   /* blue-yellow */
};
#define CSF_B_MAX 0.04

/* Linear sRGB to XYZ (D65), the matrix metrics.c uses. */
static const double rgb_to_xyz[3][3] = { { 0.4124564, 0.3575761, 0.1804375 },
                                         { 0.2126729, 0.7151522, 0.0721750 },
                                         { 0.0193339, 0.1191920, 0.9503041 } };

typedef struct colour_space {
    double xyz_to_rgb[3][3];
    double white[3];          /* XYZ of linear (1, 1, 1): the reference white */
    double linear[256];       /* 8-bit sRGB to linear */
} colour_space;

static void mat3_apply(const double m[3][3], const double v[3], double out[3]) {
    for (int i = 0; i < 3; i++) out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
}

static void colour_space_init(colour_space *cs) {
    const double (*m)[3] = rgb_to_xyz;
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            /* the adjugate's (i, j): the cofactor of (j, i) */
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            cs->xyz_to_rgb[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
    mat3_apply(m, (const double[3]){ 1.0, 1.0, 1.0 }, cs->white);
    for (int i = 0; i < 256; i++) {
        double c = i / 255.0;
        cs->linear[i] = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
    }
}

static double lab_f(double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

/* Linear RGB to Hunt-adjusted CIELAB. */
static void hunt_lab(const colour_space *cs, const double rgb[3], double out[3]) {
    double xyz[3];
    mat3_apply(rgb_to_xyz, rgb, xyz);
    double fx = lab_f(xyz[0] / cs->white[0]), fy = lab_f(xyz[1] / cs->white[1]), fz = lab_f(xyz[2] / cs->white[2]);
    double l = 116.0 * fy - 16.0;
    out[0] = l;
    out[1] = 0.01 * l * 500.0 * (fx - fy);
    out[2] = 0.01 * l * 200.0 * (fy - fz);
}

static double hyab(const double a[3], const double b[3]) {
    return fabs(a[0] - b[0]) + hypot(a[1] - b[1], a[2] - b[2]);
}

/* ---- separable convolution, clamped at the border ---- */

typedef struct kernel {
    double *w;                /* 2r + 1 weights, w[r] at offset 0 */
    int r;
} kernel;

/* out = in convolved with kx along rows then ky along columns; tmp is w×h. */
static void convolve(const double *in, double *out, double *tmp, int w, int h, const kernel *kx, const kernel *ky) {
    for (int y = 0; y < h; y++) {
        const double *row = in + (size_t)y * w;
        for (int x = 0; x < w; x++) {
            double s = 0.0;
            for (int i = -kx->r; i <= kx->r; i++) {
                int xx = x + i < 0 ? 0 : x + i >= w ? w - 1 : x + i;
                s += kx->w[i + kx->r] * row[xx];
            }
            tmp[(size_t)y * w + x] = s;
        }
    }
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double s = 0.0;
            for (int i = -ky->r; i <= ky->r; i++) {
                int yy = y + i < 0 ? 0 : y + i >= h ? h - 1 : y + i;
                s += ky->w[i + ky->r] * tmp[(size_t)yy * w + x];
            }
            out[(size_t)y * w + x] = s;
        }
}

/* The kernels for one ppd: per channel its Gaussians (normalised to sum 1
   in 1D, weighted so the 2D sum of the channel is 1), and the feature
   detectors' 1D factors. */
typedef struct kernels {
    kernel gauss[3][2];
    double weight[3][2];      /* 0: the term is absent */
    kernel smooth, edge, point;
    double *storage;
} kernels;

static bool kernels_init(kernels *k, double ppd) {
    memset(k, 0, sizeof *k);
    int rc = (int)ceil(3.0 * sqrt(CSF_B_MAX / (2.0 * PI * PI)) * ppd);
    double sigma = 0.5 * FEATURE_W * ppd;
    int rf = (int)ceil(3.0 * sigma);
    k->storage = malloc(sizeof *k->storage * (size_t)(6 * (2 * rc + 1) + 3 * (2 * rf + 1)));
    if (!k->storage) return false;
    double *next = k->storage;
    for (int c = 0; c < 3; c++) {
        double total = 0.0, raw[2] = { 0.0, 0.0 };
        for (int t = 0; t < 2; t++) {
            double a = csf[c][t][0], b = csf[c][t][1], sum = 0.0;
            kernel *g = &k->gauss[c][t];
            g->w = next, g->r = rc, next += 2 * rc + 1;
            for (int i = -rc; i <= rc; i++) {
                double x = i / ppd;
                g->w[i + rc] = exp(-PI * PI * x * x / b);
                sum += g->w[i + rc];
            }
            for (int i = 0; i <= 2 * rc; i++) g->w[i] /= sum;
            /* The 2D term a √(π/b) g(x) g(y) sums to a √(π/b) sum². */
            raw[t] = a * sqrt(PI / b) * sum * sum;
            total += raw[t];
        }
        for (int t = 0; t < 2; t++) k->weight[c][t] = raw[t] / total;
    }
    kernel *f[3] = { &k->smooth, &k->edge, &k->point };
    for (int j = 0; j < 3; j++) f[j]->w = next, f[j]->r = rf, next += 2 * rf + 1;
    double gsum = 0.0, epos = 0.0, ppos = 0.0, pneg = 0.0;
    for (int i = -rf; i <= rf; i++) {
        double g = exp(-(double)(i * i) / (2.0 * sigma * sigma));
        double e = -i * g, p = ((double)(i * i) / (sigma * sigma) - 1.0) * g;
        k->smooth.w[i + rf] = g, k->edge.w[i + rf] = e, k->point.w[i + rf] = p;
        gsum += g;
        if (e > 0) epos += e;
        if (p > 0) ppos += p;
        else pneg -= p;
    }
    /* A separable 2D detector's positive (negative) weights sum to the
       1D factor's positive (negative) sum times the smoothing sum. Below
       about 1 ppd the Gaussian underflows off its centre: a side with no
       weight stays 0 (no features at that scale) instead of 0/0. */
    for (int i = 0; i <= 2 * rf; i++) {
        k->smooth.w[i] /= gsum;
        k->edge.w[i] = epos > 0.0 ? k->edge.w[i] / epos : 0.0;
        double side = k->point.w[i] > 0 ? ppos : pneg;
        k->point.w[i] = side > 0.0 ? k->point.w[i] / side : 0.0;
    }
    return true;
}

/* ---- the comparison ---- */

/* Per image: YyCxCz planes, then filtered; the achromatic Y/Yn; the
   feature magnitudes. */
typedef struct planes {
    double *opp[3], *achromatic, *edge, *point;
} planes;

static void to_opponent(const colour_space *cs, const uint8_t *rgba, size_t n, planes *p) {
    for (size_t i = 0; i < n; i++) {
        double rgb[3] = { cs->linear[rgba[4 * i]], cs->linear[rgba[4 * i + 1]], cs->linear[rgba[4 * i + 2]] }, xyz[3];
        mat3_apply(rgb_to_xyz, rgb, xyz);
        double x = xyz[0] / cs->white[0], y = xyz[1] / cs->white[1], z = xyz[2] / cs->white[2];
        p->opp[0][i] = 116.0 * y - 16.0;
        p->opp[1][i] = 500.0 * (x - y);
        p->opp[2][i] = 200.0 * (y - z);
        p->achromatic[i] = y;
    }
}

/* The CSF filtering of the three channels in place, then the features;
   scratch holds 2 planes. */
static void filter_image(const kernels *k, planes *p, double *scratch, int w, int h) {
    size_t n = (size_t)w * (size_t)h;
    double *tmp = scratch, *acc = scratch + n;
    for (int c = 0; c < 3; c++) {
        double *sum = NULL;
        for (int t = 0; t < 2; t++) {
            if (k->weight[c][t] == 0.0) continue;
            if (!sum) {
                /* The first term lands in the edge plane, free until the features. */
                sum = p->edge;
                convolve(p->opp[c], sum, tmp, w, h, &k->gauss[c][t], &k->gauss[c][t]);
                for (size_t i = 0; i < n; i++) sum[i] *= k->weight[c][t];
            } else {
                convolve(p->opp[c], acc, tmp, w, h, &k->gauss[c][t], &k->gauss[c][t]);
                for (size_t i = 0; i < n; i++) sum[i] += k->weight[c][t] * acc[i];
            }
        }
        memcpy(p->opp[c], sum, n * sizeof *sum);
    }
    /* Edges: d/dx and d/dy of the Gaussian; points: the second derivatives. */
    convolve(p->achromatic, acc, tmp, w, h, &k->edge, &k->smooth);
    convolve(p->achromatic, p->edge, tmp, w, h, &k->smooth, &k->edge);
    for (size_t i = 0; i < n; i++) p->edge[i] = hypot(p->edge[i], acc[i]);
    convolve(p->achromatic, acc, tmp, w, h, &k->point, &k->smooth);
    convolve(p->achromatic, p->point, tmp, w, h, &k->smooth, &k->point);
    for (size_t i = 0; i < n; i++) p->point[i] = hypot(p->point[i], acc[i]);
}

/* Filtered YyCxCz back to linear RGB, clamped to [0, 1], to Hunt-adjusted Lab. */
static void filtered_lab(const colour_space *cs, const planes *p, size_t i, double lab[3]) {
    double y = (p->opp[0][i] + 16.0) / 116.0;
    double xyz[3] = { (p->opp[1][i] / 500.0 + y) * cs->white[0], y * cs->white[1],
                      (y - p->opp[2][i] / 200.0) * cs->white[2] };
    double rgb[3];
    mat3_apply(cs->xyz_to_rgb, xyz, rgb);
    for (int c = 0; c < 3; c++) rgb[c] = rgb[c] < 0.0 ? 0.0 : rgb[c] > 1.0 ? 1.0 : rgb[c];
    hunt_lab(cs, rgb, lab);
}

static int compare_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

ht_result ht_flip_compare(const ht_flip_desc *d, double *map, ht_flip_result *out, char *err, size_t err_size) {
    if (!d || !d->reference || !d->test) {
        snprintf(err, err_size, "ht_flip_compare: reference and test images are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (d->width < 1 || d->height < 1 || (long long)d->width * d->height > (1LL << 26)) {
        snprintf(err, err_size, "ht_flip_compare: %d x %d: width and height must be 1 or more, 64 Mi pixels at most",
                 d->width, d->height);
        return HT_ERR_INVALID_ARGUMENT;
    }
    double ppd = d->pixels_per_degree == 0.0 ? HT_FLIP_DEFAULT_PPD : d->pixels_per_degree;
    if (!(ppd > 0.0 && ppd <= HT_FLIP_MAX_PPD)) {
        snprintf(err, err_size, "ht_flip_compare: pixels_per_degree: %g is outside (0, %g]", ppd, HT_FLIP_MAX_PPD);
        return HT_ERR_INVALID_ARGUMENT;
    }
    int w = d->width, h = d->height;
    size_t n = (size_t)w * (size_t)h;
    kernels k;
    double *block = malloc(sizeof *block * n * 14);
    double *errors = map ? map : malloc(sizeof *errors * n);
    if (!block || !errors || !kernels_init(&k, ppd)) {
        free(block);
        if (!map) free(errors);
        snprintf(err, err_size, "ht_flip_compare: out of memory for %d x %d", w, h);
        return HT_ERR_OUT_OF_MEMORY;
    }
    planes p[2];
    double *next = block;
    for (int j = 0; j < 2; j++) {
        for (int c = 0; c < 3; c++) p[j].opp[c] = next, next += n;
        p[j].achromatic = next, next += n;
        p[j].edge = next, next += n;
        p[j].point = next, next += n;
    }
    double *scratch = next;
    colour_space cs;
    colour_space_init(&cs);
    to_opponent(&cs, d->reference, n, &p[0]);
    to_opponent(&cs, d->test, n, &p[1]);
    filter_image(&k, &p[0], scratch, w, h);
    filter_image(&k, &p[1], scratch, w, h);

    double green[3], blue[3];
    hunt_lab(&cs, (const double[3]){ 0.0, 1.0, 0.0 }, green);
    hunt_lab(&cs, (const double[3]){ 0.0, 0.0, 1.0 }, blue);
    const double cmax = pow(hyab(green, blue), Q_C);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        double lr[3], lt[3];
        filtered_lab(&cs, &p[0], i, lr);
        filtered_lab(&cs, &p[1], i, lt);
        double dc = pow(hyab(lr, lt), Q_C);
        double ec = dc < P_C * cmax ? P_T / (P_C * cmax) * dc
                                    : P_T + (dc - P_C * cmax) / (cmax - P_C * cmax) * (1.0 - P_T);
        double df = fmax(fabs(p[0].edge[i] - p[1].edge[i]), fabs(p[0].point[i] - p[1].point[i]));
        double ef = pow(df / sqrt(2.0), Q_F);
        errors[i] = pow(ec, 1.0 - ef);
        sum += errors[i];
    }
    if (out) {
        out->pixels = (long)n;
        out->mean = sum / (double)n;
        /* The sort reuses the image planes, done with. */
        memcpy(block, errors, n * sizeof *block);
        qsort(block, n, sizeof *block, compare_double);
        out->p95 = block[(size_t)ceil(0.95 * (double)n) - 1];
    }
    free(k.storage);
    free(block);
    if (!map) free(errors);
    return HT_OK;
}

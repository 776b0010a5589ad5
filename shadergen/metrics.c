/* metrics.c — PSNR, SSIM and CIEDE2000 between two RGBA8 frames, over the
   whole frame and over the hair's pixels (metrics.h has the definitions). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "metrics.h"

#define PI 3.14159265358979323846
#define SSIM_WINDOW 11
#define SSIM_RADIUS 5
#define SSIM_SIGMA 1.5
#define SSIM_K1 0.01
#define SSIM_K2 0.03
#define PEAK 255.0

static double srgb_to_linear(double c) {
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

static double lab_f(double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

void ht_metrics_srgb_to_lab(const uint8_t rgb[3], double lab[3]) {
    double r = srgb_to_linear(rgb[0] / 255.0), g = srgb_to_linear(rgb[1] / 255.0),
           b = srgb_to_linear(rgb[2] / 255.0);
    /* linear sRGB to XYZ, the matrix derived from the sRGB primaries and
       D65 (Lindbloom's, 7 digits: the 4-digit IEC one moves red's L by
       0.008); divided by the matrix's own white (its rows' sums, D65
       0.95047, 1, 1.08883), so sRGB white maps to L = 100, a = b = 0. */
    static const double m[3][3] = { { 0.4124564, 0.3575761, 0.1804375 },
                                    { 0.2126729, 0.7151522, 0.0721750 },
                                    { 0.0193339, 0.1191920, 0.9503041 } };
    double f[3];
    for (int i = 0; i < 3; i++)
        f[i] = lab_f((m[i][0] * r + m[i][1] * g + m[i][2] * b) / (m[i][0] + m[i][1] + m[i][2]));
    double fx = f[0], fy = f[1], fz = f[2];
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

static double deg(double rad) { return rad * (180.0 / PI); }
static double rad(double deg) { return deg * (PI / 180.0); }

/* Hue angle in degrees [0, 360); 0 for a colour without chroma (the
   paper's convention, which its test pairs 7 and 8 exercise). */
static double hue(double b, double a) {
    if (a == 0.0 && b == 0.0) return 0.0;
    double h = deg(atan2(b, a));
    return h < 0.0 ? h + 360.0 : h;
}

double ht_metrics_ciede2000(const double lab1[3], const double lab2[3]) {
    const double pow25_7 = 6103515625.0; /* 25^7 */
    double c1 = hypot(lab1[1], lab1[2]), c2 = hypot(lab2[1], lab2[2]);
    double cbar = 0.5 * (c1 + c2), cbar7 = pow(cbar, 7.0);
    double g = 0.5 * (1.0 - sqrt(cbar7 / (cbar7 + pow25_7)));
    double a1 = (1.0 + g) * lab1[1], a2 = (1.0 + g) * lab2[1];
    double cp1 = hypot(a1, lab1[2]), cp2 = hypot(a2, lab2[2]);
    double hp1 = hue(lab1[2], a1), hp2 = hue(lab2[2], a2);

    double dl = lab2[0] - lab1[0], dc = cp2 - cp1, dh = 0.0;
    bool achromatic = cp1 * cp2 == 0.0;
    if (!achromatic) {
        dh = hp2 - hp1;
        if (dh > 180.0) dh -= 360.0;
        else if (dh < -180.0) dh += 360.0;
    }
    double dH = 2.0 * sqrt(cp1 * cp2) * sin(rad(dh / 2.0));

    double lbar = 0.5 * (lab1[0] + lab2[0]), cpbar = 0.5 * (cp1 + cp2);
    double hbar = hp1 + hp2;
    if (!achromatic) {
        if (fabs(hp1 - hp2) > 180.0) hbar += hbar < 360.0 ? 360.0 : -360.0;
        hbar *= 0.5;
    }
    double t = 1.0 - 0.17 * cos(rad(hbar - 30.0)) + 0.24 * cos(rad(2.0 * hbar)) +
               0.32 * cos(rad(3.0 * hbar + 6.0)) - 0.20 * cos(rad(4.0 * hbar - 63.0));
    double dtheta = 30.0 * exp(-((hbar - 275.0) / 25.0) * ((hbar - 275.0) / 25.0));
    double cpbar7 = pow(cpbar, 7.0);
    double rc = 2.0 * sqrt(cpbar7 / (cpbar7 + pow25_7));
    double l50 = (lbar - 50.0) * (lbar - 50.0);
    double sl = 1.0 + 0.015 * l50 / sqrt(20.0 + l50);
    double sc = 1.0 + 0.045 * cpbar;
    double sh = 1.0 + 0.015 * cpbar * t;
    double rt = -sin(rad(2.0 * dtheta)) * rc;
    double ql = dl / sl, qc = dc / sc, qh = dH / sh;
    double sq = ql * ql + qc * qc + qh * qh + rt * qc * qh;
    return sqrt(sq > 0.0 ? sq : 0.0);
}

/* The k-th smallest of v[0..n) (0-based), v reordered: what v[k] would be
   after sorting it, without sorting (Hoare's selection; the nearest-rank
   p95 needs one rank of the region's 10⁵–10⁶ values). */
static double kth_smallest(double *v, long n, long k) {
    long lo = 0, hi = n - 1;
    while (lo < hi) {
        const double pivot = v[lo + (hi - lo) / 2];
        long i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot) i++;
            while (v[j] > pivot) j--;
            if (i <= j) {
                const double t = v[i];
                v[i++] = v[j];
                v[j--] = t;
            }
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else return v[k];
    }
    return v[k];
}

/* Sums of one region (whole frame or hair pixels). */
typedef struct region {
    double squared_error;   /* over R, G, B */
    double ssim_sum;
    long ssim_windows;
    double *delta_e;        /* one per pixel of the region */
    long pixels;
} region;

static void finish(region *g, bool identical_images, ht_metrics *out) {
    memset(out, 0, sizeof *out);
    out->pixels = g->pixels;
    out->psnr_db = g->squared_error == 0.0
                       ? INFINITY
                       : 10.0 * log10(PEAK * PEAK / (g->squared_error / (3.0 * (double)g->pixels)));
    if (g->ssim_windows) out->ssim = g->ssim_sum / (double)g->ssim_windows;
    else out->ssim = identical_images || g->pixels == 0 ? 1.0 : NAN;
    if (g->pixels) {
        double sum = 0.0;
        for (long i = 0; i < g->pixels; i++) sum += g->delta_e[i];
        out->delta_e00_mean = sum / (double)g->pixels;
        long rank = (long)ceil(0.95 * (double)g->pixels); /* nearest rank, 1-based */
        out->delta_e00_p95 = kth_smallest(g->delta_e, g->pixels, rank - 1);
    }
}

/* Gaussian filtering of the five SSIM statistics over windows wholly
   inside the image: a horizontal then a vertical pass of the separable
   kernel. in: 5 planes of w×h; out: 5 planes of (w-10)×(h-10). */
static void ssim_filter(const double *in, double *tmp, double *out, int w, int h, const double k[SSIM_WINDOW]) {
    int ow = w - 2 * SSIM_RADIUS, oh = h - 2 * SSIM_RADIUS;
    size_t plane = (size_t)w * (size_t)h, tplane = (size_t)ow * (size_t)h, oplane = (size_t)ow * (size_t)oh;
    for (int p = 0; p < 5; p++) {
        for (int y = 0; y < h; y++)
            for (int x = 0; x < ow; x++) {
                double s = 0.0;
                for (int i = 0; i < SSIM_WINDOW; i++) s += k[i] * in[p * plane + (size_t)y * w + x + i];
                tmp[p * tplane + (size_t)y * ow + x] = s;
            }
        for (int y = 0; y < oh; y++)
            for (int x = 0; x < ow; x++) {
                double s = 0.0;
                for (int i = 0; i < SSIM_WINDOW; i++) s += k[i] * tmp[p * tplane + (size_t)(y + i) * ow + x];
                out[p * oplane + (size_t)y * ow + x] = s;
            }
    }
}

double ht_metrics_delta_e00_pixel(const uint8_t a[3], const uint8_t b[3]) {
    if (memcmp(a, b, 3) == 0) return 0.0;
    double la[3], lb[3];
    ht_metrics_srgb_to_lab(a, la);
    ht_metrics_srgb_to_lab(b, lb);
    return ht_metrics_ciede2000(la, lb);
}

/* The images and size every entry point needs; `who` names it in err. */
static ht_result check_desc(const ht_metrics_desc *d, const char *who, char *err, size_t err_size) {
    if (!d || !d->reference || !d->test) {
        snprintf(err, err_size, "%s: reference and test images are required", who);
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (d->width < 1 || d->height < 1 || (long long)d->width * d->height > (1LL << 26)) {
        snprintf(err, err_size, "%s: %d x %d: width and height must be 1 or more, 64 Mi pixels at most", who,
                 d->width, d->height);
        return HT_ERR_INVALID_ARGUMENT;
    }
    return HT_OK;
}

ht_result ht_metrics_delta_e00_map(const ht_metrics_desc *d, double *map, char *err, size_t err_size) {
    ht_result r = check_desc(d, "ht_metrics_delta_e00_map", err, err_size);
    if (r != HT_OK) return r;
    if (!map) {
        snprintf(err, err_size, "ht_metrics_delta_e00_map: no output map");
        return HT_ERR_INVALID_ARGUMENT;
    }
    size_t n = (size_t)d->width * (size_t)d->height;
    for (size_t i = 0; i < n; i++) map[i] = ht_metrics_delta_e00_pixel(d->reference + 4 * i, d->test + 4 * i);
    return HT_OK;
}

ht_result ht_metrics_compare(const ht_metrics_desc *d, ht_metrics *whole, ht_metrics *hair, char *err,
                             size_t err_size) {
    ht_result r = check_desc(d, "ht_metrics_compare", err, err_size);
    if (r != HT_OK) return r;
    int w = d->width, h = d->height;
    size_t n = (size_t)w * (size_t)h;
    const uint8_t *bg = d->background ? d->background : d->reference;
    bool *is_hair = malloc(n * sizeof *is_hair);
    double *de_all = malloc(n * sizeof *de_all), *de_hair = malloc(n * sizeof *de_hair);
    double *planes = NULL, *tmp = NULL, *filtered = NULL;
    bool windows = w >= SSIM_WINDOW && h >= SSIM_WINDOW;
    if (windows) {
        planes = malloc(5 * n * sizeof *planes);
        tmp = malloc(5 * n * sizeof *tmp);
        filtered = malloc(5 * n * sizeof *filtered);
    }
    if (!is_hair || !de_all || !de_hair || (windows && (!planes || !tmp || !filtered))) {
        free(is_hair), free(de_all), free(de_hair), free(planes), free(tmp), free(filtered);
        snprintf(err, err_size, "ht_metrics_compare: out of memory for %d x %d", w, h);
        return HT_ERR_OUT_OF_MEMORY;
    }

    region all = { .delta_e = de_all }, hr = { .delta_e = de_hair };
    bool identical = true;
    for (size_t i = 0; i < n; i++) {
        const uint8_t *a = d->reference + 4 * i, *b = d->test + 4 * i;
        double se = 0.0;
        for (int c = 0; c < 3; c++) se += ((double)a[c] - b[c]) * ((double)a[c] - b[c]);
        if (se) identical = false;
        is_hair[i] = memcmp(a, bg, 3) != 0 || memcmp(b, bg, 3) != 0;
        double de = ht_metrics_delta_e00_pixel(a, b);
        all.squared_error += se;
        all.delta_e[all.pixels++] = de;
        if (is_hair[i]) {
            hr.squared_error += se;
            hr.delta_e[hr.pixels++] = de;
        }
        if (windows) {
            double ya = 0.299 * a[0] + 0.587 * a[1] + 0.114 * a[2];
            double yb = 0.299 * b[0] + 0.587 * b[1] + 0.114 * b[2];
            planes[i] = ya;
            planes[n + i] = yb;
            planes[2 * n + i] = ya * ya;
            planes[3 * n + i] = yb * yb;
            planes[4 * n + i] = ya * yb;
        }
    }

    if (windows) {
        double k[SSIM_WINDOW], ksum = 0.0;
        for (int i = 0; i < SSIM_WINDOW; i++) {
            double x = i - SSIM_RADIUS;
            k[i] = exp(-x * x / (2.0 * SSIM_SIGMA * SSIM_SIGMA));
            ksum += k[i];
        }
        for (int i = 0; i < SSIM_WINDOW; i++) k[i] /= ksum;
        ssim_filter(planes, tmp, filtered, w, h, k);
        const double c1 = (SSIM_K1 * PEAK) * (SSIM_K1 * PEAK), c2 = (SSIM_K2 * PEAK) * (SSIM_K2 * PEAK);
        int ow = w - 2 * SSIM_RADIUS, oh = h - 2 * SSIM_RADIUS;
        size_t on = (size_t)ow * (size_t)oh;
        for (int y = 0; y < oh; y++)
            for (int x = 0; x < ow; x++) {
                size_t o = (size_t)y * ow + x;
                double mu1 = filtered[o], mu2 = filtered[on + o];
                double s11 = filtered[2 * on + o] - mu1 * mu1, s22 = filtered[3 * on + o] - mu2 * mu2,
                       s12 = filtered[4 * on + o] - mu1 * mu2;
                double v = ((2.0 * mu1 * mu2 + c1) * (2.0 * s12 + c2)) /
                           ((mu1 * mu1 + mu2 * mu2 + c1) * (s11 + s22 + c2));
                all.ssim_sum += v;
                all.ssim_windows++;
                if (is_hair[(size_t)(y + SSIM_RADIUS) * w + x + SSIM_RADIUS]) {
                    hr.ssim_sum += v;
                    hr.ssim_windows++;
                }
            }
    }
    if (whole) finish(&all, identical, whole);
    if (hair) finish(&hr, identical, hair);
    free(is_hair), free(de_all), free(de_hair), free(planes), free(tmp), free(filtered);
    return HT_OK;
}

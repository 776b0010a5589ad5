/* marschner_lut.c — bakes the Marschner tier's lookup textures from the
   oracle and reads them back as the fragment shader does. */
#include "marschner_lut.h"
#include "model_marschner_bake.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int ht_marschner_lut_m_size(const ht_marschner *m) {
    double narrowest = ht_marschner_width(m, HT_LOBE_TT);
    double wanted = 6 * HT_PI / narrowest; /* texels over [-pi/2, pi/2] */
    int size = 64;
    while (size < wanted && size < 1024) size *= 2;
    return size;
}

static double axis(int i, int size, double lo, double hi) { return lo + (hi - lo) * i / (size - 1); }

/* v / scale in [0, 1] as 16 bits. */
static uint16_t encode(double v, double scale) {
    double x = scale > 0 ? v / scale : 0;
    x = x < 0 ? 0 : (x > 1 ? 1 : x);
    return (uint16_t)lrint(x * HT_MARSCHNER_LUT_MAX);
}

/* Texel (x, y) of half `half` of an atlas of n x n halves: the high byte
   in the top rows, the low byte n rows below. */
static void put(ht_image *img, int half, int x, int y, int channel, uint16_t v) {
    int n = img->height / 2;
    size_t at = ((size_t)y * img->width + (size_t)half * n + x) * 4 + channel;
    img->pixels[at] = (uint8_t)(v >> 8);
    img->pixels[at + (size_t)n * img->width * 4] = (uint8_t)(v & 0xff);
}

double ht_marschner_lut_texel(const ht_image *img, int half, int x, int y, int channel) {
    int n = img->height / 2;
    size_t at = ((size_t)y * img->width + (size_t)half * n + x) * 4 + channel;
    return (img->pixels[at] * 256 + img->pixels[at + (size_t)n * img->width * 4]) / (double)HT_MARSCHNER_LUT_MAX;
}

/* M spans 0 to hundreds (the normalised lobes pile up at the poles, where
   cos(theta_i) weighs them down), so it is stored in logarithms:
   t = log(1 + M / k) / log(1 + scale / k), decoded k (exp(t log(1 + scale / k)) - 1):
   a step of t is a fixed fraction of M + k. */
static double log_scale_of(double scale) { return log1p(scale / HT_MARSCHNER_LUT_LOG_KNEE); }

/* log_scale: log_scale_of(the channel's scale), made once per channel. */
static uint16_t encode_log(double v, double scale, double log_scale) {
    if (!(scale > 0)) return 0;
    return encode(log1p(fmax(v, 0) / HT_MARSCHNER_LUT_LOG_KNEE), log_scale);
}

double ht_marschner_lut_decode_log(double t, double scale) {
    return HT_MARSCHNER_LUT_LOG_KNEE * expm1(t * log_scale_of(scale));
}

/* Raw values at every texel, then scaled: per texel M_R, M_TT, M_TRT,
   REST rgb for the M axes; N_TRT rgb for the N axes. */
ht_result ht_marschner_lut_bake(const ht_marschner *m, ht_marschner_lut *out) {
    memset(out, 0, sizeof *out);
    const int ms = ht_marschner_lut_m_size(m), ns = HT_MARSCHNER_LUT_N_SIZE;
    out->m_size = ms;
    out->n_size = ns;
    out->fibre = *m;
    double *mv = malloc(sizeof *mv * (size_t)ms * ms * 6);
    double *nv = malloc(sizeof *nv * (size_t)ns * ns * 3);
    ht_result r = HT_ERR_OUT_OF_MEMORY;
    if (!mv || !nv || ht_image_alloc(&out->m, 2 * ms, 2 * ms, 4) != HT_OK ||
        ht_image_alloc(&out->n, ns, 2 * ns, 4) != HT_OK)
        goto done;
    /* N_rest depends on theta_r only: once per row. */
    double *rest_n = malloc(sizeof *rest_n * (size_t)ms * 3);
    if (!rest_n) goto done;
    for (int y = 0; y < ms; y++) {
        ht_marschner_azimuthal(m, HT_LOBE_REST, cos(axis(y, ms, -HT_PI / 2, HT_PI / 2)), 0, &rest_n[y * 3]);
    }
    /* M a row at a time (one theta_r), its values ht_marschner_longitudinal's */
    double *sines = malloc(sizeof *sines * (size_t)ms * 2);
    if (!sines) {
        free(rest_n);
        goto done;
    }
    double *row = sines + ms;
    for (int x = 0; x < ms; x++) sines[x] = sin(axis(x, ms, -HT_PI / 2, HT_PI / 2));
    for (int p = 0; p < HT_LOBE_COUNT; p++) {
        ht_marschner_m_lobe lobe = ht_marschner_m_lobe_for(m, (ht_marschner_lobe)p);
        for (int y = 0; y < ms; y++) {
            ht_marschner_m_lobe_row(&lobe, sines[y], sines, ms, row);
            for (int x = 0; x < ms; x++) {
                double *v = &mv[((size_t)y * ms + x) * 6];
                if (p < HT_LOBE_REST) v[p] = row[x];
                else
                    for (int c = 0; c < 3; c++) v[3 + c] = row[x] * rest_n[y * 3 + c];
            }
        }
    }
    free(sines);
    free(rest_n);
    /* N_TRT a column of phi at a time (one theta_r), its values ht_marschner_azimuthal's */
    double phis[HT_MARSCHNER_LUT_N_SIZE], column[HT_MARSCHNER_LUT_N_SIZE][3];
    for (int y = 0; y < ns; y++) phis[y] = axis(y, ns, 0, HT_PI);
    for (int x = 0; x < ns; x++) {
        ht_marschner_trt_column(m, cos(axis(x, ns, 0, HT_PI / 2)), phis, ns, column);
        for (int y = 0; y < ns; y++) memcpy(&nv[((size_t)y * ns + x) * 3], column[y], sizeof column[y]);
    }
    for (size_t i = 0; i < (size_t)ms * ms; i++) {
        for (int p = 0; p < 3; p++) out->m_scale[p] = fmax(out->m_scale[p], mv[i * 6 + p]);
        for (int c = 0; c < 3; c++) out->rest_scale = fmax(out->rest_scale, mv[i * 6 + 3 + c]);
    }
    for (size_t i = 0; i < (size_t)ns * ns * 3; i++) out->n_scale = fmax(out->n_scale, nv[i]);
    memset(out->m.pixels, 255, (size_t)out->m.width * out->m.height * 4); /* the unused alpha: opaque */
    memset(out->n.pixels, 255, (size_t)out->n.width * out->n.height * 4);
    double log_m_scale[3], log_rest_scale = log_scale_of(out->rest_scale);
    for (int p = 0; p < 3; p++) log_m_scale[p] = log_scale_of(out->m_scale[p]);
    for (int y = 0; y < ms; y++)
        for (int x = 0; x < ms; x++) {
            const double *v = &mv[((size_t)y * ms + x) * 6];
            for (int p = 0; p < 3; p++) put(&out->m, 0, x, y, p, encode_log(v[p], out->m_scale[p], log_m_scale[p]));
            for (int c = 0; c < 3; c++)
                put(&out->m, 1, x, y, c, encode_log(v[3 + c], out->rest_scale, log_rest_scale));
        }
    for (int y = 0; y < ns; y++)
        for (int x = 0; x < ns; x++) {
            const double *v = &nv[((size_t)y * ns + x) * 3];
            for (int c = 0; c < 3; c++) put(&out->n, 0, x, y, c, encode(v[c], out->n_scale));
        }
    r = HT_OK;
done:
    free(mv);
    free(nv);
    if (r != HT_OK) ht_marschner_lut_free(out);
    return r;
}

void ht_marschner_lut_free(ht_marschner_lut *lut) {
    ht_image_free(&lut->m);
    ht_image_free(&lut->n);
    memset(lut, 0, sizeof *lut);
}

/* Bilinear in half `half` (0 left, 1 right) of an atlas at x in
   [lo_x, hi_x] and y in [lo_y, hi_y], clamped to the half's outer texel
   centres, as the shader filters the 16-bit texels it reads; out in [0, 1]. */
static void bilinear(const ht_image *img, int half, double x, double lo_x, double hi_x, double y, double lo_y,
                     double hi_y, double out[4]) {
    int n = img->height / 2;
    double fx = (x - lo_x) / (hi_x - lo_x) * (n - 1), fy = (y - lo_y) / (hi_y - lo_y) * (n - 1);
    fx = fmin(fmax(fx, 0), n - 1);
    fy = fmin(fmax(fy, 0), n - 1);
    int x0 = (int)floor(fx), y0 = (int)floor(fy);
    if (x0 > n - 2) x0 = n - 2;
    if (y0 > n - 2) y0 = n - 2;
    double ax = fx - x0, ay = fy - y0;
    for (int c = 0; c < 4; c++) {
        double top = ht_marschner_lut_texel(img, half, x0, y0, c) * (1 - ax) +
                     ht_marschner_lut_texel(img, half, x0 + 1, y0, c) * ax;
        double bottom = ht_marschner_lut_texel(img, half, x0, y0 + 1, c) * (1 - ax) +
                        ht_marschner_lut_texel(img, half, x0 + 1, y0 + 1, c) * ax;
        out[c] = top * (1 - ay) + bottom * ay;
    }
}

void ht_marschner_lut_fibre(const ht_marschner_lut *lut, double sin_i, double sin_r, double cos_phi,
                            double rgb[3]) {
    double m[4], rest[4], ntrt[4], nr[3], ntt[3];
    const double h = HT_PI / 2;
    double theta_i = asin(fmax(-1, fmin(1, sin_i))), theta_r = asin(fmax(-1, fmin(1, sin_r)));
    double phi = acos(fmax(-1, fmin(1, cos_phi)));
    bilinear(&lut->m, 0, theta_i, -h, h, theta_r, -h, h, m);
    bilinear(&lut->m, 1, theta_i, -h, h, theta_r, -h, h, rest);
    bilinear(&lut->n, 0, fabs(theta_r), 0, h, phi, 0, HT_PI, ntrt);
    /* the shader's N_R and N_TT: these equations in GLSL (emit_marschner.c) */
    ht_marschner_azimuthal(&lut->fibre, HT_LOBE_R, cos(theta_r), phi, nr);
    ht_marschner_azimuthal(&lut->fibre, HT_LOBE_TT, cos(theta_r), phi, ntt);
    double mr = ht_marschner_lut_decode_log(m[0], lut->m_scale[0]);
    double mtt = ht_marschner_lut_decode_log(m[1], lut->m_scale[1]);
    double mtrt = ht_marschner_lut_decode_log(m[2], lut->m_scale[2]);
    for (int c = 0; c < 3; c++)
        rgb[c] = mr * nr[c] + mtt * ntt[c] + mtrt * lut->n_scale * ntrt[c] +
                 ht_marschner_lut_decode_log(rest[c], lut->rest_scale);
}

/* fixed_device.c — the fixed tier's device-only variant (fixed_device.h):
   its program, its 2D LUT resampled from the exact 3D one, its static
   vectors. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixed_device.h"
#include "vecmath.h"

/* Samples per unknown angle: the mean over a 12 x 12 grid of (phi, phi'). */
enum { ROLL_SAMPLES = 12 };

bool ht_fixed_device_applies(const ht_combiner_program *p) {
    return p->model == HT_MODEL_SCHEUERMANN && ht_combiner_lut_coords(p) == HT_COORDS_CPU_DOTS;
}

void ht_fixed_device_program(const ht_combiner_program *p, ht_combiner_program *out) {
    ht_combiner_program d = *p;
    d.model = HT_MODEL_KAJIYA_KAY;
    d.lut_size[2] = 1;
    for (int i = 0; i < d.stage_count; i++) {
        ht_combiner_stage *st = &d.stages[i];
        if (st->coords != HT_COORDS_CPU_DOTS) continue;
        st->coords = HT_COORDS_TEXTURE_MATRIX;
        st->target = GL_TEXTURE_2D;
    }
    *out = d;
}

/* One texel channel of the 3D LUT at dot products (a, b, c), trilinear
   over the "endpoints" mapping (texel x holds d = 2x/(n-1) - 1). */
static void sample3d(const ht_image *img, const int n[3], const double d[3], double rgb[3]) {
    int i0[3];
    double f[3];
    for (int k = 0; k < 3; k++) {
        double x = n[k] > 1 ? (fmin(fmax(d[k], -1.0), 1.0) + 1.0) * 0.5 * (n[k] - 1) : 0.0;
        i0[k] = (int)floor(x);
        if (i0[k] > n[k] - 2) i0[k] = n[k] > 1 ? n[k] - 2 : 0;
        f[k] = n[k] > 1 ? x - i0[k] : 0.0;
    }
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    for (int corner = 0; corner < 8; corner++) {
        int idx[3];
        double w = 1.0;
        for (int k = 0; k < 3; k++) {
            int bit = (corner >> k) & 1;
            idx[k] = i0[k] + (n[k] > 1 ? bit : 0);
            w *= bit ? f[k] : 1.0 - f[k];
        }
        if (w == 0.0) continue;
        const uint8_t *px = img->pixels + ((size_t)(idx[2] * n[1] + idx[1]) * (size_t)img->width + (size_t)idx[0]) *
                                              (size_t)img->channels;
        for (int c = 0; c < 3; c++) rgb[c] += w * px[c < img->channels ? c : 0];
    }
}

ht_result ht_fixed_device_lut(const ht_combiner_program *p, const ht_image *lut3d, ht_image *out) {
    const int *n = p->lut_size;
    if (!lut3d || lut3d->width != n[0] || lut3d->height != n[1] * n[2] || lut3d->channels < 1)
        return HT_ERR_INVALID_ARGUMENT;
    ht_result r = ht_image_alloc(out, n[0], n[1], 3);
    if (r != HT_OK) return r;
    const double a1 = atan(p->shift[0]), delta = atan(p->shift[1]) - atan(p->shift[0]);
    double roll[ROLL_SAMPLES];
    for (int k = 0; k < ROLL_SAMPLES; k++) roll[k] = cos(2.0 * M_PI * (k + 0.5) / ROLL_SAMPLES);
    for (int y = 0; y < n[1]; y++) {
        const double th = ht_combiner_lut_centre(y, n[1]), th_side = sqrt(fmax(0.0, 1.0 - th * th));
        for (int x = 0; x < n[0]; x++) {
            const double tl = ht_combiner_lut_centre(x, n[0]), tl_side = sqrt(fmax(0.0, 1.0 - tl * tl));
            double sum[3] = { 0, 0, 0 };
            for (int i = 0; i < ROLL_SAMPLES; i++)
                for (int j = 0; j < ROLL_SAMPLES; j++) {
                    const double d[3] = { sin(a1) * tl + cos(a1) * tl_side * roll[i], th,
                                          cos(delta) * th + sin(delta) * th_side * roll[j] };
                    double rgb[3];
                    sample3d(lut3d, n, d, rgb);
                    for (int c = 0; c < 3; c++) sum[c] += rgb[c];
                }
            uint8_t *px = out->pixels + ((size_t)y * (size_t)n[0] + (size_t)x) * 3;
            for (int c = 0; c < 3; c++) {
                double v = sum[c] / (ROLL_SAMPLES * ROLL_SAMPLES);
                px[c] = (uint8_t)lround(fmin(fmax(v, 0.0), 255.0));
            }
        }
    }
    return HT_OK;
}

void ht_fixed_device_vectors(const ht_combiner_program *p, ht_vertex *v, size_t count) {
    for (size_t i = 0; i < count; i++) {
        double T[3], N[3], raw[3], t1[3] = { 0, 0, 0 };
        ht_vec3_from_float(T, v[i].tangent);
        ht_vec3_from_float(raw, v[i].normal);
        ht_vec3_direction(N, raw);
        if (ht_vec3_direction(T, T)) {
            for (int k = 0; k < 3; k++) raw[k] = T[k] + p->shift[0] * N[k];
            ht_vec3_direction(t1, raw);
        }
        ht_vec3_store(v[i].tangent, t1);
    }
}

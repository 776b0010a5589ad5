/* heatmap.c — cubehelix colours and error images (heatmap.h). */
#include <math.h>

#include "heatmap.h"

#define PI 3.14159265358979323846
#define CUBEHELIX_START 0.5
#define CUBEHELIX_ROTATIONS (-1.5)
#define CUBEHELIX_HUE 1.2

void heatmap_colour(double t, uint8_t rgb[3]) {
    if (!(t > 0.0)) t = 0.0; /* NaN too */
    if (t > 1.0) t = 1.0;
    /* Green 2011, eq. 2: the grey level t plus a deviation of amplitude a
       in the plane perpendicular to the grey diagonal, at angle phi. */
    double phi = 2.0 * PI * (CUBEHELIX_START / 3.0 + CUBEHELIX_ROTATIONS * t);
    double a = CUBEHELIX_HUE * t * (1.0 - t) / 2.0;
    double c = cos(phi), s = sin(phi);
    double v[3] = { t + a * (-0.14861 * c + 1.78277 * s), t + a * (-0.29227 * c - 0.90649 * s), t + a * (1.97294 * c) };
    for (int i = 0; i < 3; i++) {
        double x = v[i] < 0.0 ? 0.0 : v[i] > 1.0 ? 1.0 : v[i];
        rgb[i] = (uint8_t)lround(x * 255.0);
    }
}

double heatmap_luma(const uint8_t rgb[3]) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

ht_result heatmap_image(const double *map, int width, int height, bool bottom_up, double max, ht_image *out) {
    if (!map || !(max > 0.0)) return HT_ERR_INVALID_ARGUMENT;
    ht_result r = ht_image_alloc(out, width, height, 3);
    if (r != HT_OK) return r;
    for (int y = 0; y < height; y++) {
        const double *row = map + (size_t)(bottom_up ? height - 1 - y : y) * (size_t)width;
        uint8_t *dst = out->pixels + (size_t)y * (size_t)width * 3;
        for (int x = 0; x < width; x++) heatmap_colour(row[x] / max, dst + 3 * x);
    }
    return HT_OK;
}

/* support_coverage.c — see support_coverage.h. A point is in a triangle
   when its three edge functions agree in sign; uv by barycentrics. */
#include "support_coverage.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define GRID HT_TEST_COVERAGE_GRID

/* The two axes a view down `axis` keeps. */
static void plane_axes(int axis, int *a, int *b) {
    *a = axis == 0 ? 1 : 0;
    *b = axis == 2 ? 1 : 2;
}

ht_test_view ht_test_view_of(const ht_mesh *m, int axis) {
    int a, b;
    plane_axes(axis, &a, &b);
    double lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY };
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const double p[2] = { m->vertices[i].position[a], m->vertices[i].position[b] };
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    return (ht_test_view){ axis, { lo[0], lo[1] }, fmax(hi[0] - lo[0], hi[1] - lo[1]) / GRID };
}

static double atlas_alpha(const ht_image *img, double u, double v) {
    int x = (int)floor(u * img->width), y = (int)floor(v * img->height);
    x = x < 0 ? 0 : x >= img->width ? img->width - 1 : x;
    y = y < 0 ? 0 : y >= img->height ? img->height - 1 : y;
    return img->pixels[((size_t)y * img->width + x) * img->channels + img->channels - 1] / 255.0;
}

double ht_test_covered_fraction(const ht_mesh *m, const ht_test_view *v, double alpha, const ht_image *atlas) {
    int a, b;
    plane_axes(v->axis, &a, &b);
    double *transmit = malloc(sizeof *transmit * GRID * GRID);
    if (!transmit) return NAN;
    for (size_t i = 0; i < (size_t)GRID * GRID; i++) transmit[i] = 1;
    for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
        double x[3], y[3];
        const ht_vertex *vx[3];
        for (int k = 0; k < 3; k++) {
            vx[k] = &m->vertices[m->indices[t + k]];
            x[k] = (vx[k]->position[a] - v->lo[0]) / v->cell;
            y[k] = (vx[k]->position[b] - v->lo[1]) / v->cell;
        }
        const double area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        if (area == 0) continue;
        const int x0 = (int)fmax(0, floor(fmin(x[0], fmin(x[1], x[2])))),
                  x1 = (int)fmin(GRID - 1, ceil(fmax(x[0], fmax(x[1], x[2]))));
        const int y0 = (int)fmax(0, floor(fmin(y[0], fmin(y[1], y[2])))),
                  y1 = (int)fmin(GRID - 1, ceil(fmax(y[0], fmax(y[1], y[2]))));
        for (int py = y0; py <= y1; py++)
            for (int px = x0; px <= x1; px++) {
                const double cx = px + 0.5, cy = py + 0.5;
                double e[3];
                for (int k = 0; k < 3; k++) {
                    const int j = (k + 1) % 3;
                    e[k] = (x[j] - x[k]) * (cy - y[k]) - (y[j] - y[k]) * (cx - x[k]);
                }
                if (!((e[0] >= 0 && e[1] >= 0 && e[2] >= 0) || (e[0] <= 0 && e[1] <= 0 && e[2] <= 0))) continue;
                double al = alpha;
                if (atlas) {
                    /* e[k] is the edge opposite vertex (k + 2) % 3, weighted by the area. */
                    const double w0 = e[1] / area, w1 = e[2] / area, w2 = e[0] / area;
                    const double u = w0 * vx[0]->uv[0] + w1 * vx[1]->uv[0] + w2 * vx[2]->uv[0];
                    const double vv = w0 * vx[0]->uv[1] + w1 * vx[1]->uv[1] + w2 * vx[2]->uv[1];
                    al = atlas_alpha(atlas, u, vv);
                }
                transmit[py * GRID + px] *= 1 - al;
            }
    }
    double sum = 0;
    for (size_t i = 0; i < (size_t)GRID * GRID; i++) sum += 1 - transmit[i];
    free(transmit);
    return sum / ((double)GRID * GRID);
}

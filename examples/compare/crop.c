/* crop.c — the brightest window and its enlargement (crop.h). */
#include <stdlib.h>
#include <string.h>

#include "crop.h"
#include "heatmap.h"

static const uint8_t *pixel(const ht_image *img, int x, int y) {
    return img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}

ht_result crop_find_brightest(const ht_image *img, const uint8_t background[3], int size, crop_region *out) {
    if (!img || !img->pixels || img->channels < 3 || !background || size < 1 || !out) return HT_ERR_INVALID_ARGUMENT;
    int w = img->width, h = img->height;
    int cw = size < w ? size : w, ch = size < h ? size : h;
    /* A summed-area table: every window's sum in four reads. */
    size_t stride = (size_t)w + 1;
    double *sat = calloc(stride * ((size_t)h + 1), sizeof *sat);
    if (!sat) return HT_ERR_OUT_OF_MEMORY;
    for (int y = 0; y < h; y++) {
        double row = 0.0;
        for (int x = 0; x < w; x++) {
            const uint8_t *p = pixel(img, x, y);
            if (memcmp(p, background, 3) != 0) row += heatmap_luma(p);
            sat[(size_t)(y + 1) * stride + (size_t)x + 1] = sat[(size_t)y * stride + (size_t)x + 1] + row;
        }
    }
    double best = -1.0;
    for (int y = 0; y + ch <= h; y++)
        for (int x = 0; x + cw <= w; x++) {
            double s = sat[(size_t)(y + ch) * stride + (size_t)(x + cw)] - sat[(size_t)y * stride + (size_t)(x + cw)] -
                       sat[(size_t)(y + ch) * stride + (size_t)x] + sat[(size_t)y * stride + (size_t)x];
            if (s > best + 1e-6) { /* strictly more: the first of equals stays */
                best = s;
                *out = (crop_region){ .x = x, .y = y, .w = cw, .h = ch };
            }
        }
    free(sat);
    return HT_OK;
}

ht_result crop_zoom(const ht_image *src, const crop_region *region, int scale, ht_image *out) {
    if (!src || !src->pixels || !region || !out || scale < 1 || region->w < 1 || region->h < 1 || region->x < 0 ||
        region->y < 0 || region->x > src->width - region->w || region->y > src->height - region->h ||
        (unsigned)region->w > HT_IMAGE_MAX_SIDE / (unsigned)scale ||
        (unsigned)region->h > HT_IMAGE_MAX_SIDE / (unsigned)scale)
        return HT_ERR_INVALID_ARGUMENT;
    ht_result r = ht_image_alloc(out, region->w * scale, region->h * scale, src->channels);
    if (r != HT_OK) return r;
    size_t c = (size_t)src->channels;
    for (int y = 0; y < out->height; y++) {
        uint8_t *dst = out->pixels + (size_t)y * (size_t)out->width * c;
        for (int x = 0; x < out->width; x++)
            memcpy(dst + (size_t)x * c, pixel(src, region->x + x / scale, region->y + y / scale), c);
    }
    return HT_OK;
}

/* heatmap.h — per-pixel error as an image a person reads: values mapped
   through cubehelix (Green 2011, "A colour scheme for the display of
   astronomical intensity images"), a perceptual colour map whose
   luminance rises monotonically from black to white, so the brighter
   pixel always has the larger error, in grey print and for colour-blind
   readers too.

   Usage:
       uint8_t rgb[3];
       heatmap_colour(0.3, rgb);                       // t in [0, 1]
       heatmap_image(map, width, height, true, 10.0, &img);  // map[i] / 10, rows flipped */
#ifndef HT_EXAMPLES_HEATMAP_H
#define HT_EXAMPLES_HEATMAP_H

#include <stdbool.h>
#include <stdint.h>

#include <hairtier/image.h>

/* The colour at t (clamped to [0, 1]; NaN reads as 0): black at 0, white
   at 1, cubehelix start 0.5, rotations -1.5, hue 1.2, gamma 1. */
void heatmap_colour(double t, uint8_t rgb[3]);
/* Relative luminance (Rec. 709 weights on the 8-bit values): what rises
   along the map. */
double heatmap_luma(const uint8_t rgb[3]);
/* map (width * height values, rows bottom-up when bottom_up) into an RGB
   image with top-down rows, value / max through heatmap_colour (max > 0;
   values at or above max are white). */
ht_result heatmap_image(const double *map, int width, int height, bool bottom_up, double max, ht_image *out);

#endif

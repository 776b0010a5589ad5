/* crop.h — the report's zoomed crops: where the reference's brightest
   highlight is, and that region of any image cut out and enlarged with
   nearest-neighbour pixels (no filtering, so what the eye compares are
   the tiers' own pixels).

   Usage:
       crop_region region;
       crop_find_brightest(&reference_rgb, background, 32, &region);
       ht_image zoomed = { 0 };
       crop_zoom(&tier_rgb, &region, 4, &zoomed);   // 128 x 128
       ht_image_free(&zoomed); */
#ifndef HT_EXAMPLES_CROP_H
#define HT_EXAMPLES_CROP_H

#include <stdint.h>

#include <hairtier/image.h>

typedef struct crop_region {
    int x, y;       /* top-left, image pixels, rows top-down */
    int w, h;
} crop_region;

/* The size x size window of img (RGB or RGBA, top-down) with the largest
   sum of luminance over hair pixels (those unlike `background` in any of
   R, G, B, as shadergen/metrics.h counts them; background counts 0), so a
   bright sky never wins over the hair. The window shrinks to the image
   when it is smaller; ties go to the topmost, then leftmost. */
ht_result crop_find_brightest(const ht_image *img, const uint8_t background[3], int size, crop_region *out);

/* region of src enlarged `scale` times (nearest neighbour) into out, with
   src's channels. HT_ERR_INVALID_ARGUMENT when the region is not inside src. */
ht_result crop_zoom(const ht_image *src, const crop_region *region, int scale, ht_image *out);

#endif

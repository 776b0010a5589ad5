/* support_coverage.h — the covered fraction of a hair mesh seen down one
   axis, rasterised on the CPU (no GL): what test_lod and test_cards
   compare a LOD's or the cards' coverage with full detail's by. */
#ifndef HT_TEST_SUPPORT_COVERAGE_H
#define HT_TEST_SUPPORT_COVERAGE_H

#include <hairtier/hairtier.h>
#include <hairtier/image.h>

#define HT_TEST_COVERAGE_GRID 384

/* An orthographic view down -axis (0 x, 1 y, 2 z) framing the mesh's
   bounding square in GRID x GRID pixels. */
typedef struct ht_test_view {
    int axis;
    double lo[2], cell;
} ht_test_view;
ht_test_view ht_test_view_of(const ht_mesh *m, int axis);

/* The mean over the pixels of 1 - prod(1 - alpha) over the triangles
   covering each pixel centre: alpha is `alpha`, or, with an atlas, its
   last channel at the triangle's uv there (nearest texel). */
double ht_test_covered_fraction(const ht_mesh *m, const ht_test_view *v, double alpha, const ht_image *atlas);

#endif

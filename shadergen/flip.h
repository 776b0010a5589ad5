/* flip.h — LDR-FLIP, the perceptual difference of two 8-bit sRGB frames
   (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild,
   "FLIP: A Difference Evaluator for Alternating Images", HPG 2020),
   written from the paper. Internal to libhairgen beside metrics.h: what
   hairgen --measure records as a tier's flip_mean / flip_p95 and what the
   error:flip:<E> policy reads.

   Usage:
       ht_flip_result f;
       double *map = malloc(sizeof *map * 256 * 256);   (or NULL)
       ht_result r = ht_flip_compare(&(ht_flip_desc){
               .reference = full_rgba, .test = fixed_rgba, .width = 256, .height = 256 },
           map, &f, err, sizeof err);

   The pipeline (every constant the paper's):
   - colour: sRGB (IEC 61966-2-1) → linear → XYZ (D65) → YyCxCz (the
     linearised CIELAB opponent space); each channel filtered by the
     contrast sensitivity function as a sum of Gaussians
     S(x) = Σ a_i √(π/b_i) exp(−π² x² / b_i), x in degrees, sampled at
     1/ppd over a radius of ⌈3 √(b_max / 2π²) ppd⌉ pixels, normalised to
     sum 1 per channel (achromatic a1 1, b1 0.0047; red–green a1 1,
     b1 0.0053; blue–yellow a1 34.1, b1 0.04, a2 13.5, b2 0.025); back to
     linear RGB clamped to [0, 1], to CIELAB, the Hunt adjustment
     (a, b scaled by 0.01 L); the HyAB distance |ΔL| + √(Δa² + Δb²), raised
     to q_c = 0.7 and mapped piecewise linearly so that p_c = 0.4 of the
     largest distance (Hunt-adjusted green to blue, also ^q_c) lands on
     p_t = 0.95 and the largest on 1.
   - features: on the achromatic channel Y/Yn of the unfiltered images,
     first (edges) and second (points) derivatives of a Gaussian of
     σ = 0.5 · 0.082° · ppd pixels over a radius of ⌈3σ⌉, each kernel's
     positive weights scaled to sum 1 and its negative ones to −1;
     ΔE_f = (max(|‖edge_r‖ − ‖edge_t‖|, |‖point_r‖ − ‖point_t‖|) / √2)^q_f,
     q_f = 0.5.
   - per pixel: ΔE_c^(1 − ΔE_f), in [0, 1]; 0 for identical images.
     Convolutions clamp at the frame's border (edge pixels repeat).
   mean: over all pixels; p95: nearest rank (the ceil(0.95 n)-th smallest),
   as metrics.h's ΔE p95. FLIP is symmetric: swapping the images gives the
   same map. */
#ifndef HT_FLIP_H
#define HT_FLIP_H

#include <stddef.h>
#include <stdint.h>

#include <hairtier/hairtier.h>

#define HT_FLIP_DEFAULT_PPD 67.0     /* the paper's: a 0.7 m distance from a 24" 4K monitor */
#define HT_FLIP_MAX_PPD 1000.0       /* bounds the kernels (radius 136 pixels at most) */

typedef struct ht_flip_desc {
    const uint8_t *reference;        /* required: RGBA8 (alpha ignored), rows tightly packed */
    const uint8_t *test;             /* required: the same layout and size */
    int width, height;               /* required, ≥ 1 */
    double pixels_per_degree;        /* 0 → HT_FLIP_DEFAULT_PPD; else (0, HT_FLIP_MAX_PPD] */
} ht_flip_desc;

typedef struct ht_flip_result {
    double mean;                     /* [0, 1]; 0 for identical images */
    double p95;                      /* [0, 1] */
    long pixels;
} ht_flip_result;

/* map, when not NULL, receives width × height per-pixel errors in the
   images' row order (the heatmap). out may be NULL when only the map is
   wanted. HT_ERR_INVALID_ARGUMENT with one line in err for a missing image,
   a bad size or a bad ppd; HT_ERR_OUT_OF_MEMORY. */
ht_result ht_flip_compare(const ht_flip_desc *desc, double *map, ht_flip_result *out, char *err, size_t err_size);

#endif

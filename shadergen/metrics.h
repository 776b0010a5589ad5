/* metrics.h — how far one rendered frame is from another: PSNR, SSIM and
   CIEDE2000, over the whole frame and over the hair's pixels. Internal to
   libhairgen (no runtime code compares images); hairgen's measuring step,
   the comparison programs and the tests use it, and the
   numbers it gives are what a bundle's per-tier `measured` object records
   (manifest.h) and what the `error:<dB>` policy reads.

   Usage:
       ht_metrics whole, hair;
       ht_result r = ht_metrics_compare(&(ht_metrics_desc){
               .reference = full_rgba, .test = fixed_rgba, .width = 256, .height = 256 },
           &whole, &hair, err, sizeof err);

   Definitions (each one the usual one, written down so numbers compare):
   - PSNR: 10 log10(255² / MSE), MSE over the R, G and B channels of 8-bit
     values; identical images give INFINITY.
   - SSIM: Wang, Bovik, Sheikh, Simoncelli 2004 — 11×11 Gaussian window,
     σ = 1.5, normalised to sum 1; K1 = 0.01, K2 = 0.03, L = 255; on the
     luminance Y = 0.299 R + 0.587 G + 0.114 B (Rec. 601, MATLAB's
     rgb2gray, in 8-bit units, not rounded); windows wholly inside the
     image only (the paper's MATLAB ssim_index: a (W-10)×(H-10) map), and
     the mean of that map. An image smaller than 11 pixels on a side has no
     window: SSIM is 1 when the images are identical, else NAN.
   - CIEDE2000: sRGB (IEC 61966-2-1, 8 bit) → linear → XYZ (D65) → CIELAB
     (reference white D65, Y = 1), then Sharma, Wu, Dalal 2005's formula
     with kL = kC = kH = 1; mean and 95th percentile (nearest rank:
     the ceil(0.95 n)-th smallest) over the pixels.
   - Hair pixels: where either image differs from the background colour
     (any of R, G, B); SSIM over hair pixels is the mean of the map over
     windows whose centre is a hair pixel. No hair pixel: count 0, PSNR
     INFINITY, SSIM 1, ΔE 0. */
#ifndef HT_METRICS_H
#define HT_METRICS_H

#include <stddef.h>
#include <stdint.h>

#include <hairtier/hairtier.h>

typedef struct ht_metrics_desc {
    const uint8_t *reference;   /* required: RGBA8 (alpha ignored), rows tightly packed */
    const uint8_t *test;        /* required: the same layout and size */
    int width, height;          /* required, ≥ 1 */
    const uint8_t *background;  /* NULL → the reference's first pixel (a frame cleared to one colour) */
} ht_metrics_desc;

typedef struct ht_metrics {
    double psnr_db;             /* INFINITY when identical */
    double ssim;                /* 1 when identical */
    double delta_e00_mean;
    double delta_e00_p95;
    long pixels;                /* pixels measured */
} ht_metrics;

/* whole and hair may be NULL (not wanted). HT_ERR_INVALID_ARGUMENT with
   one line in err for a missing image or a bad size; HT_ERR_OUT_OF_MEMORY. */
ht_result ht_metrics_compare(const ht_metrics_desc *desc, ht_metrics *whole, ht_metrics *hair,
                             char *err, size_t err_size);

/* 8-bit sRGB to CIELAB (D65). */
void ht_metrics_srgb_to_lab(const uint8_t rgb[3], double lab[3]);
/* CIEDE2000 between two CIELAB colours (kL = kC = kH = 1); symmetric. */
double ht_metrics_ciede2000(const double lab1[3], const double lab2[3]);
/* CIEDE2000 between two 8-bit sRGB colours: the per-pixel value whose mean
   and 95th percentile ht_metrics_compare reports (0 for equal colours). */
double ht_metrics_delta_e00_pixel(const uint8_t a[3], const uint8_t b[3]);
/* The per-pixel CIEDE2000 of test against reference into map (width ×
   height values, the images' row order): what an error heatmap shows.
   The same argument checks as ht_metrics_compare, and a NULL map is
   HT_ERR_INVALID_ARGUMENT. */
ht_result ht_metrics_delta_e00_map(const ht_metrics_desc *desc, double *map, char *err, size_t err_size);

#endif

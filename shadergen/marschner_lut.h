/* marschner_lut.h — the Marschner tier's lookup textures, baked from the
   oracle (runtime/model_marschner.h), and the lookup the tier's fragment
   shader makes (the same arithmetic in C, so tests can hold the textures
   to the oracle without a GL context).

   The fibre splits into functions of two angles each:
       fibre = sR  M_R(si, sr)  N_R(|sr|, phi)
             + sTT M_TT(si, sr) N_TT(|sr|, phi)       (RGB)
             + sTRT M_TRT(si, sr) N_TRT(|sr|, phi)    (RGB)
             + REST(si, sr)                            (RGB: M_rest N_rest, N_rest uniform in phi)
   with si = sin(theta_i) = T.L, sr = sin(theta_r) = T.V, phi = acos(cphi).
   M, REST and N_TRT are textures; N_R and N_TT are not: the shader
   evaluates them from the equations (ht_marschner_azimuthal: the exit
   azimuth's cubic solved as model_marschner.c solves it, Bravais Fresnel,
   absorption), because past theta_r of about 57 degrees (eta = 1.55) the
   parallel polarisation's index eta'' falls below 1 and its critical angle
   h = eta'' puts a square-root kink inside both lobes, on a curve in
   (theta_r, phi) that bilinear texels round off at any size (30/255 from
   the oracle at worst over random directions with N_R and N_TT in 256^2
   texels over (theta_r, phi); tests/test_marschner_lut.c). N_TRT is
   smooth there: its caustic's Gaussian spread also spreads the kink.
   Two RGBA8 atlases, every value 16 bits (the high byte in the top n rows,
   the low byte in the n rows below), every channel divided by its own
   scale (the largest value at a texel, so each uses the full 0..65535):
       m (2 m_size x 2 m_size, two halves side by side, axes theta_i,
          theta_r in [-pi/2, pi/2]):
           left M_R, M_TT, M_TRT, unused; right REST rgb, unused
       n (n_size x 2 n_size, one half, axes |theta_r| in [0, pi/2], phi in
          [0, pi]): N_TRT rgb, unused
   16 bits because 8 were not enough where TT glows: lit from behind, M
   is in the hundreds near the poles and a log code step of 8 bits is
   3% of it; and a device's own filtering of 8-bit texels is itself 8-bit
   (llvmpipe: 9-11/255 from the same textures filtered in double). So the
   shader fetches the four texels around a point at their centres (where
   GL_LINEAR returns the texel itself) and filters the 16-bit values in
   float, as ht_marschner_lut_fibre does in double.
   The axes are angles, not the dot products: in sin(theta) the lobes
   crowd at the poles and in cos(phi) the TT and R peaks crowd at the ends
   (measured with the capped caustic: 10/255 at the 99th percentile in
   dot products, 1.55 in angles), so the
   shader pays an asin and an acos per light. Texel i of an axis [lo, hi]
   holds x = lo + (hi - lo) i / (size - 1): the end points are texel
   centres. */
#ifndef HT_MARSCHNER_LUT_H
#define HT_MARSCHNER_LUT_H

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include <hairtier/model_marschner.h>

typedef struct ht_marschner_lut {
    ht_image m, n;
    int m_size, n_size;
    double m_scale[3];    /* M_R, M_TT, M_TRT */
    double rest_scale;
    double n_scale;       /* N_TRT */
    ht_marschner fibre;   /* the constants N_R and N_TT are evaluated from */
} ht_marschner_lut;

/* The M axes' resolution from the narrowest lobe (beta_TT = beta_R / 2):
   at least 6 texels across it, a power of two in [64, 1024]. */
int ht_marschner_lut_m_size(const ht_marschner *m);
/* M and REST are stored in logarithms (marschner_lut.c): the knee k of
   t = log(1 + M / k) / log(1 + scale / k). */
#define HT_MARSCHNER_LUT_LOG_KNEE 0.05
double ht_marschner_lut_decode_log(double t, double scale);

/* The largest 16-bit code, and the value in [0, 1] of texel (x, y) of
   half `half` (0 left, 1 right; n has only 0) of an atlas, channel `channel`. */
#define HT_MARSCHNER_LUT_MAX 65535
double ht_marschner_lut_texel(const ht_image *img, int half, int x, int y, int channel);

/* The N axes' resolution (N does not depend on beta). */
#define HT_MARSCHNER_LUT_N_SIZE 256

/* Bakes every texture; *out is zeroed on failure. */
ht_result ht_marschner_lut_bake(const ht_marschner *m, ht_marschner_lut *out);
void ht_marschner_lut_free(ht_marschner_lut *lut);

/* What the fragment shader computes: bilinear reads of the textures at
   the angles of the three dot products, the decode, N_R and N_TT from the
   equations, the sum. */
void ht_marschner_lut_fibre(const ht_marschner_lut *lut, double sin_i, double sin_r, double cos_phi,
                            double rgb[3]);

#endif

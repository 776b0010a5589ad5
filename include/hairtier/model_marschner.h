/* model_marschner.h — Marschner's fibre model (Marschner et al. 2003), the
   oracle of `model: "marschner"` materials, in double precision.

   One fibre, lobes p = R (0), TT (1), TRT (2) and the rest of the series
   (3: TRRT and longer, as pbrt-v4 closes it):

       fibre(L, V) = sum over p of M_p(theta_i, theta_r) * N_p(theta_r, phi)

   with theta the longitudinal angle of a direction from the plane normal to
   the fibre (sin theta = dot(T, dir)) and phi the azimuth between L and V
   projected onto that plane (phi = 0: the light is on the viewer's side,
   phi = pi: the light is behind the fibre).

   Normalisation (said once here, used everywhere): fibre() is S(wi, wr) *
   cos(theta_i), the radiance a directional light of unit irradiance
   reflects, i.e. the Marschner scattering function times the fibre's
   projected width. Its integral over the sphere of wi (d omega = cos(theta_i)
   d theta_i d phi) is the white furnace, 1 when absorption is 0, because:
   - M_p is d'Eon et al. 2011's normalised longitudinal function (the one
     pbrt-v4 uses, written here from the paper), not Marschner's Gaussian in
     theta_h: for every theta_r, the integral of M_p * cos(theta_i) over
     theta_i in [-pi/2, pi/2] is 1, also for wide lobes where a Gaussian is
     cut off at the poles. Its variance is v = beta_p^2; the lobe is centred
     on theta_h = alpha_p (theta_r is rotated by -2 alpha_p).
   - N_p is Marschner's azimuthal function for a smooth fibre: the sum over
     the rays h that leave at azimuth phi of A_p(h) / |2 dphi/dh|, so its
     integral over phi is the mean of A_p over h in [-1, 1]. The exit
     azimuth is the cubic approximation of Marschner 2003 (eq. 10):
       phi(p, gamma_i) = (6 p c / pi - 2) gamma_i - 8 p c / pi^3 gamma_i^3 + p pi,
       c = asin(1 / eta'), h = sin(gamma_i),
     solved for gamma_i in closed form (one or three real roots). The rest
     (p = 3) is uniform in phi: the mean of its A over h, over 2 pi.
   - A_p carries Fresnel with the Bravais indices eta' (perpendicular) and
     eta'' (parallel polarisation), averaged, and absorption along the
     internal path: A_R = F, A_TT = (1-F)^2 T, A_TRT = (1-F)^2 F T^2, the rest
     A_TRT F T / (1 - F T), with T = exp(-2 sigma_a cos(gamma_t) /
     cos(theta_t)), sigma_a per fibre radius, sin(gamma_t) = h / eta',
     sin(theta_t) = sin(theta_r) / eta. With sigma_a = 0 they sum to 1.
   - N_p (and A_p) take theta_r, the viewer's angle, where Marschner takes
     theta_d = (theta_r - theta_i) / 2: pbrt-v4 does the same, and it is what
     makes the furnace hold: with theta_d, a lobe shifted by alpha_p is
     weighted by another lobe's Fresnel split (measured: 0.84 at theta_r =
     -60 degrees, beta_R = 0.1). The N_TRT lookup texture is indexed by
     theta_r and phi accordingly.

   Documented answers at the undefined points (no NaN, no Inf):
   - The TRT caustic, where dphi/dgamma = 0 and the smooth fibre's
     1 / |dphi/dh| is infinite (and N_TRT jumps from that peak to a single
     branch, a step no lookup texture holds): N_TRT is the smooth-fibre
     function convolved in phi with a unit-area Gaussian of width
     HT_MARSCHNER_CAUSTIC_WIDTH, as Marschner 2003 spreads the caustic over
     an azimuthal width w_c (10 to 25 degrees there). It is evaluated as the
     integral over h of A_TRT(h) / 2 times that Gaussian at phi - phi(2, h)
     (64-point midpoint rule in gamma, exact to 1e-12 for this width):
     finite everywhere, its integral over phi still the mean of A_TRT. R
     and TT are sums over the cubic's roots. R has no caustic; TT has none
     while eta' > 1.155 (|dphi/dgamma| >= 2 - 6c/pi > 0 needs c < pi/3),
     i.e. for every theta_r when eta >= 1.155; below that, near theta_r = 0,
     TT's exit azimuth folds back near phi = pi and N_TT is unbounded at
     the fold (measured: 140 at theta_r 7.5 degrees, eta 1.1, against at
     most 0.69 anywhere at eta 1.55 without absorption), not spread as
     TRT's is.
   - A parallel-polarisation index eta'' below 1 (theta_r near 90 degrees)
     can reflect totally: Fresnel is then 1 for that polarisation; grazing
     rays (|h| = 1) reflect entirely.
   - The rest's 1 / (1 - F T) at F T = 1 takes its limit, 0.
   - sin(theta) outside [-1, 1] is clamped; a zero T, L or V gives fibre = 0
     (no strand or no ray, no scattering); L or V parallel to T has no
     azimuth and takes cos(phi) = 1.
   - M_p is evaluated in logarithms (I0 and sinh overflow for narrow lobes).

   Colour: sigma_a is RGB, so N_TT, N_TRT and the rest are RGB; M and N_R
   are grey.

   Usage (a blond fibre lit from behind; degrees to radians with HT_PI):
       ht_marschner m = { .absorption = { 0.06, 0.10, 0.20 }, .shift_r = -5 * HT_PI / 180,
                          .width_r = 10 * HT_PI / 180, .eta = 1.55 };
       const double T[3] = { 0, 1, 0 }, L[3] = { 0, 0.2, -1 }, V[3] = { 0, 0, 1 };
       double rgb[3];
       ht_marschner_fibre_vectors(&m, T, L, V, rgb);   // mostly TT: forward scattering
       printf("%g %g %g\n", rgb[0], rgb[1], rgb[2]); */
#ifndef HT_MODEL_MARSCHNER_H
#define HT_MODEL_MARSCHNER_H

#include "export.h"

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Below this squared length a vector has no direction: the rule of every
   shading function, Marschner's and model.h's (which includes this file). */
#define HT_MODEL_MIN_LENGTH2 1e-12

#define HT_PI 3.14159265358979323846

typedef enum ht_marschner_lobe {
    HT_LOBE_R = 0,
    HT_LOBE_TT = 1,
    HT_LOBE_TRT = 2,
    HT_LOBE_REST = 3, /* TRRT and every longer path */
    HT_LOBE_COUNT = 4,
} ht_marschner_lobe;

/* The material's constants (docs/materials.md: "marschner"), radians. */
typedef struct ht_marschner {
    double absorption[3]; /* sigma_a per fibre radius, RGB, [0, 50] */
    double shift_r;       /* alpha_R, radians; TT = -alpha_R / 2, TRT = -3 alpha_R / 2, rest 0 */
    double width_r;       /* beta_R, radians; TT = beta_R / 2, TRT = rest = 2 beta_R */
    double eta;           /* index of refraction, [1.1, 3] */
} ht_marschner;

/* The azimuthal width (radians, a Gaussian's sigma) TRT's caustic is spread over: 15 degrees. */
#define HT_MARSCHNER_CAUSTIC_WIDTH (15 * HT_PI / 180)

/* alpha_p and beta_p of lobe p from alpha_R and beta_R. */
HT_API double ht_marschner_shift(const ht_marschner *m, ht_marschner_lobe p);
HT_API double ht_marschner_width(const ht_marschner *m, ht_marschner_lobe p);

/* M_p with sin(theta_i) and sin(theta_r) (clamped to [-1, 1]). */
HT_API double ht_marschner_longitudinal(const ht_marschner *m, ht_marschner_lobe p,
                                 double sin_i, double sin_r);
/* M normalised for a variance v > 0 and unshifted angles (d'Eon 2011). */
HT_API double ht_marschner_longitudinal_v(double v, double sin_i, double sin_r);

/* Fresnel reflectance for the Bravais indices of cos(theta_r) at the
   in-plane incidence gamma_i with sin(gamma_i) = h. */
HT_API double ht_marschner_fresnel(double eta, double cos_theta_r, double h);

/* A_p(h) for cos(theta_r), RGB. */
HT_API void ht_marschner_attenuation(const ht_marschner *m, ht_marschner_lobe p,
                              double cos_theta_r, double h, double out[3]);

/* N_p(phi) for cos(theta_r) in [0, 1] and phi (radians, any value), RGB. */
HT_API void ht_marschner_azimuthal(const ht_marschner *m, ht_marschner_lobe p,
                            double cos_theta_r, double phi, double out[3]);

/* sum_p M_p N_p for the angles (see the normalisation above), RGB. */
HT_API void ht_marschner_fibre(const ht_marschner *m, double sin_i, double sin_r, double cos_phi,
                        double rgb[3]);

/* The same from unit-or-zero vectors T (fibre), L (to the light), V (to
   the viewer). */
HT_API void ht_marschner_fibre_vectors(const ht_marschner *m, const double T[3], const double L[3],
                                const double V[3], double rgb[3]);

#ifdef __cplusplus
}
#endif

#endif

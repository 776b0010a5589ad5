/* model_marschner_bake.h — the oracle's functions as the Marschner tier's
   bake (shadergen/marschner_lut.c) calls them thousands of times with the
   same fibre: each value bit for bit what model_marschner.h's function
   returns, only what does not change between calls computed once.
   Internal: not exported from the shared library. */
#ifndef HT_MODEL_MARSCHNER_BAKE_H
#define HT_MODEL_MARSCHNER_BAKE_H

#include <hairtier/model_marschner.h>

/* M_p's constants: variance v = beta_p^2, rotation by -2 alpha_p. */
typedef struct ht_marschner_m_lobe {
    double v, log_norm, cos_2a, sin_2a;
} ht_marschner_m_lobe;

ht_marschner_m_lobe ht_marschner_m_lobe_of(double v, double two_alpha);
/* Lobe p's: v = beta_p^2, two_alpha = 2 alpha_p. */
ht_marschner_m_lobe ht_marschner_m_lobe_for(const ht_marschner *m, ht_marschner_lobe p);
/* out[x] = ht_marschner_longitudinal(m, p, sin_i[x], sin_r) for x < count,
   l = ht_marschner_m_lobe_for(m, p): a row of the M texture. */
void ht_marschner_m_lobe_row(const ht_marschner_m_lobe *l, double sin_r, const double *sin_i, int count,
                             double *out);

/* out[i] = ht_marschner_azimuthal(m, HT_LOBE_TRT, cos_theta_r, phi[i]),
   RGB, for i < count: the same adaptive integration at the same
   tolerance, but every node's azimuth-free part (the attenuation, dh/dx,
   the exit azimuth) is computed once per column of azimuths, not once per
   azimuth (every azimuth bisects the same panels at the same points). */
void ht_marschner_trt_column(const ht_marschner *m, double cos_theta_r, const double *phi, int count,
                             double (*out)[3]);

#endif

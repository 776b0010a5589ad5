/* model_terms.h — ht_model_shade_d's Scheuermann terms for one light,
   each remade on its own: what the Marschner fit (shadergen/
   marschner_fit.c) needs to change one parameter at a time without
   shading everything again. Each term is bit for bit what shade_d adds
   for a white light with base = ao = sparkle = 1 and shift_tex = 0.5:
   the surface's and the light's vectors are normalised once here.
   Internal: not exported from the shared library. */
#ifndef HT_MODEL_TERMS_H
#define HT_MODEL_TERMS_H

#include <hairtier/model.h>

typedef struct ht_model_light_terms {
    double T[3], N[3], L[3], H[3]; /* unit or zero, as shade_d makes them */
    double n_dot_l;
    bool has_transmission;         /* T, L and V have directions */
    double mean_angle, transmission_base; /* the lobe's longitudinal angle and azimuth base */
} ht_model_light_terms;

void ht_model_light_terms_init(const ht_surface *s, const double L[3], ht_model_light_terms *g);
/* The diffuse term is ht_model_wrap_diffuse_d(g->n_dot_l, wrap). */
/* S(t, H) with t = T shifted by `shift` along N (primary or secondary). */
double ht_model_light_highlight(const ht_model_light_terms *g, double shift, double exponent);
/* tt of the transmission lobe t (ht_model_transmission_d's value). */
double ht_model_light_transmission(const ht_model_light_terms *g, const ht_transmission *t);

#endif

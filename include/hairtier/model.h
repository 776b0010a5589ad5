/* model.h — the hair shading model in C: the oracle every tier is compared to.

   The shading of docs/DESIGN.md ("The shading model"), evaluated per pixel:

       s      = shift_tex - 0.5
       t1     = normalize(T + (primary.shift   + s) * N)
       t2     = normalize(T + (secondary.shift + s) * N)
       H      = normalize(L + V)
       S(t,e) = smoothstep(-1, 0, dot(t,H)) * sin(t,H)^e
       diff   = saturate(mix(wrap, 1, dot(N,L))) * diffuse.color
       spec   = primary.color * S(t1, e1) + secondary.color * sparkle * S(t2, e2)
       tt     = transmission.color * ht_model_transmission(T, L, V)  (when present)
       rgb    = sum over lights of (diff + spec + tt) * base * light.color * ao

   Kajiya-Kay: diff = sin(T,L) * diffuse.color, spec = primary.color * S(T, e1).
   Marschner:  diff = sin(T,L) * diffuse.color, spec = ht_marschner_fibre_vectors
               (T, L, V) (model_marschner.h; no shift texture, no sparkle), in
               double in both precisions (the tier reads LUTs baked in double).

   Two precisions from one source (model.c is compiled twice over `real`):
   the _d functions are the truth, the _f ones mirror what a GPU does in
   32-bit float. Every undefined point has a finite documented answer, listed
   in model.c and docs/DESIGN.md; no function here returns NaN or Inf for
   finite inputs.

   Public: installed beside hairtier.h because hairgen.h's materials carry
   an ht_shading; it includes nothing of ours.

   Usage (one point lit by one light, in double: what every tier is held to):
       ht_shading m = { .model = HT_MODEL_SCHEUERMANN, .diffuse_color = { 0.3, 0.2, 0.1 }, .wrap = 0.25,
                        .primary = { .color = { 1, 1, 1 }, .exponent = 80, .shift = -0.1 },
                        .secondary = { .color = { 0.5, 0.4, 0.3 }, .exponent = 20, .shift = 0.1 } };
       ht_surface s = { .T = { 0, 1, 0 }, .N = { 0, 0, 1 }, .V = { 0, 0, 1 }, .base = { 1, 1, 1 },
                        .shift_tex = 0.5, .sparkle = 1, .ao = 1 };
       ht_light_ray light = { .L = { 0.6, 0.8, 0.7 }, .color = { 1, 1, 1 } };
       double rgb[3];
       ht_model_shade_d(&m, &s, &light, 1, rgb);
       printf("%g %g %g\n", rgb[0], rgb[1], rgb[2]); */
#ifndef HT_MODEL_H
#define HT_MODEL_H

#include "export.h"

#include <stdbool.h>

#include "model_marschner.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum ht_model_kind {
    HT_MODEL_SCHEUERMANN = 0, /* two shifted highlights, wrapped diffuse */
    HT_MODEL_KAJIYA_KAY = 1,  /* one unshifted highlight, sin(T,L) diffuse */
    HT_MODEL_MARSCHNER = 2,   /* Marschner's fibre (model_marschner.h), sin(T,L) diffuse */
} ht_model_kind;

typedef struct ht_lobe {
    double color[3]; /* [0,1] each */
    double exponent; /* [0,10000]; 0 means sin^0 = 1 everywhere */
    double shift;    /* along N, any finite value; [-100,100] from files */
} ht_lobe;

/* Scheuermann's transmission lobe, light passing through the fibre towards
   the viewer (a fit of Marschner's TT; HT_MODEL_SCHEUERMANN only):
       h   = (asin(T.L) + asin(T.V)) / 2  theta_h, radians (Marschner's M_TT
                                          is a Gaussian in it: measured 3x
                                          closer than in sines)
       a   = (1 - cos phi) / 2            phi between L and V around T
       tt  = exp2(-sharpness (h - centre)^2) * a^azimuth
   cos phi = dot of L and V projected normal to T (each unit, or zero when
   parallel to T: then cos phi = 0); tt = 0 when T, L or V has no direction;
   a^0 = 1. A zero colour is no lobe: no term, bit for bit the shading
   without it (every tier leaves it out). */
typedef struct ht_transmission {
    double color[3];  /* [0, HT_LIMIT_TRANSMISSION] each; all 0: no transmission */
    double centre;    /* theta_h at the peak, radians, [-1, 1] */
    double sharpness; /* [0, 10000] */
    double azimuth;   /* [0, 10000] */
} ht_transmission;

/* The material constants the shading needs (textures excluded). */
typedef struct ht_shading {
    ht_model_kind model;
    double diffuse_color[3];
    double wrap;          /* [0,1] */
    ht_lobe primary;
    ht_lobe secondary;    /* ignored by Kajiya-Kay */
    ht_marschner marschner; /* Marschner only; primary, secondary and wrap are then unused */
    ht_transmission transmission; /* Scheuermann only; zero: none (last: positional initialisers keep their meaning) */
} ht_shading;

/* What one shaded point sees. Vectors need not be unit length. */
typedef struct ht_surface {
    double T[3];       /* tangent, root to tip */
    double N[3];       /* normal */
    double V[3];       /* towards the viewer */
    double base[3];    /* base(uv).rgb; 1 when the material has no base */
    double shift_tex;  /* shift(uv) in [0,1]; 0.5 when not modelled */
    double sparkle;    /* sparkle(uv) in [0,1]; 1 when not modelled */
    double ao;         /* [0,1] */
} ht_surface;

typedef struct ht_light_ray {
    double L[3];       /* towards the light, any length */
    double color[3];
} ht_light_ray;

/* HT_MODEL_MIN_LENGTH2, the direction rule: in model_marschner.h. */

/* rgb = the model's colour, before any framebuffer clamp. Always finite,
   within [0, sum of light.color * (diffuse + primary + secondary colour)]. */
HT_API void ht_model_shade_d(const ht_shading *m, const ht_surface *s,
                      const ht_light_ray *lights, int light_count, double rgb[3]);
/* The same computed in 32-bit float throughout (inputs rounded to float). */
HT_API void ht_model_shade_f(const ht_shading *m, const ht_surface *s,
                      const ht_light_ray *lights, int light_count, double rgb[3]);

/* S(t,e) for t and h of any length; 0 when either has no direction. */
HT_API double ht_model_highlight_d(const double t[3], const double h[3], double exponent);
HT_API float ht_model_highlight_f(const float t[3], const float h[3], float exponent);

/* True when m draws a transmission lobe (a Scheuermann shading with a
   non-zero transmission colour): the one test every tier asks. */
HT_API bool ht_model_has_transmission(const ht_shading *m);
/* The lobe's scalar factor tt (see ht_transmission) for T, L, V of any length. */
HT_API double ht_model_transmission_d(const ht_transmission *t, const double T[3], const double L[3],
                                      const double V[3]);

/* S as a function of c = dot(t,H) of unit vectors (what a LUT indexes). */
HT_API double ht_model_highlight_of_cos_d(double c, double exponent);

/* saturate(mix(wrap, 1, n_dot_l)) */
HT_API double ht_model_wrap_diffuse_d(double n_dot_l, double wrap);

/* The shading as a function of three dot products of unit vectors, for one
   white light with base = ao = sparkle = 1 and no shift texture (Heidrich-
   Seidel: what a lookup texture indexed by dot products can hold):
     Scheuermann: a = N.L, b = t1.H, c = t2.H
       diffuse.color * wrap_diffuse(a) + primary.color * S(b) + secondary.color * S(c)
     Kajiya-Kay:  a = T.L, b = T.H, c unused
       diffuse.color * sqrt(1 - a^2) + primary.color * S(b)
   The fixed tier bakes its LUT from this. */
HT_API void ht_model_dot_terms_d(const ht_shading *m, double a, double b, double c,
                          double rgb[3]);

/* ht_model_dot_terms_d is separable: each dot product feeds one scalar
   factor, rgb[i] = diffuse.color[i] * f[0] + primary.color[i] * f[1]
   + secondary.color[i] * f[2]. A LUT baker evaluates each axis once
   (axis 0, 1, 2 = a, b, c) and combines; the result is bit-identical to
   ht_model_dot_terms_d. */
HT_API double ht_model_dot_factor_d(const ht_shading *m, int axis, double value);
HT_API void ht_model_dot_combine_d(const ht_shading *m, const double factors[3], double rgb[3]);

/* The largest value any channel of ht_model_dot_terms_d can take. */
HT_API double ht_model_dot_terms_max(const ht_shading *m);

#ifdef __cplusplus
}
#endif

#endif

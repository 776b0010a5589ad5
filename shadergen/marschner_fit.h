/* marschner_fit.h — Scheuermann constants with a transmission lobe
   (model.h's ht_transmission) fitted to a Marschner material under a
   scene's lights, so the tiers below `marschner` (full, vertex, fixed4,
   fixed, gl11) draw a physical material too.

   Least squares over a fixed, seeded set of HT_MARSCHNER_FIT_SAMPLES
   shading points of the scene's light layout: V a ray of its camera's
   field of view, its lights with their directions and colours (a point
   light as seen from the camera's target), T anywhere, N perpendicular
   to T facing the viewer, base = ao = 1. The lights fall on the hair from
   the front and from behind (backlit.json's key; every scene's fill).
   The target is ht_model_shade_d of the Marschner material under all the
   lights, clamped to [0, 1] (what a framebuffer keeps); the fit
   ht_model_shade_d of the Scheuermann one, clamped likewise: a sample the
   fit already drives past 1 has a constant error and leaves the colour
   solve (censored least squares, repeated until the set holds).
   First the lobe's shape (centre, sharpness, azimuth) against the
   fibre's M_TT N_TT alone, with its colour; then the colours enter
   linearly (per channel: diffuse, primary, secondary in [0, 1],
   transmission in [0, HT_LIMIT_TRANSMISSION], solved exactly for the
   nonlinear ones); wrap, the exponents, the shifts and the lobe's shape
   by coordinate search (golden section on each in turn, from a coarse
   grid's best). Like Karis 2016 fits his approximation to the Marschner
   lobes, but to the phenomenological model every lower tier draws. */
#ifndef HT_MARSCHNER_FIT_H
#define HT_MARSCHNER_FIT_H

#include <hairtier/hairtier.h>
#include <hairtier/model.h>
#include <hairtier/scene.h>

#define HT_MARSCHNER_FIT_SAMPLES 4000

typedef struct ht_marschner_fit {
    ht_shading shading;   /* model Scheuermann */
    double rms;           /* root mean square error per channel, both sides clamped, [0, 1] units */
    double max_error;     /* the largest channel error over the samples */
    double tt_rms;        /* the transmission's shape against M_TT N_TT alone, rms, [0, 1] units */
} ht_marschner_fit;

/* m must be a Marschner shading, scene the bundle's; the result is deterministic. */
ht_result ht_marschner_fit_scheuermann(const ht_shading *m, const ht_scene *scene, ht_marschner_fit *out);

#endif

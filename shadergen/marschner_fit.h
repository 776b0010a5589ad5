/* marschner_fit.h — Scheuermann constants fitted to a Marschner material,
   so the tiers below `marschner` (full, vertex, fixed4, fixed, gl11) draw
   a physical material too.

   Least squares over a fixed, seeded set of HT_MARSCHNER_FIT_SAMPLES
   shading points (T, N perpendicular to T, L and V anywhere on the sphere
   with the light above the ribbon's horizon, N.L > -0.25, and the viewer in
   front, N.V > 0), one white light, base = ao = 1: the target is
   ht_model_shade_d of the Marschner material clamped to [0, 1] (what a
   framebuffer keeps); the fit ht_model_shade_d of the Scheuermann one.
   The colours enter linearly (per channel: diffuse, primary, secondary,
   each in [0, 1], solved exactly for the nonlinear ones); wrap, the
   exponents and the shifts by coordinate search (golden section on each in
   turn, from a coarse grid's best). Like Karis 2016 fits his approximation
   to the Marschner lobes, but to the phenomenological model every lower
   tier already draws. */
#ifndef HT_MARSCHNER_FIT_H
#define HT_MARSCHNER_FIT_H

#include <hairtier/hairtier.h>
#include <hairtier/model.h>
#include <hairtier/scene.h>

#define HT_MARSCHNER_FIT_SAMPLES 4000 /* half lit from the front, half from behind */

typedef struct ht_marschner_fit {
    ht_shading shading;   /* model Scheuermann */
    double rms;           /* root mean square error per channel, in [0, 1] output units */
    double max_error;     /* the largest channel error over the samples */
    double tt_rms;        /* the transmission's shape against M_TT N_TT alone, rms, [0, 1] units */
} ht_marschner_fit;

/* m must be a Marschner shading; the result is deterministic. */
ht_result ht_marschner_fit_scheuermann(const ht_shading *m, const ht_scene *scene, ht_marschner_fit *out);

#endif

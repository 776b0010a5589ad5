/* emit_fixed4.c — the `fixed4` tier: the program fixed4.json
   (fallback/fixed4_program.h) holding the material constants of the four
   fixed combiner stages. The LUTs are baked by the runtime for the frame's
   light colours, so the bundle carries no LUT image; the albedo is the
   GLSL tiers' packed one.

   LUT axes: a highlight of exponent e takes the next power of two of
   8 sqrt(e) texels, clamped to [16, 256] (as the fixed tier's axes);
   Kajiya-Kay's sin(T.L) takes 256 (infinite slope at T.L = +-1). With two
   lights a Scheuermann LUT is n x n, at most 256 x 256 RGB8. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "emit.h"
#include "errfmt.h"
#include "fixed4_program.h"
#include "strbuf.h"

static int axis_for(double exponent, const double color[3]) {
    if (color[0] <= 0.0 && color[1] <= 0.0 && color[2] <= 0.0) return 16;
    int n = ht_lut_highlight_texels(exponent);
    return n < 16 ? 16 : (n > HT_FIXED4_MAX_AXIS ? HT_FIXED4_MAX_AXIS : n);
}

void ht_fixed4_program_from_plan(const ht_plan *plan, ht_fixed4_program *p) {
    memset(p, 0, sizeof *p);
    p->shading = ht_plan_unmasked_shading(plan);
    p->lights = plan->light_count < HT_FIXED4_MAX_LIGHTS ? plan->light_count : HT_FIXED4_MAX_LIGHTS;
    p->ao = plan->ao;
    if (p->shading.model == HT_MODEL_KAJIYA_KAY) {
        p->lut_axis[0] = HT_FIXED4_MAX_AXIS;
        p->lut_axis[1] = axis_for(p->shading.primary.exponent, p->shading.primary.color);
    } else {
        p->lut_axis[0] = axis_for(p->shading.primary.exponent, p->shading.primary.color);
        p->lut_axis[1] = axis_for(p->shading.secondary.exponent, p->shading.secondary.color);
    }
}

static void list(const ht_plan *plan, const ht_fixed4_program *p, ht_tier_output *out) {
    char line[160];
    const bool kk = p->shading.model == HT_MODEL_KAJIYA_KAY;
    ht_output_add_model_features(out, plan);
    if (plan->base) ht_output_add_feature(out, "base");
    if (plan->alpha) ht_output_add_feature(out, "alpha");
    if (plan->ao) ht_output_add_feature(out, "ao");
    int w = 0, h = 0;
    ht_fixed4_lut_size(p, 0, &w, &h);
    snprintf(line, sizeof line, "%d luts %dx%d rgb8, baked by the runtime", ht_fixed4_lut_count(p), w, h);
    ht_output_add_feature(out, line);
    if (p->viewer == HT_FIXED4_VIEWER_LOCAL) {
        snprintf(line, sizeof line, "coords cpu-local-viewer (the hair spans %.1f deg from the eye)",
                 plan->viewer_spread * 180.0 / M_PI);
        ht_output_add_feature(out, line);
    } else {
        ht_output_add_feature(out, "coords texture-matrix");
    }
    if (!kk) ht_output_add_feature(out, "diffuse gl-lighting");

    if (plan->shift) ht_output_add_dropped(out, "shift: the per-texel jitter (t1, t2 are static per vertex)");
    ht_output_drop_transmission(out, plan, "its azimuth needs L.V beside T.L and T.V, a LUT axis that moves with "
                                           "the eye, and the four units hold the two lights' highlights");
    if (plan->sparkle) {
        snprintf(line, sizeof line, "sparkle: approximated by its mean %.3f scaling the secondary highlight "
                                    "(four ARB_texture_env_combine stages hold no second product)",
                 plan->sparkle_mean);
        ht_output_add_dropped(out, line);
    }
    if (plan->light_count > HT_FIXED4_MAX_LIGHTS) {
        snprintf(line, sizeof line, "lights: %d of %d (one LUT axis per light)", HT_FIXED4_MAX_LIGHTS,
                 plan->light_count);
        ht_output_add_dropped(out, line);
    }
    if (p->viewer == HT_FIXED4_VIEWER_INFINITE)
        ht_output_add_dropped(out, "viewer: infinite for H (a texture matrix holds one V per frame; the scene's "
                                   "hair is far enough for that)");
    else
        ht_output_add_dropped(out, "per-vertex CPU work: the LUT coordinates, in float, only when the eye or a "
                                   "light moved (the scene's viewer is too close for one V per frame)");
    if (!kk && p->lights > 1)
        ht_output_add_dropped(out, "diffuse: with two lights GL lighting clamps each light at N.L = 0, not at "
                                   "the wrapped zero: up to wrap x diffuse x light colour too bright behind");
    ht_output_add_dropped(out, "light colours: summed terms above 4 clamp (GL_RGB_SCALE is at most 4)");
    ht_output_add_dropped(out, "LUT: 8-bit, texel error up to 0.5/255 x scale, linear interpolation between "
                               "texels");
    ht_output_add_dropped(out, "a vertex without a tangent is black (the texture matrix cannot tell T = 0)");
}

ht_result ht_emit_fixed4(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->tier = HT_TIER_FIXED4;
    if (!plan) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "fixed4: NULL plan");
    ht_fixed4_program p;
    ht_fixed4_program_from_plan(plan, &p);
    if (p.lights < 1) return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "fixed4: no light to shade");
    for (int l = 0; l < p.lights; l++)
        if (plan->light_types[l] != HT_LIGHT_DIRECTIONAL)
            return ht_fail(err, err_size, HT_ERR_UNSUPPORTED,
                           "fixed4: light %d is a point light (a texture matrix holds one L per frame)", l);
    p.viewer = plan->local_viewer ? HT_FIXED4_VIEWER_LOCAL : HT_FIXED4_VIEWER_INFINITE;

    snprintf(out->requires.gl, sizeof out->requires.gl, "1.2"); /* GL_CLAMP_TO_EDGE */
    snprintf(out->requires.extensions[out->requires.extension_count++], sizeof out->requires.extensions[0],
             "GL_ARB_multitexture");
    snprintf(out->requires.extensions[out->requires.extension_count++], sizeof out->requires.extensions[0],
             "GL_ARB_texture_env_combine");
    out->requires.texture_units = ht_fixed4_units(&p);
    if (plan->base || plan->alpha) {
        if (ht_output_add_sampler(out, plan, "albedo"))
            out->samplers[out->sampler_count - 1].unit = ht_fixed4_lut_count(&p);
    }
    list(plan, &p, out);

    char *text = NULL;
    ht_result r = ht_fixed4_write(&p, &text, err, err_size);
    if (r == HT_OK)
        r = ht_output_add_text(out, "fixed4.json", "program", text, HT_STAGE_NONE, 0, false, err, err_size);
    if (r != HT_OK) ht_tier_output_free(out);
    return r;
}

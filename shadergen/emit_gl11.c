/* emit_gl11.c — the `gl11` tier, the last resort: the program gl11.json
   (fallback/gl11_program.h) holding the material constants the runtime's
   per-vertex CPU shading needs; the one texture is the GLSL tiers' packed
   albedo (or none: the runtime's white texel). Requirements: GL 1.1, no
   extension, one texture unit. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emit.h"
#include "errfmt.h"
#include "gl11_program.h"
#include "strbuf.h"

static void list(const ht_plan *plan, const ht_gl11_program *p, ht_tier_output *out) {
    char line[160];
    ht_output_add_model_features(out, plan);
    if (plan->base) ht_output_add_feature(out, "base");
    if (plan->alpha) ht_output_add_feature(out, "alpha");
    if (plan->ao) ht_output_add_feature(out, "ao");
    ht_output_add_feature(out, "lighting per vertex on the cpu (float, local viewer)");
    if (ht_model_has_transmission(&plan->shading)) ht_output_add_feature(out, "transmission per vertex");
    snprintf(line, sizeof line, "albedo x %.3f, vertex colours / %.3f", p->albedo_scale, p->albedo_scale);
    ht_output_add_feature(out, line);

    ht_output_add_dropped(out, "per-pixel lighting: the model is evaluated per vertex and interpolated (Gouraud); "
                               "highlights narrower than a ribbon segment are lost");
    if (plan->shift) ht_output_add_dropped(out, "shift: the per-texel jitter (t1, t2 are static per vertex)");
    if (plan->sparkle) {
        snprintf(line, sizeof line, "sparkle: approximated by its mean %.3f scaling the secondary highlight",
                 plan->sparkle_mean);
        ht_output_add_dropped(out, line);
    }
    snprintf(line, sizeof line, "lighting above %.3f clamps: GL 1.1 clamps vertex colours to [0, 1] and has no "
                                "RGB_SCALE (the albedo is uploaded x %.3f to make that headroom)",
             p->albedo_scale, p->albedo_scale);
    ht_output_add_dropped(out, line);
}

ht_result ht_emit_gl11(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->tier = HT_TIER_GL11;
    if (!plan) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "gl11: NULL plan");
    ht_gl11_program p;
    memset(&p, 0, sizeof p);
    p.shading = ht_plan_unmasked_shading(plan);
    p.lights = plan->light_count;
    p.ao = plan->ao;
    p.albedo_scale = plan->base ? ht_gl11_albedo_scale(plan->albedo_max) : 1.0;

    snprintf(out->requires.gl, sizeof out->requires.gl, "1.1");
    out->requires.texture_units = 1;
    if (plan->base || plan->alpha) {
        if (ht_output_add_sampler(out, plan, "albedo")) out->samplers[out->sampler_count - 1].unit = 0;
    }
    list(plan, &p, out);

    char *text = NULL;
    ht_result r = ht_gl11_write(&p, &text, err, err_size);
    if (r == HT_OK)
        r = ht_output_add_text(out, "gl11.json", "program", text, HT_STAGE_NONE, 0, false, err, err_size);
    if (r != HT_OK) ht_tier_output_free(out);
    return r;
}

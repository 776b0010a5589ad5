/* plan.c — decides what the tiers model: the scene's lights, the textures the
   material has, and the texture units the GLSL tiers bind them to. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "hairgen_internal.h"
#include "shader_interface.h"

#define DEFAULT_OPAQUE_CUTOFF 0.98

static void note(ht_plan *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void note(ht_plan *p, const char *fmt, ...) {
    if (p->note_count >= HT_MAX_NOTES) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(p->notes[p->note_count++], sizeof p->notes[0], fmt, ap);
    va_end(ap);
}

static void add_texture(ht_plan *p, const char *name, const char *sampler, const char *contents) {
    ht_plan_texture *t = &p->textures[p->texture_count];
    snprintf(t->name, sizeof t->name, "%s", name);
    snprintf(t->sampler, sizeof t->sampler, "%s", sampler);
    snprintf(t->contents, sizeof t->contents, "%s", contents);
    t->unit = p->texture_count++;
}

static bool has(const ht_material *m, ht_texture_slot s) {
    return m->textures[s].origin != HT_TEXTURE_ABSENT;
}

/* A sphere around the origin holding the scene's hair: both builders grow
   hair from there (fur ball: strands of (joints - 1) segments, bent by
   gravity; patches: a head of head_radius with strips hanging below it).
   A strand file's extent is not known until it is read: its hair is taken
   to fill the view (the near-viewer plan, never wrong, only more work). */
static double hair_radius(const ht_scene *s) {
    if (s->geometry == HT_GEOMETRY_STRANDS) return INFINITY;
    if (s->geometry == HT_GEOMETRY_PATCHES) {
        double r = s->patches.head_radius > 0 ? s->patches.head_radius : 1.0;
        return 2.0 * r;
    }
    int joints = s->furball.joints > 0 ? s->furball.joints : 16;
    double length = s->furball.length > 0 ? s->furball.length : 0.08;
    return 1.2 * (double)(joints - 1) * length;
}

static void plan_viewer(const ht_scene *scene, ht_plan *out) {
    const float *e = scene->camera.eye;
    double dist = sqrt((double)e[0] * e[0] + (double)e[1] * e[1] + (double)e[2] * e[2]);
    double r = hair_radius(scene);
    out->viewer_spread = dist > r ? asin(r / dist) : M_PI / 2;
    double e_max = out->shading.primary.exponent;
    if (out->secondary && out->shading.secondary.exponent > e_max) e_max = out->shading.secondary.exponent;
    double width = 1.0 / sqrt(e_max > 1.0 ? e_max : 1.0);
    /* H turns by half of V's turn; d = t.H moves by up to that much. */
    out->local_viewer = 0.5 * out->viewer_spread > 0.25 * width;
}

void ht_plan_make(const ht_material *m, const ht_scene *scene, ht_plan *out) {
    memset(out, 0, sizeof *out);
    out->shading = m->shading;
    const bool marschner = m->shading.model == HT_MODEL_MARSCHNER;
    /* Marschner, like Kajiya-Kay, has no shifted tangents, sparkle or secondary. */
    const bool kajiya_kay = m->shading.model == HT_MODEL_KAJIYA_KAY || marschner;

    int lights = scene->light_count;
    if (lights < 0) lights = 0;
    if (lights > HT_MAX_LIGHTS) lights = HT_MAX_LIGHTS;
    out->light_count = lights;
    for (int i = 0; i < lights; i++) {
        out->light_types[i] = scene->lights[i].type;
        for (int c = 0; c < 3; c++) out->light_colors[i][c] = scene->lights[i].color[c];
    }

    out->base = has(m, HT_TEX_BASE);
    out->alpha = has(m, HT_TEX_ALPHA);
    out->shift = !kajiya_kay && has(m, HT_TEX_SHIFT);
    out->sparkle = !kajiya_kay && has(m, HT_TEX_SPARKLE);
    out->secondary = !kajiya_kay;
    out->ao = true; /* every mesh carries per-vertex ao */
    out->sparkle_mean = 1.0;
    out->albedo_max = 1.0;
    /* The material parser enforces (0,1]; a hand-built material may leave 0. */
    out->opaque_cutoff = m->opaque_cutoff > 0.0 && m->opaque_cutoff <= 1.0 ? m->opaque_cutoff
                                                                            : DEFAULT_OPAQUE_CUTOFF;

    plan_viewer(scene, out);
    if (lights > 0 && scene->lights[0].type == HT_LIGHT_DIRECTIONAL) {
        double dot = 0.0;
        for (int i = 0; i < 3; i++)
            dot += (double)scene->lights[0].vector[i] * ((double)scene->camera.eye[i] - scene->camera.target[i]);
        out->key_behind = dot < 0.0;
    }

    if (out->base || out->alpha) add_texture(out, "albedo", HT_U_ALBEDO, "base.rgb alpha.a");
    if (out->shift || out->sparkle) add_texture(out, "detail", HT_U_DETAIL, "shift.r sparkle.g");

    if (!out->base) note(out, "base: not modelled: the material has no base texture (base = 1)");
    if (!out->alpha) note(out, "alpha: not modelled: the material has no alpha texture (alpha = 1)");
    if (marschner) {
        note(out, "lower tiers: Scheuermann constants fitted to the Marschner fibre (manifest \"fit\", with its error)");
    } else if (kajiya_kay) {
        note(out, "secondary: not modelled: kajiya-kay has a single highlight");
        note(out, "shift: not modelled: kajiya-kay does not shift the tangent");
        note(out, "sparkle: not modelled: kajiya-kay has no secondary highlight to mask");
    } else {
        if (!out->shift) note(out, "shift: not modelled: the material has no shift texture (no jitter)");
        if (!out->sparkle) note(out, "sparkle: not modelled: the material has no sparkle texture (sparkle = 1)");
    }
}

ht_shading ht_plan_unmasked_shading(const ht_plan *plan) {
    ht_shading s = plan->shading;
    if (plan->sparkle)
        for (int i = 0; i < 3; i++) s.secondary.color[i] *= plan->sparkle_mean;
    return s;
}

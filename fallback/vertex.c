/* vertex.c — the `vertex` tier's backend (vertex.h): the bundle's vertex
   program makes, per vertex with the local viewer, the LUT coordinates,
   uv and the wrapped diffuse (docs/bundle.md); the fragment stage is
   fixed4's combiner stages over LUTs baked here for the frame's light
   colours, and the program's u_lut_scale is the final stage's scale. Both
   programs transform with ftransform(), so depth matches every pass. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "fixed4_stages.h"
#include "glsl_program.h"
#include "shader_interface.h"
#include "vertex.h"

typedef struct vertex_state {
    const ht_gl *gl;
    ht_log_fn log;
    void *log_user;
    int light_count;                 /* the manifest's: the size of the uniform arrays */
    ht_glsl_program main, prime;
    bool has_prime;
    ht_fixed4_program luts;          /* what the LUTs are baked from */
    ht_fixed4_stages stages;
    int scale;                       /* this frame's */
    bool es;                         /* GL ES: the stages are the ES text's fragment stage */
} vertex_state;

static void destroy(void *state) {
    vertex_state *s = state;
    if (!s) return;
    const ht_gl *gl = s->gl;
    if (s->main.id) gl->DeleteProgram(s->main.id);
    if (s->prime.id && s->prime.id != s->main.id) gl->DeleteProgram(s->prime.id);
    ht_fixed4_stages_release(&s->stages);
    free(s);
}

/* The vertex tier's fragment stages: the program ("program", fixed4's
   format), the unit count, the albedo and LUTs baked for white lights until
   the first frame says otherwise (a bake that cannot succeed fails here,
   where the tier can still drop). */
static ht_result load_vertex_stages(vertex_state *s, const ht_tier_context *ctx, int index, char *err,
                                    size_t err_size) {
    const ht_manifest *b = ctx->bundle;
    const char *file = ht_manifest_tier_file(ctx->tier, "program");
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    if (!file)
        return ht_fail(err, err_size, HT_ERR_PARSE, "%s/manifest.json: tiers[%d].files: needs \"program\"", b->dir,
                       index);
    if (!ht_manifest_path(b, file, path, sizeof path))
        return ht_fail(err, err_size, HT_ERR_IO, "%s: path too long", file);
    char *text = ht_manifest_read_text(b, file, err, err_size);
    if (!text) return HT_ERR_IO;
    ht_result r = ht_fixed4_parse(text, path, &s->luts, err, err_size);
    free(text);
    if (r != HT_OK) return r;
    ht_fixed4_stages_init(&s->stages, s->gl, &s->luts, "vertex");
    /* The albedo sits after the LUTs (fixed4_program.h's table). */
    for (int i = 0; i < ctx->tier->sampler_count; i++)
        if (ctx->tier->samplers[i].unit != s->stages.luts)
            return ht_fail(err, err_size, HT_ERR_PARSE, "%s/manifest.json: tiers[%d].samplers[%d].unit: %d, the "
                           "vertex tier's albedo unit is %d (after its LUTs)", b->dir, index, i,
                           ctx->tier->samplers[i].unit, s->stages.luts);
    if (s->stages.units > ctx->caps->texture_units)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "needs %d texture units, have %d", s->stages.units,
                       ctx->caps->texture_units);
    if ((r = ht_fixed4_stages_load_albedo(&s->stages, ctx, err, err_size)) != HT_OK) return r;
    float white[HT_FIXED4_MAX_LIGHTS][3] = { { 0 } };
    float all[HT_MAX_LIGHTS][3] = { { 0 } };
    for (int l = 0; l < s->light_count && l < HT_MAX_LIGHTS; l++) {
        for (int i = 0; i < 3; i++) all[l][i] = 1.0f;
        if (l < HT_FIXED4_MAX_LIGHTS) memcpy(white[l], all[l], sizeof white[l]);
    }
    s->scale = ht_fixed4_scale_lights(&s->luts, (const float(*)[3])all, s->light_count);
    return ht_fixed4_stages_bake(&s->stages, (const float(*)[3])white, s->scale, err, err_size);
}

/* GL ES: the ES target's vertex + fragment program; the fragment stage
   samples the LUTs and the albedo on fixed4's units (u_lut0.., u_albedo). */
static ht_result create_es(vertex_state *s, const ht_tier_context *ctx, char *err, size_t err_size) {
    const ht_manifest_es *e = ht_glsl_es_target(ctx, err, err_size);
    if (!e) return HT_ERR_UNSUPPORTED;
    ht_result r = ht_glsl_program_build(ctx, e->vertex, e->fragment, &s->main, err, err_size);
    if (r != HT_OK) return r;
    s->prime = s->main;
    s->es = true;
    const int index = (int)(ctx->tier - ctx->bundle->tiers);
    if ((r = load_vertex_stages(s, ctx, index, err, err_size)) != HT_OK) return r;
    const ht_gl *gl = s->gl;
    gl->UseProgram(s->main.id);
    for (int k = 0; k < s->stages.luts; k++) {
        char name[32]; /* "u_lut" and an int */
        snprintf(name, sizeof name, HT_ES_U_LUT_PREFIX "%d", k);
        GLint loc = gl->GetUniformLocation(s->main.id, name);
        if (loc >= 0) gl->Uniform1i(loc, k);
    }
    GLint albedo = gl->GetUniformLocation(s->main.id, HT_U_ALBEDO);
    if (albedo >= 0) gl->Uniform1i(albedo, s->stages.luts);
    gl->UseProgram(0);
    return HT_OK;
}

static ht_result create(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    *out = NULL;
    if (!ctx->gl->has_shaders) return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "no shader entry points");
    /* Selection checks the manifest; a bundle written before the vertex tier
       listed GL_ARB_texture_env_combine is caught here (desktop GL only: on
       ES the combiner stages are a fragment shader). */
    if (!ctx->caps->es && !ctx->caps->has_combine)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "needs GL_ARB_texture_env_combine");
    if (!ctx->caps->es && (!ctx->gl->has_multitexture || !ctx->gl->ActiveTexture))
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "no glActiveTexture");
    vertex_state *s = calloc(1, sizeof *s);
    if (!s) return HT_ERR_OUT_OF_MEMORY;
    s->gl = ctx->gl;
    s->log = ctx->log;
    s->log_user = ctx->log_user;
    s->light_count = ctx->bundle->light_count;
    if (ctx->caps->es) {
        ht_result r = create_es(s, ctx, err, err_size);
        if (r != HT_OK) {
            destroy(s);
            return r;
        }
        *out = s;
        return HT_OK;
    }
    const ht_manifest_tier *t = ctx->tier;
    const char *vert = ht_manifest_tier_file(t, "vertex");
    const char *pvert = ht_manifest_tier_file(t, "prime_vertex");
    const int index = (int)(t - ctx->bundle->tiers); /* manifest fields are named tiers[i] */
    ht_result r;
    if (!vert) {
        r = ht_fail(err, err_size, HT_ERR_PARSE, "%s/manifest.json: tiers[%d].files: needs \"vertex\"",
                    ctx->bundle->dir, index);
        goto fail;
    }
    if ((r = ht_glsl_program_build(ctx, vert, NULL, &s->main, err, err_size)) != HT_OK) goto fail;
    /* Without a prime program the main one primes Z (colour writes are off). */
    s->prime = s->main;
    if (pvert) {
        if ((r = ht_glsl_program_build(ctx, pvert, NULL, &s->prime, err, err_size)) != HT_OK) goto fail;
        s->has_prime = true;
    }
    if ((r = load_vertex_stages(s, ctx, index, err, err_size)) != HT_OK) goto fail;
    *out = s;
    return HT_OK;
fail:
    destroy(s);
    return r;
}

/* The scale (over every planned light: those after the LUTs' two add into
   the primary colour) and LUTs for this frame's colours. */
static void begin_frame(void *state, const ht_tier_frame *f) {
    vertex_state *s = state;
    s->stages.opacity_cut = f->opacity_cut;
    float colors[HT_MAX_LIGHTS][3] = { { 0 } };
    for (int l = 0; l < s->light_count && l < f->light_count && l < HT_MAX_LIGHTS; l++)
        memcpy(colors[l], f->lights[l].color, sizeof colors[l]);
    s->scale = ht_fixed4_scale_lights(&s->luts, (const float(*)[3])colors, s->light_count);
    ht_fixed4_stages_update(&s->stages, (const float(*)[3])colors, s->scale, s->log, s->log_user);
    ht_glsl_program_set_frame(s->gl, &s->main, f, s->light_count, (float)s->scale);
    if (s->has_prime) ht_glsl_program_set_frame(s->gl, &s->prime, f, s->light_count, (float)s->scale);
}

static void bind_pass(void *state, ht_pass pass, int sub_pass) {
    (void)sub_pass;
    vertex_state *s = state;
    s->gl->UseProgram(pass == HT_PASS_PRIME_Z ? s->prime.id : s->main.id);
    if (s->es) ht_fixed4_stages_bind_textures(&s->stages);
    else ht_fixed4_stages_bind(&s->stages, pass == HT_PASS_PRIME_Z);
}

/* Nothing is drawn until the LUTs are baked. */
static bool set_arrays(void *state, ht_pass pass, int sub_pass) {
    (void)pass;
    (void)sub_pass;
    return ht_fixed4_stages_ready(&((vertex_state *)state)->stages);
}

static void end_frame(void *state) {
    vertex_state *s = state;
    s->gl->UseProgram(0);
    if (s->es) ht_fixed4_stages_unbind_textures(&s->stages);
    else ht_fixed4_stages_unbind(&s->stages);
}

/* Only the ES texts: the desktop combiner stages have no per-vertex alpha
   to spare (the primary colour's carries ao), so there the rule is per draw. */
static bool vertex_width_rule(void *state) {
    const vertex_state *s = state;
    return s->es && s->main.u_width_rule >= 0;
}

const ht_tier_backend ht_tier_vertex_backend = {
    .tier = HT_TIER_VERTEX,
    .generic_attributes = true,
    .create = create,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .set_arrays = set_arrays,
    .end_frame = end_frame,
    .destroy = destroy,
    .vertex_width_rule = vertex_width_rule,
};

/* tier_glsl.c — the `full` tier's backend: a vertex + fragment program
   shading every pixel (glsl_program.h builds it), the bundle's textures on
   their sampler units. It transforms with ftransform(), so depth matches
   the fixed-function head and every pass bit for bit. The other GLSL tier,
   `vertex`, has a fixed-function fragment stage and lives with the other
   combiner tiers (fallback/vertex.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glsl_program.h"

typedef struct glsl_texture {
    GLuint id;
    int unit;
} glsl_texture;

typedef struct full_state {
    const ht_gl *gl;
    int light_count;                         /* the manifest's: the size of the uniform arrays */
    ht_glsl_program main, prime;
    bool has_prime;
    glsl_texture textures[HT_MANIFEST_MAX_SAMPLERS];
    int texture_count;
} full_state;

static void destroy(void *state) {
    full_state *s = state;
    if (!s) return;
    const ht_gl *gl = s->gl;
    if (s->main.id) gl->DeleteProgram(s->main.id);
    if (s->prime.id && s->prime.id != s->main.id) gl->DeleteProgram(s->prime.id);
    for (int i = 0; i < s->texture_count; i++)
        if (s->textures[i].id) gl->DeleteTextures(1, &s->textures[i].id);
    free(s);
}

static ht_result create(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    *out = NULL;
    if (!ctx->gl->has_shaders) {
        snprintf(err, err_size, "no shader entry points");
        return HT_ERR_UNSUPPORTED;
    }
    full_state *s = calloc(1, sizeof *s);
    if (!s) return HT_ERR_OUT_OF_MEMORY;
    s->gl = ctx->gl;
    s->light_count = ctx->bundle->light_count;
    const ht_manifest_tier *t = ctx->tier;
    const char *vert = ht_manifest_tier_file(t, "vertex");
    const char *frag = ht_manifest_tier_file(t, "fragment");
    const char *pvert = ht_manifest_tier_file(t, "prime_vertex");
    const char *pfrag = ht_manifest_tier_file(t, "prime_fragment");
    const int index = (int)(t - ctx->bundle->tiers); /* manifest fields are named tiers[i] */
    ht_result r;
    if (ctx->caps->es) {
        /* The ES target selection chose (its main program primes Z too). */
        const ht_manifest_es *e = ht_glsl_es_target(ctx, err, err_size);
        if (!e) {
            r = HT_ERR_UNSUPPORTED;
            goto fail;
        }
        vert = e->vertex;
        frag = e->fragment;
        pvert = pfrag = NULL;
    }
    if (!vert || !frag) {
        snprintf(err, err_size, "%s/manifest.json: tiers[%d].files: needs \"vertex\" and \"fragment\"",
                 ctx->bundle->dir, index);
        r = HT_ERR_PARSE;
        goto fail;
    }
    if ((r = ht_glsl_program_build(ctx, vert, frag, &s->main, err, err_size)) != HT_OK) goto fail;
    /* Without a prime program the main one primes Z (colour writes are off). */
    s->prime = s->main;
    if (pvert && pfrag) {
        if ((r = ht_glsl_program_build(ctx, pvert, pfrag, &s->prime, err, err_size)) != HT_OK) goto fail;
        s->has_prime = true;
    }
    for (int i = 0; i < t->sampler_count; i++) {
        const ht_manifest_sampler *smp = &t->samplers[i];
        const ht_manifest_texture *bt = ht_manifest_find_texture(ctx->bundle, t, smp->texture);
        glsl_texture *gt = &s->textures[s->texture_count];
        gt->unit = smp->unit;
        if (!bt) {
            snprintf(err, err_size, "%s/manifest.json: tiers[%d].samplers[%d].texture: \"%s\" is not listed in textures",
                     ctx->bundle->dir, index, i, smp->texture);
            r = HT_ERR_PARSE;
            goto fail;
        }
        if (gt->unit >= ctx->caps->texture_units) {
            snprintf(err, err_size, "%s/manifest.json: tiers[%d].samplers[%d].unit: %d, device has %d units",
                     ctx->bundle->dir, index, i, gt->unit, ctx->caps->texture_units);
            r = HT_ERR_UNSUPPORTED;
            goto fail;
        }
        s->texture_count++;
        if ((r = ht_glsl_texture_upload(s->gl, ctx->bundle, bt, &gt->id, err, err_size)) != HT_OK) goto fail;
    }
    *out = s;
    return HT_OK;
fail:
    destroy(s);
    return r;
}

static void begin_frame(void *state, const ht_tier_frame *f) {
    full_state *s = state;
    ht_glsl_program_set_frame(s->gl, &s->main, f, s->light_count, 1.0f);
    if (s->has_prime) ht_glsl_program_set_frame(s->gl, &s->prime, f, s->light_count, 1.0f);
    const ht_gl *gl = s->gl;
    for (int i = 0; i < s->texture_count; i++) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)s->textures[i].unit);
        gl->BindTexture(GL_TEXTURE_2D, s->textures[i].id);
    }
    if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0);
}

static void bind_pass(void *state, ht_pass pass, int sub_pass) {
    (void)sub_pass;
    full_state *s = state;
    s->gl->UseProgram(pass == HT_PASS_PRIME_Z ? s->prime.id : s->main.id);
}

/* Both programs widen alike, or the Z-prime's depth is not the colour passes'. */
static bool vertex_width_rule(void *state) {
    const full_state *s = state;
    return s->main.u_width_rule >= 0 && s->prime.u_width_rule >= 0;
}

static void end_frame(void *state) {
    full_state *s = state;
    const ht_gl *gl = s->gl;
    gl->UseProgram(0);
    for (int i = s->texture_count - 1; i >= 0; i--) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)s->textures[i].unit);
        gl->BindTexture(GL_TEXTURE_2D, 0);
    }
    if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0);
}

const ht_tier_backend ht_tier_glsl_full_backend = {
    .tier = HT_TIER_FULL,
    .generic_attributes = true,
    .create = create,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .end_frame = end_frame,
    .destroy = destroy,
    .vertex_width_rule = vertex_width_rule,
};

/* Nothing here depends on the shading: the marschner tier's program reads
   its lookup textures through the manifest's samplers like any texture. */
const ht_tier_backend ht_tier_glsl_marschner_backend = {
    .tier = HT_TIER_MARSCHNER,
    .generic_attributes = true,
    .create = create,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .end_frame = end_frame,
    .destroy = destroy,
    .vertex_width_rule = vertex_width_rule,
};

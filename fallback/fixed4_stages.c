/* fixed4_stages.c — see fixed4_stages.h. Moved out of fixed4.c unchanged
   so the vertex tier runs the same stages. */
#include "fixed4_stages.h"

#include <stdio.h>
#include <string.h>

#include "errfmt.h"
#include "gl_texture.h"
#include <hairtier/image.h>

void ht_fixed4_stages_init(ht_fixed4_stages *st, const ht_gl *gl, const ht_fixed4_program *program,
                           const char *name) {
    memset(st, 0, sizeof *st);
    st->gl = gl;
    st->program = program;
    st->name = name;
    st->luts = ht_fixed4_lut_count(program);
    st->units = ht_fixed4_units(program);
    st->scale = 1;
}

void ht_fixed4_stages_release(ht_fixed4_stages *st) {
    if (!st->gl) return;
    for (int i = 0; i < HT_FIXED4_MAX_LUTS; i++)
        if (st->lut_textures[i]) st->gl->DeleteTextures(1, &st->lut_textures[i]);
    if (st->albedo) st->gl->DeleteTextures(1, &st->albedo);
    memset(st->lut_textures, 0, sizeof st->lut_textures);
    st->albedo = 0;
    st->baked = false;
}

ht_result ht_fixed4_stages_load_albedo(ht_fixed4_stages *st, const ht_tier_context *ctx, char *err,
                                       size_t err_size) {
    const ht_manifest *b = ctx->bundle;
    const ht_manifest_texture *t = ht_manifest_find_texture(b, ctx->tier, "albedo");
    ht_image img = { 0 };
    char path[HT_LIMIT_BUNDLE_FILE_PATH] = "white albedo";
    static const unsigned char white[4] = { 255, 255, 255, 255 };
    if (t) {
        ht_result r = ht_manifest_read_texture(b, t, &img, path, sizeof path, err, err_size);
        if (r != HT_OK) return r;
        r = ht_gl_texture_check_size(ctx->caps, img.width, img.height, 1, path, err, err_size);
        if (r != HT_OK) {
            ht_image_free(&img);
            return r;
        }
    } else {
        /* no albedo: a white texel keeps the final stage's scale and alpha 1 */
        img = (ht_image){ .width = 1, .height = 1, .channels = 4, .pixels = (uint8_t *)white };
        st->albedo_is_white = true;
    }
    ht_result r = ht_gl_texture_upload(st->gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D, .image = &img,
                                                                      .filter = GL_LINEAR, .wrap = GL_REPEAT,
                                                                      .name = path },
                                       &st->albedo, err, err_size);
    if (t) ht_image_free(&img);
    return r;
}

ht_result ht_fixed4_stages_bake(ht_fixed4_stages *st, const float light_colors[][3], int scale, char *err,
                                size_t err_size) {
    st->scale = scale;
    for (int k = 0; k < st->luts; k++) {
        ht_image img = { 0 };
        ht_result r = ht_fixed4_bake_lut(st->program, k, light_colors, scale, &img);
        if (r != HT_OK) return ht_fail(err, err_size, r, "%s: LUT %d: out of memory", st->name, k);
        if (st->lut_textures[k]) st->gl->DeleteTextures(1, &st->lut_textures[k]);
        st->lut_textures[k] = 0;
        char name[32];
        snprintf(name, sizeof name, "%s LUT %d", st->name, k);
        r = ht_gl_texture_upload(st->gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D, .image = &img,
                                                                .filter = GL_LINEAR, .wrap = GL_CLAMP_TO_EDGE,
                                                                .name = name },
                                 &st->lut_textures[k], err, err_size);
        ht_image_free(&img);
        if (r != HT_OK) return r;
    }
    memset(st->baked_colors, 0, sizeof st->baked_colors);
    for (int l = 0; l < st->program->lights && l < HT_FIXED4_MAX_LIGHTS; l++)
        memcpy(st->baked_colors[l], light_colors[l], sizeof st->baked_colors[l]);
    st->baked = true;
    return HT_OK;
}

void ht_fixed4_stages_update(ht_fixed4_stages *st, const float light_colors[][3], int scale, ht_log_fn log,
                             void *log_user) {
    float colors[HT_FIXED4_MAX_LIGHTS][3] = { { 0 } };
    for (int l = 0; l < st->program->lights && l < HT_FIXED4_MAX_LIGHTS; l++)
        memcpy(colors[l], light_colors[l], sizeof colors[l]);
    if (st->baked && scale == st->scale && memcmp(st->baked_colors, colors, sizeof colors) == 0) return;
    char err[256];
    if (ht_fixed4_stages_bake(st, (const float(*)[3])colors, scale, err, sizeof err) != HT_OK) {
        st->baked = false;
        ht_log_linef(log, log_user, "hairtier: %s: %s", st->name, err);
    }
}

typedef struct env {
    GLenum rgb, alpha;
    GLenum src_rgb[3], op_rgb[3];
    GLenum src_alpha[2], op_alpha[2]; /* the second: GL_MODULATE's */
    int scale;
    float constant_alpha;             /* the width rule's opacity where src_alpha[1] is GL_CONSTANT */
} env;

static void apply_env(const ht_gl *gl, const env *e) {
    gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
    gl->TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, (GLint)e->rgb);
    gl->TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, (GLint)e->alpha);
    static const GLenum src_rgb[3] = { GL_SOURCE0_RGB, GL_SOURCE1_RGB, GL_SOURCE2_RGB };
    static const GLenum op_rgb[3] = { GL_OPERAND0_RGB, GL_OPERAND1_RGB, GL_OPERAND2_RGB };
    for (int a = 0; a < 2; a++) {
        gl->TexEnvi(GL_TEXTURE_ENV, src_rgb[a], (GLint)e->src_rgb[a]);
        gl->TexEnvi(GL_TEXTURE_ENV, op_rgb[a], (GLint)e->op_rgb[a]);
    }
    gl->TexEnvi(GL_TEXTURE_ENV, GL_SOURCE0_ALPHA, (GLint)e->src_alpha[0]);
    gl->TexEnvi(GL_TEXTURE_ENV, GL_OPERAND0_ALPHA, (GLint)e->op_alpha[0]);
    if (e->alpha == GL_MODULATE) {
        gl->TexEnvi(GL_TEXTURE_ENV, GL_SOURCE1_ALPHA, (GLint)e->src_alpha[1]);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_OPERAND1_ALPHA, (GLint)e->op_alpha[1]);
        const GLfloat constant[4] = { 0, 0, 0, e->constant_alpha };
        gl->TexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, constant);
    }
    gl->TexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE, (GLfloat)e->scale);
    gl->TexEnvf(GL_TEXTURE_ENV, GL_ALPHA_SCALE, 1.0f);
}

/* The stage of `unit` (fixed4_program.h's table). */
static env stage_env(const ht_fixed4_stages *st, int unit) {
    const int albedo_unit = st->luts;
    if (unit < st->luts) {
        /* first LUT: + primary (Scheuermann's diffuse; Kajiya-Kay's is black) */
        GLenum other = unit == 0 ? GL_PRIMARY_COLOR : GL_PREVIOUS;
        return (env){ GL_ADD, GL_REPLACE, { GL_TEXTURE, other }, { GL_SRC_COLOR, GL_SRC_COLOR },
                      { other, other }, { GL_SRC_ALPHA, GL_SRC_ALPHA }, 1, 1.0f };
    }
    if (unit == albedo_unit)
        return (env){ GL_MODULATE, GL_REPLACE, { GL_TEXTURE, GL_PREVIOUS }, { GL_SRC_COLOR, GL_SRC_COLOR },
                      { GL_PREVIOUS, GL_PREVIOUS }, { GL_SRC_ALPHA, GL_SRC_ALPHA }, 1, 1.0f };
    /* final: rgb x ao (carried in alpha) x scale; alpha = the albedo's
       coverage, x the width rule's opacity (a constant) where it applies */
    const bool scaled = st->opacity_cut > 0.0f;
    return (env){ GL_MODULATE, scaled ? GL_MODULATE : GL_REPLACE, { GL_PREVIOUS, GL_PREVIOUS },
                  { GL_SRC_COLOR, GL_SRC_ALPHA }, { GL_TEXTURE, GL_CONSTANT }, { GL_SRC_ALPHA, GL_SRC_ALPHA },
                  st->scale, 1.0f - st->opacity_cut };
}

void ht_fixed4_stages_bind(const ht_fixed4_stages *st, bool prime) {
    const ht_gl *gl = st->gl;
    const int final_unit = st->units - 1;
    for (int u = 0; u < st->units; u++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->Disable(GL_TEXTURE_2D);
        if (prime && u != final_unit) continue;
        gl->BindTexture(GL_TEXTURE_2D, u < st->luts ? st->lut_textures[u] : st->albedo);
        gl->Enable(GL_TEXTURE_2D);
        env e = stage_env(st, u);
        apply_env(gl, &e);
    }
    gl->ActiveTexture(GL_TEXTURE0);
}

void ht_fixed4_stages_unbind(const ht_fixed4_stages *st) {
    const ht_gl *gl = st->gl;
    for (int u = st->units - 1; u >= 0; u--) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        gl->TexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE, 1.0f);
        gl->BindTexture(GL_TEXTURE_2D, 0);
        gl->Disable(GL_TEXTURE_2D);
    }
    gl->ActiveTexture(GL_TEXTURE0);
}

void ht_fixed4_stages_bind_textures(const ht_fixed4_stages *st) {
    const ht_gl *gl = st->gl;
    for (int u = 0; u <= st->luts; u++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->BindTexture(GL_TEXTURE_2D, u < st->luts ? st->lut_textures[u] : st->albedo);
    }
    gl->ActiveTexture(GL_TEXTURE0);
}

void ht_fixed4_stages_unbind_textures(const ht_fixed4_stages *st) {
    const ht_gl *gl = st->gl;
    for (int u = st->luts; u >= 0; u--) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->BindTexture(GL_TEXTURE_2D, 0);
    }
}

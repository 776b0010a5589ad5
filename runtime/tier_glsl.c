/* tier_glsl.c — the GLSL tier backends: `full` (vertex + fragment program,
   per-pixel shading) and `vertex` (vertex program, fixed-function fragment:
   fixed4's combiner stages over LUTs baked here for the frame's light
   colours, fallback/fixed4_stages.h; the vertex shader makes the LUT
   coordinates and the diffuse; docs/bundle.md). Both transform with
   ftransform(), so depth matches the fixed-function head and every pass bit
   for bit. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_error.h"
#include "errfmt.h"
#include "file_open.h"
#include "fixed4_stages.h"
#include "gl_texture.h"
#include "image.h"
#include "shader_interface.h"
#include "tier.h"

typedef struct glsl_program {
    GLuint id;
    GLint u_eye, u_light_vector, u_light_color, u_lut_scale;
} glsl_program;

typedef struct glsl_texture {
    GLuint id;
    int unit;
} glsl_texture;

typedef struct glsl_state {
    const ht_gl *gl;
    ht_log_fn log;
    void *log_user;
    bool vertex_only;
    int light_count;                         /* the manifest's: the size of the uniform arrays */
    glsl_program main, prime;
    bool has_prime;
    glsl_texture textures[HT_MANIFEST_MAX_SAMPLERS];
    int texture_count;
    /* the vertex tier's fragment stages: the program its LUTs are baked
       from, the stages, this frame's scale */
    ht_fixed4_program luts;
    ht_fixed4_stages stages;
    int scale;
} glsl_state;

/* The first non-empty line of a driver's info log. */
static void first_line(const char *log, char *out, size_t size) {
    while (*log == '\n' || *log == '\r' || *log == ' ') log++;
    size_t n = strcspn(log, "\r\n");
    if (n >= size) n = size - 1;
    memcpy(out, log, n);
    out[n] = '\0';
    if (!out[0]) snprintf(out, size, "(no log)");
}

/* Logs every line of an info log, prefixed with the file it belongs to. */
static void log_info(const glsl_state *s, const char *file, const char *log) {
    while (*log) {
        size_t n = strcspn(log, "\r\n");
        if (n) ht_log_linef(s->log, s->log_user, "hairtier: %s: %.*s", file, (int)n, log);
        log += n;
        while (*log == '\r' || *log == '\n') log++;
    }
}

static GLuint compile(glsl_state *s, const ht_manifest *b, const char *file, GLenum stage,
                      char *err, size_t err_size) {
    const ht_gl *gl = s->gl;
    char rerr[512];
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    char *text = NULL;
    if (!file) ht_set_error(rerr, sizeof rerr, "%s/manifest.json: files: role missing", b->dir);
    else if (!ht_manifest_path(b, file, path, sizeof path)) ht_set_error(rerr, sizeof rerr, "%s: path too long", file);
    else text = ht_file_read_text(path, HT_FILE_MAX_SHADER, rerr, sizeof rerr); /* regular files, 1 MiB */
    if (!text) {
        snprintf(err, err_size, "compile failed: %s", rerr);
        return 0;
    }
    while (gl->GetError() != GL_NO_ERROR) {}
    GLuint sh = gl->CreateShader(stage);
    if (!sh) {
        /* A driver that refuses the stage outright (no info log to read). */
        GLenum e = gl->GetError();
        snprintf(err, err_size, "compile failed: %s: glCreateShader(%s) refused (%s)", file,
                 stage == GL_VERTEX_SHADER ? "GL_VERTEX_SHADER" : "GL_FRAGMENT_SHADER", ht_gl_error_name(e));
        free(text);
        return 0;
    }
    const GLchar *src = text;
    gl->ShaderSource(sh, 1, &src, NULL);
    gl->CompileShader(sh);
    free(text);
    GLint ok = GL_FALSE, len = 0;
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (ok == GL_TRUE) return sh;
    gl->GetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
    char *log = calloc((size_t)(len > 0 ? len : 1) + 1, 1);
    if (log && len > 0) gl->GetShaderInfoLog(sh, len, NULL, log);
    char line[256];
    first_line(log ? log : "", line, sizeof line);
    log_info(s, file, log ? log : "");
    snprintf(err, err_size, "compile failed: %s: %s", file, line);
    free(log);
    gl->DeleteShader(sh);
    return 0;
}

static ht_result build_program(glsl_state *s, const ht_tier_context *ctx, const char *vert,
                               const char *frag, glsl_program *out, char *err, size_t err_size) {
    const ht_gl *gl = s->gl;
    memset(out, 0, sizeof *out);
    GLuint vs = compile(s, ctx->bundle, vert, GL_VERTEX_SHADER, err, err_size);
    if (!vs) return HT_ERR_COMPILE;
    GLuint fs = 0;
    if (frag && !(fs = compile(s, ctx->bundle, frag, GL_FRAGMENT_SHADER, err, err_size))) {
        gl->DeleteShader(vs);
        return HT_ERR_COMPILE;
    }
    GLuint prog = gl->CreateProgram();
    if (!prog) {
        snprintf(err, err_size, "link failed: %s: glCreateProgram refused (%s)", vert, ht_gl_error_name(gl->GetError()));
        gl->DeleteShader(vs);
        if (fs) gl->DeleteShader(fs);
        return HT_ERR_COMPILE;
    }
    gl->AttachShader(prog, vs);
    if (fs) gl->AttachShader(prog, fs);
    /* Where the renderer's arrays feed them; a program without one (the
       prime pass) ignores the binding. */
    gl->BindAttribLocation(prog, HT_ATTR_TANGENT_LOCATION, HT_ATTR_TANGENT);
    gl->BindAttribLocation(prog, HT_ATTR_AO_LOCATION, HT_ATTR_AO);
    gl->LinkProgram(prog);
    gl->DeleteShader(vs); /* flagged; freed with the program */
    if (fs) gl->DeleteShader(fs);
    GLint ok = GL_FALSE, len = 0;
    gl->GetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        gl->GetProgramiv(prog, GL_INFO_LOG_LENGTH, &len);
        char *log = calloc((size_t)(len > 0 ? len : 1) + 1, 1);
        if (log && len > 0) gl->GetProgramInfoLog(prog, len, NULL, log);
        char line[256], files[160];
        snprintf(files, sizeof files, "%s%s%s", vert, frag ? "+" : "", frag ? frag : "");
        first_line(log ? log : "", line, sizeof line);
        log_info(s, files, log ? log : "");
        snprintf(err, err_size, "link failed: %s: %s", files, line);
        free(log);
        gl->DeleteProgram(prog);
        return HT_ERR_COMPILE;
    }
    out->id = prog;
    out->u_eye = gl->GetUniformLocation(prog, HT_U_EYE);
    out->u_light_vector = gl->GetUniformLocation(prog, HT_U_LIGHT_VECTOR);
    out->u_light_color = gl->GetUniformLocation(prog, HT_U_LIGHT_COLOR);
    out->u_lut_scale = gl->GetUniformLocation(prog, HT_U_LUT_SCALE);
    /* Samplers are fixed for the program's life: bind them to units once. */
    gl->UseProgram(prog);
    for (int i = 0; i < ctx->tier->sampler_count; i++) {
        GLint loc = gl->GetUniformLocation(prog, ctx->tier->samplers[i].uniform);
        if (loc >= 0) gl->Uniform1i(loc, ctx->tier->samplers[i].unit);
    }
    gl->UseProgram(0);
    return HT_OK;
}

static ht_result upload_texture(glsl_state *s, const ht_manifest *b, const ht_manifest_texture *t,
                                GLuint *out, char *err, size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH], ierr[512];
    if (!ht_manifest_path(b, t->file, path, sizeof path)) {
        snprintf(err, err_size, "%s: path too long", t->file);
        return HT_ERR_IO;
    }
    if (t->depth != 1) {
        snprintf(err, err_size, "%s/manifest.json: textures.%s.depth: %d, GLSL tiers sample 2D textures",
                 b->dir, t->name, t->depth);
        return HT_ERR_PARSE;
    }
    uint32_t hw, hh;
    if (ht_image_png_header_size(path, &hw, &hh) && (hw != (uint32_t)t->width || hh != (uint32_t)t->height)) {
        snprintf(err, err_size, "%s: %ux%u, manifest says %dx%d", path, hw, hh, t->width, t->height);
        return HT_ERR_PARSE;
    }
    ht_image img = { 0 };
    ht_result r = ht_image_read_png(path, &img, ierr, sizeof ierr);
    if (r != HT_OK) {
        snprintf(err, err_size, "%s", ierr);
        return r;
    }
    if (img.width != t->width || img.height != t->height) {
        snprintf(err, err_size, "%s: %dx%d, manifest says %dx%d", path, img.width, img.height, t->width, t->height);
        ht_image_free(&img);
        return HT_ERR_PARSE;
    }
    /* uv wraps (REPEAT); no mipmaps: the textures are stretched along
       strands, where mip blending smears the alpha. */
    r = ht_gl_texture_upload(s->gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D, .image = &img,
                                                           .filter = GL_LINEAR, .wrap = GL_REPEAT, .name = path },
                             out, err, err_size);
    ht_image_free(&img);
    return r;
}

static void destroy(void *state) {
    glsl_state *s = state;
    if (!s) return;
    const ht_gl *gl = s->gl;
    if (s->main.id) gl->DeleteProgram(s->main.id);
    if (s->prime.id && s->prime.id != s->main.id) gl->DeleteProgram(s->prime.id);
    for (int i = 0; i < s->texture_count; i++)
        if (s->textures[i].id) gl->DeleteTextures(1, &s->textures[i].id);
    ht_fixed4_stages_release(&s->stages);
    free(s);
}

/* The vertex tier's fragment stages: the program ("program", fixed4's
   format), the unit count, the albedo and LUTs baked for white lights until
   the first frame says otherwise (a bake that cannot succeed fails here,
   where the tier can still drop). */
static ht_result load_vertex_stages(glsl_state *s, const ht_tier_context *ctx, int index, char *err,
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

static ht_result create(const ht_tier_context *ctx, bool vertex_only, void **out, char *err, size_t err_size) {
    *out = NULL;
    if (!ctx->gl->has_shaders) {
        snprintf(err, err_size, "no shader entry points");
        return HT_ERR_UNSUPPORTED;
    }
    /* Selection checks the manifest; a bundle written before the vertex tier
       listed GL_ARB_texture_env_combine is caught here. */
    if (vertex_only && !ctx->caps->has_combine) {
        snprintf(err, err_size, "needs GL_ARB_texture_env_combine");
        return HT_ERR_UNSUPPORTED;
    }
    if (vertex_only && (!ctx->gl->has_multitexture || !ctx->gl->ActiveTexture)) {
        snprintf(err, err_size, "no glActiveTexture");
        return HT_ERR_UNSUPPORTED;
    }
    glsl_state *s = calloc(1, sizeof *s);
    if (!s) return HT_ERR_OUT_OF_MEMORY;
    s->gl = ctx->gl;
    s->log = ctx->log;
    s->log_user = ctx->log_user;
    s->vertex_only = vertex_only;
    s->light_count = ctx->bundle->light_count;
    const ht_manifest_tier *t = ctx->tier;
    const char *vert = ht_manifest_tier_file(t, "vertex");
    const char *frag = vertex_only ? NULL : ht_manifest_tier_file(t, "fragment");
    const char *pvert = ht_manifest_tier_file(t, "prime_vertex");
    const char *pfrag = vertex_only ? NULL : ht_manifest_tier_file(t, "prime_fragment");
    const int index = (int)(t - ctx->bundle->tiers); /* manifest fields are named tiers[i] */
    ht_result r;
    if (!vert || (!vertex_only && !frag)) {
        snprintf(err, err_size, "%s/manifest.json: tiers[%d].files: needs \"vertex\"%s", ctx->bundle->dir, index,
                 vertex_only ? "" : " and \"fragment\"");
        r = HT_ERR_PARSE;
        goto fail;
    }
    if ((r = build_program(s, ctx, vert, frag, &s->main, err, err_size)) != HT_OK) goto fail;
    /* Without a prime program the main one primes Z (colour writes are off). */
    s->prime = s->main;
    if (pvert && (vertex_only || pfrag)) {
        if ((r = build_program(s, ctx, pvert, pfrag, &s->prime, err, err_size)) != HT_OK) goto fail;
        s->has_prime = true;
    }
    if (vertex_only) {
        if ((r = load_vertex_stages(s, ctx, index, err, err_size)) != HT_OK) goto fail;
        *out = s;
        return HT_OK;
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
        if ((r = upload_texture(s, ctx->bundle, bt, &gt->id, err, err_size)) != HT_OK) goto fail;
    }
    *out = s;
    return HT_OK;
fail:
    destroy(s);
    return r;
}

static ht_result create_full(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    return create(ctx, false, out, err, err_size);
}

static ht_result create_vertex(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    return create(ctx, true, out, err, err_size);
}

static void set_uniforms(const glsl_state *s, const glsl_program *p, const ht_tier_frame *f) {
    const ht_gl *gl = s->gl;
    float vectors[HT_MAX_LIGHTS * 4] = { 0 }, colors[HT_MAX_LIGHTS * 3] = { 0 };
    int n = s->light_count;
    /* Lights beyond the frame's are black: the arrays keep the planned size. */
    for (int i = 0; i < n && i < f->light_count; i++) {
        const ht_light *l = &f->lights[i];
        for (int k = 0; k < 3; k++) {
            vectors[4 * i + k] = l->vector[k];
            colors[3 * i + k] = l->color[k];
        }
        vectors[4 * i + 3] = l->type == HT_LIGHT_POINT ? 1.0f : 0.0f;
    }
    gl->UseProgram(p->id);
    if (p->u_eye >= 0) gl->Uniform3fv(p->u_eye, 1, f->eye);
    if (p->u_light_vector >= 0) gl->Uniform4fv(p->u_light_vector, n, vectors);
    if (p->u_light_color >= 0) gl->Uniform3fv(p->u_light_color, n, colors);
    if (p->u_lut_scale >= 0) gl->Uniform1f(p->u_lut_scale, (float)s->scale);
}

/* The vertex tier's scale (over every planned light: those after the LUTs'
   two add into the primary colour) and LUTs for this frame's colours. */
static void update_vertex_stages(glsl_state *s, const ht_tier_frame *f) {
    float colors[HT_MAX_LIGHTS][3] = { { 0 } };
    for (int l = 0; l < s->light_count && l < f->light_count && l < HT_MAX_LIGHTS; l++)
        memcpy(colors[l], f->lights[l].color, sizeof colors[l]);
    s->scale = ht_fixed4_scale_lights(&s->luts, (const float(*)[3])colors, s->light_count);
    ht_fixed4_stages_update(&s->stages, (const float(*)[3])colors, s->scale, s->log, s->log_user);
}

static void begin_frame(void *state, const ht_tier_frame *f) {
    glsl_state *s = state;
    if (s->vertex_only) update_vertex_stages(s, f);
    set_uniforms(s, &s->main, f);
    if (s->has_prime) set_uniforms(s, &s->prime, f);
    const ht_gl *gl = s->gl;
    for (int i = 0; i < s->texture_count; i++) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)s->textures[i].unit);
        gl->BindTexture(GL_TEXTURE_2D, s->textures[i].id);
    }
    if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0);
}

static void bind_pass(void *state, ht_pass pass, int sub_pass) {
    (void)sub_pass;
    glsl_state *s = state;
    s->gl->UseProgram(pass == HT_PASS_PRIME_Z ? s->prime.id : s->main.id);
    if (s->vertex_only) ht_fixed4_stages_bind(&s->stages, pass == HT_PASS_PRIME_Z);
}

/* The vertex tier draws nothing until its LUTs are baked. */
static bool set_arrays(void *state, ht_pass pass, int sub_pass) {
    (void)pass;
    (void)sub_pass;
    return ht_fixed4_stages_ready(&((glsl_state *)state)->stages);
}

static void end_frame(void *state) {
    glsl_state *s = state;
    const ht_gl *gl = s->gl;
    gl->UseProgram(0);
    for (int i = s->texture_count - 1; i >= 0; i--) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)s->textures[i].unit);
        gl->BindTexture(GL_TEXTURE_2D, 0);
    }
    if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0);
    if (s->vertex_only) ht_fixed4_stages_unbind(&s->stages);
}

const ht_tier_backend ht_tier_glsl_full_backend = {
    .tier = HT_TIER_FULL,
    .generic_attributes = true,
    .create = create_full,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .end_frame = end_frame,
    .destroy = destroy,
};

const ht_tier_backend ht_tier_glsl_vertex_backend = {
    .tier = HT_TIER_VERTEX,
    .generic_attributes = true,
    .create = create_vertex,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .set_arrays = set_arrays,
    .end_frame = end_frame,
    .destroy = destroy,
};

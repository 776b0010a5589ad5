/* glsl_program.c — see glsl_program.h. */
#include "glsl_program.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "gl_error.h"
#include "gl_texture.h"
#include <hairtier/image.h>
#include "select.h"
#include "shader_interface.h"

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
static void log_info(ht_log_fn log_fn, void *log_user, const char *file, const char *log) {
    while (*log) {
        size_t n = strcspn(log, "\r\n");
        if (n) ht_log_linef(log_fn, log_user, "hairtier: %s: %.*s", file, (int)n, log);
        log += n;
        while (*log == '\r' || *log == '\n') log++;
    }
}

static GLuint compile(const ht_tier_context *ctx, const char *file, GLenum stage, char *err, size_t err_size) {
    const ht_gl *gl = ctx->gl;
    const ht_manifest *b = ctx->bundle;
    char rerr[512];
    char *text = ht_manifest_read_shader(b, file, rerr, sizeof rerr); /* regular files or memory, 1 MiB */
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
    log_info(ctx->log, ctx->log_user, file, log ? log : "");
    snprintf(err, err_size, "compile failed: %s: %s", file, line);
    free(log);
    gl->DeleteShader(sh);
    return 0;
}

const ht_manifest_es *ht_glsl_es_target(const ht_tier_context *ctx, char *err, size_t err_size) {
    char why[HT_SELECT_REASON];
    int i = ht_select_es_target(ctx->caps, ctx->tier, why, sizeof why);
    if (i < 0) {
        snprintf(err, err_size, "%s", why);
        return NULL;
    }
    const ht_manifest_es *e = &ctx->tier->es[i];
    ht_log_linef(ctx->log, ctx->log_user, "hairtier: %s: GL ES %d.%d text %s + %s (ESSL %d.%02d, fragment %s)",
                 ctx->tier->name, e->es_major, e->es_minor, e->vertex, e->fragment, e->essl_major, e->essl_minor,
                 e->mediump ? "mediump" : "highp");
    return e;
}

ht_result ht_glsl_program_build(const ht_tier_context *ctx, const char *vert, const char *frag,
                                ht_glsl_program *out, char *err, size_t err_size) {
    const ht_gl *gl = ctx->gl;
    memset(out, 0, sizeof *out);
    GLuint vs = compile(ctx, vert, GL_VERTEX_SHADER, err, err_size);
    if (!vs) return HT_ERR_COMPILE;
    GLuint fs = 0;
    if (frag && !(fs = compile(ctx, frag, GL_FRAGMENT_SHADER, err, err_size))) {
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
    gl->BindAttribLocation(prog, HT_ATTR_SIDE_LOCATION, HT_ATTR_SIDE);
    if (ctx->caps->es) {
        gl->BindAttribLocation(prog, HT_ES_ATTR_POSITION_LOCATION, HT_ES_ATTR_POSITION);
        gl->BindAttribLocation(prog, HT_ES_ATTR_NORMAL_LOCATION, HT_ES_ATTR_NORMAL);
        gl->BindAttribLocation(prog, HT_ES_ATTR_UV_LOCATION, HT_ES_ATTR_UV);
    }
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
        log_info(ctx->log, ctx->log_user, files, log ? log : "");
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
    out->u_mvp = gl->GetUniformLocation(prog, HT_ES_U_MVP);
    out->u_opacity_cut = gl->GetUniformLocation(prog, HT_U_OPACITY_CUT);
    out->u_width_rule = gl->GetUniformLocation(prog, HT_U_WIDTH_RULE);
    /* Samplers are fixed for the program's life: bind them to units once. */
    gl->UseProgram(prog);
    for (int i = 0; i < ctx->tier->sampler_count; i++) {
        GLint loc = gl->GetUniformLocation(prog, ctx->tier->samplers[i].uniform);
        if (loc >= 0) gl->Uniform1i(loc, ctx->tier->samplers[i].unit);
    }
    gl->UseProgram(0);
    return HT_OK;
}

ht_result ht_glsl_texture_upload(const ht_gl *gl, const ht_manifest *b, const ht_manifest_texture *t, GLuint *out,
                                 char *err, size_t err_size) {
    if (t->depth != 1) {
        snprintf(err, err_size, "%s/manifest.json: textures.%s.depth: %d, GLSL tiers sample 2D textures",
                 b->dir, t->name, t->depth);
        return HT_ERR_PARSE;
    }
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    ht_image img;
    ht_result r = ht_manifest_read_texture(b, t, &img, path, sizeof path, err, err_size);
    if (r != HT_OK) return r;
    /* uv wraps (REPEAT); no mipmaps: the textures are stretched along
       strands, where mip blending smears the alpha. */
    r = ht_gl_texture_upload(gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D, .image = &img,
                                                        .filter = GL_LINEAR, .wrap = GL_REPEAT, .name = path },
                             out, err, err_size);
    ht_image_free(&img);
    return r;
}

void ht_glsl_mvp(const ht_tier_frame *f, float out[16]) {
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            float v = 0.0f;
            for (int k = 0; k < 4; k++) v += f->projection[k * 4 + r] * f->view[c * 4 + k];
            out[c * 4 + r] = v;
        }
}

void ht_glsl_program_set_frame(const ht_gl *gl, const ht_glsl_program *p, const ht_tier_frame *f, int light_count,
                               float lut_scale) {
    float vectors[HT_MAX_LIGHTS * 4] = { 0 }, colors[HT_MAX_LIGHTS * 3] = { 0 };
    int n = light_count;
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
    if (p->u_lut_scale >= 0) gl->Uniform1f(p->u_lut_scale, lut_scale);
    if (p->u_opacity_cut >= 0) gl->Uniform1f(p->u_opacity_cut, f->opacity_cut);
    if (p->u_width_rule >= 0) gl->Uniform1f(p->u_width_rule, f->width_rule);
    if (p->u_mvp >= 0) {
        /* What the fixed-function transform computes: projection x view
           (column-major; the model matrix is identity). */
        float mvp[16];
        ht_glsl_mvp(f, mvp);
        gl->UniformMatrix4fv(p->u_mvp, 1, GL_FALSE, mvp);
    }
}


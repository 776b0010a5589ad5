/* fixed4.c — the `fixed4` tier's backend (fixed4_program.h has the layout
   and the why). No shader object anywhere: GL 1.3 texture combiners,
   texture matrices and GL's fixed-function lighting.

   Per mesh (set_mesh): the static arrays: the shifted tangents t1, t2
   (Kajiya-Kay: T) as 3-component texture coordinates, uv, and the colour
   (1, 1, 1, ao) whose alpha carries ao through the combiners; in buffer
   objects when the device has them, client memory otherwise.
   Per frame (begin_frame): one texture matrix per LUT unit (16 floats from
   the lights and the infinite viewer) and, only when a light colour or the
   scale changed, the LUTs rebaked and reloaded (O(LUT texels)). Nothing is
   proportional to the vertex count, but under a local-viewer program: its
   LUT coordinates of the draw range's vertices (tier.h), when the eye or a
   light moved, written into their buffers with glBufferSubData.
   Per pass: GL lighting (Scheuermann) for the diffuse term into the
   primary colour; the prime-Z pass enables only the last unit (the
   albedo's alpha), with lighting off. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "fixed4.h"
#include "fixed4_program.h"
#include "fixed4_stages.h"
#include "gl_error.h"
#include "tier_program.h"

enum { MAX_UNITS = HT_FIXED4_MAX_LUTS + 2 };

typedef enum array_kind { ARRAY_VEC0 = 0, ARRAY_VEC1, ARRAY_UV, ARRAY_COLOR, ARRAY_COUNT } array_kind;

typedef struct fixed4_state {
    const ht_gl *gl;
    const ht_caps *caps;
    ht_fixed4_program program;
    int luts, units;
    ht_fixed4_stages stages; /* the LUT textures, the albedo, the combiner stages */
    /* static per-vertex arrays: client memory, or offsets into buffers */
    float *arrays[ARRAY_COUNT];
    GLuint buffers[ARRAY_COUNT];
    bool have_mesh;
    /* the local-viewer rule: SoA inputs, this frame's coordinates (2 floats per
       vertex per LUT), what they were made for, and how much work it was */
    ht_fixed4_soa soa;
    float *coords[HT_FIXED4_MAX_LUTS];
    GLuint coord_buffers[HT_FIXED4_MAX_LUTS];
    bool coords_valid;
    float coords_key[3 + 3 * HT_FIXED4_MAX_LIGHTS];
    uint32_t coords_range[2];                 /* the vertices they were made for: first, count */
    uint64_t cpu_vertices;
    int scale;
    bool device_variant;   /* a local-viewer program drawn with the infinite viewer (ht_variant) */
    /* this frame */
    float matrices[HT_FIXED4_MAX_LUTS][16];
    float light_dirs[HT_FIXED4_MAX_LIGHTS][3];
    float light_colors[HT_FIXED4_MAX_LIGHTS][3];
    float view[16];
    ht_log_fn log;
    void *log_user;
} fixed4_state;

static void destroy(void *state) {
    fixed4_state *s = state;
    if (!s) return;
    ht_fixed4_stages_release(&s->stages);
    for (int i = 0; i < ARRAY_COUNT; i++) {
        free(s->arrays[i]);
        if (s->buffers[i]) s->gl->DeleteBuffers(1, &s->buffers[i]);
    }
    for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++) {
        free(s->coords[k]);
        if (s->coord_buffers[k]) s->gl->DeleteBuffers(1, &s->coord_buffers[k]);
    }
    ht_fixed4_soa_free(&s->soa);
    free(s);
}

static ht_result load_program(fixed4_state *s, const ht_tier_context *ctx, char *err, size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    ht_result r;
    char *text = ht_tier_program_read(ctx, path, sizeof path, &r, err, err_size);
    if (!text) return r;
    r = ht_fixed4_parse(text, path, &s->program, err, err_size);
    free(text);
    return r;
}

static ht_result check_device(const fixed4_state *s, const ht_tier_context *ctx, char *err, size_t err_size) {
    const ht_caps *c = ctx->caps;
    const ht_gl *gl = ctx->gl;
    if (!c->has_combine) return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "needs GL_ARB_texture_env_combine");
    if (!c->has_multitexture || !gl->ActiveTexture || !gl->ClientActiveTexture)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "needs GL_ARB_multitexture");
    if (s->units > c->texture_units)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "needs %d texture units, have %d", s->units,
                       c->texture_units);
    return HT_OK;
}

static ht_result create(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    *out = NULL;
    fixed4_state *s = calloc(1, sizeof *s);
    if (!s) return HT_ERR_OUT_OF_MEMORY;
    s->gl = ctx->gl;
    s->caps = ctx->caps;
    s->log = ctx->log;
    s->log_user = ctx->log_user;
    ht_result r = load_program(s, ctx, err, err_size);
    /* The device-only variant: the texture matrices' infinite viewer in
       place of the local viewer's per-vertex CPU coordinates. */
    if (r == HT_OK && ctx->device_variant && s->program.viewer == HT_FIXED4_VIEWER_LOCAL) {
        s->program.viewer = HT_FIXED4_VIEWER_INFINITE;
        s->device_variant = true;
    }
    if (r == HT_OK) {
        s->luts = ht_fixed4_lut_count(&s->program);
        s->units = ht_fixed4_units(&s->program);
        ht_fixed4_stages_init(&s->stages, s->gl, &s->program, "fixed4");
        r = check_device(s, ctx, err, err_size);
    }
    if (r == HT_OK) r = ht_fixed4_stages_load_albedo(&s->stages, ctx, err, err_size);
    /* LUTs for white lights until the first frame says otherwise: a bake
       that cannot succeed fails here, where the tier can still drop. */
    for (int l = 0; r == HT_OK && l < HT_FIXED4_MAX_LIGHTS; l++)
        s->light_colors[l][0] = s->light_colors[l][1] = s->light_colors[l][2] = l < s->program.lights ? 1.0f : 0.0f;
    if (r == HT_OK) {
        s->scale = ht_fixed4_scale(&s->program, (const float(*)[3])s->light_colors);
        r = ht_fixed4_stages_bake(&s->stages, (const float(*)[3])s->light_colors, s->scale, err, err_size);
    }
    if (r != HT_OK) {
        destroy(s);
        return r;
    }
    int w = 0, h = 0;
    ht_fixed4_lut_size(&s->program, 0, &w, &h);
    ht_log_linef(s->log, s->log_user, "hairtier: fixed4: %d units, %d LUT%s %dx%d, %d light%s, coordinates %s, "
                 "diffuse by GL lighting%s", s->units, s->luts,
                 s->luts == 1 ? "" : "s", w, h, s->program.lights, s->program.lights == 1 ? "" : "s",
                 s->program.viewer == HT_FIXED4_VIEWER_LOCAL ? "per vertex on the CPU (local viewer)"
                 : s->device_variant ? "by the texture matrix (infinite viewer: the device-only variant)"
                                     : "by the texture matrix (infinite viewer)",
                 s->program.shading.model == HT_MODEL_KAJIYA_KAY ? " (none: Kajiya-Kay's is in the LUT)" : "");
    *out = s;
    return HT_OK;
}

/* ---- per mesh ---- */

static ht_result set_mesh(void *state, const ht_mesh *mesh) {
    fixed4_state *s = state;
    const ht_gl *gl = s->gl;
    size_t n = mesh->vertex_count;
    static const int widths[ARRAY_COUNT] = { 3, 3, 2, 4 };
    float *a[ARRAY_COUNT] = { NULL };
    for (int i = 0; i < ARRAY_COUNT; i++) {
        a[i] = malloc(n ? n * (size_t)widths[i] * sizeof(float) : sizeof(float));
        if (!a[i]) {
            for (int j = 0; j < i; j++) free(a[j]);
            return HT_ERR_OUT_OF_MEMORY;
        }
    }
    const bool kk = s->program.shading.model == HT_MODEL_KAJIYA_KAY;
    ht_fixed4_vertex_arrays(&s->program, mesh->vertices, n, a[ARRAY_VEC0], kk ? NULL : a[ARRAY_VEC1],
                            a[ARRAY_COLOR]);
    if (kk) memcpy(a[ARRAY_VEC1], a[ARRAY_VEC0], n * 3 * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        a[ARRAY_UV][2 * i] = mesh->vertices[i].uv[0];
        a[ARRAY_UV][2 * i + 1] = mesh->vertices[i].uv[1];
    }
    if (s->program.viewer == HT_FIXED4_VIEWER_LOCAL) {
        ht_fixed4_soa soa;
        float *coords[HT_FIXED4_MAX_LUTS] = { NULL };
        bool ok = ht_fixed4_soa_from_arrays(mesh->vertices, n, a[ARRAY_VEC0], a[ARRAY_VEC1], &soa) == HT_OK;
        for (int k = 0; ok && k < s->luts; k++) ok = (coords[k] = malloc((n ? n : 1) * 2 * sizeof(float))) != NULL;
        if (!ok) {
            if (soa.count || soa.px) ht_fixed4_soa_free(&soa);
            for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++) free(coords[k]);
            for (int i = 0; i < ARRAY_COUNT; i++) free(a[i]);
            return HT_ERR_OUT_OF_MEMORY;
        }
        ht_fixed4_soa_free(&s->soa);
        s->soa = soa;
        for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++) {
            free(s->coords[k]);
            s->coords[k] = coords[k];
        }
        s->coords_valid = false;
        /* The LUT coordinates are made per frame from the soa: the static
           vectors are neither drawn nor uploaded. */
        for (int i = ARRAY_VEC0; i <= ARRAY_VEC1; i++) {
            free(a[i]);
            a[i] = NULL;
        }
    }
    for (int i = 0; i < ARRAY_COUNT; i++) {
        free(s->arrays[i]);
        s->arrays[i] = a[i];
    }
    s->have_mesh = true;
    if (!gl->GenBuffers || !s->caps->has_vbo) return HT_OK;
    /* Uploaded once: the draw reads them from the device every frame. */
    while (gl->GetError() != GL_NO_ERROR) {}
    for (int i = 0; i < ARRAY_COUNT; i++) {
        if (!s->arrays[i]) continue;
        if (!s->buffers[i]) gl->GenBuffers(1, &s->buffers[i]);
        gl->BindBuffer(GL_ARRAY_BUFFER, s->buffers[i]);
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(n * (size_t)widths[i] * sizeof(float)), s->arrays[i],
                       GL_STATIC_DRAW);
    }
    for (int k = 0; s->program.viewer == HT_FIXED4_VIEWER_LOCAL && k < s->luts; k++) {
        if (!s->coord_buffers[k]) gl->GenBuffers(1, &s->coord_buffers[k]);
        gl->BindBuffer(GL_ARRAY_BUFFER, s->coord_buffers[k]);
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(n * 2 * sizeof(float)), NULL, GL_DYNAMIC_DRAW);
    }
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    GLenum e = gl->GetError();
    if (e != GL_NO_ERROR) { /* the renderer logs the one line */
        s->have_mesh = false;
        return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
    }
    /* The client copies are no longer read. */
    for (int i = 0; i < ARRAY_COUNT; i++) {
        free(s->arrays[i]);
        s->arrays[i] = NULL;
    }
    return HT_OK;
}

/* ---- per frame ---- */

/* The local-viewer rule's per-vertex work: only when the eye or a light
   direction moved since the coordinates were made. */
static void update_local_coords(fixed4_state *s, const ht_tier_frame *f) {
    float key[3 + 3 * HT_FIXED4_MAX_LIGHTS];
    memcpy(key, f->eye, 3 * sizeof(float));
    memcpy(key + 3, s->light_dirs, sizeof s->light_dirs);
    /* the draw range's vertices only (tier.h) */
    const size_t n = s->soa.count;
    const uint32_t range[2] = { f->first_vertex < n ? f->first_vertex : 0,
                                f->first_vertex < n && f->vertex_count <= n - f->first_vertex ? f->vertex_count
                                : (uint32_t)(n - (f->first_vertex < n ? f->first_vertex : 0)) };
    if (!s->have_mesh || (s->coords_valid && memcmp(key, s->coords_key, sizeof key) == 0 &&
                          memcmp(range, s->coords_range, sizeof range) == 0))
        return;
    const ht_fixed4_soa part = ht_fixed4_soa_range(&s->soa, range[0], range[1]);
    float *coords[HT_FIXED4_MAX_LUTS];
    for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++) coords[k] = s->coords[k] ? s->coords[k] + 2 * (size_t)range[0] : NULL;
    ht_fixed4_local_coords(&s->program, &part, (const float(*)[3])s->light_dirs, f->eye, coords);
    s->cpu_vertices += range[1];
    const ht_gl *gl = s->gl;
    for (int k = 0; k < s->luts && s->coord_buffers[k]; k++) {
        gl->BindBuffer(GL_ARRAY_BUFFER, s->coord_buffers[k]);
        gl->BufferSubData(GL_ARRAY_BUFFER, (GLintptr)(2 * (size_t)range[0] * sizeof(float)),
                          (GLsizeiptr)(2 * (size_t)range[1] * sizeof(float)), coords[k]);
    }
    if (s->coord_buffers[0]) {
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
        /* set_arrays draws nothing until an upload succeeds */
        GLenum e = gl->GetError();
        if (e != GL_NO_ERROR) {
            ht_log_linef(s->log, s->log_user, "hairtier: fixed4: glBufferSubData: %s: hair not drawn",
                         ht_gl_error_name(e));
            s->coords_valid = false;
            return;
        }
    }
    memcpy(s->coords_key, key, sizeof key);
    memcpy(s->coords_range, range, sizeof range);
    s->coords_valid = true;
}

static void begin_frame(void *state, const ht_tier_frame *f) {
    fixed4_state *s = state;
    s->stages.opacity_cut = f->opacity_cut;
    const ht_fixed4_program *p = &s->program;
    for (int l = 0; l < HT_FIXED4_MAX_LIGHTS; l++) {
        const bool lit = l < p->lights && l < f->light_count;
        for (int i = 0; i < 3; i++) {
            s->light_dirs[l][i] = lit ? f->lights[l].vector[i] : 0.0f;
            s->light_colors[l][i] = lit ? f->lights[l].color[i] : 0.0f;
        }
    }
    memcpy(s->view, f->view, sizeof s->view);
    /* the view matrix's third row is the unit direction from the target to the eye */
    const float view_dir[3] = { f->view[2], f->view[6], f->view[10] };
    if (p->viewer == HT_FIXED4_VIEWER_LOCAL) update_local_coords(s, f);
    else
        for (int k = 0; k < s->luts; k++)
            ht_fixed4_texture_matrix(p, k, (const float(*)[3])s->light_dirs, view_dir, s->matrices[k]);
    s->scale = ht_fixed4_scale(p, (const float(*)[3])s->light_colors);
    ht_fixed4_stages_update(&s->stages, (const float(*)[3])s->light_colors, s->scale, s->log, s->log_user);
}

static void active_unit(const fixed4_state *s, int unit) { s->gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit); }

static void load_texture_matrix(const fixed4_state *s, int unit, const float *m) {
    const ht_gl *gl = s->gl;
    active_unit(s, unit);
    gl->MatrixMode(GL_TEXTURE);
    if (m) gl->LoadMatrixf(m);
    else gl->LoadIdentity();
    gl->MatrixMode(GL_MODELVIEW);
}

/* GL lighting for Scheuermann's wrapped diffuse, per light l along L_l
   (ambient + diffuse) and, when back[l] > 0, a second GL light along -L_l
   with a negative diffuse (ht_fixed4_back_slopes says which slope and why):
       primary = sum_l kd lc_l (wrap + (1 - wrap) max(N.L_l, 0)
                                - back_l max(-N.L_l, 0)) / scale
   clamped to [0, 1] by GL, alpha = the colour array's ao. */
static void set_lighting(const fixed4_state *s) {
    const ht_gl *gl = s->gl;
    const ht_fixed4_program *p = &s->program;
    const double w = p->shading.wrap, inv = 1.0 / (double)s->scale;
    static const float zero[4] = { 0, 0, 0, 1 }, one[4] = { 1, 1, 1, 1 };
    double back[HT_FIXED4_MAX_LIGHTS];
    ht_fixed4_back_slopes(p, (const float(*)[3])s->light_colors, back);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadIdentity(); /* positions given in eye space below */
    int gl_light = 0;
    for (int l = 0; l < p->lights; l++) {
        double L[3];
        for (int i = 0; i < 3; i++) L[i] = s->light_dirs[l][i];
        double eye[3];
        for (int i = 0; i < 3; i++)
            eye[i] = s->view[0 * 4 + i] * L[0] + s->view[1 * 4 + i] * L[1] + s->view[2 * 4 + i] * L[2];
        float ambient[4] = { 0, 0, 0, 1 }, diffuse[4] = { 0, 0, 0, 1 }, negative[4] = { 0, 0, 0, 1 };
        for (int i = 0; i < 3; i++) {
            double kl = p->shading.diffuse_color[i] * (double)s->light_colors[l][i] * inv;
            ambient[i] = (float)(w * kl);
            diffuse[i] = (float)((1.0 - w) * kl);
            negative[i] = (float)(-back[l] * kl);
        }
        const float pos[4] = { (float)eye[0], (float)eye[1], (float)eye[2], 0.0f };
        GLenum id = GL_LIGHT0 + (GLenum)gl_light++;
        gl->Enable(id);
        gl->Lightfv(id, GL_AMBIENT, ambient);
        gl->Lightfv(id, GL_DIFFUSE, diffuse);
        gl->Lightfv(id, GL_SPECULAR, zero);
        gl->Lightfv(id, GL_POSITION, pos);
        if (back[l] > 0.0) {
            const float back[4] = { -pos[0], -pos[1], -pos[2], 0.0f };
            id = GL_LIGHT0 + (GLenum)gl_light++;
            gl->Enable(id);
            gl->Lightfv(id, GL_AMBIENT, zero);
            gl->Lightfv(id, GL_DIFFUSE, negative);
            gl->Lightfv(id, GL_SPECULAR, zero);
            gl->Lightfv(id, GL_POSITION, back);
        }
    }
    gl->LoadMatrixf(s->view);
    const float no_ambient[4] = { 0, 0, 0, 1 };
    gl->LightModelfv(GL_LIGHT_MODEL_AMBIENT, no_ambient);
    gl->LightModelf(GL_LIGHT_MODEL_TWO_SIDE, 0.0f);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_AMBIENT, one);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_SPECULAR, zero);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_EMISSION, zero);
    /* ES 1.x has no glColorMaterial: its colour material is ambient and
       diffuse, the same here (the colour array's rgb is 1, as the ambient). */
    if (gl->ColorMaterial) gl->ColorMaterial(GL_FRONT_AND_BACK, GL_DIFFUSE);
    gl->Enable(GL_COLOR_MATERIAL);
    gl->Enable(GL_LIGHTING);
}

static void clear_lighting(const fixed4_state *s) {
    const ht_gl *gl = s->gl;
    gl->Disable(GL_LIGHTING);
    gl->Disable(GL_COLOR_MATERIAL);
    for (int i = 0; i < 2 * HT_FIXED4_MAX_LIGHTS; i++) gl->Disable(GL_LIGHT0 + (GLenum)i);
}

static void bind_pass(void *state, ht_pass pass, int sub_pass) {
    (void)sub_pass;
    fixed4_state *s = state;
    const bool prime = pass == HT_PASS_PRIME_Z;
    ht_fixed4_stages_bind(&s->stages, prime);
    for (int u = 0; !prime && u < s->luts && s->program.viewer == HT_FIXED4_VIEWER_INFINITE; u++)
        load_texture_matrix(s, u, s->matrices[u]);
    active_unit(s, 0);
    if (!prime && s->program.shading.model == HT_MODEL_SCHEUERMANN) set_lighting(s);
    else clear_lighting(s);
}

static const void *array_pointer(const fixed4_state *s, array_kind k) {
    if (s->buffers[k]) {
        s->gl->BindBuffer(GL_ARRAY_BUFFER, s->buffers[k]);
        return NULL; /* offset 0 in the bound buffer */
    }
    ht_gl_bind_buffer(s->gl, GL_ARRAY_BUFFER, 0);
    return s->arrays[k];
}

static bool set_arrays(void *state, ht_pass pass, int sub_pass) {
    (void)pass;
    (void)sub_pass;
    fixed4_state *s = state;
    const ht_gl *gl = s->gl;
    if (!s->have_mesh || !ht_fixed4_stages_ready(&s->stages)) return false;
    if (s->program.viewer == HT_FIXED4_VIEWER_LOCAL && !s->coords_valid) return false;
    const GLuint bound = ht_gl_array_buffer_binding(gl);
    for (int u = 0; u < s->units; u++) {
        gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->EnableClientState(GL_TEXTURE_COORD_ARRAY);
        if (u < s->luts && s->program.viewer == HT_FIXED4_VIEWER_LOCAL) {
            ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, s->coord_buffers[u]);
            gl->TexCoordPointer(2, GL_FLOAT, 0, s->coord_buffers[u] ? NULL : s->coords[u]);
        } else if (u < s->luts) {
            const void *ptr = array_pointer(s, u == 0 ? ARRAY_VEC0 : ARRAY_VEC1);
            gl->TexCoordPointer(3, GL_FLOAT, 0, ptr);
        } else {
            gl->TexCoordPointer(2, GL_FLOAT, 0, array_pointer(s, ARRAY_UV));
        }
    }
    gl->ClientActiveTexture(GL_TEXTURE0);
    gl->EnableClientState(GL_COLOR_ARRAY);
    gl->ColorPointer(4, GL_FLOAT, 0, array_pointer(s, ARRAY_COLOR));
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, bound);
    return true;
}

static void end_frame(void *state) {
    fixed4_state *s = state;
    const ht_gl *gl = s->gl;
    ht_fixed4_stages_unbind(&s->stages);
    for (int u = s->units - 1; u >= 0; u--) {
        if (u < s->luts) load_texture_matrix(s, u, NULL);
        gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    active_unit(s, 0);
    gl->ClientActiveTexture(GL_TEXTURE0);
    gl->DisableClientState(GL_COLOR_ARRAY);
    clear_lighting(s);
    gl->Color4f(1, 1, 1, 1);
}

static uint64_t cpu_vertices(void *state) { return ((const fixed4_state *)state)->cpu_vertices; }
static bool device_variant(void *state) { return ((const fixed4_state *)state)->device_variant; }

const ht_tier_backend ht_tier_fixed4_backend = {
    .tier = HT_TIER_FIXED4,
    .create = create,
    .set_mesh = set_mesh,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .set_arrays = set_arrays,
    .end_frame = end_frame,
    .destroy = destroy,
    .cpu_vertices = cpu_vertices,
    .device_variant = device_variant,
};

/* renderer.c — probes the device, selects a tier, and draws hair in
   Scheuermann's four passes (docs: DESIGN.md "Passes and sort order"). The
   pass list and its state live here, once, so every tier draws the same
   passes over the same index ranges; backends (tier.h) only shade. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "renderer_internal.h"

#if defined(__has_include)
#  if __has_include("fixed.h")
#    include "fixed.h"
#    define HT_HAVE_FIXED_BACKEND 1
#  endif
#endif

#define DEFAULT_Z_NEAR 0.05f
#define DEFAULT_Z_FAR 100.0f
#define DEFAULT_CUTOFF 0.98f

static const ht_tier_backend *backend_for(ht_tier t) {
    switch (t) {
    case HT_TIER_FULL: return &ht_tier_glsl_full_backend;
    case HT_TIER_VERTEX: return &ht_tier_glsl_vertex_backend;
#ifdef HT_HAVE_FIXED_BACKEND
    case HT_TIER_FIXED: return &ht_tier_fixed_backend;
#endif
    default: return NULL;
    }
}

static void log_stderr(void *user, const char *line) {
    (void)user;
    fprintf(stderr, "%s\n", line);
}

/* Truncating copy (a reason longer than its slot is cut, not dropped). */
static void copy_text(char *dst, size_t size, const char *src) {
    size_t n = strlen(src);
    if (n >= size) n = size - 1;
    memcpy(dst, src, n);
    dst[n] = '\0';
}

/* ---- matrices ---- */

static float dot3(const float a[3], const float b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const float a[3], const float b[3], float out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static bool normalize3(float v[3]) {
    float len2 = dot3(v, v);
    if (!(len2 > 1e-20f) || !isfinite(len2)) return false;
    float inv = 1.0f / sqrtf(len2);
    for (int i = 0; i < 3; i++) v[i] *= inv;
    return true;
}

bool ht_mat4_perspective(float out[16], float fov_y, float aspect, float z_near, float z_far) {
    if (!(fov_y > 0 && fov_y < 180) || !(aspect > 0) || !isfinite(aspect) || !(z_near > 0) ||
        !(z_far > z_near) || !isfinite(z_far))
        return false;
    float f = 1.0f / tanf(fov_y * 3.14159265358979f / 360.0f);
    memset(out, 0, 16 * sizeof *out);
    out[0] = f / aspect;
    out[5] = f;
    out[10] = (z_far + z_near) / (z_near - z_far);
    out[11] = -1.0f;
    out[14] = 2.0f * z_far * z_near / (z_near - z_far);
    return true;
}

bool ht_mat4_look_at(float out[16], const float eye[3], const float target[3], const float up[3]) {
    float f[3] = { target[0] - eye[0], target[1] - eye[1], target[2] - eye[2] };
    float u0[3] = { up[0], up[1], up[2] };
    float s[3], u[3];
    if (!normalize3(f) || !normalize3(u0)) return false;
    cross3(f, u0, s);
    if (!normalize3(s)) return false;
    cross3(s, f, u);
    const float m[16] = {
        s[0], u[0], -f[0], 0,
        s[1], u[1], -f[1], 0,
        s[2], u[2], -f[2], 0,
        -dot3(s, eye), -dot3(u, eye), dot3(f, eye), 1,
    };
    memcpy(out, m, sizeof m);
    return true;
}

/* ---- creation ---- */

static ht_result create_backend(ht_renderer *r, const ht_renderer_desc *desc) {
    char failed_text[HT_BUNDLE_MAX_TIERS][HT_SELECT_REASON];
    ht_select_desc sd = {
        .caps = &r->caps, .bundle = &r->bundle, .requested = desc->tier,
        .env_tier = getenv("HAIRTIER_TIER"), .strict = desc->strict,
    };
    for (int t = HT_TIER_FULL; t < HT_TIER_COUNT; t++) sd.have_backend[t] = backend_for((ht_tier)t) != NULL;
    char err[1024];
    for (;;) {
        ht_selection sel;
        ht_result res = ht_select_tier(&sd, &sel, err, sizeof err);
        for (int i = 0; i < sel.skipped_count; i++)
            ht_log_linef(r->log, r->log_user, "hairtier: skipped %s", sel.skipped[i]);
        if (res != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
            return res;
        }
        const ht_tier_backend *be = backend_for(sel.tier);
        ht_tier_context ctx = { .gl = &r->gl, .caps = &r->caps, .bundle = &r->bundle,
                                .tier = &r->bundle.tiers[sel.index], .log = r->log, .log_user = r->log_user };
        void *state = NULL;
        while (r->gl.GetError() != GL_NO_ERROR) {}
        res = be->create(&ctx, &state, err, sizeof err);
        if (res == HT_OK) {
            r->backend = be;
            r->backend_state = state;
            r->tier = sel.tier;
            copy_text(r->reason, sizeof r->reason, sel.reason);
            ht_log_linef(r->log, r->log_user, "hairtier: tier %s (%s)", ht_tier_name(r->tier), r->reason);
            return HT_OK;
        }
        copy_text(failed_text[sel.index], sizeof failed_text[0], err);
        sd.failed[sel.index] = failed_text[sel.index];
        while (r->gl.GetError() != GL_NO_ERROR) {}
    }
}

ht_result ht_renderer_create(const ht_renderer_desc *desc, ht_renderer **out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    *out = NULL;
    ht_log_fn log = desc && desc->log ? desc->log : log_stderr;
    void *log_user = desc ? desc->log_user : NULL;
    if (!desc || !desc->getproc) {
        log(log_user, "hairtier: ht_renderer_desc: getproc: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (!desc->flat && (!desc->bundle_dir || !desc->bundle_dir[0])) {
        log(log_user, "hairtier: ht_renderer_desc: bundle_dir: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_renderer *r = calloc(1, sizeof *r);
    if (!r) return HT_ERR_OUT_OF_MEMORY;
    r->log = log;
    r->log_user = log_user;
    r->record_trace = desc->record_trace;
    r->flat = desc->flat;
    r->tier = HT_TIER_COUNT;

    char err[1024];
    ht_result res = ht_gl_load(&r->gl, desc->getproc, err, sizeof err);
    if (res != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
        goto fail;
    }
    if ((res = ht_caps_probe(desc->getproc, &r->caps)) != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: glGetString(GL_VERSION): no answer (is a GL context current?)");
        goto fail;
    }
    ht_caps_apply_profile(&r->caps, &desc->profile);
    /* The runtime itself must not call what the profile hides. */
    ht_gl_restrict(&r->gl, r->caps.has_3d_textures, r->caps.has_multitexture, r->caps.has_vbo,
                   r->caps.has_shaders);
    ht_log_linef(r->log, r->log_user, "hairtier: device GL %d.%d, GLSL %d.%02d, %d texture units, %s%s",
                 r->caps.gl_major, r->caps.gl_minor, r->caps.glsl_major, r->caps.glsl_minor, r->caps.texture_units,
                 r->caps.renderer, r->caps.has_vbo ? "" : ", no VBOs");

    if (desc->bundle_dir && desc->bundle_dir[0]) {
        if ((res = ht_bundle_load(desc->bundle_dir, &r->bundle, err, sizeof err)) != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: %s", err);
            goto fail;
        }
        r->have_bundle = true;
    }

    if (r->flat) {
        bool zero = desc->flat_color[0] == 0 && desc->flat_color[1] == 0 && desc->flat_color[2] == 0;
        for (int i = 0; i < 3; i++) {
            float c = zero ? 0.5f : desc->flat_color[i];
            r->flat_color[i] = isfinite(c) ? fminf(fmaxf(c, 0.0f), 1.0f) : 0.5f;
        }
        snprintf(r->reason, sizeof r->reason, "flat: geometry floor, one colour, no textures or shaders");
        ht_log_linef(r->log, r->log_user, "hairtier: %s", r->reason);
    } else if ((res = create_backend(r, desc)) != HT_OK) {
        goto fail;
    }
    *out = r;
    return HT_OK;
fail:
    ht_renderer_destroy(r);
    return res;
}

ht_tier ht_renderer_tier(const ht_renderer *r) { return r ? r->tier : HT_TIER_COUNT; }
const char *ht_renderer_reason(const ht_renderer *r) { return r ? r->reason : ""; }
const ht_trace *ht_renderer_trace(const ht_renderer *r) { return r ? &r->trace : NULL; }
const ht_caps *ht_renderer_caps(const ht_renderer *r) { return r ? &r->caps : NULL; }

static void release_mesh(ht_renderer *r) {
    if (r->vbo) r->gl.DeleteBuffers(1, &r->vbo);
    if (r->ibo) r->gl.DeleteBuffers(1, &r->ibo);
    r->vbo = r->ibo = 0;
    free(r->vertices);
    free(r->indices);
    r->vertices = NULL;
    r->indices = NULL;
    r->has_mesh = false;
}

void ht_renderer_destroy(ht_renderer *r) {
    if (!r) return;
    if (r->backend && r->backend->destroy) r->backend->destroy(r->backend_state);
    release_mesh(r);
    free(r);
}

ht_result ht_renderer_set_mesh(ht_renderer *r, const ht_mesh *mesh) {
    if (!r || !mesh) return HT_ERR_INVALID_ARGUMENT;
    if ((mesh->index_count && (!mesh->indices || !mesh->vertices)) || mesh->index_count % 3 ||
        mesh->index_count > (uint32_t)INT32_MAX) {
        ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: mesh: index buffer is not whole triangles");
        return HT_ERR_INVALID_ARGUMENT;
    }
    for (uint32_t i = 0; i < mesh->index_count; i++)
        if (mesh->indices[i] >= mesh->vertex_count) {
            ht_log_linef(r->log, r->log_user,
                         "hairtier: ht_renderer_set_mesh: mesh: indices[%u] = %u, only %u vertices", i,
                         mesh->indices[i], mesh->vertex_count);
            return HT_ERR_INVALID_ARGUMENT;
        }
    release_mesh(r);
    size_t vbytes = (size_t)mesh->vertex_count * sizeof(ht_vertex);
    size_t ibytes = (size_t)mesh->index_count * sizeof(uint32_t);
    if (r->caps.has_vbo) {
        while (r->gl.GetError() != GL_NO_ERROR) {}
        r->gl.GenBuffers(1, &r->vbo);
        r->gl.GenBuffers(1, &r->ibo);
        r->gl.BindBuffer(GL_ARRAY_BUFFER, r->vbo);
        r->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)vbytes, mesh->vertices, GL_STATIC_DRAW);
        r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
        r->gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)ibytes, mesh->indices, GL_STATIC_DRAW);
        r->gl.BindBuffer(GL_ARRAY_BUFFER, 0);
        r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        GLenum e = r->gl.GetError();
        if (e != GL_NO_ERROR) {
            ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: glBufferData: GL error 0x%04x", e);
            release_mesh(r);
            return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
        }
    } else {
        r->vertices = malloc(vbytes ? vbytes : 1);
        r->indices = malloc(ibytes ? ibytes : 1);
        if (!r->vertices || !r->indices) {
            release_mesh(r);
            return HT_ERR_OUT_OF_MEMORY;
        }
        if (vbytes) memcpy(r->vertices, mesh->vertices, vbytes);
        if (ibytes) memcpy(r->indices, mesh->indices, ibytes);
    }
    r->vertex_count = mesh->vertex_count;
    r->index_count = mesh->index_count;
    r->has_mesh = true;
    if (r->backend && r->backend->set_mesh) {
        ht_result res = r->backend->set_mesh(r->backend_state, mesh);
        if (res != HT_OK) {
            release_mesh(r);
            return res;
        }
    }
    return HT_OK;
}

/* ---- drawing ---- */

/* Arrays of ht_vertex: base is NULL with a bound VBO (offsets), else the
   data. Units past what the device has are left alone. */
static void set_arrays(ht_renderer *r, const ht_vertex *base, bool hair_attributes) {
    const ht_gl *gl = &r->gl;
    const GLsizei stride = (GLsizei)sizeof(ht_vertex);
    const char *b = (const char *)base;
    gl->EnableClientState(GL_VERTEX_ARRAY);
    gl->VertexPointer(3, GL_FLOAT, stride, b + offsetof(ht_vertex, position));
    gl->EnableClientState(GL_NORMAL_ARRAY);
    gl->NormalPointer(GL_FLOAT, stride, b + offsetof(ht_vertex, normal));
    if (!hair_attributes) return;
    static const struct { int size; size_t offset; } units[3] = {
        { 2, offsetof(ht_vertex, uv) }, { 3, offsetof(ht_vertex, tangent) }, { 1, offsetof(ht_vertex, ao) },
    };
    int n = r->caps.has_multitexture ? (r->caps.texture_units < 3 ? r->caps.texture_units : 3) : 1;
    for (int u = 0; u < n; u++) {
        if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->EnableClientState(GL_TEXTURE_COORD_ARRAY);
        gl->TexCoordPointer(units[u].size, GL_FLOAT, stride, b + units[u].offset);
    }
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
}

static void clear_arrays(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    int n = r->caps.has_multitexture ? (r->caps.texture_units < 3 ? r->caps.texture_units : 3) : 1;
    for (int u = n - 1; u >= 0; u--) {
        if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    gl->DisableClientState(GL_NORMAL_ARRAY);
    gl->DisableClientState(GL_VERTEX_ARRAY);
}

/* The head: simple fixed-function lighting from the frame's lights. */
static void draw_opaque_scene(ht_renderer *r, const ht_mesh *m, const ht_frame_desc *f) {
    const ht_gl *gl = &r->gl;
    if (!m->vertices || !m->indices || m->index_count == 0) return;
    if (r->caps.has_vbo) {
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
        gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    }
    gl->Disable(GL_CULL_FACE);
    gl->Disable(GL_BLEND);
    gl->Disable(GL_ALPHA_TEST);
    gl->DepthFunc(GL_LESS);
    gl->DepthMask(GL_TRUE);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->Enable(GL_LIGHTING);
    gl->Enable(GL_NORMALIZE);
    const float ambient[4] = { 0.08f, 0.08f, 0.08f, 1 }, zero[4] = { 0, 0, 0, 1 };
    const float material[4] = { 0.55f, 0.5f, 0.45f, 1 };
    gl->LightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE, material);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_SPECULAR, zero);
    for (int i = 0; i < HT_MAX_LIGHTS; i++) {
        GLenum light = GL_LIGHT0 + (GLenum)i;
        if (i >= f->light_count) {
            gl->Disable(light);
            continue;
        }
        const ht_light *l = &f->lights[i];
        /* glLightfv transforms the position by the current modelview (the view). */
        float pos[4] = { l->vector[0], l->vector[1], l->vector[2], l->type == HT_LIGHT_POINT ? 1.0f : 0.0f };
        float color[4] = { l->color[0], l->color[1], l->color[2], 1 };
        gl->Lightfv(light, GL_POSITION, pos);
        gl->Lightfv(light, GL_DIFFUSE, color);
        gl->Lightfv(light, GL_SPECULAR, zero);
        gl->Lightfv(light, GL_AMBIENT, zero);
        gl->Enable(light);
    }
    set_arrays(r, m->vertices, false);
    gl->DrawElements(GL_TRIANGLES, (GLsizei)m->index_count, GL_UNSIGNED_INT, m->indices);
    clear_arrays(r);
    for (int i = 0; i < HT_MAX_LIGHTS; i++) gl->Disable(GL_LIGHT0 + (GLenum)i);
    gl->Disable(GL_LIGHTING);
    gl->Disable(GL_NORMALIZE);
}

/* The fixed state of each pass; the numbers are Scheuermann's scheme. */
static void set_pass_state(ht_renderer *r, ht_pass pass) {
    const ht_gl *gl = &r->gl;
    float cutoff = r->have_bundle ? r->bundle.opaque_cutoff : DEFAULT_CUTOFF;
    gl->Enable(GL_DEPTH_TEST);
    gl->Enable(GL_ALPHA_TEST);
    gl->FrontFace(GL_CCW);
    switch (pass) {
    case HT_PASS_PRIME_Z:
        gl->AlphaFunc(GL_GEQUAL, cutoff);
        gl->Disable(GL_CULL_FACE);
        gl->DepthMask(GL_TRUE);
        gl->DepthFunc(GL_LESS);
        gl->ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        gl->Disable(GL_BLEND);
        break;
    case HT_PASS_OPAQUE:
        gl->AlphaFunc(GL_GEQUAL, cutoff);
        gl->Disable(GL_CULL_FACE);
        gl->DepthMask(GL_FALSE);
        gl->DepthFunc(GL_EQUAL);
        gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl->Disable(GL_BLEND);
        break;
    case HT_PASS_BACK:
    case HT_PASS_FRONT:
        gl->AlphaFunc(GL_LESS, cutoff);
        gl->Enable(GL_CULL_FACE);
        gl->CullFace(pass == HT_PASS_BACK ? GL_FRONT : GL_BACK);
        gl->DepthMask(pass == HT_PASS_FRONT ? GL_TRUE : GL_FALSE);
        gl->DepthFunc(GL_LESS);
        gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl->Enable(GL_BLEND);
        gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        break;
    case HT_PASS_COUNT:
        break;
    }
}

/* Read back from GL, so the trace shows what was set, not what was meant. */
static void record_state(ht_renderer *r, ht_trace_entry *e) {
    const ht_gl *gl = &r->gl;
    GLint v = 0;
    GLboolean b[4] = { 0 };
    GLfloat f = 0;
    e->cull = gl->IsEnabled(GL_CULL_FACE) == GL_TRUE;
    gl->GetIntegerv(GL_CULL_FACE_MODE, &v);
    e->cull_face = (unsigned)v;
    gl->GetIntegerv(GL_DEPTH_FUNC, &v);
    e->depth_func = (unsigned)v;
    gl->GetBooleanv(GL_DEPTH_WRITEMASK, b);
    e->depth_write = b[0] == GL_TRUE;
    gl->GetBooleanv(GL_COLOR_WRITEMASK, b);
    e->color_write = b[0] || b[1] || b[2] || b[3];
    e->blend = gl->IsEnabled(GL_BLEND) == GL_TRUE;
    e->alpha_test = gl->IsEnabled(GL_ALPHA_TEST) == GL_TRUE;
    gl->GetIntegerv(GL_ALPHA_TEST_FUNC, &v);
    e->alpha_func = (unsigned)v;
    gl->GetFloatv(GL_ALPHA_TEST_REF, &f);
    e->alpha_ref = f;
}

static void bind_flat(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    if (gl->ActiveTexture) {
        for (int u = 0; u < r->caps.texture_units && u < 8; u++) {
            gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
            gl->Disable(GL_TEXTURE_2D);
        }
        gl->ActiveTexture(GL_TEXTURE0);
    } else {
        gl->Disable(GL_TEXTURE_2D);
    }
    if (gl->UseProgram) gl->UseProgram(0);
    gl->Disable(GL_LIGHTING);
    gl->Color4f(r->flat_color[0], r->flat_color[1], r->flat_color[2], 1.0f);
}

ht_result ht_renderer_draw(ht_renderer *r, const ht_frame_desc *f) {
    if (!r || !f) return HT_ERR_INVALID_ARGUMENT;
    const ht_gl *gl = &r->gl;
    const ht_camera *cam = &f->camera;
    if (f->light_count < 0 || f->light_count > HT_MAX_LIGHTS || (f->light_count > 0 && !f->lights)) {
        ht_log_linef(r->log, r->log_user, "hairtier: ht_frame_desc: light_count: %d, expected 0..%d with lights set",
                     f->light_count, HT_MAX_LIGHTS);
        return HT_ERR_INVALID_ARGUMENT;
    }
    float aspect = f->aspect;
    if (aspect == 0) {
        GLint vp[4] = { 0, 0, 0, 0 };
        gl->GetIntegerv(GL_VIEWPORT, vp);
        aspect = vp[3] > 0 ? (float)vp[2] / (float)vp[3] : 1.0f;
    }
    float z_near = cam->z_near != 0 ? cam->z_near : DEFAULT_Z_NEAR;
    float z_far = cam->z_far != 0 ? cam->z_far : DEFAULT_Z_FAR;
    ht_tier_frame tf = { .lights = f->lights, .light_count = f->light_count };
    memcpy(tf.eye, cam->eye, sizeof tf.eye);
    if (!ht_mat4_perspective(tf.projection, cam->fov_y, aspect, z_near, z_far)) {
        ht_log_linef(r->log, r->log_user,
                     "hairtier: ht_frame_desc: camera: fov_y %g, aspect %g, z %g..%g is not a projection",
                     (double)cam->fov_y, (double)aspect, (double)z_near, (double)z_far);
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (!ht_mat4_look_at(tf.view, cam->eye, cam->target, cam->up)) {
        ht_log_linef(r->log, r->log_user,
                     "hairtier: ht_frame_desc: camera: eye on target or up along the view direction");
        return HT_ERR_INVALID_ARGUMENT;
    }
    while (gl->GetError() != GL_NO_ERROR) {}
    r->trace.count = 0;

    gl->MatrixMode(GL_PROJECTION);
    gl->LoadMatrixf(tf.projection);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadMatrixf(tf.view);
    gl->Enable(GL_DEPTH_TEST);

    if (f->opaque) draw_opaque_scene(r, f->opaque, f);
    if (!r->has_mesh || r->index_count == 0) return HT_OK;

    if (r->caps.has_vbo) {
        gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo);
        gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    }
    set_arrays(r, r->caps.has_vbo ? NULL : r->vertices, true);
    const void *indices = r->caps.has_vbo ? NULL : r->indices;

    if (r->backend) r->backend->begin_frame(r->backend_state, &tf);
    ht_result result = HT_OK;
    for (int p = 0; p < HT_PASS_COUNT; p++) {
        ht_pass pass = (ht_pass)p;
        set_pass_state(r, pass);
        int subs = r->backend && r->backend->sub_passes ? r->backend->sub_passes(r->backend_state, pass) : 1;
        for (int sub = 0; sub < subs; sub++) {
            if (r->backend) r->backend->bind_pass(r->backend_state, pass, sub);
            else bind_flat(r);
            ht_trace_entry e = { .pass = pass, .sub_pass = sub, .first_index = 0, .index_count = r->index_count };
            if (r->record_trace) record_state(r, &e);
            bool drawn = r->backend && r->backend->draw &&
                         r->backend->draw(r->backend_state, pass, sub, 0, r->index_count);
            if (!drawn) gl->DrawElements(GL_TRIANGLES, (GLsizei)r->index_count, GL_UNSIGNED_INT, indices);
            e.gl_error = gl->GetError();
            if (e.gl_error != GL_NO_ERROR) {
                ht_log_linef(r->log, r->log_user, "hairtier: pass %d.%d (%s): GL error 0x%04x", p, sub,
                             r->backend ? ht_tier_name(r->tier) : "flat", e.gl_error);
                result = HT_ERR_GL;
                while (gl->GetError() != GL_NO_ERROR) {}
            }
            if (r->record_trace && r->trace.count < HT_TRACE_MAX) r->trace.entries[r->trace.count++] = e;
        }
    }
    if (r->backend) r->backend->end_frame(r->backend_state);

    clear_arrays(r);
    if (r->caps.has_vbo) {
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
        gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    }
    /* Leave the app GL's defaults for what the passes changed. */
    gl->Disable(GL_BLEND);
    gl->Disable(GL_ALPHA_TEST);
    gl->Disable(GL_CULL_FACE);
    gl->DepthMask(GL_TRUE);
    gl->DepthFunc(GL_LESS);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    return result;
}

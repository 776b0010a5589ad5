/* renderer.c — probes the device, selects a tier, and draws hair in
   Scheuermann's four passes (docs: DESIGN.md "Passes and sort order"). The
   pass list and its state live here, once, so every tier draws the same
   passes over the same index ranges; backends (tier.h) only shade. A frame
   runs between saving the application's GL state, with a baseline of its
   own, and restoring it (hairtier.h: ht_renderer_draw). */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "fixed.h"
#include "model.h"
#include "renderer_internal.h"
#include "shader_interface.h"

#define DEFAULT_Z_NEAR 0.05f
#define DEFAULT_Z_FAR 100.0f
#define DEFAULT_CUTOFF 0.98f

static const ht_tier_backend *backend_for(ht_tier t) {
    switch (t) {
    case HT_TIER_FULL: return &ht_tier_glsl_full_backend;
    case HT_TIER_VERTEX: return &ht_tier_glsl_vertex_backend;
    case HT_TIER_FIXED: return &ht_tier_fixed_backend;
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

/* In double: a camera far from the origin (|eye| ~ 1e20) squares past
   float's range, although its matrices are finite. */
static double dot3d(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3d(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* False (v untouched) below the model's shortest direction, or not finite. */
static bool normalize3d(double v[3]) {
    double len2 = dot3d(v, v);
    if (!(len2 > HT_MODEL_MIN_LENGTH2) || !isfinite(len2)) return false;
    double inv = 1.0 / sqrt(len2);
    for (int i = 0; i < 3; i++) v[i] *= inv;
    return true;
}

static bool all_finite(const float *v, int n) {
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

bool ht_mat4_perspective(float out[16], float fov_y, float aspect, float z_near, float z_far) {
    if (!(fov_y > 0 && fov_y < 180) || !(aspect > 0) || !isfinite(aspect) || !(z_near > 0) ||
        !(z_far > z_near) || !isfinite(z_far))
        return false;
    float f = 1.0f / tanf(fov_y * 3.14159265358979f / 360.0f);
    float m[16] = { 0 };
    m[0] = f / aspect;
    m[5] = f;
    m[10] = (z_far + z_near) / (z_near - z_far);
    m[11] = -1.0f;
    m[14] = 2.0f * z_far * z_near / (z_near - z_far);
    /* A tiny fov or a huge far plane overflows float. */
    if (!all_finite(m, 16)) return false;
    memcpy(out, m, sizeof m);
    return true;
}

bool ht_mat4_look_at(float out[16], const float eye[3], const float target[3], const float up[3]) {
    if (!all_finite(eye, 3) || !all_finite(target, 3) || !all_finite(up, 3)) return false;
    double e[3] = { eye[0], eye[1], eye[2] };
    double f[3] = { (double)target[0] - e[0], (double)target[1] - e[1], (double)target[2] - e[2] };
    double u0[3] = { up[0], up[1], up[2] };
    double s[3], u[3];
    if (!normalize3d(f) || !normalize3d(u0)) return false;
    cross3d(f, u0, s);
    if (!normalize3d(s)) return false;
    cross3d(s, f, u);
    const float m[16] = {
        (float)s[0], (float)u[0], (float)-f[0], 0,
        (float)s[1], (float)u[1], (float)-f[1], 0,
        (float)s[2], (float)u[2], (float)-f[2], 0,
        (float)-dot3d(s, e), (float)-dot3d(u, e), (float)dot3d(f, e), 1,
    };
    if (!all_finite(m, 16)) return false;
    memcpy(out, m, sizeof m);
    return true;
}

/* ---- creation ---- */

static int clamp_int(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

static ht_result create_backend(ht_renderer *r, const ht_renderer_desc *desc) {
    char failed_text[HT_MANIFEST_MAX_TIERS][HT_SELECT_REASON];
    ht_select_desc sd = {
        .caps = &r->caps, .bundle = &r->bundle, .requested = desc->tier,
        .env_tier = getenv("HAIRTIER_TIER"), .strict = desc->strict,
    };
    char err[1024];
    /* Each round's skipped list extends the previous round's (tiers are
       walked best first, a failed one joins the list): log only what is new. */
    int logged = 0;
    for (;;) {
        ht_selection sel;
        ht_result res = ht_select_tier(&sd, &sel, err, sizeof err);
        for (int i = logged; i < sel.skipped_count; i++)
            ht_log_linef(r->log, r->log_user, "hairtier: skipped %s", sel.skipped[i]);
        logged = sel.skipped_count;
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
    if ((res = ht_caps_probe_gl(&r->gl, &r->caps)) != HT_OK) {
        ht_log_linef(r->log, r->log_user, "hairtier: glGetString(GL_VERSION): no answer (is a GL context current?)");
        goto fail;
    }
    ht_caps_apply_profile(&r->caps, &desc->profile);
    /* The runtime itself must not call what the profile hides. */
    ht_gl_restrict(&r->gl, r->caps.has_3d_textures, r->caps.has_multitexture, r->caps.has_vbo,
                   r->caps.has_shaders);
    /* What the frame's baseline covers beyond the units (renderer.c). */
    GLint lights = HT_MAX_LIGHTS, attribs = 0;
    r->gl.GetIntegerv(GL_MAX_LIGHTS, &lights);
    r->max_lights = clamp_int(lights, HT_MAX_LIGHTS, HT_RENDERER_MAX_LIGHTS);
    if (r->caps.has_shaders) r->gl.GetIntegerv(GL_MAX_VERTEX_ATTRIBS, &attribs);
    r->vertex_attribs = clamp_int(attribs, 0, HT_RENDERER_MAX_ATTRIBS);
    ht_log_linef(r->log, r->log_user, "hairtier: device GL %d.%d, GLSL %d.%02d, %d texture units, %s%s",
                 r->caps.gl_major, r->caps.gl_minor, r->caps.glsl_major, r->caps.glsl_minor, r->caps.texture_units,
                 r->caps.renderer, r->caps.has_vbo ? "" : ", no VBOs");

    if (desc->bundle_dir && desc->bundle_dir[0]) {
        if ((res = ht_manifest_load(desc->bundle_dir, &r->bundle, err, sizeof err)) != HT_OK) {
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

/* ---- what callers hand in ---- */

/* Logs "hairtier: WHAT: FIELD: ..." and returns HT_ERR_INVALID_ARGUMENT. */
__attribute__((format(printf, 4, 5)))
static ht_result reject(const ht_renderer *r, const char *what, const char *field, const char *fmt, ...) {
    char line[HT_LOG_LINE_MAX];
    va_list ap;
    va_start(ap, fmt);
    ht_set_field_error_v(line, sizeof line, what, field, fmt, ap);
    va_end(ap);
    ht_log_linef(r->log, r->log_user, "hairtier: %s", line);
    return HT_ERR_INVALID_ARGUMENT;
}

/* Whole triangles, every index naming a vertex, every vertex number finite
   (a NaN normal or tangent would reach the shaders, which owe nothing to
   NaN input). Degenerate but finite data is fine: the model defines zero
   normals, tangents and ao. */
static ht_result check_mesh(const ht_renderer *r, const char *what, const ht_mesh *m) {
    char field[96];
    if (m->index_count % 3)
        return reject(r, what, "index_count", "%u is not whole triangles", m->index_count);
    if (m->index_count > (uint32_t)INT32_MAX)
        return reject(r, what, "index_count", "%u, more than one glDrawElements draws", m->index_count);
    if (m->index_count && !m->indices)
        return reject(r, what, "indices", "NULL with index_count %u", m->index_count);
    if (m->vertex_count && !m->vertices)
        return reject(r, what, "vertices", "NULL with vertex_count %u", m->vertex_count);
    for (uint32_t i = 0; i < m->index_count; i++)
        if (m->indices[i] >= m->vertex_count) {
            snprintf(field, sizeof field, "indices[%u]", i);
            return reject(r, what, field, "%u, only %u vertices", m->indices[i], m->vertex_count);
        }
    static const struct { const char *name; size_t offset; int n; } members[] = {
        { "position", offsetof(ht_vertex, position), 3 }, { "normal", offsetof(ht_vertex, normal), 3 },
        { "tangent", offsetof(ht_vertex, tangent), 3 },   { "uv", offsetof(ht_vertex, uv), 2 },
        { "ao", offsetof(ht_vertex, ao), 1 },
    };
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const ht_vertex *x = &m->vertices[v];
        if (all_finite(x->position, 3) && all_finite(x->normal, 3) && all_finite(x->tangent, 3) &&
            all_finite(x->uv, 2) && isfinite(x->ao))
            continue;
        for (size_t k = 0; k < sizeof members / sizeof members[0]; k++) {
            const float *f = (const float *)((const char *)x + members[k].offset);
            for (int c = 0; c < members[k].n; c++)
                if (!isfinite(f[c])) {
                    if (members[k].n == 1) snprintf(field, sizeof field, "vertices[%u].%s", v, members[k].name);
                    else snprintf(field, sizeof field, "vertices[%u].%s[%d]", v, members[k].name, c);
                    return reject(r, what, field, "%g is not finite", (double)f[c]);
                }
        }
    }
    return HT_OK;
}

ht_result ht_renderer_set_mesh(ht_renderer *r, const ht_mesh *mesh) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!mesh) return reject(r, "ht_renderer_set_mesh", "mesh", "NULL");
    /* A rejected mesh leaves the previous one in place. */
    ht_result checked = check_mesh(r, "ht_renderer_set_mesh: mesh", mesh);
    if (checked != HT_OK) return checked;
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
            ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: mesh: out of memory for %u vertices",
                         mesh->vertex_count);
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
            ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: %s tier: %s", ht_tier_name(r->tier),
                         ht_result_string(res));
            release_mesh(r);
            return res;
        }
    }
    return HT_OK;
}

/* ---- drawing ---- */

/* A member of ht_vertex: an offset into the bound VBO when base is NULL
   (GL takes offsets as pointers), else its address in base. */
static const void *array_at(const ht_vertex *base, size_t offset) {
    return base ? (const void *)((const char *)base + offset) : (const void *)(uintptr_t)offset;
}

static bool glsl_tier(const ht_renderer *r) {
    return r->backend && (r->tier == HT_TIER_FULL || r->tier == HT_TIER_VERTEX);
}

/* Arrays of ht_vertex: base is NULL with a bound VBO, else the data. The
   hair gets uv as texture coordinate set 0 and, for the GLSL tiers, tangent
   and ao as generic attributes (shader_interface.h); the fixed tier points
   the coordinate sets its stages read itself (tier.h: draw). */
static void set_arrays(ht_renderer *r, const ht_vertex *base, bool hair_attributes) {
    const ht_gl *gl = &r->gl;
    const GLsizei stride = (GLsizei)sizeof(ht_vertex);
    gl->EnableClientState(GL_VERTEX_ARRAY);
    gl->VertexPointer(3, GL_FLOAT, stride, array_at(base, offsetof(ht_vertex, position)));
    gl->EnableClientState(GL_NORMAL_ARRAY);
    gl->NormalPointer(GL_FLOAT, stride, array_at(base, offsetof(ht_vertex, normal)));
    if (!hair_attributes) return;
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
    gl->EnableClientState(GL_TEXTURE_COORD_ARRAY);
    gl->TexCoordPointer(2, GL_FLOAT, stride, array_at(base, offsetof(ht_vertex, uv)));
    if (glsl_tier(r)) {
        gl->VertexAttribPointer(HT_ATTR_TANGENT_LOCATION, 3, GL_FLOAT, GL_FALSE, stride,
                                array_at(base, offsetof(ht_vertex, tangent)));
        gl->EnableVertexAttribArray(HT_ATTR_TANGENT_LOCATION);
        gl->VertexAttribPointer(HT_ATTR_AO_LOCATION, 1, GL_FLOAT, GL_FALSE, stride,
                                array_at(base, offsetof(ht_vertex, ao)));
        gl->EnableVertexAttribArray(HT_ATTR_AO_LOCATION);
    }
}

/* Off again before the next draw of the frame (the head's arrays are not
   the hair's), whatever the app's arrays were: those come back with the
   client attributes at the end of the frame. */
static void clear_arrays(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    if (glsl_tier(r)) {
        gl->DisableVertexAttribArray(HT_ATTR_AO_LOCATION);
        gl->DisableVertexAttribArray(HT_ATTR_TANGENT_LOCATION);
    }
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
    gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    gl->DisableClientState(GL_NORMAL_ARRAY);
    gl->DisableClientState(GL_VERTEX_ARRAY);
}

/* ---- the application's state ---- */

typedef struct app_state {
    GLint program;
    GLfloat projection[16], modelview[16];
    GLfloat texture[HT_RENDERER_MAX_UNITS][16];
} app_state;

/* The units the baseline covers: every one the device has (as far as the
   profile lets the runtime see). */
static int baseline_units(const ht_renderer *r) {
    if (!r->gl.ActiveTexture) return 1;
    return r->caps.texture_units < HT_RENDERER_MAX_UNITS ? r->caps.texture_units : HT_RENDERER_MAX_UNITS;
}

static bool version_at_least(const ht_caps *c, int major, int minor) {
    return c->gl_major > major || (c->gl_major == major && c->gl_minor >= minor);
}

/* glPushAttrib and glPushClientAttrib, the program and the matrices (read,
   not pushed: the projection and texture stacks may be only 2 deep). A full
   attribute stack is HT_ERR_GL with one line and nothing changed. */
static ht_result save_app_state(ht_renderer *r, app_state *s) {
    const ht_gl *gl = &r->gl;
    const char *failed = "glPushAttrib";
    gl->PushAttrib(GL_ALL_ATTRIB_BITS);
    GLenum e = gl->GetError();
    if (e == GL_NO_ERROR) {
        failed = "glPushClientAttrib";
        gl->PushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS);
        e = gl->GetError();
        if (e != GL_NO_ERROR) gl->PopAttrib();
    }
    if (e != GL_NO_ERROR) {
        ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_draw: %s: GL error 0x%04x (is the application's "
                     "attribute stack full?); nothing drawn", failed, e);
        while (gl->GetError() != GL_NO_ERROR) {}
        return HT_ERR_GL;
    }
    s->program = 0;
    if (gl->UseProgram) gl->GetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    gl->GetFloatv(GL_PROJECTION_MATRIX, s->projection);
    gl->GetFloatv(GL_MODELVIEW_MATRIX, s->modelview);
    for (int u = 0; u < baseline_units(r); u++) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->GetFloatv(GL_TEXTURE_MATRIX, s->texture[u]);
    }
    return HT_OK;
}

/* Fixed-function state the application may have left that would reach the
   hair or the head: off, or GL's initial value. Where and how deep to draw
   (viewport, scissor, stencil, clip planes, depth range, framebuffer) stay
   the application's. */
static void set_baseline(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    const ht_caps *c = &r->caps;
    static const GLenum off[] = { GL_LIGHTING, GL_FOG, GL_COLOR_MATERIAL, GL_NORMALIZE, GL_POLYGON_OFFSET_FILL,
                                  GL_POLYGON_STIPPLE, GL_COLOR_LOGIC_OP, GL_BLEND, GL_ALPHA_TEST, GL_CULL_FACE };
    for (size_t i = 0; i < sizeof off / sizeof off[0]; i++) gl->Disable(off[i]);
    if (version_at_least(c, 1, 4)) gl->Disable(GL_COLOR_SUM);
    gl->ShadeModel(GL_SMOOTH);
    gl->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (gl->UseProgram) gl->UseProgram(0);

    const bool cube = version_at_least(c, 1, 3) || ht_extension_list_has(c->extensions, "GL_ARB_texture_cube_map") ||
                      ht_extension_list_has(c->extensions, "GL_EXT_texture_cube_map");
    const bool rectangle = version_at_least(c, 3, 1) ||
                           ht_extension_list_has(c->extensions, "GL_ARB_texture_rectangle") ||
                           ht_extension_list_has(c->extensions, "GL_NV_texture_rectangle") ||
                           ht_extension_list_has(c->extensions, "GL_EXT_texture_rectangle");
    static const GLenum texgen[4] = { GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q };
    gl->MatrixMode(GL_TEXTURE);
    for (int u = baseline_units(r) - 1; u >= 0; u--) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->Disable(GL_TEXTURE_1D);
        gl->Disable(GL_TEXTURE_2D);
        if (c->has_3d_textures) gl->Disable(GL_TEXTURE_3D);
        if (cube) gl->Disable(GL_TEXTURE_CUBE_MAP);
        if (rectangle) gl->Disable(GL_TEXTURE_RECTANGLE);
        for (int k = 0; k < 4; k++) gl->Disable(texgen[k]);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        gl->LoadIdentity();
        if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    gl->MatrixMode(GL_MODELVIEW);

    /* No array but the renderer's own: an app's array left enabled would be
       read past its end. */
    gl->DisableClientState(GL_COLOR_ARRAY);
    gl->DisableClientState(GL_INDEX_ARRAY);
    gl->DisableClientState(GL_EDGE_FLAG_ARRAY);
    if (version_at_least(c, 1, 4)) {
        gl->DisableClientState(GL_SECONDARY_COLOR_ARRAY);
        gl->DisableClientState(GL_FOG_COORD_ARRAY);
    }
    for (int i = 0; i < r->vertex_attribs; i++) gl->DisableVertexAttribArray((GLuint)i);
}

/* Reloads the matrices and program, then pops both attribute stacks (which
   bring back the matrix mode, active units, enables, bindings, arrays). */
static void restore_app_state(ht_renderer *r, const app_state *s) {
    const ht_gl *gl = &r->gl;
    gl->MatrixMode(GL_TEXTURE);
    for (int u = 0; u < baseline_units(r); u++) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->LoadMatrixf(s->texture[u]);
    }
    gl->MatrixMode(GL_PROJECTION);
    gl->LoadMatrixf(s->projection);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadMatrixf(s->modelview);
    if (gl->UseProgram) gl->UseProgram((GLuint)s->program);
    gl->PopClientAttrib();
    gl->PopAttrib();
}

/* The head: simple fixed-function lighting from the frame's lights. Every
   lighting parameter that shapes it is set here, not inherited. */
static void draw_opaque_scene(ht_renderer *r, const ht_mesh *m, const ht_tier_frame *f) {
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
    gl->LightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
    gl->LightModeli(GL_LIGHT_MODEL_LOCAL_VIEWER, GL_FALSE);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE, material);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_SPECULAR, zero);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_EMISSION, zero);
    for (int i = 0; i < r->max_lights; i++) {
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
        gl->Lightf(light, GL_SPOT_CUTOFF, 180.0f);
        gl->Lightf(light, GL_CONSTANT_ATTENUATION, 1.0f);
        gl->Lightf(light, GL_LINEAR_ATTENUATION, 0.0f);
        gl->Lightf(light, GL_QUADRATIC_ATTENUATION, 0.0f);
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

/* Flat mode: the baseline has no texture, lighting or program. */
static void bind_flat(ht_renderer *r) {
    r->gl.Color4f(r->flat_color[0], r->flat_color[1], r->flat_color[2], 1.0f);
}

/* Frame warnings logged once per renderer: bit 0 too many lights, bit 1 + i
   light i's type differs from the plan. */
#define WARN_LIGHT_COUNT 1u
#define WARN_LIGHT_TYPE(i) (2u << (i))

static const char *light_type_name(ht_light_type t) { return t == HT_LIGHT_POINT ? "point" : "directional"; }

/* Every number of the frame finite and in range, each failure one line
   naming the field; out receives the camera's matrices. */
static ht_result check_frame(const ht_renderer *r, const ht_frame_desc *f, ht_tier_frame *out) {
    static const char what[] = "ht_frame_desc";
    const ht_camera *cam = &f->camera;
    if (f->light_count < 0 || f->light_count > HT_MAX_LIGHTS)
        return reject(r, what, "light_count", "%d outside 0..%d", f->light_count, HT_MAX_LIGHTS);
    if (f->light_count > 0 && !f->lights)
        return reject(r, what, "lights", "NULL with light_count %d", f->light_count);
    char field[48];
    for (int i = 0; i < f->light_count; i++) {
        const ht_light *l = &f->lights[i];
        if (l->type != HT_LIGHT_DIRECTIONAL && l->type != HT_LIGHT_POINT) {
            snprintf(field, sizeof field, "lights[%d].type", i);
            return reject(r, what, field, "%d is not HT_LIGHT_DIRECTIONAL or HT_LIGHT_POINT", (int)l->type);
        }
        if (!all_finite(l->vector, 3)) {
            snprintf(field, sizeof field, "lights[%d].vector", i);
            return reject(r, what, field, "(%g, %g, %g) is not finite", (double)l->vector[0], (double)l->vector[1],
                          (double)l->vector[2]);
        }
        for (int k = 0; k < 3; k++)
            if (!(l->color[k] >= 0 && l->color[k] <= 4)) {
                snprintf(field, sizeof field, "lights[%d].color", i);
                return reject(r, what, field, "(%g, %g, %g) outside [0, 4]", (double)l->color[0],
                              (double)l->color[1], (double)l->color[2]);
            }
    }
    static const struct { const char *name; size_t offset; } vectors[] = {
        { "camera.eye", offsetof(ht_camera, eye) }, { "camera.target", offsetof(ht_camera, target) },
        { "camera.up", offsetof(ht_camera, up) },
    };
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++) {
        const float *v = (const float *)((const char *)cam + vectors[i].offset);
        if (!all_finite(v, 3))
            return reject(r, what, vectors[i].name, "(%g, %g, %g) is not finite", (double)v[0], (double)v[1],
                          (double)v[2]);
    }
    double view[3], up[3], side[3];
    for (int k = 0; k < 3; k++) {
        view[k] = (double)cam->target[k] - (double)cam->eye[k];
        up[k] = cam->up[k];
    }
    if (!normalize3d(view)) return reject(r, what, "camera.target", "equals camera.eye: no view direction");
    if (!normalize3d(up)) return reject(r, what, "camera.up", "zero vector");
    cross3d(view, up, side);
    if (!normalize3d(side))
        return reject(r, what, "camera.up", "parallel to the view direction (target - eye): the roll is undefined");
    if (!(cam->fov_y > 0 && cam->fov_y < 180))
        return reject(r, what, "camera.fov_y", "%g outside (0, 180) degrees", (double)cam->fov_y);
    float z_near = cam->z_near != 0 ? cam->z_near : DEFAULT_Z_NEAR;
    float z_far = cam->z_far != 0 ? cam->z_far : DEFAULT_Z_FAR;
    if (!(z_near > 0) || !isfinite(z_near))
        return reject(r, what, "camera.z_near", "%g, expected > 0 (0 means %g)", (double)z_near,
                      (double)DEFAULT_Z_NEAR);
    if (!(z_far > z_near) || !isfinite(z_far))
        return reject(r, what, "camera.z_far", "%g, expected finite and > z_near %g", (double)z_far, (double)z_near);
    float aspect = f->aspect;
    if (aspect == 0) {
        GLint vp[4] = { 0, 0, 0, 0 };
        r->gl.GetIntegerv(GL_VIEWPORT, vp);
        aspect = vp[3] > 0 && vp[2] > 0 ? (float)vp[2] / (float)vp[3] : 1.0f;
    }
    if (!(aspect > 0) || !isfinite(aspect))
        return reject(r, what, "aspect", "%g, expected > 0 (0 means the viewport's)", (double)aspect);
    if (!ht_mat4_perspective(out->projection, cam->fov_y, aspect, z_near, z_far))
        return reject(r, what, "camera", "fov_y %g, aspect %g, z %g..%g overflow the projection matrix",
                      (double)cam->fov_y, (double)aspect, (double)z_near, (double)z_far);
    if (!ht_mat4_look_at(out->view, cam->eye, cam->target, cam->up))
        return reject(r, what, "camera.eye", "(%g, %g, %g) overflows the view matrix", (double)cam->eye[0],
                      (double)cam->eye[1], (double)cam->eye[2]);
    memcpy(out->eye, cam->eye, sizeof out->eye);
    if (f->opaque) return check_mesh(r, "ht_frame_desc: opaque", f->opaque);
    return HT_OK;
}

/* The lights every backend and the head see: directional vectors unit
   length in double (a huge one would overflow the shaders' float
   normalize), zero staying zero; within the bundle's plan each light takes
   the planned type, which is what the generated shaders evaluate, so every
   tier shades the same light. Deviations are logged once per renderer. */
static int plan_lights(ht_renderer *r, const ht_frame_desc *f, ht_light out[HT_MAX_LIGHTS]) {
    int n = f->light_count;
    const int planned = r->have_bundle && r->backend ? r->bundle.light_count : n;
    if (n > planned) {
        if (!(r->warned & WARN_LIGHT_COUNT))
            ht_log_linef(r->log, r->log_user,
                         "hairtier: ht_frame_desc: light_count: %d, the bundle plans %d; lights[%d..%d] are not drawn",
                         n, planned, planned, n - 1);
        r->warned |= WARN_LIGHT_COUNT;
        n = planned;
    }
    for (int i = 0; i < n; i++) {
        out[i] = f->lights[i];
        if (r->have_bundle && r->backend && out[i].type != r->bundle.lights[i]) {
            if (!(r->warned & WARN_LIGHT_TYPE(i)))
                ht_log_linef(r->log, r->log_user,
                             "hairtier: ht_frame_desc: lights[%d].type: %s, the bundle plans %s; shaded as %s",
                             i, light_type_name(out[i].type), light_type_name(r->bundle.lights[i]),
                             light_type_name(r->bundle.lights[i]));
            r->warned |= WARN_LIGHT_TYPE(i);
            out[i].type = r->bundle.lights[i];
        }
        if (out[i].type == HT_LIGHT_DIRECTIONAL) {
            double v[3] = { out[i].vector[0], out[i].vector[1], out[i].vector[2] };
            if (!normalize3d(v)) v[0] = v[1] = v[2] = 0;
            for (int k = 0; k < 3; k++) out[i].vector[k] = (float)v[k];
        }
    }
    return n;
}

/* The frame proper, between saving and restoring the app's state. */
static ht_result draw_frame(ht_renderer *r, const ht_frame_desc *f, const ht_tier_frame *tf) {
    const ht_gl *gl = &r->gl;
    gl->MatrixMode(GL_PROJECTION);
    gl->LoadMatrixf(tf->projection);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadMatrixf(tf->view);
    gl->Enable(GL_DEPTH_TEST);

    if (f->opaque) draw_opaque_scene(r, f->opaque, tf);
    if (!r->has_mesh || r->index_count == 0) return HT_OK;

    if (r->caps.has_vbo) {
        gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo);
        gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    }
    set_arrays(r, r->caps.has_vbo ? NULL : r->vertices, true);
    const void *indices = r->caps.has_vbo ? NULL : r->indices;

    if (r->backend) r->backend->begin_frame(r->backend_state, tf);
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
    return result;
}

ht_result ht_renderer_draw(ht_renderer *r, const ht_frame_desc *f) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!f) return reject(r, "ht_renderer_draw", "frame", "NULL");
    ht_tier_frame tf = { 0 };
    ht_result checked = check_frame(r, f, &tf);
    if (checked != HT_OK) return checked;
    ht_light lights[HT_MAX_LIGHTS];
    tf.light_count = plan_lights(r, f, lights);
    tf.lights = lights;
    while (r->gl.GetError() != GL_NO_ERROR) {}
    r->trace.count = 0;

    app_state saved;
    ht_result result = save_app_state(r, &saved);
    if (result != HT_OK) return result;
    set_baseline(r);
    result = draw_frame(r, f, &tf);
    restore_app_state(r, &saved);
    return result;
}

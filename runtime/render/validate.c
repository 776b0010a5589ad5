/* validate.c — what callers hand the renderer, checked before any GL call:
   meshes (whole triangles, indices in range, finite vertices), frames
   (camera, lights; the camera's matrices come out of the check) and the
   frame's lights fitted to what the bundle planned. Each refusal is one log
   line naming the field. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "errfmt.h"
#include "renderer_internal.h"
#include "vecmath.h"

#define DEFAULT_Z_NEAR 0.05f
#define DEFAULT_Z_FAR 100.0f

/* Logs "hairtier: WHAT: FIELD: ..." and returns HT_ERR_INVALID_ARGUMENT. */
__attribute__((format(printf, 4, 5)))
ht_result ht_renderer_reject(const ht_renderer *r, const char *what, const char *field, const char *fmt, ...) {
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
ht_result ht_renderer_check_mesh(const ht_renderer *r, const char *what, const ht_mesh *m) {
    char field[96];
    if (m->index_count % 3)
        return ht_renderer_reject(r, what, "index_count", "%u is not whole triangles", m->index_count);
    if (m->index_count > (uint32_t)INT32_MAX)
        return ht_renderer_reject(r, what, "index_count", "%u, more than one glDrawElements draws", m->index_count);
    if (m->index_count && !m->indices)
        return ht_renderer_reject(r, what, "indices", "NULL with index_count %u", m->index_count);
    if (m->vertex_count && !m->vertices)
        return ht_renderer_reject(r, what, "vertices", "NULL with vertex_count %u", m->vertex_count);
    for (uint32_t i = 0; i < m->index_count; i++)
        if (m->indices[i] >= m->vertex_count) {
            snprintf(field, sizeof field, "indices[%u]", i);
            return ht_renderer_reject(r, what, field, "%u, only %u vertices", m->indices[i], m->vertex_count);
        }
    static const struct { const char *name; size_t offset; int n; } members[] = {
        { "position", offsetof(ht_vertex, position), 3 }, { "normal", offsetof(ht_vertex, normal), 3 },
        { "tangent", offsetof(ht_vertex, tangent), 3 },   { "uv", offsetof(ht_vertex, uv), 2 },
        { "ao", offsetof(ht_vertex, ao), 1 },
    };
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const ht_vertex *x = &m->vertices[v];
        if (ht_all_finite(x->position, 3) && ht_all_finite(x->normal, 3) && ht_all_finite(x->tangent, 3) &&
            ht_all_finite(x->uv, 2) && isfinite(x->ao))
            continue;
        for (size_t k = 0; k < sizeof members / sizeof members[0]; k++) {
            const float *f = (const float *)((const char *)x + members[k].offset);
            for (int c = 0; c < members[k].n; c++)
                if (!isfinite(f[c])) {
                    if (members[k].n == 1) snprintf(field, sizeof field, "vertices[%u].%s", v, members[k].name);
                    else snprintf(field, sizeof field, "vertices[%u].%s[%d]", v, members[k].name, c);
                    return ht_renderer_reject(r, what, field, "%g is not finite", (double)f[c]);
                }
        }
    }
    return HT_OK;
}

/* Frame warnings logged once per renderer: bit 0 too many lights, bit 1 + i
   light i's type differs from the plan. */
#define WARN_LIGHT_COUNT 1u
#define WARN_LIGHT_TYPE(i) (2u << (i))

static const char *light_type_name(ht_light_type t) { return t == HT_LIGHT_POINT ? "point" : "directional"; }

/* Every number of the frame finite and in range, each failure one line
   naming the field; out receives the camera's matrices. */
ht_result ht_renderer_check_frame(const ht_renderer *r, const ht_frame_desc *f, ht_tier_frame *out) {
    static const char what[] = "ht_frame_desc";
    const ht_camera *cam = &f->camera;
    if (f->light_count < 0 || f->light_count > HT_MAX_LIGHTS)
        return ht_renderer_reject(r, what, "light_count", "%d outside 0..%d", f->light_count, HT_MAX_LIGHTS);
    if (f->light_count > 0 && !f->lights)
        return ht_renderer_reject(r, what, "lights", "NULL with light_count %d", f->light_count);
    char field[48];
    for (int i = 0; i < f->light_count; i++) {
        const ht_light *l = &f->lights[i];
        if (l->type != HT_LIGHT_DIRECTIONAL && l->type != HT_LIGHT_POINT) {
            snprintf(field, sizeof field, "lights[%d].type", i);
            return ht_renderer_reject(r, what, field, "%d is not HT_LIGHT_DIRECTIONAL or HT_LIGHT_POINT", (int)l->type);
        }
        if (!ht_all_finite(l->vector, 3)) {
            snprintf(field, sizeof field, "lights[%d].vector", i);
            return ht_renderer_reject(r, what, field, "(%g, %g, %g) is not finite", (double)l->vector[0], (double)l->vector[1],
                          (double)l->vector[2]);
        }
        for (int k = 0; k < 3; k++)
            if (!(l->color[k] >= 0 && l->color[k] <= 4)) {
                snprintf(field, sizeof field, "lights[%d].color", i);
                return ht_renderer_reject(r, what, field, "(%g, %g, %g) outside [0, 4]", (double)l->color[0],
                              (double)l->color[1], (double)l->color[2]);
            }
    }
    static const struct { const char *name; size_t offset; } vectors[] = {
        { "camera.eye", offsetof(ht_camera, eye) }, { "camera.target", offsetof(ht_camera, target) },
        { "camera.up", offsetof(ht_camera, up) },
    };
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++) {
        const float *v = (const float *)((const char *)cam + vectors[i].offset);
        if (!ht_all_finite(v, 3))
            return ht_renderer_reject(r, what, vectors[i].name, "(%g, %g, %g) is not finite", (double)v[0], (double)v[1],
                          (double)v[2]);
    }
    double view[3], up[3], side[3];
    for (int k = 0; k < 3; k++) {
        view[k] = (double)cam->target[k] - (double)cam->eye[k];
        up[k] = cam->up[k];
    }
    if (!ht_vec3_direction(view, view)) return ht_renderer_reject(r, what, "camera.target", "equals camera.eye: no view direction");
    if (!ht_vec3_direction(up, up)) return ht_renderer_reject(r, what, "camera.up", "zero vector");
    ht_vec3_cross(side, view, up);
    if (!ht_vec3_direction(side, side))
        return ht_renderer_reject(r, what, "camera.up", "parallel to the view direction (target - eye): the roll is undefined");
    if (!(cam->fov_y > 0 && cam->fov_y < 180))
        return ht_renderer_reject(r, what, "camera.fov_y", "%g outside (0, 180) degrees", (double)cam->fov_y);
    float z_near = cam->z_near != 0 ? cam->z_near : DEFAULT_Z_NEAR;
    float z_far = cam->z_far != 0 ? cam->z_far : DEFAULT_Z_FAR;
    if (!(z_near > 0) || !isfinite(z_near))
        return ht_renderer_reject(r, what, "camera.z_near", "%g, expected > 0 (0 means %g)", (double)z_near,
                      (double)DEFAULT_Z_NEAR);
    if (!(z_far > z_near) || !isfinite(z_far))
        return ht_renderer_reject(r, what, "camera.z_far", "%g, expected finite and > z_near %g", (double)z_far, (double)z_near);
    float aspect = f->aspect;
    if (aspect == 0) {
        GLint vp[4] = { 0, 0, 0, 0 };
        r->gl.GetIntegerv(GL_VIEWPORT, vp);
        aspect = vp[3] > 0 && vp[2] > 0 ? (float)vp[2] / (float)vp[3] : 1.0f;
    }
    if (!(aspect > 0) || !isfinite(aspect))
        return ht_renderer_reject(r, what, "aspect", "%g, expected > 0 (0 means the viewport's)", (double)aspect);
    if (!ht_mat4_perspective(out->projection, cam->fov_y, aspect, z_near, z_far))
        return ht_renderer_reject(r, what, "camera", "fov_y %g, aspect %g, z %g..%g overflow the projection matrix",
                      (double)cam->fov_y, (double)aspect, (double)z_near, (double)z_far);
    if (!ht_mat4_look_at(out->view, cam->eye, cam->target, cam->up))
        return ht_renderer_reject(r, what, "camera.eye", "(%g, %g, %g) overflows the view matrix", (double)cam->eye[0],
                      (double)cam->eye[1], (double)cam->eye[2]);
    memcpy(out->eye, cam->eye, sizeof out->eye);
    if (f->opaque) return ht_renderer_check_mesh(r, "ht_frame_desc: opaque", f->opaque);
    return HT_OK;
}

/* The lights every backend and the head see: directional vectors unit
   length in double (a huge one would overflow the shaders' float
   normalize), zero staying zero; within the bundle's plan each light takes
   the planned type, which is what the generated shaders evaluate, so every
   tier shades the same light. Deviations are logged once per renderer. */
int ht_renderer_plan_lights(ht_renderer *r, const ht_frame_desc *f, ht_light out[HT_MAX_LIGHTS]) {
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
            ht_vec3_direction(v, v); /* zero stays zero */
            for (int k = 0; k < 3; k++) out[i].vector[k] = (float)v[k];
        }
    }
    return n;
}

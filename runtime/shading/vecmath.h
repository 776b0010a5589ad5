/* vecmath.h — the small double-precision vec3 helpers the runtime shares
   (cglm's habit: header-only, static inline, r first for outputs): the mesh
   builders, the renderer's camera matrices and frame checks, and the fixed
   tier's per-vertex coordinates; and the two camera matrices GLU would
   give (no GLU dependency). Internal to libhairtier.

   Geometry is computed in double and stored as float, so rounding never
   turns a unit vector into a slightly non-unit one that accumulates, and a
   camera far from the origin (|eye| ~ 1e20) squares without overflowing.

   Two normalizations, because two rules exist: ht_vec3_normalize keeps any
   direction longer than 1e-12 (the mesh builders' construction vectors);
   ht_vec3_direction is the shading model's rule (model.c: shorter than
   sqrt(HT_MODEL_MIN_LENGTH2), or not finite, is no direction: zero). */
#ifndef HT_VECMATH_H
#define HT_VECMATH_H

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include <hairtier/model.h>

static inline void ht_vec3_set(double r[3], double x, double y, double z) { r[0] = x; r[1] = y; r[2] = z; }
static inline void ht_vec3_copy(double r[3], const double a[3]) { r[0] = a[0]; r[1] = a[1]; r[2] = a[2]; }
static inline void ht_vec3_from_float(double r[3], const float a[3]) { r[0] = a[0]; r[1] = a[1]; r[2] = a[2]; }
static inline void ht_vec3_store(float r[3], const double a[3]) {
    r[0] = (float)a[0]; r[1] = (float)a[1]; r[2] = (float)a[2];
}
static inline double ht_vec3_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double ht_vec3_length(const double a[3]) { return sqrt(ht_vec3_dot(a, a)); }

static inline void ht_vec3_cross(double r[3], const double a[3], const double b[3]) {
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    ht_vec3_set(r, x, y, z);
}

/* r = a + s * b (r may be a or b) */
static inline void ht_vec3_mad(double r[3], const double a[3], double s, const double b[3]) {
    for (int i = 0; i < 3; i++) r[i] = a[i] + s * b[i];
}

/* Normalizes a in place; false (a untouched) when |a| is too small for the
   direction to mean anything. */
static inline bool ht_vec3_normalize(double a[3]) {
    double len = ht_vec3_length(a);
    if (!(len > 1e-12)) return false;
    for (int i = 0; i < 3; i++) a[i] /= len;
    return true;
}

/* r = v / |v| by the model's rule; false and r = 0 when v has no
   direction. r may be v. */
static inline bool ht_vec3_direction(double r[3], const double v[3]) {
    double len2 = ht_vec3_dot(v, v);
    if (!(len2 > HT_MODEL_MIN_LENGTH2) || !isfinite(len2)) {
        ht_vec3_set(r, 0, 0, 0);
        return false;
    }
    double inv = 1.0 / sqrt(len2);
    for (int i = 0; i < 3; i++) r[i] = v[i] * inv;
    return true;
}

/* The shifted tangent, the shading model's one rule (model.c):
   r = normalize(T + shift * N) for a unit or zero T and N. A strand without
   a direction (has_t false) has none after the shift either: T + shift * N
   alone would turn a zero T into N. False, and r zero, when r has none. */
static inline bool ht_vec3_shifted_tangent(double r[3], const double T[3], bool has_t, const double N[3],
                                           double shift) {
    double v[3];
    for (int i = 0; i < 3; i++) v[i] = T[i] + shift * N[i];
    return has_t ? ht_vec3_direction(r, v) : (ht_vec3_set(r, 0, 0, 0), false);
}

/* A unit vector perpendicular to unit a: crossed with the world axis a is
   least aligned with, so the choice is stable (the same a gives the same
   answer) and never degenerate. */
static inline void ht_vec3_any_perpendicular(double r[3], const double a[3]) {
    double axis[3] = { 0, 0, 0 };
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(a[i]) < fabs(a[k])) k = i;
    axis[k] = 1;
    ht_vec3_cross(r, a, axis);
    ht_vec3_normalize(r);
}

/* Removes from v its component along unit t; false when nothing is left. */
static inline bool ht_vec3_orthonormalize(double v[3], const double t[3]) {
    ht_vec3_mad(v, v, -ht_vec3_dot(v, t), t);
    return ht_vec3_normalize(v);
}

/* NaN clamps to 0: a colour or weight never carries a NaN onwards. */
static inline double ht_clamp01(double x) { return x > 0.0 ? (x < 1.0 ? x : 1.0) : 0.0; }
static inline double ht_clamp_unit(double x) { return x > 1.0 ? 1.0 : (x < -1.0 ? -1.0 : x); }

static inline bool ht_all_finite(const float *v, int n) {
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

/* ---- mat4 (float[16], column-major, as glLoadMatrixf takes it) ---- */

/* gluPerspective, column-major. False (out untouched) for fov outside
   (0,180), aspect <= 0, near <= 0, far <= near, or a matrix that overflows
   float (a tiny fov, a huge far plane). */
static inline bool ht_mat4_perspective(float out[16], float fov_y, float aspect, float z_near, float z_far) {
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
    if (!ht_all_finite(m, 16)) return false;
    memcpy(out, m, sizeof m);
    return true;
}

/* gluLookAt, column-major, computed in double. False (out untouched) when
   eye is on target, up is parallel to the view direction, or an input or
   the result is not finite. */
static inline bool ht_mat4_look_at(float out[16], const float eye[3], const float target[3], const float up[3]) {
    if (!ht_all_finite(eye, 3) || !ht_all_finite(target, 3) || !ht_all_finite(up, 3)) return false;
    double e[3] = { eye[0], eye[1], eye[2] };
    double f[3] = { (double)target[0] - e[0], (double)target[1] - e[1], (double)target[2] - e[2] };
    double u0[3] = { up[0], up[1], up[2] };
    double s[3], u[3];
    if (!ht_vec3_direction(f, f) || !ht_vec3_direction(u0, u0)) return false;
    ht_vec3_cross(s, f, u0);
    if (!ht_vec3_direction(s, s)) return false;
    ht_vec3_cross(u, s, f);
    const float m[16] = {
        (float)s[0], (float)u[0], (float)-f[0], 0,
        (float)s[1], (float)u[1], (float)-f[1], 0,
        (float)s[2], (float)u[2], (float)-f[2], 0,
        (float)-ht_vec3_dot(s, e), (float)-ht_vec3_dot(u, e), (float)ht_vec3_dot(f, e), 1,
    };
    if (!ht_all_finite(m, 16)) return false;
    memcpy(out, m, sizeof m);
    return true;
}

#endif

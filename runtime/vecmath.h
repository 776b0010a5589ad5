/* vecmath.h — the small double-precision vec3 helpers the runtime shares
   (cglm's habit: header-only, static inline, r first for outputs): the mesh
   builders, the renderer's camera matrices and frame checks, and the fixed
   tier's per-vertex coordinates. Internal to libhairtier.

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

#include "model.h"

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

#endif

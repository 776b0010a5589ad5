/* mesh_internal.h — what the hair mesh builders (mesh_furball.c,
   mesh_patches.c) share with mesh.c: storage, the sort key, and a few
   double-precision vector helpers. Not part of the public API.

   Geometry is computed in double and stored as float, so rounding never
   turns a unit vector into a slightly non-unit one that accumulates. */
#ifndef HT_MESH_INTERNAL_H
#define HT_MESH_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "hairtier.h"

/* Zeroes *m, then allocates the three arrays and sets the counts.
   HT_ERR_INVALID_ARGUMENT when a count does not fit the uint32 fields,
   HT_ERR_OUT_OF_MEMORY (with nothing left allocated) when malloc fails. */
ht_result ht_mesh_alloc(ht_mesh *m, uint64_t vertex_count, uint64_t index_count,
                        uint64_t component_count);

/* Distance from m->center to the mean position of the vertex run
   [first_vertex, first_vertex + count): the builders write each component's
   vertices contiguously, so this is the component's vertex centroid. */
float ht_mesh_centroid_distance(const ht_mesh *m, uint32_t first_vertex, uint32_t count);

/* ---- vectors (double[3]) ---- */

static inline void v3_set(double r[3], double x, double y, double z) { r[0] = x; r[1] = y; r[2] = z; }
static inline void v3_copy(double r[3], const double a[3]) { r[0] = a[0]; r[1] = a[1]; r[2] = a[2]; }
static inline double v3_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double v3_length(const double a[3]) { return sqrt(v3_dot(a, a)); }

static inline void v3_cross(double r[3], const double a[3], const double b[3]) {
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    v3_set(r, x, y, z);
}

/* r = a + s * b */
static inline void v3_mad(double r[3], const double a[3], double s, const double b[3]) {
    for (int i = 0; i < 3; i++) r[i] = a[i] + s * b[i];
}

/* Normalizes a in place; returns false (a untouched) when |a| is too small
   for the direction to mean anything. */
static inline int v3_normalize(double a[3]) {
    double len = v3_length(a);
    if (!(len > 1e-12)) return 0;
    for (int i = 0; i < 3; i++) a[i] /= len;
    return 1;
}

/* A unit vector perpendicular to unit a: crossed with the world axis a is
   least aligned with, so the choice is stable (the same a gives the same
   answer) and never degenerate. */
static inline void v3_any_perpendicular(double r[3], const double a[3]) {
    double axis[3] = { 0, 0, 0 };
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(a[i]) < fabs(a[k])) k = i;
    axis[k] = 1;
    v3_cross(r, a, axis);
    v3_normalize(r);
}

/* Removes from v its component along unit t; false when nothing is left. */
static inline int v3_orthonormalize(double v[3], const double t[3]) {
    v3_mad(v, v, -v3_dot(v, t), t);
    return v3_normalize(v);
}

static inline void v3_store(float out[3], const double a[3]) {
    out[0] = (float)a[0]; out[1] = (float)a[1]; out[2] = (float)a[2];
}

static inline double clamp01(double x) { return x < 0 ? 0 : x > 1 ? 1 : x; }

#endif

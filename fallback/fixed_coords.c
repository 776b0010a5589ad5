/* fixed_coords.c — per-vertex LUT coordinates and primary colours of the
   fixed tier, and the texture matrix that replaces the coordinates for
   Kajiya-Kay under a directional light (see fixed_coords.h), in double
   precision like the oracle. */
#include "fixed_coords.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vecmath.h"

/* d = t.H of the shifted tangent, or -1 (S = 0) without a direction. */
static double shifted_dot(const double T[3], const double N[3], double shift, const double H[3],
                          bool has_h) {
    double t[3];
    if (!ht_vec3_shifted_tangent(t, T, has_h, N, shift)) return -1.0;
    return ht_clamp_unit(ht_vec3_dot(t, H));
}

static const ht_light *nth_light(int index, const ht_light *lights, int light_count) {
    return index >= 0 && index < light_count ? &lights[index] : NULL;
}

/* The primary colour of one vertex: clamp(light.color * ao / light_scale),
   alpha 1. */
static void vertex_color(const ht_combiner_program *p, const ht_vertex *v, const double color[3], bool black,
                         float out[4]) {
    double ao = p->ao ? ht_clamp01((double)v->ao) : 1.0;
    for (int i = 0; i < 3; i++) out[i] = black ? 0.0f : (float)ht_clamp01(color[i] * ao);
    out[3] = 1.0f;
}

/* The light's colour over the program's light scale (0 without a light). */
static void light_color(const ht_combiner_program *p, const ht_light *light, double color[3]) {
    const double scale = p->light_scale >= 1.0 ? p->light_scale : 1.0;
    for (int i = 0; i < 3; i++)
        color[i] = light && isfinite(light->color[i]) ? (double)light->color[i] / scale : 0.0;
}

ht_result ht_fixed_coords_colors(const ht_combiner_program *p, const ht_vertex *vertices, size_t count,
                                 const ht_light *lights, int light_count, float *colors,
                                 char *err, size_t err_size) {
    return ht_fixed_coords_colors_of(p, p ? p->light : 0, vertices, count, lights, light_count, colors, err,
                                     err_size);
}

ht_result ht_fixed_coords_colors_of(const ht_combiner_program *p, int light, const ht_vertex *vertices,
                                    size_t count, const ht_light *lights, int light_count, float *colors,
                                    char *err, size_t err_size) {
    if (!p || (count > 0 && (!vertices || !colors)) || (light_count > 0 && !lights)) {
        snprintf(err, err_size, "fixed_coords: NULL argument");
        return HT_ERR_INVALID_ARGUMENT;
    }
    double color[3];
    light_color(p, nth_light(light, lights, light_count), color);
    const bool matrix = ht_combiner_lut_coords(p) == HT_COORDS_TEXTURE_MATRIX;
    for (size_t vi = 0; vi < count; vi++) {
        double T[3], unit[3];
        ht_vec3_from_float(T, vertices[vi].tangent);
        bool black = matrix && !ht_vec3_direction(unit, T);
        vertex_color(p, &vertices[vi], color, black, &colors[4 * vi]);
    }
    return HT_OK;
}

/* Row `row` of the column-major m: (k * dir, offset) where the LUT axis of
   `size` texels maps d to k d + offset (ht_combiner_lut_coord is affine on
   [-1,1]); a row without a direction is the constant coordinate of d_none. */
static void matrix_row(float m[16], int row, int size, const double dir[3], bool has_dir, double d_none) {
    const double lo = ht_combiner_lut_coord(-1.0, size), hi = ht_combiner_lut_coord(1.0, size);
    const double k = 0.5 * (hi - lo), offset = 0.5 * (hi + lo);
    for (int col = 0; col < 3; col++) m[4 * col + row] = has_dir ? (float)(k * dir[col]) : 0.0f;
    m[12 + row] = has_dir ? (float)offset : ht_combiner_lut_coord(d_none, size);
}

ht_result ht_fixed_coords_texture_matrix(const ht_combiner_program *p, const ht_light *lights,
                                         int light_count, const float view_dir[3], float m[16],
                                         char *err, size_t err_size) {
    return ht_fixed_coords_texture_matrix_of(p, p ? p->light : 0, lights, light_count, view_dir, m, err,
                                             err_size);
}

ht_result ht_fixed_coords_texture_matrix_of(const ht_combiner_program *p, int light_index,
                                            const ht_light *lights, int light_count, const float view_dir[3],
                                            float m[16], char *err, size_t err_size) {
    if (m) {
        memset(m, 0, 16 * sizeof *m);
        m[0] = m[5] = m[10] = m[15] = 1.0f;
    }
    if (!p || !view_dir || !m || (light_count > 0 && !lights)) {
        snprintf(err, err_size, "fixed_coords: NULL argument");
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (ht_combiner_lut_coords(p) != HT_COORDS_TEXTURE_MATRIX || p->model != HT_MODEL_KAJIYA_KAY) {
        snprintf(err, err_size, "fixed_coords: the program's LUT stage is not texture-matrix");
        return HT_ERR_INVALID_ARGUMENT;
    }
    const ht_light *light = nth_light(light_index, lights, light_count);
    if (light && light->type == HT_LIGHT_POINT) {
        snprintf(err, err_size, "fixed_coords: light %d is a point light: its L varies per vertex, the "
                 "texture matrix needs a directional one", light_index);
        return HT_ERR_UNSUPPORTED;
    }
    double raw[3] = { 0, 0, 0 }, L[3], V[3], H[3];
    if (light) ht_vec3_from_float(raw, light->vector);
    bool has_l = ht_vec3_direction(L, raw);
    ht_vec3_from_float(raw, view_dir);
    ht_vec3_direction(V, raw);
    for (int i = 0; i < 3; i++) raw[i] = L[i] + V[i];
    bool has_h = ht_vec3_direction(H, raw);
    /* the CPU rule's answers without a direction: sin(T,L) = 0, S = 0 */
    matrix_row(m, 0, p->lut_size[0], L, has_l, 1.0);
    matrix_row(m, 1, p->lut_size[1], H, has_h, -1.0);
    matrix_row(m, 2, p->lut_size[2], L, false, 0.0);
    m[15] = 1.0f;
    return HT_OK;
}

ht_result ht_fixed_coords_compute(const ht_combiner_program *p, const ht_vertex *vertices,
                                  size_t count, const ht_light *lights, int light_count,
                                  const float eye[3], float *lut_coords, float *colors,
                                  char *err, size_t err_size) {
    if (!p || (count > 0 && (!vertices || !lut_coords || !colors)) || !eye ||
        (light_count > 0 && !lights)) {
        snprintf(err, err_size, "fixed_coords: NULL argument");
        return HT_ERR_INVALID_ARGUMENT;
    }
    const ht_light *light = nth_light(p->light, lights, light_count);
    double eye_d[3], light_v[3] = { 0, 0, 0 };
    ht_vec3_from_float(eye_d, eye);
    if (light) ht_vec3_from_float(light_v, light->vector);
    const bool kajiya_kay = p->model == HT_MODEL_KAJIYA_KAY;

    for (size_t vi = 0; vi < count; vi++) {
        const ht_vertex *v = &vertices[vi];
        double pos[3], T[3], N[3], raw[3], L[3], V[3], H[3];
        ht_vec3_from_float(pos, v->position);
        ht_vec3_from_float(raw, v->tangent);
        bool has_t = ht_vec3_direction(T, raw);
        ht_vec3_from_float(raw, v->normal);
        ht_vec3_direction(N, raw);
        for (int i = 0; i < 3; i++)
            raw[i] = light && light->type == HT_LIGHT_POINT ? light_v[i] - pos[i] : light_v[i];
        bool has_l = ht_vec3_direction(L, raw);
        for (int i = 0; i < 3; i++) raw[i] = eye_d[i] - pos[i];
        ht_vec3_direction(V, raw);
        for (int i = 0; i < 3; i++) raw[i] = L[i] + V[i];
        bool has_h = ht_vec3_direction(H, raw);

        double d[3];
        if (kajiya_kay) {
            d[0] = has_t && has_l ? ht_clamp_unit(ht_vec3_dot(T, L)) : 1.0;
            d[1] = has_t && has_h ? ht_clamp_unit(ht_vec3_dot(T, H)) : -1.0;
            d[2] = 0.0;
        } else {
            /* the model shifts the normalized T along the normalized N; a
               zero T stays without direction after the shift (model.c) */
            d[0] = ht_clamp_unit(ht_vec3_dot(N, L));
            d[1] = shifted_dot(T, N, p->shift[0], H, has_t && has_h);
            d[2] = shifted_dot(T, N, p->shift[1], H, has_t && has_h);
        }
        for (int i = 0; i < 3; i++) lut_coords[3 * vi + i] = ht_combiner_lut_coord(d[i], p->lut_size[i]);
    }
    return ht_fixed_coords_colors(p, vertices, count, lights, light_count, colors, err, err_size);
}

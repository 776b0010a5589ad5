/* fixed4_program.c — see fixed4_program.h. */
#include "fixed4_program.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "combiner.h"
#include "errfmt.h"
#include "json_check.h"
#include "program_json.h"
#include "shading_check.h"
#include "vecmath.h"

static bool kajiya_kay(const ht_fixed4_program *p) { return p->shading.model == HT_MODEL_KAJIYA_KAY; }

int ht_fixed4_lut_count(const ht_fixed4_program *p) { return kajiya_kay(p) ? p->lights : 2; }

int ht_fixed4_units(const ht_fixed4_program *p) { return ht_fixed4_lut_count(p) + 2; }

void ht_fixed4_lut_size(const ht_fixed4_program *p, int k, int *width, int *height) {
    if (kajiya_kay(p)) {
        *width = p->lut_axis[0];
        *height = p->lut_axis[1];
    } else {
        *width = p->lut_axis[k];
        *height = p->lights == 2 ? p->lut_axis[k] : 1;
    }
}

static bool axis_ok(int n) { return n >= 2 && n <= HT_FIXED4_MAX_AXIS && (n & (n - 1)) == 0; }

ht_result ht_fixed4_validate(const ht_fixed4_program *p, char *err, size_t err_size) {
    if (!p) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "fixed4: no program");
    const ht_shading *s = &p->shading;
    if (s->model != HT_MODEL_SCHEUERMANN && s->model != HT_MODEL_KAJIYA_KAY)
        return ht_fail(err, err_size, HT_ERR_PARSE, "model: unknown");
    if (p->lights < 1 || p->lights > HT_FIXED4_MAX_LIGHTS)
        return ht_fail(err, err_size, HT_ERR_PARSE, "lights: %d outside [1, %d]", p->lights, HT_FIXED4_MAX_LIGHTS);
    char why[256];
    if (!ht_shading_check(s, "fixed4.json", why, sizeof why)) return ht_fail(err, err_size, HT_ERR_PARSE, "%s", why);
    for (int i = 0; i < 2; i++)
        if (!axis_ok(p->lut_axis[i]))
            return ht_fail(err, err_size, HT_ERR_PARSE, "lut_axis[%d]: %d is not a power of two in [2, %d]", i,
                           p->lut_axis[i], HT_FIXED4_MAX_AXIS);
    return HT_OK;
}

/* ---- JSON ---- */

ht_result ht_fixed4_write(const ht_fixed4_program *p, char **text, char *err, size_t err_size) {
    *text = NULL;
    ht_result r = ht_fixed4_validate(p, err, err_size);
    if (r != HT_OK) return r;
    cJSON *root = cJSON_CreateObject();
    if (!root) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "fixed4.json: out of memory");
    cJSON_AddStringToObject(root, "format", HT_FIXED4_FORMAT);
    cJSON_AddStringToObject(root, "model", kajiya_kay(p) ? "kajiya-kay" : "scheuermann");
    cJSON_AddNumberToObject(root, "lights", p->lights);
    cJSON_AddBoolToObject(root, "ao", p->ao);
    cJSON_AddStringToObject(root, "viewer", p->viewer == HT_FIXED4_VIEWER_LOCAL ? "local" : "infinite");
    ht_program_json_add_shading(root, &p->shading);
    cJSON *axes = cJSON_AddArrayToObject(root, "lut_axis");
    for (int i = 0; i < 2; i++) cJSON_AddItemToArray(axes, cJSON_CreateNumber(p->lut_axis[i]));
    return ht_program_json_print(root, "fixed4.json", text, err, err_size);
}

static ht_result parse_program(const ht_jctx *c, const cJSON *root, ht_fixed4_program *p) {
    static const char *const keys[] = { "format", "model", "lights", "ao", "viewer", "diffuse", "primary",
                                        "secondary", "lut_axis", NULL };
    static const char *const viewers[] = { "infinite", "local", NULL };
    ht_result r = ht_json_keys(c, root, "", keys);
    if (r == HT_OK) r = ht_json_format(c, root, HT_FIXED4_FORMAT, "a fixed4 tier program");
    if (r == HT_OK) r = ht_program_json_parse_model(c, root, &p->shading.model);
    int64_t lights = 0;
    if (r == HT_OK) r = ht_json_int(c, root, "", "lights", NULL, 1, HT_FIXED4_MAX_LIGHTS, &lights);
    p->lights = (int)lights;
    if (r == HT_OK) r = ht_json_bool(c, root, "", "ao", NULL, &p->ao);
    int viewer = 0;
    if (r == HT_OK) r = ht_json_enum(c, root, "", "viewer", -1, viewers, &viewer);
    p->viewer = viewer == 1 ? HT_FIXED4_VIEWER_LOCAL : HT_FIXED4_VIEWER_INFINITE;
    if (r == HT_OK) r = ht_program_json_parse_shading(c, root, &p->shading);
    double axes[2] = { 0, 0 };
    if (r == HT_OK) r = ht_json_vec(c, root, "", "lut_axis", NULL, 2, HT_JRANGE(2, HT_FIXED4_MAX_AXIS), axes);
    for (int i = 0; r == HT_OK && i < 2; i++) {
        p->lut_axis[i] = (int)axes[i];
        if ((double)p->lut_axis[i] != axes[i] || !axis_ok(p->lut_axis[i])) {
            char field[32];
            snprintf(field, sizeof field, "lut_axis[%d]", i);
            r = ht_json_fail(c, field, "%g is not a power of two in [2, %d]", axes[i], HT_FIXED4_MAX_AXIS);
        }
    }
    return r;
}

ht_result ht_fixed4_parse(const char *json_text, const char *file_name, ht_fixed4_program *out, char *err,
                          size_t err_size) {
    ht_jctx c = { file_name, err, err_size };
    cJSON *root = NULL;
    ht_result r = ht_json_parse_entry(&c, json_text, out, &root);
    if (r != HT_OK) return r;
    ht_fixed4_program p;
    memset(&p, 0, sizeof p);
    r = parse_program(&c, root, &p);
    cJSON_Delete(root);
    if (r == HT_OK) *out = p;
    return r;
}

/* ---- what the device is fed ---- */

int ht_fixed4_scale(const ht_fixed4_program *p, const float light_colors[][3]) {
    return ht_fixed4_scale_lights(p, light_colors, p->lights);
}

int ht_fixed4_scale_lights(const ht_fixed4_program *p, const float light_colors[][3], int light_count) {
    const ht_shading *s = &p->shading;
    double worst = 0.0;
    for (int ch = 0; ch < 3; ch++) {
        double sum_lc = 0.0;
        for (int l = 0; l < light_count; l++) sum_lc += light_colors ? fmax(0.0, (double)light_colors[l][ch]) : 0.0;
        double terms = s->diffuse_color[ch] + s->primary.color[ch] +
                       (kajiya_kay(p) ? 0.0 : s->secondary.color[ch]);
        double v = sum_lc * terms;
        if (v > worst) worst = v;
    }
    return worst <= 1.0 ? 1 : (worst <= 2.0 ? 2 : 4);
}

void ht_fixed4_back_slopes(const ht_fixed4_program *p, const float light_colors[][3],
                           double back[HT_FIXED4_MAX_LIGHTS]) {
    const double w = p->shading.wrap;
    const double chord = fmin(w, 1.0 - w);
    int brightest = 0;
    double best = -1.0;
    for (int l = 0; l < p->lights && l < HT_FIXED4_MAX_LIGHTS; l++) {
        double sum = 0.0;
        for (int ch = 0; ch < 3; ch++)
            sum += p->shading.diffuse_color[ch] * (light_colors ? fmax(0.0, (double)light_colors[l][ch]) : 0.0);
        if (sum > best) {
            best = sum;
            brightest = l;
        }
    }
    /* with wrap 0 or at least 1/2 the chord is the model's own diffuse */
    const bool chord_exact = w <= 0.0 || w >= 0.5;
    for (int l = 0; l < HT_FIXED4_MAX_LIGHTS; l++)
        back[l] = !chord_exact && l < p->lights && l == brightest ? 1.0 - w : chord;
}

static uint8_t texel(double v) {
    if (!(v > 0.0)) return 0;
    if (v >= 1.0) return 255;
    return (uint8_t)lround(v * 255.0);
}

ht_result ht_fixed4_bake_lut(const ht_fixed4_program *p, int k, const float light_colors[][3], int scale,
                             ht_image *out) {
    int w = 0, h = 0;
    ht_fixed4_lut_size(p, k, &w, &h);
    ht_result r = ht_image_alloc(out, w, h, 3);
    if (r != HT_OK) return r;
    const ht_shading *s = &p->shading;
    double lc[HT_FIXED4_MAX_LIGHTS][3] = { { 0 } };
    for (int l = 0; l < p->lights; l++)
        for (int ch = 0; ch < 3; ch++) lc[l][ch] = light_colors ? fmax(0.0, (double)light_colors[l][ch]) : 0.0;
    /* Separable: one factor per texel column and row (ht_model_dot_factor_d). */
    double *fx = malloc(sizeof *fx * (size_t)w), *fy = malloc(sizeof *fy * (size_t)h);
    if (!fx || !fy) {
        free(fx);
        free(fy);
        ht_image_free(out);
        return HT_ERR_OUT_OF_MEMORY;
    }
    const double inv = 1.0 / (double)scale;
    if (kajiya_kay(p)) {
        /* LUT k = light k: x = T.L (diffuse sin), y = T.H (highlight). */
        for (int x = 0; x < w; x++) fx[x] = ht_model_dot_factor_d(s, 0, ht_combiner_lut_centre(x, w));
        for (int y = 0; y < h; y++) fy[y] = ht_model_dot_factor_d(s, 1, ht_combiner_lut_centre(y, h));
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                for (int ch = 0; ch < 3; ch++) {
                    double v = lc[k][ch] * (s->diffuse_color[ch] * fx[x] + s->primary.color[ch] * fy[y]);
                    out->pixels[((size_t)y * (size_t)w + (size_t)x) * 3 + (size_t)ch] = texel(v * inv);
                }
    } else {
        /* LUT k = lobe k: x = t_k.H0, y = t_k.H1. */
        const double *color = k == 0 ? s->primary.color : s->secondary.color;
        for (int x = 0; x < w; x++) fx[x] = ht_model_dot_factor_d(s, 1 + k, ht_combiner_lut_centre(x, w));
        for (int y = 0; y < h; y++) fy[y] = h > 1 ? ht_model_dot_factor_d(s, 1 + k, ht_combiner_lut_centre(y, h)) : 0.0;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                for (int ch = 0; ch < 3; ch++) {
                    double v = color[ch] * (lc[0][ch] * fx[x] + lc[1][ch] * fy[y]);
                    out->pixels[((size_t)y * (size_t)w + (size_t)x) * 3 + (size_t)ch] = texel(v * inv);
                }
    }
    free(fx);
    free(fy);
    return HT_OK;
}

/* Row r of m (column-major) = (a, b, c, d): coordinate = a x + b y + c z + d. */
static void set_row(float m[16], int row, const double v[3], double offset) {
    for (int i = 0; i < 3; i++) m[i * 4 + row] = v ? (float)v[i] : 0.0f;
    m[12 + row] = (float)offset;
}

/* The row whose coordinate is the LUT coordinate of dir . vector on an axis
   of n texels: coord(d) = d (n-1)/(2n) + 1/2 (combiner.h), affine in d. A
   missing direction gives the constant coordinate of `fallback_d`. */
static void lut_row(float m[16], int row, const double dir[3], bool has_dir, int n, double fallback_d) {
    if (n <= 1) {
        set_row(m, row, NULL, 0.5);
        return;
    }
    if (!has_dir) {
        set_row(m, row, NULL, ht_combiner_lut_coord(fallback_d, n));
        return;
    }
    const double k = (double)(n - 1) / (2.0 * (double)n);
    const double scaled[3] = { dir[0] * k, dir[1] * k, dir[2] * k };
    set_row(m, row, scaled, 0.5);
}

static bool direction(const float v[3], double out[3]) {
    for (int i = 0; i < 3; i++) out[i] = v ? (double)v[i] : 0.0;
    return ht_vec3_direction(out, out);
}

void ht_fixed4_texture_matrix(const ht_fixed4_program *p, int k, const float light_dirs[][3],
                              const float view_dir[3], float m[16]) {
    memset(m, 0, 16 * sizeof *m);
    m[15] = 1.0f;
    double V[3], L[HT_FIXED4_MAX_LIGHTS][3], H[HT_FIXED4_MAX_LIGHTS][3];
    bool has_v = direction(view_dir, V);
    bool has_l[HT_FIXED4_MAX_LIGHTS] = { false }, has_h[HT_FIXED4_MAX_LIGHTS] = { false };
    for (int l = 0; l < p->lights; l++) {
        has_l[l] = direction(light_dirs ? light_dirs[l] : NULL, L[l]);
        double sum[3];
        for (int i = 0; i < 3; i++) sum[i] = (has_l[l] ? L[l][i] : 0.0) + (has_v ? V[i] : 0.0);
        H[l][0] = sum[0];
        H[l][1] = sum[1];
        H[l][2] = sum[2];
        has_h[l] = ht_vec3_direction(H[l], H[l]);
    }
    int w = 0, h = 0;
    ht_fixed4_lut_size(p, k, &w, &h);
    if (kajiya_kay(p)) {
        /* no L: sin(T, L) read at d = 1 (0, the CPU rule's answer); no H: S = 0 at d = -1 */
        lut_row(m, 0, L[k], has_l[k], w, 1.0);
        lut_row(m, 1, H[k], has_h[k], h, -1.0);
    } else {
        lut_row(m, 0, H[0], has_h[0], w, -1.0);
        lut_row(m, 1, p->lights > 1 ? H[1] : NULL, p->lights > 1 && has_h[1], h, -1.0);
    }
    set_row(m, 2, NULL, 0.5);
}

void ht_fixed4_vertex_arrays(const ht_fixed4_program *p, const ht_vertex *v, size_t count, float *vec0,
                             float *vec1, float *colors) {
    const bool kk = kajiya_kay(p);
    for (size_t i = 0; i < count; i++) {
        double T[3] = { v[i].tangent[0], v[i].tangent[1], v[i].tangent[2] };
        double N[3] = { v[i].normal[0], v[i].normal[1], v[i].normal[2] };
        bool has_t = ht_vec3_direction(T, T);
        if (!ht_vec3_direction(N, N)) N[0] = N[1] = N[2] = 0.0;
        double t[2][3];
        const double shift[2] = { p->shading.primary.shift, p->shading.secondary.shift };
        for (int k = 0; k < 2; k++) ht_vec3_shifted_tangent(t[k], T, has_t, N, kk ? 0.0 : shift[k]);
        for (int j = 0; j < 3; j++) {
            if (vec0) vec0[3 * i + (size_t)j] = (float)t[0][j];
            if (vec1) vec1[3 * i + (size_t)j] = (float)t[1][j];
        }
        double ao = p->ao ? fmin(1.0, fmax(0.0, (double)v[i].ao)) : 1.0;
        if (!isfinite(ao)) ao = 0.0;
        const float rgb = kk ? 0.0f : 1.0f;
        colors[4 * i + 0] = rgb;
        colors[4 * i + 1] = rgb;
        colors[4 * i + 2] = rgb;
        colors[4 * i + 3] = has_t ? (float)ao : 0.0f;
    }
}

/* ---- the local-viewer rule ---- */

void ht_fixed4_soa_free(ht_fixed4_soa *soa) {
    free(soa->px);
    free(soa->py);
    free(soa->pz);
    for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++)
        for (int j = 0; j < 3; j++) free(soa->v[k][j]);
    memset(soa, 0, sizeof *soa);
}

ht_result ht_fixed4_soa_from_arrays(const ht_vertex *v, size_t count, const float *vec0, const float *vec1,
                                    ht_fixed4_soa *out) {
    memset(out, 0, sizeof *out);
    size_t bytes = (count ? count : 1) * sizeof(float);
    bool ok = (out->px = malloc(bytes)) && (out->py = malloc(bytes)) && (out->pz = malloc(bytes));
    for (int k = 0; ok && k < HT_FIXED4_MAX_LUTS; k++)
        for (int j = 0; ok && j < 3; j++) ok = (out->v[k][j] = malloc(bytes)) != NULL;
    if (!ok) {
        ht_fixed4_soa_free(out);
        return HT_ERR_OUT_OF_MEMORY;
    }
    const float *vec[HT_FIXED4_MAX_LUTS] = { vec0, vec1 ? vec1 : vec0 };
    for (size_t i = 0; i < count; i++) {
        out->px[i] = v[i].position[0];
        out->py[i] = v[i].position[1];
        out->pz[i] = v[i].position[2];
        for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++)
            for (int j = 0; j < 3; j++) out->v[k][j][i] = vec[k][3 * i + (size_t)j];
    }
    out->count = count;
    return HT_OK;
}

ht_result ht_fixed4_soa_make(const ht_fixed4_program *p, const ht_vertex *v, size_t count, ht_fixed4_soa *out) {
    memset(out, 0, sizeof *out);
    size_t bytes = (count ? count : 1) * sizeof(float);
    float *vec[HT_FIXED4_MAX_LUTS] = { malloc(3 * bytes), malloc(3 * bytes) };
    float *colors = malloc(4 * bytes);
    ht_result r = HT_ERR_OUT_OF_MEMORY;
    if (vec[0] && vec[1] && colors) {
        const bool kk = kajiya_kay(p);
        ht_fixed4_vertex_arrays(p, v, count, vec[0], kk ? NULL : vec[1], colors);
        r = ht_fixed4_soa_from_arrays(v, count, vec[0], kk ? NULL : vec[1], out);
    }
    free(vec[0]);
    free(vec[1]);
    free(colors);
    return r;
}

/* One LUT axis: the coordinate of d = dot(vec, H) with H = normalize(L + V),
   V = normalize(eye - p), per vertex. Written as plain loops over float
   arrays with no branches but selects, so GCC's -O2 vectoriser takes them. */
static void axis_coords(const ht_fixed4_soa *soa, const float *const vec[3], const float L[3],
                        const float eye[3], int n, double fallback_d, float *out, int stride) {
    const float k = n > 1 ? (float)(n - 1) / (2.0f * (float)n) : 0.0f;
    const float fallback = ht_combiner_lut_coord(fallback_d, n);
    const size_t count = soa->count;
    for (size_t i = 0; i < count; i++) {
        float vx = eye[0] - soa->px[i], vy = eye[1] - soa->py[i], vz = eye[2] - soa->pz[i];
        float v2 = vx * vx + vy * vy + vz * vz;
        float iv = v2 > 1e-12f ? 1.0f / sqrtf(v2) : 0.0f;
        /* L is unit or zero (no light): H = normalize(L + V) as model.c */
        float hx = vx * iv + L[0], hy = vy * iv + L[1], hz = vz * iv + L[2];
        float h2 = hx * hx + hy * hy + hz * hz;
        bool has_h = h2 > 1e-12f;
        float ih = has_h ? 1.0f / sqrtf(h2) : 0.0f;
        float d = (vec[0][i] * hx + vec[1][i] * hy + vec[2][i] * hz) * ih;
        d = d > 1.0f ? 1.0f : (d < -1.0f ? -1.0f : d);
        out[i * (size_t)stride] = has_h && n > 1 ? d * k + 0.5f : fallback;
    }
}

/* T.L for Kajiya-Kay's diffuse axis: no viewer in it. */
static void light_axis_coords(const ht_fixed4_soa *soa, const float *const vec[3], const float L[3], bool has_l,
                              int n, float *out, int stride) {
    const float k = n > 1 ? (float)(n - 1) / (2.0f * (float)n) : 0.0f;
    const float fallback = ht_combiner_lut_coord(1.0, n);
    for (size_t i = 0; i < soa->count; i++) {
        float d = vec[0][i] * L[0] + vec[1][i] * L[1] + vec[2][i] * L[2];
        d = d > 1.0f ? 1.0f : (d < -1.0f ? -1.0f : d);
        out[i * (size_t)stride] = has_l && n > 1 ? d * k + 0.5f : fallback;
    }
}

void ht_fixed4_local_coords(const ht_fixed4_program *p, const ht_fixed4_soa *soa, const float light_dirs[][3],
                            const float eye[3], float *coords[HT_FIXED4_MAX_LUTS]) {
    float L[HT_FIXED4_MAX_LIGHTS][3] = { { 0 } };
    bool has_l[HT_FIXED4_MAX_LIGHTS] = { false };
    for (int l = 0; l < p->lights; l++) {
        double d[3];
        has_l[l] = direction(light_dirs ? light_dirs[l] : NULL, d);
        for (int j = 0; j < 3; j++) L[l][j] = (float)d[j];
    }
    for (int k = 0; k < ht_fixed4_lut_count(p); k++) {
        int w = 0, h = 0;
        ht_fixed4_lut_size(p, k, &w, &h);
        const float *const *vec = (const float *const *)soa->v[k];
        if (kajiya_kay(p)) {
            light_axis_coords(soa, vec, L[k], has_l[k], w, coords[k], 2);
            axis_coords(soa, vec, L[k], eye, h, -1.0, coords[k] + 1, 2);
        } else {
            axis_coords(soa, vec, L[0], eye, w, -1.0, coords[k], 2);
            if (p->lights > 1) axis_coords(soa, vec, L[1], eye, h, -1.0, coords[k] + 1, 2);
            else
                for (size_t i = 0; i < soa->count; i++) coords[k][2 * i + 1] = 0.5f;
        }
    }
}

ht_fixed4_soa ht_fixed4_soa_range(const ht_fixed4_soa *soa, size_t first, size_t count) {
    ht_fixed4_soa v = *soa;
    float **pos[] = { &v.px, &v.py, &v.pz };
    for (int j = 0; j < 3; j++)
        if (*pos[j]) *pos[j] += first;
    for (int k = 0; k < HT_FIXED4_MAX_LUTS; k++)
        for (int j = 0; j < 3; j++)
            if (v.v[k][j]) v.v[k][j] += first;
    v.count = count;
    return v;
}

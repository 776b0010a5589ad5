/* gl11_program.c — see gl11_program.h.

   The shading loops are written for GCC's -O2 vectoriser (the "very cheap"
   cost model of GCC 12, which takes a loop only when no scalar epilogue is
   needed): whole blocks of HT_GL11_BLOCK vertices over padded float arrays,
   no branches but selects, no libm call but sqrtf, and pow made of exp2 and
   log2 polynomials (pow01 below). The Makefile compiles this file with
   -fno-math-errno -fno-trapping-math (sqrtf inline, selects if-converted);
   neither changes a result. */
#include "gl11_program.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>

#include "errfmt.h"
#include "json_check.h"
#include "program_json.h"
#include "shading_check.h"
#include "vecmath.h"

static bool kajiya_kay(const ht_gl11_program *p) { return p->shading.model == HT_MODEL_KAJIYA_KAY; }

ht_result ht_gl11_validate(const ht_gl11_program *p, char *err, size_t err_size) {
    if (!p) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "gl11: no program");
    const ht_shading *s = &p->shading;
    if (s->model != HT_MODEL_SCHEUERMANN && s->model != HT_MODEL_KAJIYA_KAY)
        return ht_fail(err, err_size, HT_ERR_PARSE, "model: unknown");
    if (p->lights < 0 || p->lights > HT_MAX_LIGHTS)
        return ht_fail(err, err_size, HT_ERR_PARSE, "lights: %d outside [0, %d]", p->lights, HT_MAX_LIGHTS);
    if (!(p->albedo_scale >= 1.0 && p->albedo_scale <= HT_GL11_MAX_SCALE))
        return ht_fail(err, err_size, HT_ERR_PARSE, "albedo_scale: outside [1, %g]", HT_GL11_MAX_SCALE);
    char why[256];
    if (!ht_shading_check(s, "gl11.json", why, sizeof why)) return ht_fail(err, err_size, HT_ERR_PARSE, "%s", why);
    return HT_OK;
}

double ht_gl11_albedo_scale(double max_rgb) {
    if (!(max_rgb > 1.0 / HT_GL11_MAX_SCALE)) return HT_GL11_MAX_SCALE;
    double s = 1.0 / max_rgb;
    return s < 1.0 ? 1.0 : s;
}

/* ---- JSON ---- */

ht_result ht_gl11_write(const ht_gl11_program *p, char **text, char *err, size_t err_size) {
    *text = NULL;
    ht_result r = ht_gl11_validate(p, err, err_size);
    if (r != HT_OK) return r;
    cJSON *root = cJSON_CreateObject();
    if (!root) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "gl11.json: out of memory");
    cJSON_AddStringToObject(root, "format", HT_GL11_FORMAT);
    cJSON_AddStringToObject(root, "model", kajiya_kay(p) ? "kajiya-kay" : "scheuermann");
    cJSON_AddNumberToObject(root, "lights", p->lights);
    cJSON_AddBoolToObject(root, "ao", p->ao);
    cJSON_AddNumberToObject(root, "albedo_scale", p->albedo_scale);
    ht_program_json_add_shading(root, &p->shading);
    if (ht_model_has_transmission(&p->shading)) { /* absent otherwise: the text stays byte for byte */
        const ht_transmission *t = &p->shading.transmission;
        cJSON *o = cJSON_AddObjectToObject(root, "transmission");
        cJSON_AddItemToObject(o, "color", cJSON_CreateDoubleArray(t->color, 3));
        cJSON_AddNumberToObject(o, "centre", t->centre);
        cJSON_AddNumberToObject(o, "sharpness", t->sharpness);
        cJSON_AddNumberToObject(o, "azimuth", t->azimuth);
    }
    return ht_program_json_print(root, "gl11.json", text, err, err_size);
}

static ht_result parse_program(const ht_jctx *c, const cJSON *root, ht_gl11_program *p) {
    static const char *const keys[] = { "format", "model", "lights", "ao", "albedo_scale", "diffuse", "primary",
                                        "secondary", "transmission", NULL };
    ht_result r = ht_json_keys(c, root, "", keys);
    if (r == HT_OK) r = ht_json_format(c, root, HT_GL11_FORMAT, "a gl11 tier program");
    if (r == HT_OK) r = ht_program_json_parse_model(c, root, &p->shading.model);
    int64_t lights = 0;
    if (r == HT_OK) r = ht_json_int(c, root, "", "lights", NULL, 0, HT_MAX_LIGHTS, &lights);
    p->lights = (int)lights;
    if (r == HT_OK) r = ht_json_bool(c, root, "", "ao", NULL, &p->ao);
    if (r == HT_OK)
        r = ht_json_number(c, root, "", "albedo_scale", NULL, HT_JRANGE(1, HT_GL11_MAX_SCALE), &p->albedo_scale);
    if (r == HT_OK) r = ht_program_json_parse_shading(c, root, &p->shading);
    const cJSON *t = NULL;
    if (r == HT_OK) r = ht_json_object(c, root, "", "transmission", false, &t);
    if (r == HT_OK && t) { /* ranges: the one shading check, ht_gl11_validate */
        static const char *const tkeys[] = { "color", "centre", "sharpness", "azimuth", NULL };
        const ht_jrange any = HT_JRANGE(-HUGE_VAL, HUGE_VAL);
        ht_transmission *o = &p->shading.transmission;
        r = ht_json_keys(c, t, "transmission", tkeys);
        if (r == HT_OK) r = ht_json_vec(c, t, "transmission", "color", NULL, 3, any, o->color);
        if (r == HT_OK) r = ht_json_number(c, t, "transmission", "centre", NULL, any, &o->centre);
        if (r == HT_OK) r = ht_json_number(c, t, "transmission", "sharpness", NULL, any, &o->sharpness);
        if (r == HT_OK) r = ht_json_number(c, t, "transmission", "azimuth", NULL, any, &o->azimuth);
        if (r == HT_OK && !ht_shading_check(&p->shading, c->file ? c->file : "<input>", c->err, c->err_size))
            r = HT_ERR_PARSE;
    }
    return r;
}

ht_result ht_gl11_parse(const char *json_text, const char *file_name, ht_gl11_program *out, char *err,
                        size_t err_size) {
    ht_jctx c = { file_name, err, err_size };
    cJSON *root = NULL;
    ht_result r = ht_json_parse_entry(&c, json_text, out, &root);
    if (r != HT_OK) return r;
    ht_gl11_program p;
    memset(&p, 0, sizeof p);
    r = parse_program(&c, root, &p);
    cJSON_Delete(root);
    if (r == HT_OK) *out = p;
    return r;
}

/* ---- the per-mesh arrays ---- */

void ht_gl11_soa_free(ht_gl11_soa *soa) {
    free(soa->a[0]);
    memset(soa, 0, sizeof *soa);
}

ht_result ht_gl11_soa_make(const ht_gl11_program *p, const ht_vertex *v, size_t count, ht_gl11_soa *out) {
    memset(out, 0, sizeof *out);
    size_t padded = (count + HT_GL11_BLOCK - 1) / HT_GL11_BLOCK * HT_GL11_BLOCK;
    if (padded == 0) padded = HT_GL11_BLOCK;
    if (padded > SIZE_MAX / sizeof(float) / HT_GL11_ARRAYS) return HT_ERR_OUT_OF_MEMORY;
    float *all = calloc(padded * HT_GL11_ARRAYS, sizeof(float));
    if (!all) return HT_ERR_OUT_OF_MEMORY;
    for (int k = 0; k < HT_GL11_ARRAYS; k++) out->a[k] = all + (size_t)k * padded;
    out->count = count;
    out->padded = padded;
    const bool kk = kajiya_kay(p);
    const double shift[2] = { p->shading.primary.shift, p->shading.secondary.shift };
    for (size_t i = 0; i < count; i++) {
        double T[3] = { v[i].tangent[0], v[i].tangent[1], v[i].tangent[2] };
        double N[3] = { v[i].normal[0], v[i].normal[1], v[i].normal[2] };
        bool has_t = ht_vec3_direction(T, T);
        if (!ht_vec3_direction(N, N)) N[0] = N[1] = N[2] = 0.0;
        for (int k = 0; k < 2; k++) {
            double t[3];
            ht_vec3_shifted_tangent(t, T, has_t, N, kk ? 0.0 : shift[k]);
            for (int j = 0; j < 3; j++) out->a[(k ? HT_GL11_T2X : HT_GL11_T1X) + j][i] = (float)t[j];
        }
        for (int j = 0; j < 3; j++) {
            out->a[HT_GL11_PX + j][i] = v[i].position[j];
            out->a[HT_GL11_NX + j][i] = (float)N[j];
            out->a[HT_GL11_TX + j][i] = has_t ? (float)T[j] : 0.0f;
        }
        float ao = p->ao ? v[i].ao : 1.0f;
        out->a[HT_GL11_AO][i] = isfinite(ao) ? fminf(1.0f, fmaxf(0.0f, ao)) : 0.0f;
    }
    return HT_OK;
}

/* ---- the shading, vectorisable ---- */

/* log2 of a positive normal float: exponent + 2 atanh((m-1)/(m+1)) / ln 2
   with m in [sqrt(1/2), sqrt(2)); the odd series to z^9 is within 4e-10
   of ln m there, below float rounding. */
/* Bit casts through a union (C11 6.5.2.3): GCC vectorises these, not memcpy. */
static inline float float_of_bits(uint32_t b) {
    union { uint32_t u; float f; } x = { .u = b };
    return x.f;
}

static inline uint32_t bits_of_float(float f) {
    union { uint32_t u; float f; } x = { .f = f };
    return x.u;
}

static inline float log2_positive(float x) {
    const uint32_t bits = bits_of_float(x);
    int32_t e = (int32_t)(bits >> 23) - 127;
    float m = float_of_bits((bits & 0x007fffffu) | 0x3f800000u);
    const bool big = m > 1.41421356f;
    m = big ? m * 0.5f : m;
    e = big ? e + 1 : e;
    const float z = (m - 1.0f) / (m + 1.0f), z2 = z * z;
    const float ln_m = z * (2.0f + z2 * (2.0f / 3.0f + z2 * (2.0f / 5.0f + z2 * (2.0f / 7.0f + z2 * (2.0f / 9.0f)))));
    return (float)e + ln_m * 1.44269504f;
}

/* 2^y for y <= 0: 2^k (built in the exponent bits) x 2^f, f = y - k in
   (-1/2, 1/2], 2^f by its Taylor series to degree 7 (within 3e-9). Below
   2^-126 the answer is 0. */
static inline float exp2_nonpositive(float y) {
    y = y < -127.0f ? -127.0f : y;
    const int32_t k = (int32_t)(y - 0.5f); /* towards zero: the nearest integer for y <= 0 */
    const float f = (y - (float)k) * 0.69314718f;
    const float ef = 1.0f + f * (1.0f + f * (1.0f / 2 + f * (1.0f / 6 + f * (1.0f / 24 + f * (1.0f / 120 +
                                 f * (1.0f / 720 + f * (1.0f / 5040)))))));
    const float scale = float_of_bits((uint32_t)(k + 127 > 0 ? k + 127 : 0) << 23);
    return k < -126 ? 0.0f : ef * scale;
}

/* x^e for x in [0, 1] and e >= 0, model.c's answers: x^0 = 1 (exactly:
   2^(0 x log2 x)), 0^e = zero_power, which the caller sets to 1 for e = 0
   and 0 otherwise (a loop-invariant condition in the select would keep
   GCC from vectorising). */
static inline float pow01(float x, float e, float zero_power) {
    const float xs = x < FLT_MIN ? FLT_MIN : x;
    const float r = exp2_nonpositive(e * log2_positive(xs));
    return x > 0.0f ? r : zero_power;
}

static inline float clamp1(float x) { return x > 1.0f ? 1.0f : (x < -1.0f ? -1.0f : x); }

/* One light's constants, passed by value (no pointer the loop could alias). */
typedef struct light_consts {
    float L[3];       /* directional: the unit vector; point: the position */
    float point;      /* 1 for a point light: L = L - position per vertex */
    float wrap;
    float kd[3];      /* diffuse colour x light colour */
} light_consts;

#if defined(__GNUC__)
#define ALWAYS_INLINE inline __attribute__((always_inline))
#else
#define ALWAYS_INLINE inline
#endif

/* Per vertex for one light: L, H = normalize(L + V) into h (zero when it
   has no direction) and the diffuse term added to the sums, over n (a
   multiple of HT_GL11_BLOCK) vertices. kk is a constant in each caller, so
   each loop is branch-free; the arrays are restrict parameters, as GCC's
   very cheap model does not version a loop for aliasing. The highlights
   are separate loops (lobe_loop): GCC 12 vectorises neither half of one
   loop holding both. */
static ALWAYS_INLINE void light_loop(size_t n, const float *restrict px, const float *restrict py,
                                     const float *restrict pz, const float *restrict nx, const float *restrict ny,
                                     const float *restrict nz, const float *restrict tx, const float *restrict ty,
                                     const float *restrict tz, const float *restrict vx, const float *restrict vy,
                                     const float *restrict vz, float *restrict hx, float *restrict hy,
                                     float *restrict hz, float *restrict sr, float *restrict sg, float *restrict sb,
                                     const light_consts c, const bool kk) {
    n &= ~(size_t)(HT_GL11_BLOCK - 1);
    const float min2 = (float)HT_MODEL_MIN_LENGTH2;
    for (size_t i = 0; i < n; i++) {
        float lx = c.L[0] - c.point * px[i], ly = c.L[1] - c.point * py[i], lz = c.L[2] - c.point * pz[i];
        const float l2 = lx * lx + ly * ly + lz * lz;
        const float il = l2 > min2 ? 1.0f / sqrtf(l2 > min2 ? l2 : 1.0f) : 0.0f;
        lx *= il;
        ly *= il;
        lz *= il;
        const float x = lx + vx[i], y = ly + vy[i], z = lz + vz[i];
        const float h2 = x * x + y * y + z * z;
        const float ih = h2 > min2 ? 1.0f / sqrtf(h2 > min2 ? h2 : 1.0f) : 0.0f;
        hx[i] = x * ih;
        hy[i] = y * ih;
        hz[i] = z * ih;
        float diff;
        if (kk) {
            /* sin(T, L) = |T x L|: 0 when either has no direction */
            const float ax = tx[i], ay = ty[i], az = tz[i];
            const float cx = ay * lz - az * ly, cy = az * lx - ax * lz, cz = ax * ly - ay * lx;
            const float s = sqrtf(cx * cx + cy * cy + cz * cz);
            diff = s > 1.0f ? 1.0f : s;
        } else {
            const float nl = nx[i] * lx + ny[i] * ly + nz[i] * lz;
            diff = c.wrap + (1.0f - c.wrap) * nl;
            diff = diff < 0.0f ? 0.0f : (diff > 1.0f ? 1.0f : diff);
        }
        sr[i] += diff * c.kd[0];
        sg[i] += diff * c.kd[1];
        sb[i] += diff * c.kd[2];
    }
}

static void light_loop_scheuermann(ht_gl11_soa *soa, const light_consts c) {
    float *const *a = soa->a;
    light_loop(soa->padded, a[HT_GL11_PX], a[HT_GL11_PY], a[HT_GL11_PZ], a[HT_GL11_NX], a[HT_GL11_NY],
               a[HT_GL11_NZ], a[HT_GL11_T1X], a[HT_GL11_T1Y], a[HT_GL11_T1Z], a[HT_GL11_VX], a[HT_GL11_VY],
               a[HT_GL11_VZ], a[HT_GL11_HX], a[HT_GL11_HY], a[HT_GL11_HZ], a[HT_GL11_R], a[HT_GL11_G],
               a[HT_GL11_B], c, false);
}

static void light_loop_kajiya_kay(ht_gl11_soa *soa, const light_consts c) {
    float *const *a = soa->a;
    light_loop(soa->padded, a[HT_GL11_PX], a[HT_GL11_PY], a[HT_GL11_PZ], a[HT_GL11_NX], a[HT_GL11_NY],
               a[HT_GL11_NZ], a[HT_GL11_T1X], a[HT_GL11_T1Y], a[HT_GL11_T1Z], a[HT_GL11_VX], a[HT_GL11_VY],
               a[HT_GL11_VZ], a[HT_GL11_HX], a[HT_GL11_HY], a[HT_GL11_HZ], a[HT_GL11_R], a[HT_GL11_G],
               a[HT_GL11_B], c, true);
}

/* One highlight lobe added to the sums: k x smoothstep(-1, 0, t.H) x
   sin(t, H)^e, 0 where t or H has no direction (both are unit or zero;
   model.c's highlight_unit). zero_power = 0^e (1 for e = 0, else 0). */
static void lobe_loop(size_t n, const float *restrict tx, const float *restrict ty, const float *restrict tz,
                      const float *restrict hx, const float *restrict hy, const float *restrict hz,
                      float *restrict sr, float *restrict sg, float *restrict sb, float e, float zero_power,
                      float kr, float kg, float kb) {
    n &= ~(size_t)(HT_GL11_BLOCK - 1);
    for (size_t i = 0; i < n; i++) {
        const float ax = tx[i], ay = ty[i], az = tz[i], bx = hx[i], by = hy[i], bz = hz[i];
        const float c = clamp1(ax * bx + ay * by + az * bz);
        const float cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
        float s = sqrtf(cx * cx + cy * cy + cz * cz);
        s = s > 1.0f ? 1.0f : s;
        float u = c + 1.0f;
        u = u < 0.0f ? 0.0f : (u > 1.0f ? 1.0f : u);
        const bool has = (ax * ax + ay * ay + az * az > 0.5f) & (bx * bx + by * by + bz * bz > 0.5f);
        const float v = has ? u * u * (3.0f - 2.0f * u) * pow01(s, e, zero_power) : 0.0f;
        sr[i] += v * kr;
        sg[i] += v * kg;
        sb[i] += v * kb;
    }
}

static void add_highlight(ht_gl11_soa *soa, int tx, const ht_lobe *lobe, const float light_color[3]) {
    float *const *a = soa->a;
    const float e = (float)lobe->exponent;
    float k[3];
    for (int ch = 0; ch < 3; ch++) k[ch] = (float)lobe->color[ch] * light_color[ch];
    if (k[0] == 0.0f && k[1] == 0.0f && k[2] == 0.0f) return; /* adds nothing */
    lobe_loop(soa->padded, a[tx], a[tx + 1], a[tx + 2], a[HT_GL11_HX], a[HT_GL11_HY], a[HT_GL11_HZ],
              a[HT_GL11_R], a[HT_GL11_G], a[HT_GL11_B], e, e == 0.0f ? 1.0f : 0.0f, k[0], k[1], k[2]);
}

/* The transmission lobe (model.c's transmission_unit) added to the sums,
   per vertex in float with libm's asin, exp2 and pow: scalar, and run
   only for a material that has the lobe. */
static void add_transmission(ht_gl11_soa *soa, const ht_transmission *t, const light_consts c,
                             const float light_color[3]) {
    float *const *a = soa->a;
    const float min2 = (float)HT_MODEL_MIN_LENGTH2, centre = (float)t->centre, k = (float)t->sharpness,
                e = (float)t->azimuth;
    float kc[3];
    for (int ch = 0; ch < 3; ch++) kc[ch] = (float)t->color[ch] * light_color[ch];
    for (size_t i = 0; i < soa->count; i++) {
        const float T[3] = { a[HT_GL11_TX][i], a[HT_GL11_TY][i], a[HT_GL11_TZ][i] };
        const float V[3] = { a[HT_GL11_VX][i], a[HT_GL11_VY][i], a[HT_GL11_VZ][i] };
        float L[3] = { c.L[0] - c.point * a[HT_GL11_PX][i], c.L[1] - c.point * a[HT_GL11_PY][i],
                       c.L[2] - c.point * a[HT_GL11_PZ][i] };
        const float l2 = L[0] * L[0] + L[1] * L[1] + L[2] * L[2];
        if (!(l2 > min2) || T[0] * T[0] + T[1] * T[1] + T[2] * T[2] == 0.0f ||
            V[0] * V[0] + V[1] * V[1] + V[2] * V[2] == 0.0f)
            continue; /* no direction: no lobe */
        const float il = 1.0f / sqrtf(l2);
        float tl = 0, tv = 0;
        for (int j = 0; j < 3; j++) L[j] *= il, tl += T[j] * L[j], tv += T[j] * V[j];
        float lp[3], vp[3], lp2 = 0, vp2 = 0, d = 0;
        for (int j = 0; j < 3; j++) {
            lp[j] = L[j] - tl * T[j], vp[j] = V[j] - tv * T[j];
            lp2 += lp[j] * lp[j], vp2 += vp[j] * vp[j], d += lp[j] * vp[j];
        }
        /* along T: no azimuth, the zero vector, cos phi = 0 */
        const float cos_phi = lp2 > min2 && vp2 > min2 ? d / (sqrtf(lp2) * sqrtf(vp2)) : 0.0f;
        const float u = (asinf(clamp1(tl)) + asinf(clamp1(tv))) / 2.0f - centre;
        float az = (1.0f - cos_phi) / 2.0f;
        az = az < 0.0f ? 0.0f : (az > 1.0f ? 1.0f : az);
        const float tt = exp2f(-k * u * u) * (e == 0.0f ? 1.0f : (az > 0.0f ? powf(az, e) : 0.0f));
        a[HT_GL11_R][i] += tt * kc[0];
        a[HT_GL11_G][i] += tt * kc[1];
        a[HT_GL11_B][i] += tt * kc[2];
    }
}

/* V = normalize(eye - p) per vertex, shared by every light; sums cleared. */
static void view_loop(size_t n, const float *restrict px, const float *restrict py, const float *restrict pz,
                      float *restrict vx, float *restrict vy, float *restrict vz, float *restrict sr,
                      float *restrict sg, float *restrict sb, float ex, float ey, float ez) {
    n &= ~(size_t)(HT_GL11_BLOCK - 1);
    const float min2 = (float)HT_MODEL_MIN_LENGTH2;
    for (size_t i = 0; i < n; i++) {
        const float dx = ex - px[i], dy = ey - py[i], dz = ez - pz[i];
        const float v2 = dx * dx + dy * dy + dz * dz;
        const float iv = v2 > min2 ? 1.0f / sqrtf(v2 > min2 ? v2 : 1.0f) : 0.0f;
        vx[i] = dx * iv;
        vy[i] = dy * iv;
        vz[i] = dz * iv;
        sr[i] = 0.0f;
        sg[i] = 0.0f;
        sb[i] = 0.0f;
    }
}

/* rgba = sums x ao / albedo_scale, alpha 1. */
static void output_loop(size_t n, const float *restrict ao, const float *restrict sr, const float *restrict sg,
                        const float *restrict sb, float *restrict out, float inv) {
    n &= ~(size_t)(HT_GL11_BLOCK - 1);
    for (size_t i = 0; i < n; i++) {
        const float k = ao[i] * inv;
        out[4 * i + 0] = sr[i] * k;
        out[4 * i + 1] = sg[i] * k;
        out[4 * i + 2] = sb[i] * k;
        out[4 * i + 3] = 1.0f;
    }
}

void ht_gl11_shade(const ht_gl11_program *p, ht_gl11_soa *soa, const ht_light *lights, int light_count,
                   const float eye[3], float *rgba) {
    float *const *a = soa->a;
    view_loop(soa->padded, a[HT_GL11_PX], a[HT_GL11_PY], a[HT_GL11_PZ], a[HT_GL11_VX], a[HT_GL11_VY],
              a[HT_GL11_VZ], a[HT_GL11_R], a[HT_GL11_G], a[HT_GL11_B], eye[0], eye[1], eye[2]);
    const bool kk = kajiya_kay(p);
    const int count = light_count < p->lights ? light_count : p->lights;
    for (int l = 0; l < count && lights; l++) {
        light_consts c = { .point = lights[l].type == HT_LIGHT_POINT ? 1.0f : 0.0f,
                           .wrap = (float)p->shading.wrap };
        double L[3] = { lights[l].vector[0], lights[l].vector[1], lights[l].vector[2] };
        if (lights[l].type != HT_LIGHT_POINT && !ht_vec3_direction(L, L)) L[0] = L[1] = L[2] = 0.0;
        for (int ch = 0; ch < 3; ch++) {
            c.L[ch] = (float)L[ch];
            c.kd[ch] = (float)p->shading.diffuse_color[ch] * lights[l].color[ch];
        }
        if (kk) light_loop_kajiya_kay(soa, c);
        else light_loop_scheuermann(soa, c);
        add_highlight(soa, HT_GL11_T1X, &p->shading.primary, lights[l].color);
        if (!kk) add_highlight(soa, HT_GL11_T2X, &p->shading.secondary, lights[l].color);
        if (ht_model_has_transmission(&p->shading)) add_transmission(soa, &p->shading.transmission, c, lights[l].color);
    }
    output_loop(soa->padded, a[HT_GL11_AO], a[HT_GL11_R], a[HT_GL11_G], a[HT_GL11_B], rgba,
                (float)(1.0 / p->albedo_scale));
}

size_t ht_gl11_shade_range(const ht_gl11_program *p, ht_gl11_soa *soa, size_t first, size_t count,
                           const ht_light *lights, int light_count, const float eye[3], float *rgba) {
    if (first >= soa->count) first = count = 0;
    if (count > soa->count - first) count = soa->count - first;
    /* whole blocks: the loops run over multiples of HT_GL11_BLOCK */
    const size_t lo = first / HT_GL11_BLOCK * HT_GL11_BLOCK;
    size_t hi = (first + count + HT_GL11_BLOCK - 1) / HT_GL11_BLOCK * HT_GL11_BLOCK;
    if (hi > soa->padded) hi = soa->padded;
    if (hi <= lo) return 0;
    ht_gl11_soa view = *soa;
    for (int k = 0; k < HT_GL11_ARRAYS; k++) view.a[k] = soa->a[k] + lo;
    view.padded = hi - lo;
    view.count = (hi < soa->count ? hi : soa->count) - lo;
    ht_gl11_shade(p, &view, lights, light_count, eye, rgba + 4 * lo);
    return view.count;
}

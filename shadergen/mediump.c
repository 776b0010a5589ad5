/* mediump.c — builds the mediump shading table (mediump.h says why one
   table, and which rescalings keep every step inside fp16). The steps
   follow runtime/shading/model.c's order of operations. */
#include "mediump.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "strbuf.h"

/* ---- types ---- */

static ht_mp_type function_type(const ht_mp_program *p, int fn) { return p->functions[fn].type; }

ht_mp_type ht_mp_arg_type(const ht_mp_program *p, const ht_mp_function *f, int step, const char *arg) {
    (void)p;
    if (strncmp(arg, "vec3(", 5) == 0) return HT_MP_VEC3;
    if (arg[0] == '-' || arg[0] == '.' || (arg[0] >= '0' && arg[0] <= '9')) return HT_MP_FLOAT;
    for (int i = step - 1; i >= 0; i--)
        if (strcmp(f->steps[i].dst, arg) == 0) return ht_mp_step_type(p, f, i);
    for (int i = 0; i < f->param_count; i++)
        if (strcmp(f->params[i], arg) == 0) return f->param_types[i];
    return HT_MP_FLOAT; /* unknown names fail glslang and the mirror's compile */
}

ht_mp_type ht_mp_step_type(const ht_mp_program *p, const ht_mp_function *f, int step) {
    const ht_mp_step *s = &f->steps[step];
    switch (s->op) {
    case HT_MP_ADD:
    case HT_MP_SUB:
    case HT_MP_MUL:
    case HT_MP_DIV:
        return ht_mp_arg_type(p, f, step, s->args[0]) == HT_MP_VEC3 || ht_mp_arg_type(p, f, step, s->args[1]) == HT_MP_VEC3
                   ? HT_MP_VEC3
                   : HT_MP_FLOAT;
    case HT_MP_CROSS: return HT_MP_VEC3;
    case HT_MP_MAX:
    case HT_MP_MIN:
    case HT_MP_CLAMP: return ht_mp_arg_type(p, f, step, s->args[0]);
    case HT_MP_LT:
    case HT_MP_GT:
    case HT_MP_AND:
    case HT_MP_OR: return HT_MP_BOOL;
    case HT_MP_SELECT: return ht_mp_arg_type(p, f, step, s->args[1]);
    case HT_MP_CALL: return function_type(p, s->fn);
    default: return HT_MP_FLOAT;
    }
}

/* ---- building ---- */

static int begin(ht_mp_program *p, const char *name, ht_mp_type type) {
    ht_mp_function *f = &p->functions[p->function_count];
    memset(f, 0, sizeof *f);
    snprintf(f->name, sizeof f->name, "%s", name);
    f->type = type;
    return p->function_count++;
}

static void param(ht_mp_function *f, const char *name, ht_mp_type type) {
    snprintf(f->params[f->param_count], sizeof f->params[0], "%s", name);
    f->param_types[f->param_count++] = type;
}

static void vstep(ht_mp_function *f, const char *dst, ht_mp_op op, int fn, int n, va_list ap) {
    ht_mp_step *s = &f->steps[f->step_count++];
    s->op = op;
    s->fn = fn;
    s->arg_count = n;
    snprintf(s->dst, sizeof s->dst, "%s", dst);
    for (int i = 0; i < n; i++) snprintf(s->args[i], sizeof s->args[i], "%s", va_arg(ap, const char *));
}

static void step(ht_mp_function *f, const char *dst, ht_mp_op op, int n, ...) {
    va_list ap;
    va_start(ap, n);
    vstep(f, dst, op, -1, n, ap);
    va_end(ap);
}

static void call(ht_mp_function *f, const char *dst, int fn, int n, ...) {
    va_list ap;
    va_start(ap, n);
    vstep(f, dst, HT_MP_CALL, fn, n, ap);
    va_end(ap);
}

static void result(ht_mp_function *f, const char *what) { snprintf(f->result, sizeof f->result, "%s", what); }

typedef struct literal {
    char s[HT_GLSL_VEC3_SIZE];
} literal;

static literal num(double v) {
    literal l;
    ht_glsl_float(v, l.s);
    return l;
}

static literal vec(const double v[3]) {
    literal l;
    ht_glsl_vec3(v, l.s);
    return l;
}

/* ---- the functions ---- */

/* v / max|v_i| has length in [1, sqrt 3]: its square neither overflows nor
   underflows. max(.., 1) only matters for the zero vector (0 / 2^-14),
   keeping inversesqrt finite; the select then returns zero. */
static int normalize_or_zero(ht_mp_program *p) {
    const int fn = begin(p, "normalize_or_zero", HT_MP_VEC3);
    ht_mp_function *f = &p->functions[fn];
    const literal minimum = num(HT_MP_MIN_NORMAL);
    param(f, "v", HT_MP_VEC3);
    step(f, "m", HT_MP_ABSMAX, 1, "v");
    step(f, "has", HT_MP_GT, 2, "m", minimum.s);
    step(f, "d", HT_MP_MAX, 2, "m", minimum.s);
    step(f, "w", HT_MP_DIV, 2, "v", "d");
    step(f, "w2", HT_MP_DOT, 2, "w", "w");
    step(f, "w2", HT_MP_MAX, 2, "w2", "1.0");
    step(f, "r", HT_MP_INVSQRT, 1, "w2");
    step(f, "u", HT_MP_MUL, 2, "w", "r");
    step(f, "u", HT_MP_SELECT, 3, "has", "u", "vec3(0.0)");
    result(f, "u");
    return fn;
}

/* |v| as max|v_i| * |v / max|v_i||: exact to fp16 rounding at any scale. */
static int safe_length(ht_mp_program *p) {
    const int fn = begin(p, "safe_length", HT_MP_FLOAT);
    ht_mp_function *f = &p->functions[fn];
    const literal minimum = num(HT_MP_MIN_NORMAL);
    param(f, "v", HT_MP_VEC3);
    step(f, "m", HT_MP_ABSMAX, 1, "v");
    step(f, "d", HT_MP_MAX, 2, "m", minimum.s);
    step(f, "w", HT_MP_DIV, 2, "v", "d");
    step(f, "w2", HT_MP_DOT, 2, "w", "w");
    step(f, "w2", HT_MP_MAX, 2, "w2", "1.0");
    step(f, "r", HT_MP_SQRT, 1, "w2");
    step(f, "len", HT_MP_MUL, 2, "m", "r");
    result(f, "len");
    return fn;
}

/* normalize(T + amount N); a zero T stays zero (model.c). */
static int shifted_tangent(ht_mp_program *p, int nz) {
    const int fn = begin(p, "shifted_tangent", HT_MP_VEC3);
    ht_mp_function *f = &p->functions[fn];
    param(f, "T", HT_MP_VEC3);
    param(f, "N", HT_MP_VEC3);
    param(f, "amount", HT_MP_FLOAT);
    step(f, "tt", HT_MP_DOT, 2, "T", "T");
    step(f, "has", HT_MP_GT, 2, "tt", "0.0");
    step(f, "n", HT_MP_MUL, 2, "N", "amount");
    step(f, "v", HT_MP_ADD, 2, "T", "n");
    call(f, "t", nz, 1, "v");
    step(f, "t", HT_MP_SELECT, 3, "has", "t", "vec3(0.0)");
    result(f, "t");
    return fn;
}

/* S(t, h) = smoothstep(-1, 0, c) sin^e on unit-or-zero t, h; 0 without a
   direction. log2(sin^2) = log2(1 - c^2) by its series while c^2 < 1/8
   (4 terms: the 5th is under 6e-6 of it there), else from the cross
   product rescaled like safe_length, whose log splits 2 log2(m) +
   log2(|w|^2). An exactly parallel pair (cross = 0) gives 0 as model.c's
   sin = 0 does. */
static int highlight(ht_mp_program *p, const char *name, double exponent) {
    const int fn = begin(p, name, HT_MP_FLOAT);
    ht_mp_function *f = &p->functions[fn];
    param(f, "t", HT_MP_VEC3);
    param(f, "h", HT_MP_VEC3);
    step(f, "tt", HT_MP_DOT, 2, "t", "t");
    step(f, "hh", HT_MP_DOT, 2, "h", "h");
    step(f, "has_t", HT_MP_GT, 2, "tt", "0.0");
    step(f, "has_h", HT_MP_GT, 2, "hh", "0.0");
    step(f, "ok", HT_MP_AND, 2, "has_t", "has_h");
    step(f, "c", HT_MP_DOT, 2, "t", "h");
    step(f, "c", HT_MP_CLAMP, 3, "c", "-1.0", "1.0");
    step(f, "rise", HT_MP_SMOOTH, 1, "c");
    if (exponent == 0.0) {
        /* sin^0 = 1, also at sin = 0 (model.c) */
        step(f, "s", HT_MP_SELECT, 3, "ok", "rise", "0.0");
        result(f, "s");
        return fn;
    }
    const double k = exponent / 2.0, ln2 = log(2.0);
    const double floor_log = fmax(HT_MP_EXP2_FLOOR / k, -64.0); /* log2(sin^2) >= -28 anyway */
    const literal a1 = num(-1.0 / ln2), a2 = num(-1.0 / (2.0 * ln2)), a3 = num(-1.0 / (3.0 * ln2)),
                  a4 = num(-1.0 / (4.0 * ln2)), minimum = num(HT_MP_MIN_NORMAL), fl = num(floor_log),
                  half_e = num(k), root_half_e = num(sqrt(k)), exp2_floor = num(HT_MP_EXP2_FLOOR);
    step(f, "x", HT_MP_MUL, 2, "c", "c");
    step(f, "near_peak", HT_MP_LT, 2, "x", "0.125");
    /* e/2 log2(1 - x) = (c sqrt(e/2))^2 (a1 + x (a2 + x (a3 + x a4))):
       c^2 alone falls below 2^-14 (and flushes) while e/2 c^2 still
       matters, (c sqrt(e/2))^2 does not */
    step(f, "series", HT_MP_MUL, 2, "x", a4.s);
    step(f, "series", HT_MP_ADD, 2, "series", a3.s);
    step(f, "series", HT_MP_MUL, 2, "series", "x");
    step(f, "series", HT_MP_ADD, 2, "series", a2.s);
    step(f, "series", HT_MP_MUL, 2, "series", "x");
    step(f, "series", HT_MP_ADD, 2, "series", a1.s);
    step(f, "u", HT_MP_MUL, 2, "c", root_half_e.s);
    step(f, "u", HT_MP_MUL, 2, "u", "u");
    step(f, "series", HT_MP_MUL, 2, "series", "u");
    step(f, "cr", HT_MP_CROSS, 2, "t", "h");
    step(f, "m", HT_MP_ABSMAX, 1, "cr");
    step(f, "apart", HT_MP_GT, 2, "m", "0.0");
    step(f, "d", HT_MP_MAX, 2, "m", minimum.s);
    step(f, "w", HT_MP_DIV, 2, "cr", "d");
    step(f, "w2", HT_MP_DOT, 2, "w", "w");
    step(f, "w2", HT_MP_MAX, 2, "w2", "1.0");
    step(f, "log_w2", HT_MP_LOG2, 1, "w2");
    step(f, "log_d", HT_MP_LOG2, 1, "d");
    step(f, "log_d", HT_MP_MUL, 2, "log_d", "2.0");
    step(f, "crossed", HT_MP_ADD, 2, "log_d", "log_w2");
    /* floored before the product: e/2 (-28) would overflow */
    step(f, "crossed", HT_MP_MAX, 2, "crossed", fl.s);
    step(f, "crossed", HT_MP_MUL, 2, "crossed", half_e.s);
    step(f, "power", HT_MP_SELECT, 3, "near_peak", "series", "crossed");
    step(f, "power", HT_MP_MAX, 2, "power", exp2_floor.s);
    step(f, "power", HT_MP_EXP2, 1, "power");
    step(f, "s", HT_MP_MUL, 2, "rise", "power");
    step(f, "lit", HT_MP_OR, 2, "near_peak", "apart");
    step(f, "lit", HT_MP_AND, 2, "lit", "ok");
    step(f, "s", HT_MP_SELECT, 3, "lit", "s", "0.0");
    result(f, "s");
    return fn;
}

typedef struct fns {
    int nz, length, shifted, primary, secondary, transmission, light;
} fns;

/* model.h's ht_transmission on unit-or-zero T, L, V (mediump.h says how
   each part stays in fp16). */
static int transmission(ht_mp_program *p, const ht_transmission *t, const fns *k) {
    const int fn = begin(p, "transmission", HT_MP_FLOAT);
    ht_mp_function *f = &p->functions[fn];
    const literal centre = num(t->centre), root_sharpness = num(sqrt(t->sharpness)), azimuth = num(t->azimuth),
                  minimum = num(HT_MP_MIN_NORMAL), exp2_floor = num(HT_MP_EXP2_FLOOR),
                  floor_log = num(t->azimuth > 0 ? fmax(HT_MP_EXP2_FLOOR / t->azimuth, -64.0) : 0.0),
                  clamp_hi = num(sqrt(-HT_MP_EXP2_FLOOR)), clamp_lo = num(-sqrt(-HT_MP_EXP2_FLOOR));
    param(f, "T", HT_MP_VEC3);
    param(f, "L", HT_MP_VEC3);
    param(f, "V", HT_MP_VEC3);
    step(f, "tt", HT_MP_DOT, 2, "T", "T");
    step(f, "ll", HT_MP_DOT, 2, "L", "L");
    step(f, "vv", HT_MP_DOT, 2, "V", "V");
    /* a bool is assigned a comparison once (ht_mp_desktop_emulation
       rounds a reassigned float step and knows a bool only by && and ||) */
    step(f, "has_t", HT_MP_GT, 2, "tt", "0.0");
    step(f, "has_l", HT_MP_GT, 2, "ll", "0.0");
    step(f, "has_v", HT_MP_GT, 2, "vv", "0.0");
    step(f, "ok", HT_MP_AND, 2, "has_t", "has_l");
    step(f, "ok", HT_MP_AND, 2, "ok", "has_v");
    step(f, "tl", HT_MP_DOT, 2, "T", "L");
    step(f, "tv", HT_MP_DOT, 2, "T", "V");
    step(f, "along", HT_MP_MUL, 2, "T", "tl");
    step(f, "lr", HT_MP_SUB, 2, "L", "along");
    step(f, "along", HT_MP_MUL, 2, "T", "tv");
    step(f, "vr", HT_MP_SUB, 2, "V", "along");
    /* theta_h - centre, then the Gaussian in it */
    call(f, "across", k->length, 1, "lr");
    step(f, "theta", HT_MP_ATAN2, 2, "tl", "across");
    call(f, "across", k->length, 1, "vr");
    step(f, "u", HT_MP_ATAN2, 2, "tv", "across");
    step(f, "u", HT_MP_ADD, 2, "theta", "u");
    step(f, "u", HT_MP_MUL, 2, "u", "0.5");
    step(f, "u", HT_MP_SUB, 2, "u", centre.s);
    step(f, "u", HT_MP_MUL, 2, "u", root_sharpness.s);
    step(f, "u", HT_MP_CLAMP, 3, "u", clamp_lo.s, clamp_hi.s);
    step(f, "u", HT_MP_MUL, 2, "u", "u");
    step(f, "g", HT_MP_SUB, 2, "0.0", "u");
    step(f, "g", HT_MP_EXP2, 1, "g");
    if (t->azimuth != 0.0) {
        /* a = (1 - cos phi) / 2 = |lp - vp|^2 / 4; 1/2 (cos phi = 0) when
           L or V runs along T (model.c) */
        call(f, "lp", k->nz, 1, "lr");
        call(f, "vp", k->nz, 1, "vr");
        step(f, "d", HT_MP_SUB, 2, "lp", "vp");
        step(f, "a", HT_MP_DOT, 2, "d", "d");
        step(f, "a", HT_MP_MUL, 2, "a", "0.25");
        step(f, "a", HT_MP_MIN, 2, "a", "1.0");
        step(f, "both", HT_MP_DOT, 2, "lp", "lp");
        step(f, "has_lp", HT_MP_GT, 2, "both", "0.0");
        step(f, "both", HT_MP_DOT, 2, "vp", "vp");
        step(f, "has_vp", HT_MP_GT, 2, "both", "0.0");
        step(f, "apart", HT_MP_AND, 2, "has_lp", "has_vp");
        step(f, "a", HT_MP_SELECT, 3, "apart", "a", "0.5");
        step(f, "lit", HT_MP_GT, 2, "a", "0.0");
        step(f, "power", HT_MP_MAX, 2, "a", minimum.s);
        step(f, "power", HT_MP_LOG2, 1, "power");
        step(f, "power", HT_MP_MAX, 2, "power", floor_log.s);
        step(f, "power", HT_MP_MUL, 2, "power", azimuth.s);
        step(f, "power", HT_MP_MAX, 2, "power", exp2_floor.s);
        step(f, "power", HT_MP_EXP2, 1, "power");
        step(f, "power", HT_MP_SELECT, 3, "lit", "power", "0.0");
        step(f, "g", HT_MP_MUL, 2, "g", "power");
    }
    step(f, "g", HT_MP_SELECT, 3, "ok", "g", "0.0");
    result(f, "g");
    return fn;
}

static int hair_light_scheuermann(ht_mp_program *p, const ht_mp_desc *d, const fns *k) {
    const ht_shading *m = &d->shading;
    const int fn = begin(p, "hair_light", HT_MP_VEC3);
    ht_mp_function *f = &p->functions[fn];
    const literal wrap = num(m->wrap), rest = num(1.0 - m->wrap), kd = vec(m->diffuse_color),
                  k1 = vec(m->primary.color), k2 = vec(m->secondary.color), ktt = vec(m->transmission.color);
    param(f, "L", HT_MP_VEC3);
    param(f, "V", HT_MP_VEC3);
    param(f, "N", HT_MP_VEC3);
    param(f, "t1", HT_MP_VEC3);
    param(f, "t2", HT_MP_VEC3);
    if (d->sparkle) param(f, "sparkle", HT_MP_FLOAT);
    if (k->transmission >= 0) param(f, "T", HT_MP_VEC3);
    step(f, "h", HT_MP_ADD, 2, "L", "V");
    call(f, "H", k->nz, 1, "h");
    step(f, "nl", HT_MP_DOT, 2, "N", "L");
    step(f, "diffuse", HT_MP_MUL, 2, rest.s, "nl");
    step(f, "diffuse", HT_MP_ADD, 2, wrap.s, "diffuse");
    step(f, "diffuse", HT_MP_CLAMP, 3, "diffuse", "0.0", "1.0");
    call(f, "s1", k->primary, 2, "t1", "H");
    call(f, "s2", k->secondary, 2, "t2", "H");
    if (d->sparkle) step(f, "s2", HT_MP_MUL, 2, "s2", "sparkle");
    step(f, "rgb", HT_MP_MUL, 2, kd.s, "diffuse");
    step(f, "spec", HT_MP_MUL, 2, k1.s, "s1");
    step(f, "rgb", HT_MP_ADD, 2, "rgb", "spec");
    step(f, "spec", HT_MP_MUL, 2, k2.s, "s2");
    step(f, "rgb", HT_MP_ADD, 2, "rgb", "spec");
    if (k->transmission >= 0) {
        call(f, "through", k->transmission, 3, "T", "L", "V");
        step(f, "spec", HT_MP_MUL, 2, ktt.s, "through");
        step(f, "rgb", HT_MP_ADD, 2, "rgb", "spec");
    }
    result(f, "rgb");
    return fn;
}

static int hair_light_kajiya_kay(ht_mp_program *p, const ht_mp_desc *d, const fns *k) {
    const ht_shading *m = &d->shading;
    const int fn = begin(p, "hair_light", HT_MP_VEC3);
    ht_mp_function *f = &p->functions[fn];
    const literal kd = vec(m->diffuse_color), k1 = vec(m->primary.color);
    param(f, "L", HT_MP_VEC3);
    param(f, "V", HT_MP_VEC3);
    param(f, "T", HT_MP_VEC3);
    step(f, "h", HT_MP_ADD, 2, "L", "V");
    call(f, "H", k->nz, 1, "h");
    step(f, "cr", HT_MP_CROSS, 2, "T", "L");
    call(f, "diffuse", k->length, 1, "cr");
    step(f, "diffuse", HT_MP_MIN, 2, "diffuse", "1.0");
    call(f, "s1", k->primary, 2, "T", "H");
    step(f, "rgb", HT_MP_MUL, 2, kd.s, "diffuse");
    step(f, "spec", HT_MP_MUL, 2, k1.s, "s1");
    step(f, "rgb", HT_MP_ADD, 2, "rgb", "spec");
    result(f, "rgb");
    return fn;
}

static void shade(ht_mp_program *p, const ht_mp_desc *d, const fns *k) {
    const bool kk = d->shading.model == HT_MODEL_KAJIYA_KAY;
    ht_mp_function *f = &p->functions[begin(p, "shade", HT_MP_VEC3)];
    char name[HT_MP_NAME], colour[HT_MP_NAME];
    param(f, "position", HT_MP_VEC3);
    param(f, "tangent", HT_MP_VEC3);
    if (!kk) param(f, "normal", HT_MP_VEC3);
    param(f, "eye", HT_MP_VEC3);
    for (int i = 0; i < d->light_count; i++) {
        snprintf(name, sizeof name, "light%d", i);
        param(f, name, HT_MP_VEC3);
        snprintf(name, sizeof name, "colour%d", i);
        param(f, name, HT_MP_VEC3);
    }
    if (d->jitter) param(f, "shift_texel", HT_MP_FLOAT);
    if (d->sparkle) param(f, "sparkle", HT_MP_FLOAT);
    if (d->base) param(f, "base", HT_MP_VEC3);
    if (d->ao) param(f, "ao", HT_MP_FLOAT);

    call(f, "T", k->nz, 1, "tangent");
    if (!kk) call(f, "N", k->nz, 1, "normal");
    step(f, "view", HT_MP_SUB, 2, "eye", "position");
    call(f, "V", k->nz, 1, "view");
    if (!kk) {
        const literal s1 = num(d->shading.primary.shift), s2 = num(d->shading.secondary.shift);
        if (d->jitter) {
            step(f, "jitter", HT_MP_SUB, 2, "shift_texel", "0.5");
            step(f, "a1", HT_MP_ADD, 2, s1.s, "jitter");
            step(f, "a2", HT_MP_ADD, 2, s2.s, "jitter");
            call(f, "t1", k->shifted, 3, "T", "N", "a1");
            call(f, "t2", k->shifted, 3, "T", "N", "a2");
        } else {
            call(f, "t1", k->shifted, 3, "T", "N", s1.s);
            call(f, "t2", k->shifted, 3, "T", "N", s2.s);
        }
    }
    if (d->light_count == 0) {
        result(f, "vec3(0.0)");
        return;
    }
    for (int i = 0; i < d->light_count; i++) {
        snprintf(name, sizeof name, "light%d", i);
        snprintf(colour, sizeof colour, "colour%d", i);
        if (d->light_types[i] == HT_LIGHT_POINT) step(f, "l", HT_MP_SUB, 2, name, "position");
        else step(f, "l", HT_MP_MUL, 2, name, "1.0");
        call(f, "L", k->nz, 1, "l");
        if (kk) call(f, "lit", k->light, 3, "L", "V", "T");
        else if (d->sparkle && k->transmission >= 0)
            call(f, "lit", k->light, 7, "L", "V", "N", "t1", "t2", "sparkle", "T");
        else if (d->sparkle) call(f, "lit", k->light, 6, "L", "V", "N", "t1", "t2", "sparkle");
        else if (k->transmission >= 0) call(f, "lit", k->light, 6, "L", "V", "N", "t1", "t2", "T");
        else call(f, "lit", k->light, 5, "L", "V", "N", "t1", "t2");
        /* model.c's order: lit * base * light colour * ao */
        if (d->base) step(f, "lit", HT_MP_MUL, 2, "lit", "base");
        step(f, "lit", HT_MP_MUL, 2, "lit", colour);
        if (d->ao) step(f, "lit", HT_MP_MUL, 2, "lit", "ao");
        if (i == 0) step(f, "rgb", HT_MP_MUL, 2, "lit", "1.0");
        else step(f, "rgb", HT_MP_ADD, 2, "rgb", "lit");
    }
    result(f, "rgb");
}

void ht_mp_build(const ht_mp_desc *desc, ht_mp_program *out) {
    memset(out, 0, sizeof *out);
    const bool kk = desc->shading.model == HT_MODEL_KAJIYA_KAY;
    const bool tt = ht_model_has_transmission(&desc->shading);
    fns k = { .length = -1, .shifted = -1, .secondary = -1, .transmission = -1 };
    k.nz = normalize_or_zero(out);
    if (kk || tt) k.length = safe_length(out);
    if (!kk) k.shifted = shifted_tangent(out, k.nz);
    k.primary = highlight(out, "highlight_primary", desc->shading.primary.exponent);
    if (!kk) k.secondary = highlight(out, "highlight_secondary", desc->shading.secondary.exponent);
    if (tt) k.transmission = transmission(out, &desc->shading.transmission, &k);
    k.light = kk ? hair_light_kajiya_kay(out, desc, &k) : hair_light_scheuermann(out, desc, &k);
    shade(out, desc, &k);
}

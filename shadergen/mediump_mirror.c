/* mediump_mirror.c — see mediump_mirror.h. */
#include "mediump_mirror.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SLOTS (HT_MP_PARAMS + HT_MP_STEPS)

double ht_mp_round_half(double x) {
    if (!isfinite(x) || x == 0.0) return x;
    const double a = fabs(x);
    /* 65504 has an odd last bit, so the tie at 65520 rounds up to 2^16: Inf */
    if (a >= 65520.0) return copysign(INFINITY, x);
    uint64_t bits;
    memcpy(&bits, &a, sizeof bits);
    int q = (int)(bits >> 52) - 1022 - 11; /* frexp's exponent less 11 significant bits */
    if (q < -24) q = -24;                  /* subnormals: a fixed quantum of 2^-24 */
    /* a + 2^(q+52) has the quantum 2^q as its last bit: the sum rounds a to
       it, ties to even (the default mode, as nearbyint did), and the
       subtraction is exact; the same numbers as frexp, ldexp and nearbyint */
    const uint64_t big_bits = (uint64_t)(q + 52 + 1023) << 52;
    double big;
    memcpy(&big, &big_bits, sizeof big);
    return copysign((a + big) - big, x);
}

typedef struct ref {
    bool literal;
    int index;    /* slot, or literal of the function */
} ref;

typedef struct cstep {
    ht_mp_op op;
    int fn, dst, arg_count;
    ht_mp_type type;
    ref args[HT_MP_ARGS];
} cstep;

typedef struct cfunction {
    int param_count, step_count, literal_count;
    cstep steps[HT_MP_STEPS];
    double literals[HT_MP_ARGS * HT_MP_STEPS + 1][3];
    ref result;
} cfunction;

/* shade()'s parameters: which input each is. */
typedef enum input {
    IN_POSITION, IN_TANGENT, IN_NORMAL, IN_EYE, IN_SHIFT, IN_SPARKLE, IN_BASE, IN_AO,
    IN_LIGHT0, IN_COLOUR0 = IN_LIGHT0 + HT_MAX_LIGHTS, IN_END = IN_COLOUR0 + HT_MAX_LIGHTS
} input;

struct ht_mp_mirror {
    int function_count;
    cfunction functions[HT_MP_FUNCTIONS];
    int input_count;
    input inputs[HT_MP_PARAMS];
};

static int input_of(const char *name) {
    static const char *const fixed[] = { "position", "tangent", "normal", "eye", "shift_texel", "sparkle", "base", "ao" };
    for (int i = 0; i < (int)(sizeof fixed / sizeof fixed[0]); i++)
        if (strcmp(name, fixed[i]) == 0) return i;
    int light;
    char tail;
    if (sscanf(name, "light%d%c", &light, &tail) == 1 && light >= 0 && light < HT_MAX_LIGHTS) return IN_LIGHT0 + light;
    if (sscanf(name, "colour%d%c", &light, &tail) == 1 && light >= 0 && light < HT_MAX_LIGHTS) return IN_COLOUR0 + light;
    return -1;
}

static void input_vector(const ht_mp_inputs *in, input which, double out[3]) {
    const double *v = NULL, *scalar = NULL;
    switch (which) {
    case IN_POSITION: v = in->position; break;
    case IN_TANGENT: v = in->tangent; break;
    case IN_NORMAL: v = in->normal; break;
    case IN_EYE: v = in->eye; break;
    case IN_BASE: v = in->base; break;
    case IN_SHIFT: scalar = &in->shift_texel; break;
    case IN_SPARKLE: scalar = &in->sparkle; break;
    case IN_AO: scalar = &in->ao; break;
    default: v = which >= IN_COLOUR0 ? in->colour[which - IN_COLOUR0] : in->light[which - IN_LIGHT0]; break;
    }
    for (int k = 0; k < 3; k++) out[k] = v ? v[k] : *scalar;
}

typedef struct context {
    bool flush;
    ht_mp_stats *stats;
} context;

static double round_counted(double x, context *c) {
    double r = ht_mp_round_half(x);
    c->stats->results++;
    if (!isfinite(r)) c->stats->overflows++;
    else if (r != 0.0 && fabs(r) < HT_MP_MIN_NORMAL) {
        if (c->flush) r = copysign(0.0, r);
        else c->stats->subnormals++;
    }
    return r;
}

/* "vec3(a)", "vec3(a, b, c)" or a float; false if none. */
static bool parse_literal(const char *s, double out[3]) {
    char *end;
    if (strncmp(s, "vec3(", 5) == 0) {
        const char *p = s + 5;
        for (int i = 0; i < 3; i++) {
            out[i] = strtod(p, &end);
            if (end == p) return false;
            p = end;
            while (*p == ' ') p++;
            if (*p == ')') {
                if (i == 0) out[1] = out[2] = out[0];
                return i == 0 || i == 2;
            }
            if (*p++ != ',') return false;
        }
        return false;
    }
    out[0] = out[1] = out[2] = strtod(s, &end);
    return end != s && *end == '\0';
}

/* The slot a name has before step (a later assignment reuses it). */
static int slot_of(const ht_mp_function *f, int step, const char *name) {
    for (int i = 0; i < f->param_count; i++)
        if (strcmp(f->params[i], name) == 0) return i;
    for (int i = 0; i < step; i++)
        if (strcmp(f->steps[i].dst, name) == 0) {
            for (int j = 0; j < i; j++) /* its first assignment */
                if (strcmp(f->steps[j].dst, name) == 0) return f->param_count + j;
            return f->param_count + i;
        }
    return -1;
}

static bool resolve(const ht_mp_function *f, cfunction *cf, int step, const char *arg, ref *out, char *err,
                    size_t err_size) {
    const char c = arg[0];
    if (c == '-' || c == '.' || (c >= '0' && c <= '9') || strncmp(arg, "vec3(", 5) == 0) {
        double v[3];
        if (!parse_literal(arg, v)) {
            snprintf(err, err_size, "%s: bad literal '%s'", f->name, arg);
            return false;
        }
        for (int i = 0; i < 3; i++) cf->literals[cf->literal_count][i] = ht_mp_round_half(v[i]);
        *out = (ref){ true, cf->literal_count++ };
        return true;
    }
    const int s = slot_of(f, step, arg);
    if (s < 0) {
        snprintf(err, err_size, "%s: '%s' used before it is defined", f->name, arg);
        return false;
    }
    *out = (ref){ false, s };
    return true;
}

ht_mp_mirror *ht_mp_mirror_new(const ht_mp_program *p, char *err, size_t err_size) {
    ht_mp_mirror *m = calloc(1, sizeof *m);
    if (!m) {
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    m->function_count = p->function_count;
    for (int fi = 0; fi < p->function_count; fi++) {
        const ht_mp_function *f = &p->functions[fi];
        cfunction *cf = &m->functions[fi];
        cf->param_count = f->param_count;
        cf->step_count = f->step_count;
        for (int i = 0; i < f->step_count; i++) {
            const ht_mp_step *s = &f->steps[i];
            cstep *c = &cf->steps[i];
            c->op = s->op;
            c->fn = s->fn;
            c->arg_count = s->arg_count;
            c->type = ht_mp_step_type(p, f, i);
            if (s->op == HT_MP_CALL && (s->fn < 0 || s->fn >= fi)) {
                snprintf(err, err_size, "%s: calls a function not defined before it", f->name);
                free(m);
                return NULL;
            }
            for (int a = 0; a < s->arg_count; a++)
                if (!resolve(f, cf, i, s->args[a], &c->args[a], err, err_size)) {
                    free(m);
                    return NULL;
                }
            c->dst = slot_of(f, i + 1, s->dst);
        }
        if (!resolve(f, cf, f->step_count, f->result, &cf->result, err, err_size)) {
            free(m);
            return NULL;
        }
    }
    const ht_mp_function *shade = &p->functions[p->function_count - 1];
    m->input_count = shade->param_count;
    for (int i = 0; i < shade->param_count; i++) {
        const int which = input_of(shade->params[i]);
        if (which < 0) {
            snprintf(err, err_size, "%s: no input called '%s'", shade->name, shade->params[i]);
            free(m);
            return NULL;
        }
        m->inputs[i] = (input)which;
    }
    return m;
}

void ht_mp_mirror_free(ht_mp_mirror *m) { free(m); }

static void evaluate(const ht_mp_mirror *m, int fn, double args[][3], double out[3], context *c);

static const double *value(const cfunction *f, double slots[][3], ref r) {
    return r.literal ? f->literals[r.index] : slots[r.index];
}

static void run_step(const ht_mp_mirror *m, const cfunction *f, const cstep *s, double slots[][3], context *c) {
    const double *a = s->arg_count > 0 ? value(f, slots, s->args[0]) : NULL;
    const double *b = s->arg_count > 1 ? value(f, slots, s->args[1]) : NULL;
    const double *d = s->arg_count > 2 ? value(f, slots, s->args[2]) : NULL;
    double r[3] = { 0, 0, 0 };
    const int n = s->type == HT_MP_VEC3 ? 3 : 1;
    switch (s->op) {
    case HT_MP_ADD: for (int i = 0; i < n; i++) r[i] = round_counted(a[i] + b[i], c); break;
    case HT_MP_SUB: for (int i = 0; i < n; i++) r[i] = round_counted(a[i] - b[i], c); break;
    case HT_MP_MUL: for (int i = 0; i < n; i++) r[i] = round_counted(a[i] * b[i], c); break;
    case HT_MP_DIV: for (int i = 0; i < n; i++) r[i] = round_counted(a[i] / b[i], c); break;
    case HT_MP_DOT: {
        double sum = round_counted(a[0] * b[0], c);
        for (int i = 1; i < 3; i++) sum = round_counted(sum + round_counted(a[i] * b[i], c), c);
        r[0] = sum;
        break;
    }
    case HT_MP_CROSS:
        for (int i = 0; i < 3; i++) {
            const int j = (i + 1) % 3, k = (i + 2) % 3;
            r[i] = round_counted(round_counted(a[j] * b[k], c) - round_counted(a[k] * b[j], c), c);
        }
        break;
    case HT_MP_ABSMAX: r[0] = fmax(fmax(fabs(a[0]), fabs(a[1])), fabs(a[2])); break;
    case HT_MP_MAX: for (int i = 0; i < n; i++) r[i] = fmax(a[i], b[i]); break;
    case HT_MP_MIN: for (int i = 0; i < n; i++) r[i] = fmin(a[i], b[i]); break;
    case HT_MP_CLAMP: for (int i = 0; i < n; i++) r[i] = fmin(fmax(a[i], b[i]), d[i]); break;
    case HT_MP_SQRT: r[0] = round_counted(sqrt(a[0]), c); break;
    case HT_MP_INVSQRT: r[0] = round_counted(1.0 / sqrt(a[0]), c); break;
    case HT_MP_LOG2: r[0] = round_counted(log2(a[0]), c); break;
    case HT_MP_EXP2: r[0] = round_counted(exp2(a[0]), c); break;
    case HT_MP_ATAN2: r[0] = round_counted(atan2(a[0], b[0]), c); break;
    case HT_MP_SMOOTH: { /* t = clamp(x + 1, 0, 1); t t (3 - 2 t) */
        const double t = fmin(fmax(round_counted(a[0] + 1.0, c), 0.0), 1.0);
        r[0] = round_counted(round_counted(t * t, c) * round_counted(3.0 - 2.0 * t, c), c);
        break;
    }
    case HT_MP_LT: r[0] = a[0] < b[0]; break;
    case HT_MP_GT: r[0] = a[0] > b[0]; break;
    case HT_MP_AND: r[0] = a[0] != 0 && b[0] != 0; break;
    case HT_MP_OR: r[0] = a[0] != 0 || b[0] != 0; break;
    case HT_MP_SELECT: for (int i = 0; i < 3; i++) r[i] = a[0] != 0 ? b[i] : d[i]; break;
    case HT_MP_CALL: {
        double args[HT_MP_PARAMS][3];
        for (int i = 0; i < s->arg_count; i++) memcpy(args[i], value(f, slots, s->args[i]), sizeof args[i]);
        evaluate(m, s->fn, args, r, c);
        break;
    }
    }
    if (n == 1) r[1] = r[2] = r[0]; /* a float or bool broadcasts */
    memcpy(slots[s->dst], r, sizeof r);
}

static void evaluate(const ht_mp_mirror *m, int fn, double args[][3], double out[3], context *c) {
    const cfunction *f = &m->functions[fn];
    double slots[SLOTS][3];
    memcpy(slots, args, sizeof slots[0] * (size_t)f->param_count);
    for (int i = 0; i < f->step_count; i++) run_step(m, f, &f->steps[i], slots, c);
    memcpy(out, value(f, slots, f->result), sizeof(double[3]));
}

void ht_mp_mirror_shade(const ht_mp_mirror *m, const ht_mp_inputs *in, bool flush_subnormals, double rgb[3],
                        ht_mp_stats *stats) {
    context c = { flush_subnormals, stats };
    double args[HT_MP_PARAMS][3];
    for (int i = 0; i < m->input_count; i++) {
        double v[3];
        input_vector(in, m->inputs[i], v);
        for (int k = 0; k < 3; k++) args[i][k] = round_counted(v[k], &c); /* mediump varyings, uniforms */
    }
    evaluate(m, m->function_count - 1, args, rgb, &c);
}

/* mediump.h — the full tier's mediump fragment shading as one table of
   steps, read twice: mediump_glsl.c writes it as ESSL 1.00 functions
   (full-es2-mediump.frag), mediump_mirror.c evaluates it on the CPU with
   every step rounded to fp16. One table, so the text a device runs and the
   mirror whose error docs/accuracy.md reports cannot drift apart.

   Every step keeps its result inside fp16 (|x| <= 65504, normals from
   2^-14, relative precision 2^-11) for any input a shader can see:
   - lengths divide by the largest |component| first (no squared length
     over- or underflows);
   - sin^e is exp2(e/2 * log2(sin^2)): log2(sin^2) from a series in c^2 near
     the peak (sin near 1 has no fp16 resolution, c^2 does), from the
     rescaled cross product elsewhere (near T || H), floored so e/2 times it
     stays >= -16 (exp2 then is below 2^-16, the value is 0 to 8 bits);
   - the transmission lobe's theta is atan(T.L, |L - (T.L) T|), not asin
     (asin's slope is infinite at T || L: fp16's 2^-11 in T.L would move
     it by 2^-5 rad); exp2(-sharpness u^2) squares u sqrt(sharpness)
     clamped to +-4 (so >= 2^-16); the azimuth's (1 - cos phi) / 2 is
     |l - v|^2 / 4 of the unit projections (exact near 0, where a^e with
     e < 1 is steep), and a^e is exp2 of a floored log as sin^e is. */
#ifndef HT_MEDIUMP_H
#define HT_MEDIUMP_H

#include <stdbool.h>

#include <hairtier/hairtier.h>
#include <hairtier/model.h>

#define HT_MP_NAME 24   /* a variable, function or literal */
#define HT_MP_ARGS 8
#define HT_MP_LITERAL 128 /* "vec3(a, b, c)" of three GLSL floats */
#define HT_MP_PARAMS 24
#define HT_MP_STEPS 64
#define HT_MP_FUNCTIONS 8

typedef enum ht_mp_type { HT_MP_FLOAT, HT_MP_VEC3, HT_MP_BOOL } ht_mp_type;

typedef enum ht_mp_op {
    HT_MP_ADD, HT_MP_SUB, HT_MP_MUL, HT_MP_DIV, /* componentwise; a float operand broadcasts */
    HT_MP_DOT, HT_MP_CROSS,
    HT_MP_ABSMAX, /* max(|x|, |y|, |z|) */
    HT_MP_MAX, HT_MP_MIN, HT_MP_CLAMP,
    HT_MP_SQRT, HT_MP_INVSQRT, HT_MP_LOG2, HT_MP_EXP2,
    HT_MP_SMOOTH, /* smoothstep(-1, 0, a) */
    HT_MP_LT, HT_MP_GT, HT_MP_AND, HT_MP_OR,
    HT_MP_SELECT, /* a ? b : c */
    HT_MP_CALL,   /* function fn of the program on the args */
    HT_MP_ATAN2,  /* atan(y, x) of a, b: the angle of (x, y) */
} ht_mp_op;

/* dst = op(args): an argument is a variable of the function, a parameter,
   a float literal ("0.5", "-1.0e-4") or a vec3 literal ("vec3(0.0)",
   "vec3(0.1, 0.2, 0.3)"). A dst assigned twice is one variable. */
typedef struct ht_mp_step {
    ht_mp_op op;
    int fn; /* HT_MP_CALL: index of an earlier function */
    int arg_count;
    char dst[HT_MP_NAME];
    char args[HT_MP_ARGS][HT_MP_LITERAL];
} ht_mp_step;

typedef struct ht_mp_function {
    char name[HT_MP_NAME];
    ht_mp_type type;
    int param_count;
    char params[HT_MP_PARAMS][HT_MP_NAME];
    ht_mp_type param_types[HT_MP_PARAMS];
    int step_count;
    ht_mp_step steps[HT_MP_STEPS];
    char result[HT_MP_LITERAL]; /* returned: a variable or a literal */
} ht_mp_function;

/* What the shading depends on: the plan's model, constants and inputs. */
typedef struct ht_mp_desc {
    ht_shading shading;
    int light_count;
    ht_light_type light_types[HT_MAX_LIGHTS];
    bool jitter, sparkle, base, ao; /* inputs the shade() function takes */
} ht_mp_desc;

/* Functions in call order; the last, "shade", is what main() calls with
   (position, tangent, normal (not Kajiya-Kay), eye, light vector .xyz and
   colour of each light, then shift texel, sparkle, base, ao as desc has
   them) and returns the colour before alpha. */
typedef struct ht_mp_program {
    int function_count;
    ht_mp_function functions[HT_MP_FUNCTIONS];
} ht_mp_program;

/* The fp16 limits the table is built around. */
#define HT_MP_MIN_NORMAL 6.103515625e-05 /* 2^-14: shorter has no direction */
#define HT_MP_FP16_MAX 65504.0
/* The highlight's exp2 argument floor: sin^e below 2^-16 is 0. */
#define HT_MP_EXP2_FLOOR -16.0

void ht_mp_build(const ht_mp_desc *desc, ht_mp_program *out);
/* The type a step's dst gets (the mirror and the GLSL writer agree). */
ht_mp_type ht_mp_step_type(const ht_mp_program *p, const ht_mp_function *f, int step);
/* The type of an argument in f before step (literals by their form). */
ht_mp_type ht_mp_arg_type(const ht_mp_program *p, const ht_mp_function *f, int step, const char *arg);

#endif

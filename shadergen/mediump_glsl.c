/* mediump_glsl.c — the mediump table (mediump.h) as ESSL 1.00 functions,
   one statement per step, and the plan's table description. */
#include "mediump_glsl.h"

#include <string.h>

static const char *type_name(ht_mp_type t) {
    return t == HT_MP_VEC3 ? "vec3" : (t == HT_MP_BOOL ? "bool" : "float");
}

static void expression(ht_strbuf *sb, const ht_mp_program *p, const ht_mp_step *s) {
    const char(*a)[HT_MP_LITERAL] = s->args;
    switch (s->op) {
    case HT_MP_ADD: ht_strbuf_addf(sb, "%s + %s", a[0], a[1]); break;
    case HT_MP_SUB: ht_strbuf_addf(sb, "%s - %s", a[0], a[1]); break;
    case HT_MP_MUL: ht_strbuf_addf(sb, "%s * %s", a[0], a[1]); break;
    case HT_MP_DIV: ht_strbuf_addf(sb, "%s / %s", a[0], a[1]); break;
    case HT_MP_DOT: ht_strbuf_addf(sb, "dot(%s, %s)", a[0], a[1]); break;
    case HT_MP_CROSS: ht_strbuf_addf(sb, "cross(%s, %s)", a[0], a[1]); break;
    case HT_MP_ABSMAX: ht_strbuf_addf(sb, "max(max(abs(%s.x), abs(%s.y)), abs(%s.z))", a[0], a[0], a[0]); break;
    case HT_MP_MAX: ht_strbuf_addf(sb, "max(%s, %s)", a[0], a[1]); break;
    case HT_MP_MIN: ht_strbuf_addf(sb, "min(%s, %s)", a[0], a[1]); break;
    case HT_MP_CLAMP: ht_strbuf_addf(sb, "clamp(%s, %s, %s)", a[0], a[1], a[2]); break;
    case HT_MP_SQRT: ht_strbuf_addf(sb, "sqrt(%s)", a[0]); break;
    case HT_MP_INVSQRT: ht_strbuf_addf(sb, "inversesqrt(%s)", a[0]); break;
    case HT_MP_LOG2: ht_strbuf_addf(sb, "log2(%s)", a[0]); break;
    case HT_MP_EXP2: ht_strbuf_addf(sb, "exp2(%s)", a[0]); break;
    case HT_MP_SMOOTH: ht_strbuf_addf(sb, "smoothstep(-1.0, 0.0, %s)", a[0]); break;
    case HT_MP_LT: ht_strbuf_addf(sb, "%s < %s", a[0], a[1]); break;
    case HT_MP_GT: ht_strbuf_addf(sb, "%s > %s", a[0], a[1]); break;
    case HT_MP_AND: ht_strbuf_addf(sb, "%s && %s", a[0], a[1]); break;
    case HT_MP_OR: ht_strbuf_addf(sb, "%s || %s", a[0], a[1]); break;
    case HT_MP_SELECT: ht_strbuf_addf(sb, "%s ? %s : %s", a[0], a[1], a[2]); break;
    case HT_MP_ATAN2: ht_strbuf_addf(sb, "atan(%s, %s)", a[0], a[1]); break;
    case HT_MP_CALL:
        ht_strbuf_addf(sb, "%s(", p->functions[s->fn].name);
        for (int i = 0; i < s->arg_count; i++) ht_strbuf_addf(sb, "%s%s", i ? ", " : "", a[i]);
        ht_strbuf_add(sb, ")");
        break;
    }
}

static bool declared_before(const ht_mp_function *f, int step) {
    for (int i = 0; i < step; i++)
        if (strcmp(f->steps[i].dst, f->steps[step].dst) == 0) return true;
    return false;
}

void ht_mp_write_functions(ht_strbuf *sb, const ht_mp_program *p) {
    for (int fi = 0; fi < p->function_count; fi++) {
        const ht_mp_function *f = &p->functions[fi];
        ht_strbuf_addf(sb, "%s %s(", type_name(f->type), f->name);
        for (int i = 0; i < f->param_count; i++)
            ht_strbuf_addf(sb, "%s%s %s", i ? ", " : "", type_name(f->param_types[i]), f->params[i]);
        ht_strbuf_add(sb, ") {\n");
        for (int i = 0; i < f->step_count; i++) {
            if (declared_before(f, i)) ht_strbuf_addf(sb, "    %s = ", f->steps[i].dst);
            else ht_strbuf_addf(sb, "    %s %s = ", type_name(ht_mp_step_type(p, f, i)), f->steps[i].dst);
            expression(sb, p, &f->steps[i]);
            ht_strbuf_add(sb, ";\n");
        }
        ht_strbuf_addf(sb, "    return %s;\n}\n\n", f->result);
    }
}

ht_mp_desc ht_mp_desc_of_plan(const ht_plan *plan) {
    ht_mp_desc d = {
        .shading = plan->shading,
        .light_count = plan->light_count,
        .jitter = plan->shift,
        .sparkle = plan->sparkle,
        .base = plan->base,
        .ao = plan->ao,
    };
    memcpy(d.light_types, plan->light_types, sizeof d.light_types);
    return d;
}

/* ---- the desktop fp16 emulation (measurement only, never shipped) ---- */

/* Round-to-nearest fp16 in fp32 GLSL: 11 significant bits above 2^-14, a
   2^-24 quantum below; the exponent from log2, corrected where log2 is
   inexact next to a power of two. */
static const char emulation_functions[] =
    "float to_half(float x) {\n"
    "    float a = abs(x);\n"
    "    float e = floor(log2(max(a, 6.103515625e-05)));\n"
    "    if (a >= exp2(e + 1.0)) e += 1.0;\n"
    "    if (a < exp2(e) && e > -14.0) e -= 1.0;\n"
    "    float q = exp2(e - 10.0);\n"
    "    return sign(x) * min(floor(a / q + 0.5) * q, 65504.0);\n"
    "}\n"
    "vec3 to_half(vec3 v) { return vec3(to_half(v.x), to_half(v.y), to_half(v.z)); }\n";

static bool starts(const char *line, const char *prefix) { return strncmp(line, prefix, strlen(prefix)) == 0; }

/* One line of the ES text as the emulation writes it. */
static void emulate_line(ht_strbuf *sb, const char *line, size_t n) {
    char text[4096];
    snprintf(text, sizeof text, "%.*s", (int)n, line);
    const char *eq = strstr(text, " = ");
    if (strcmp(text, "#version 100") == 0) {
        ht_strbuf_add(sb, "#version 120\n");
    } else if (strcmp(text, "precision mediump float;") == 0) {
        ht_strbuf_add(sb, emulation_functions);
    } else if (strstr(text, "discard;") || starts(text, "uniform mediump float")) {
        /* desktop GL keeps the alpha test of the pass (GLSL 1.20 has no
           precision qualifiers) */
    } else if (starts(text, "    vec3 rgb = shade(")) {
        /* every input rounds as a mediump varying or uniform does */
        const char *args = text + strlen("    vec3 rgb = shade(");
        ht_strbuf_add(sb, "    vec3 rgb = shade(");
        const char *end = strrchr(args, ')');
        for (const char *a = args; a < end;) {
            size_t len = strcspn(a, ",)");
            ht_strbuf_addf(sb, "%sto_half(%.*s)", a == args ? "" : ", ", (int)len, a);
            a += len;
            if (*a == ',') a += 2;
        }
        ht_strbuf_add(sb, ");\n");
    } else if (eq && starts(text, "    ") && !starts(text, "    bool ") && !starts(text, "    vec4 ") &&
               !starts(text, "    gl_") &&
               !strstr(text, "&&") && !strstr(text, "||") && text[strlen(text) - 1] == ';') {
        /* a step: its result rounds to fp16 */
        ht_strbuf_addf(sb, "%.*s = to_half(%.*s);\n", (int)(eq - text), text, (int)(strlen(eq + 3) - 1), eq + 3);
    } else {
        ht_strbuf_addf(sb, "%s\n", text);
    }
}

char *ht_mp_desktop_emulation(const char *es_text) {
    ht_strbuf sb;
    ht_strbuf_init(&sb);
    for (const char *line = es_text; *line;) {
        const size_t n = strcspn(line, "\n");
        emulate_line(&sb, line, n);
        line += n + (line[n] == '\n');
    }
    return ht_strbuf_take(&sb);
}

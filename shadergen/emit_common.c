/* emit_common.c — what the emitters share: filling and freeing an
   ht_tier_output, and the shading model of runtime/shading/model.c written as GLSL
   (the full tier runs it per pixel, the vertex tier per vertex). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shader_interface.h"
#include "glsl_stages.h"
#include "strbuf.h"

void ht_tier_output_free(ht_tier_output *out) {
    if (!out) return;
    for (int i = 0; i < out->text_count && i < HT_OUT_MAX_TEXTS; i++) free(out->texts[i].text);
    for (int i = 0; i < out->image_count && i < HT_OUT_MAX_IMAGES; i++) ht_image_free(&out->images[i].image);
    memset(out, 0, sizeof *out);
}

ht_result ht_output_add_text(ht_tier_output *out, const char *file, const char *role, char *text,
                             ht_stage stage, int glsl_version, bool es, char *err, size_t err_size) {
    if (!text) {
        if (err && err_size) snprintf(err, err_size, "%s: out of memory while writing it", file);
        return HT_ERR_OUT_OF_MEMORY;
    }
    if (out->text_count >= HT_OUT_MAX_TEXTS) {
        free(text);
        if (err && err_size) snprintf(err, err_size, "%s: too many files for one tier", file);
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (stage != HT_STAGE_NONE) {
        char log[2048];
        ht_result r = ht_glsl_validate(text, stage, glsl_version, es, log, sizeof log);
        if (r != HT_OK) {
            free(text);
            if (err && err_size) snprintf(err, err_size, "%s: %s", file, log);
            return r;
        }
    }
    ht_out_text *t = &out->texts[out->text_count++];
    snprintf(t->file, sizeof t->file, "%s", file);
    snprintf(t->role, sizeof t->role, "%s", role);
    t->text = text;
    t->stage = stage;
    t->glsl_version = glsl_version;
    t->es = es;
    return HT_OK;
}

bool ht_output_add_es_entry(ht_tier_output *out, const char *version, const char *essl, const char *precision,
                            const char *vertex, const char *fragment) {
    if (out->es_count >= HT_OUT_MAX_ES) return false;
    ht_out_es *e = &out->es[out->es_count++];
    snprintf(e->version, sizeof e->version, "%s", version);
    snprintf(e->essl, sizeof e->essl, "%s", essl);
    snprintf(e->precision, sizeof e->precision, "%s", precision);
    snprintf(e->vertex, sizeof e->vertex, "%s", vertex);
    snprintf(e->fragment, sizeof e->fragment, "%s", fragment);
    return true;
}

ht_result ht_output_add_es_pair(ht_tier_output *out, const char *stem, char *vertex100, char *fragment100,
                                const char *precision, char *err, size_t err_size) {
    char names[4][48];
    snprintf(names[0], sizeof names[0], "%s-es3.vert", stem);
    snprintf(names[1], sizeof names[1], "%s-es3.frag", stem);
    snprintf(names[2], sizeof names[2], "%s-es2.vert", stem);
    snprintf(names[3], sizeof names[3], "%s-es2.frag", stem);
    char *v300 = vertex100 ? ht_glsl_essl3_from_essl1(vertex100, false) : NULL;
    char *f300 = fragment100 ? ht_glsl_essl3_from_essl1(fragment100, true) : NULL;
    ht_result r = ht_output_add_text(out, names[0], "", v300, HT_STAGE_VERTEX, 300, true, err, err_size);
    if (r == HT_OK) r = ht_output_add_text(out, names[1], "", f300, HT_STAGE_FRAGMENT, 300, true, err, err_size);
    else free(f300);
    if (r == HT_OK) r = ht_output_add_text(out, names[2], "", vertex100, HT_STAGE_VERTEX, 100, true, err, err_size);
    else free(vertex100);
    if (r == HT_OK) r = ht_output_add_text(out, names[3], "", fragment100, HT_STAGE_FRAGMENT, 100, true, err, err_size);
    else free(fragment100);
    if (r != HT_OK) return r;
    if (!ht_output_add_es_entry(out, "3.0", "3.00", precision, names[0], names[1]) ||
        !ht_output_add_es_entry(out, "2.0", "1.00", precision, names[2], names[3])) {
        if (err && err_size) snprintf(err, err_size, "%s: too many GL ES variants for one tier", stem);
        return HT_ERR_INVALID_ARGUMENT;
    }
    return HT_OK;
}

void ht_output_add_feature(ht_tier_output *out, const char *feature) {
    if (out->feature_count >= HT_OUT_MAX_LIST) return;
    snprintf(out->features[out->feature_count++], sizeof out->features[0], "%s", feature);
}

void ht_output_add_dropped(ht_tier_output *out, const char *reason) {
    if (out->dropped_count >= HT_OUT_MAX_LIST) return;
    snprintf(out->dropped[out->dropped_count++], sizeof out->dropped[0], "%s", reason);
}

void ht_output_drop_transmission(ht_tier_output *out, const ht_plan *plan, const char *why) {
    if (!ht_model_has_transmission(&plan->shading)) return;
    char line[sizeof out->dropped[0]];
    snprintf(line, sizeof line, "transmission: %s", why);
    ht_output_add_dropped(out, line);
}

void ht_output_add_model_features(ht_tier_output *out, const ht_plan *plan) {
    ht_output_add_feature(out, plan->shading.model == HT_MODEL_KAJIYA_KAY ? "kajiya-kay" : "scheuermann");
    static const struct { ht_light_type type; const char *name; } kinds[] = {
        { HT_LIGHT_DIRECTIONAL, "directional" },
        { HT_LIGHT_POINT, "point" },
    };
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        int n = 0;
        for (int i = 0; i < plan->light_count; i++) n += plan->light_types[i] == kinds[k].type;
        if (n == 0) continue;
        char line[64];
        snprintf(line, sizeof line, "%d %s light%s", n, kinds[k].name, n == 1 ? "" : "s");
        ht_output_add_feature(out, line);
    }
}

bool ht_output_add_sampler(ht_tier_output *out, const ht_plan *plan, const char *name) {
    for (int i = 0; i < plan->texture_count; i++) {
        if (strcmp(plan->textures[i].name, name) != 0) continue;
        if (out->sampler_count >= HT_MAX_UNITS) return false;
        out->samplers[out->sampler_count++] = plan->textures[i];
        return true;
    }
    return false;
}

/* ---- the shading model as GLSL ---- */

static bool kajiya_kay(const ht_plan *plan) { return plan->shading.model == HT_MODEL_KAJIYA_KAY; }

void ht_glsl_light_uniforms(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_shading_inputs *in) {
    const char *dp = in->direction_precision, *cp = in->colour_precision;
    ht_strbuf_addf(sb, "uniform %svec3 %s;\n", dp, HT_U_EYE);
    if (plan->light_count <= 0) return;
    ht_strbuf_addf(sb, "uniform %svec4 %s[%d]; /* w = 0: direction towards the light, w = 1: position */\n",
                   dp, HT_U_LIGHT_VECTOR, plan->light_count);
    ht_strbuf_addf(sb, "uniform %svec3 %s[%d];\n", cp, HT_U_LIGHT_COLOR, plan->light_count);
}

/* S(t, e) on unit-or-zero t and h, specialised to one lobe's exponent. */
static void highlight_function(ht_strbuf *sb, const char *name, double exponent, const ht_glsl_shading_inputs *in) {
    const char *dp = in->direction_precision;
    char e[HT_GLSL_FLOAT_SIZE];
    ht_strbuf_addf(sb, "%sfloat %s(%svec3 t, %svec3 h) {\n", dp, name, dp, dp);
    if (exponent == 0.0) {
        /* sin^0 = 1 even at sin = 0, so only the direction test keeps a
           zero t or h from lighting up (model.c: S = 0 without a direction). */
        ht_strbuf_add(sb, "    if (dot(t, t) == 0.0 || dot(h, h) == 0.0) return 0.0;\n");
        ht_strbuf_add(sb, "    return smoothstep(-1.0, 0.0, clamp(dot(t, h), -1.0, 1.0));\n");
    } else {
        /* A zero t or h gives sin = 0 and so S = 0 by itself. pow(0, e) is
           undefined in GLSL, hence the guard; |t x h| is better conditioned
           than sqrt(1 - dot^2) near parallel vectors. */
        ht_strbuf_addf(sb, "    %sfloat c = clamp(dot(t, h), -1.0, 1.0);\n", dp);
        ht_strbuf_addf(sb, "    %sfloat s = min(length(cross(t, h)), 1.0);\n", dp);
        ht_strbuf_addf(sb, "    return smoothstep(-1.0, 0.0, c) * (s > 0.0 ? pow(s, %s) : 0.0);\n",
                       ht_glsl_float(exponent, e));
    }
    ht_strbuf_add(sb, "}\n\n");
}

/* The transmission lobe (model.h's ht_transmission, model.c's
   transmission_unit) on unit-or-zero T, L, V, its constants as literals. */
static void transmission_function(ht_strbuf *sb, const ht_transmission *t, const ht_glsl_shading_inputs *in) {
    const char *dp = in->direction_precision;
    char centre[HT_GLSL_FLOAT_SIZE], sharp[HT_GLSL_FLOAT_SIZE], e[HT_GLSL_FLOAT_SIZE];
    ht_glsl_float(t->centre, centre);
    ht_glsl_float(t->sharpness, sharp);
    ht_glsl_float(t->azimuth, e);
    ht_strbuf_add(sb, "/* Light through the fibre: a lobe in theta_h = (asin(T.L) + asin(T.V)) / 2\n"
                      "   times the azimuth's (1 - cos phi) / 2; none without a direction. */\n");
    ht_strbuf_addf(sb, "%sfloat transmission(%svec3 T, %svec3 L, %svec3 V) {\n", dp, dp, dp, dp);
    ht_strbuf_add(sb, "    if (dot(T, T) == 0.0 || dot(L, L) == 0.0 || dot(V, V) == 0.0) return 0.0;\n");
    ht_strbuf_addf(sb, "    %sfloat tl = dot(T, L);\n", dp);
    ht_strbuf_addf(sb, "    %sfloat tv = dot(T, V);\n", dp);
    ht_strbuf_add(sb, "    /* L or V along T has no azimuth: the zero vector, cos phi = 0. */\n");
    ht_strbuf_addf(sb, "    %sfloat c = dot(normalize_or_zero(L - tl * T), normalize_or_zero(V - tv * T));\n", dp);
    ht_strbuf_addf(sb, "    %sfloat u = (asin(clamp(tl, -1.0, 1.0)) + asin(clamp(tv, -1.0, 1.0))) / 2.0 - %s;\n", dp,
                   centre);
    ht_strbuf_addf(sb, "    %sfloat a = clamp((1.0 - c) / 2.0, 0.0, 1.0);\n", dp);
    /* pow(0, e) is undefined in GLSL; model.c's power: a^0 = 1, 0^e = 0. */
    if (t->azimuth == 0.0) ht_strbuf_addf(sb, "    return exp2(-%s * u * u);\n", sharp);
    else ht_strbuf_addf(sb, "    return exp2(-%s * u * u) * (a > 0.0 ? pow(a, %s) : 0.0);\n", sharp, e);
    ht_strbuf_add(sb, "}\n\n");
}

const char *ht_glsl_transmission_arg(const ht_plan *plan) {
    return ht_model_has_transmission(&plan->shading) ? ", T" : "";
}

void ht_glsl_shading_functions(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_shading_inputs *in) {
    const char *dp = in->direction_precision, *cp = in->colour_precision;
    const ht_shading *m = &plan->shading;
    char lit[HT_GLSL_FLOAT_SIZE], wrap[HT_GLSL_FLOAT_SIZE];
    char diffuse[HT_GLSL_VEC3_SIZE], primary[HT_GLSL_VEC3_SIZE], secondary[HT_GLSL_VEC3_SIZE];

    ht_strbuf_add(sb, "/* Shorter than the model's minimum length: no direction, the zero vector. */\n");
    ht_strbuf_addf(sb, "%svec3 normalize_or_zero(%svec3 v) {\n", dp, dp);
    ht_strbuf_addf(sb, "    %sfloat len2 = dot(v, v);\n", dp);
    ht_strbuf_addf(sb, "    return len2 > %s ? v * inversesqrt(len2) : vec3(0.0);\n",
                   in->min_length2 ? in->min_length2 : ht_glsl_float(HT_MODEL_MIN_LENGTH2, lit));
    ht_strbuf_add(sb, "}\n\n");

    if (!kajiya_kay(plan)) {
        ht_strbuf_add(sb, "/* normalize(T + amount * N); a strand without a direction has none after\n"
                          "   the shift either (T + amount * N alone would turn a zero T into N). */\n");
        ht_strbuf_addf(sb, "%svec3 shifted_tangent(%svec3 T, %svec3 N, %sfloat amount) {\n", dp, dp, dp, dp);
        ht_strbuf_add(sb, "    return dot(T, T) > 0.0 ? normalize_or_zero(T + amount * N) : vec3(0.0);\n");
        ht_strbuf_add(sb, "}\n\n");
    }
    highlight_function(sb, "highlight_primary", m->primary.exponent, in);
    if (!kajiya_kay(plan)) highlight_function(sb, "highlight_secondary", m->secondary.exponent, in);
    /* Without a lobe nothing is written: the text stays byte for byte. */
    const bool tt = ht_model_has_transmission(m);
    if (tt) transmission_function(sb, &m->transmission, in);
    if (plan->light_count <= 0) return;

    ht_glsl_vec3(m->diffuse_color, diffuse);
    ht_glsl_vec3(m->primary.color, primary);
    ht_glsl_vec3(m->secondary.color, secondary);
    ht_strbuf_add(sb, "/* One light's colour before base, light colour and ao; L unit or zero. */\n");
    if (kajiya_kay(plan)) {
        ht_strbuf_addf(sb, "%svec3 hair_light(%svec3 L, %svec3 V, %svec3 T) {\n", cp, dp, dp, dp);
        ht_strbuf_addf(sb, "    %svec3 H = normalize_or_zero(L + V);\n", dp);
        ht_strbuf_add(sb, "    /* sin(T, L): 0 when either has no direction, as their cross product is. */\n");
        ht_strbuf_addf(sb, "    %sfloat diffuse = min(length(cross(T, L)), 1.0);\n", cp);
        ht_strbuf_addf(sb, "    return diffuse * %s + highlight_primary(T, H) * %s;\n", diffuse, primary);
    } else {
        ht_strbuf_addf(sb, "%svec3 hair_light(%svec3 L, %svec3 V, %svec3 N, %svec3 t1, %svec3 t2%s%s", cp, dp, dp,
                       dp, dp, dp, in->sparkle ? ", float " : "", in->sparkle ? "sparkle" : "");
        if (tt) ht_strbuf_addf(sb, ", %svec3 T", dp);
        ht_strbuf_add(sb, ") {\n");
        ht_strbuf_addf(sb, "    %svec3 H = normalize_or_zero(L + V);\n", dp);
        ht_glsl_float(m->wrap, wrap);
        ht_strbuf_addf(sb, "    %sfloat diffuse = clamp(%s + (1.0 - %s) * dot(N, L), 0.0, 1.0);\n", cp, wrap, wrap);
        ht_strbuf_addf(sb, "    %sfloat s1 = highlight_primary(t1, H);\n", cp);
        ht_strbuf_addf(sb, "    %sfloat s2 = highlight_secondary(t2, H)%s;\n", cp, in->sparkle ? " * sparkle" : "");
        ht_strbuf_addf(sb, "    return diffuse * %s + s1 * %s + s2 * %s", diffuse, primary, secondary);
        char transmitted[HT_GLSL_VEC3_SIZE];
        if (tt) ht_strbuf_addf(sb, " + transmission(T, L, V) * %s", ht_glsl_vec3(m->transmission.color, transmitted));
        ht_strbuf_add(sb, ";\n");
    }
    ht_strbuf_add(sb, "}\n\n");
}

/* t = shifted_tangent(T, N, shift + jitter) */
static void shifted_tangent(ht_strbuf *sb, const char *name, double shift, const ht_glsl_shading_inputs *in) {
    char s[HT_GLSL_FLOAT_SIZE];
    ht_glsl_float(shift, s);
    if (in->jitter)
        ht_strbuf_addf(sb, "    %svec3 %s = shifted_tangent(T, N, %s + %s);\n", in->direction_precision, name, s,
                       in->jitter);
    else
        ht_strbuf_addf(sb, "    %svec3 %s = shifted_tangent(T, N, %s);\n", in->direction_precision, name, s);
}

void ht_glsl_shading_body(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_shading_inputs *in) {
    const char *dp = in->direction_precision, *cp = in->colour_precision;
    ht_strbuf_addf(sb, "    %svec3 T = normalize_or_zero(%s);\n", dp, in->tangent);
    if (!kajiya_kay(plan)) ht_strbuf_addf(sb, "    %svec3 N = normalize_or_zero(%s);\n", dp, in->normal);
    ht_strbuf_addf(sb, "    %svec3 V = normalize_or_zero(%s - %s);\n", dp, HT_U_EYE, in->position);
    if (!kajiya_kay(plan)) {
        shifted_tangent(sb, "t1", plan->shading.primary.shift, in);
        shifted_tangent(sb, "t2", plan->shading.secondary.shift, in);
    }
    ht_strbuf_addf(sb, "    %svec3 rgb = vec3(0.0);\n", cp);
    for (int i = 0; i < plan->light_count; i++) {
        if (plan->light_types[i] == HT_LIGHT_POINT)
            ht_strbuf_addf(sb, "    %svec3 L%d = normalize_or_zero(%s[%d].xyz - %s);\n", dp, i,
                           HT_U_LIGHT_VECTOR, i, in->position);
        else
            ht_strbuf_addf(sb, "    %svec3 L%d = normalize_or_zero(%s[%d].xyz);\n", dp, i, HT_U_LIGHT_VECTOR, i);
        if (kajiya_kay(plan))
            ht_strbuf_addf(sb, "    rgb += hair_light(L%d, V, T)", i);
        else
            ht_strbuf_addf(sb, "    rgb += hair_light(L%d, V, N, t1, t2%s%s%s)", i, in->sparkle ? ", " : "",
                           in->sparkle ? in->sparkle : "", ht_glsl_transmission_arg(plan));
        /* model.c's order: lit * base * light colour * ao, per light. */
        if (in->base) ht_strbuf_addf(sb, " * %s", in->base);
        ht_strbuf_addf(sb, " * %s[%d]", HT_U_LIGHT_COLOR, i);
        if (in->ao) ht_strbuf_addf(sb, " * %s", in->ao);
        ht_strbuf_add(sb, ";\n");
    }
}

/* glsl_stages.c — see glsl_stages.h. */
#include "glsl_stages.h"

#include <stdio.h>
#include <string.h>

#include "shader_interface.h"

void ht_glsl_varyings(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_vertex_layout *l, const char *dp,
                      const char *cp) {
    ht_strbuf_addf(sb, "varying %svec3 v_position; /* world space */\n", dp);
    ht_strbuf_addf(sb, "varying %svec3 v_tangent;\n", dp);
    if (l->normal) ht_strbuf_addf(sb, "varying %svec3 v_normal;\n", dp);
    /* uv addresses texels: mediump's 11-bit mantissa is a whole texel of a
       2048 texture near uv = 1, so it gets the direction precision. */
    if (l->uv) ht_strbuf_addf(sb, "varying %svec2 v_uv;\n", dp);
    if (plan->ao) ht_strbuf_addf(sb, "varying %sfloat v_ao;\n", cp);
}

void ht_glsl_width_rule_inputs(ht_strbuf *sb) {
    ht_strbuf_addf(sb, "attribute vec3 %s; /* the offset from the ribbon's centre line */\n", HT_ATTR_SIDE);
    ht_strbuf_addf(sb, "uniform float %s; /* the width rule per vertex: the least drawn width at w = 1; 0: off */\n",
                   HT_U_WIDTH_RULE);
    ht_strbuf_addf(sb, "varying float %s; /* its own width / its drawn width */\n", HT_V_WIDTH_ALPHA);
}

void ht_glsl_width_rule_position(ht_strbuf *sb, const char *position, const char *mvp) {
    ht_strbuf_addf(sb, "    vec4 position = vec4(%s, 1.0);\n", position);
    ht_strbuf_addf(sb, "    %s = 1.0;\n", HT_V_WIDTH_ALPHA);
    ht_strbuf_add(sb, "    /* The width rule per vertex (docs/lod.md): a ribbon narrower here is drawn\n"
                      "       that wide (about a pixel) about its centre line, its alpha scaled by the ratio. */\n");
    ht_strbuf_addf(sb, "    float half_width = length(%s);\n", HT_ATTR_SIDE);
    ht_strbuf_addf(sb, "    if (%s > 0.0 && half_width > 0.0) {\n", HT_U_WIDTH_RULE);
    ht_strbuf_addf(sb, "        float widen = clamp((%s * position).w * %s / (2.0 * half_width), 1.0, 1024.0);\n", mvp,
                   HT_U_WIDTH_RULE);
    ht_strbuf_addf(sb, "        position.xyz += %s * (widen - 1.0);\n", HT_ATTR_SIDE);
    ht_strbuf_addf(sb, "        %s = 1.0 / widen;\n", HT_V_WIDTH_ALPHA);
    ht_strbuf_add(sb, "    }\n");
}

void ht_glsl_width_rule_transform(ht_strbuf *sb, bool es) {
    if (es) {
        ht_strbuf_addf(sb, "    gl_Position = %s * position;\n", HT_ES_U_MVP);
        return;
    }
    ht_strbuf_add(sb, "    /* ftransform(): depth bit-identical to every pass of every tier (with the\n"
                      "       width rule the hair's passes share this program's invariant transform). */\n");
    ht_strbuf_addf(sb, "    gl_Position = %s > 0.0 ? gl_ModelViewProjectionMatrix * position : ftransform();\n",
                   HT_U_WIDTH_RULE);
}

char *ht_glsl_main_vertex(const ht_plan *plan, const ht_glsl_vertex_layout *l, bool es) {
    ht_strbuf sb;
    ht_strbuf_init(&sb);
    ht_strbuf_add(&sb, es ? "#version 100\n" : "#version 120\n");
    l->banner(&sb, plan, es ? "ESSL vertex stage" : "vertex stage");
    if (es) {
        ht_strbuf_addf(&sb, "uniform mat4 %s;\n", HT_ES_U_MVP);
        ht_strbuf_addf(&sb, "attribute vec3 %s;\n", HT_ES_ATTR_POSITION);
    } else {
        ht_strbuf_add(&sb, "invariant gl_Position;\n");
        ht_strbuf_add(&sb, "/* Generic attributes, not texture coordinates: a device may have only\n"
                           "   one coordinate set (shader_interface.h). */\n");
    }
    ht_strbuf_addf(&sb, "attribute vec3 %s;\n", HT_ATTR_TANGENT);
    if (es) {
        if (l->normal) ht_strbuf_addf(&sb, "attribute vec3 %s;\n", HT_ES_ATTR_NORMAL);
        if (l->uv) ht_strbuf_addf(&sb, "attribute vec2 %s;\n", HT_ES_ATTR_UV);
    }
    if (plan->ao) ht_strbuf_addf(&sb, "attribute float %s;\n", HT_ATTR_AO);
    ht_glsl_width_rule_inputs(&sb);
    ht_glsl_varyings(&sb, plan, l, "", "");
    ht_strbuf_add(&sb, "\nvoid main() {\n");
    ht_glsl_width_rule_position(&sb, es ? HT_ES_ATTR_POSITION : "gl_Vertex.xyz",
                                es ? HT_ES_U_MVP : "gl_ModelViewProjectionMatrix");
    ht_glsl_width_rule_transform(&sb, es);
    ht_strbuf_add(&sb, "    v_position = position.xyz; /* the model matrix is identity */\n");
    if (es) {
        if (l->normal) ht_strbuf_addf(&sb, "    v_normal = %s;\n", HT_ES_ATTR_NORMAL);
        if (l->uv) ht_strbuf_addf(&sb, "    v_uv = %s;\n", HT_ES_ATTR_UV);
    } else {
        if (l->normal) ht_strbuf_add(&sb, "    v_normal = gl_Normal;\n");
        if (l->uv) ht_strbuf_add(&sb, "    v_uv = gl_MultiTexCoord0.xy;\n");
    }
    ht_strbuf_addf(&sb, "    v_tangent = %s;\n", HT_ATTR_TANGENT);
    if (plan->ao) ht_strbuf_addf(&sb, "    v_ao = %s;\n", HT_ATTR_AO);
    ht_strbuf_add(&sb, "}\n");
    return ht_strbuf_take(&sb);
}

void ht_glsl_opacity_uniform(ht_strbuf *sb) {
    ht_strbuf_addf(sb, "uniform float %s; /* the width rule: alpha x (1 - this) */\n", HT_U_OPACITY_CUT);
    ht_strbuf_addf(sb, "varying float %s; /* the width rule per vertex: alpha x this */\n", HT_V_WIDTH_ALPHA);
}

void ht_glsl_alpha_output(ht_strbuf *sb, const char *rgb, const char *alpha, bool es_discard) {
    ht_strbuf_addf(sb, "    float drawn_alpha = %s * (1.0 - %s) * %s;\n", alpha, HT_U_OPACITY_CUT, HT_V_WIDTH_ALPHA);
    if (es_discard)
        ht_strbuf_addf(sb, "    if ((drawn_alpha >= %s) != (%s > 0.5)) discard;\n", HT_ES_U_ALPHA_REF,
                       HT_ES_U_ALPHA_PASS_OPAQUE);
    ht_strbuf_addf(sb, "    gl_FragColor = vec4(%s, drawn_alpha);\n", rgb);
}

/* The Z-prime pass writes no colour: transform, and alpha for the test. */
char *ht_glsl_prime_stage(const ht_plan *plan, ht_glsl_banner_fn banner, bool fragment) {
    ht_strbuf sb;
    ht_strbuf_init(&sb);
    ht_strbuf_add(&sb, "#version 120\n");
    banner(&sb, plan, fragment ? "Z-prime fragment stage" : "Z-prime vertex stage");
    if (fragment && plan->alpha) ht_strbuf_addf(&sb, "uniform sampler2D %s; /* a = alpha */\n", HT_U_ALBEDO);
    if (plan->alpha) ht_strbuf_add(&sb, "varying vec2 v_uv;\n");
    if (fragment) ht_glsl_opacity_uniform(&sb);
    else {
        ht_strbuf_add(&sb, "invariant gl_Position;\n");
        ht_glsl_width_rule_inputs(&sb);
    }
    ht_strbuf_add(&sb, "\nvoid main() {\n");
    if (!fragment) {
        ht_glsl_width_rule_position(&sb, "gl_Vertex.xyz", "gl_ModelViewProjectionMatrix");
        ht_glsl_width_rule_transform(&sb, false);
        if (plan->alpha) ht_strbuf_add(&sb, "    v_uv = gl_MultiTexCoord0.xy;\n");
    } else {
        char alpha[64];
        snprintf(alpha, sizeof alpha, plan->alpha ? "texture2D(%s, v_uv).a" : "1.0", HT_U_ALBEDO);
        ht_glsl_alpha_output(&sb, "vec3(1.0)", alpha, false);
    }
    ht_strbuf_add(&sb, "}\n");
    return ht_strbuf_take(&sb);
}

/* ---- ESSL 3.00 from ESSL 1.00 ---- */

static bool ident_char(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
}

/* The identifiers ESSL 3.00 renamed or dropped, per stage. */
typedef struct rename_rule { const char *from, *to; } rename_rule;
static const rename_rule vertex_renames[] = { { "attribute", "in" }, { "varying", "out" }, { NULL, NULL } };
static const rename_rule fragment_renames[] = { { "varying", "in" },
                                                { "texture2D", "texture" },
                                                { "gl_FragColor", HT_ES3_FRAG_COLOR },
                                                { NULL, NULL } };

char *ht_glsl_essl3_from_essl1(const char *text, bool fragment) {
    static const char v100[] = "#version 100\n";
    if (!text || strncmp(text, v100, sizeof v100 - 1) != 0) return NULL;
    const rename_rule *rules = fragment ? fragment_renames : vertex_renames;
    ht_strbuf sb;
    ht_strbuf_init(&sb);
    ht_strbuf_add(&sb, "#version 300 es\n");
    bool declared = !fragment;
    for (const char *p = text + sizeof v100 - 1; *p;) {
        const bool line_start = p[-1] == '\n';
        /* gl_FragColor's stand-in is declared once, before main (after the
           default precision statement, which every fragment text has). */
        if (!declared && line_start && strncmp(p, "void main(", 10) == 0) {
            ht_strbuf_addf(&sb, "out vec4 %s;\n\n", HT_ES3_FRAG_COLOR);
            declared = true;
        }
        if (ident_char(*p) && !ident_char(p[-1])) {
            size_t n = 0;
            while (ident_char(p[n])) n++;
            const char *to = NULL;
            for (const rename_rule *r = rules; r->from; r++)
                if (strlen(r->from) == n && strncmp(p, r->from, n) == 0) to = r->to;
            if (to) ht_strbuf_add(&sb, to);
            else ht_strbuf_addn(&sb, p, n);
            p += n;
            continue;
        }
        ht_strbuf_addn(&sb, p++, 1);
    }
    return ht_strbuf_take(&sb);
}

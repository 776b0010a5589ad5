/* glsl_stages.h — the GLSL stages the per-pixel tiers (full, marschner)
   share: the varyings, the main vertex stage (GLSL 1.20 and ESSL 1.00) and
   the alpha-only Z-prime pair. Each tier brings its own banner comment and
   says which varyings its fragment stage reads. */
#ifndef HT_GLSL_STAGES_H
#define HT_GLSL_STAGES_H

#include <stdbool.h>

#include "hairgen_internal.h"
#include "strbuf.h"

/* Writes the tier's comment for one stage ("vertex stage", ...). */
typedef void (*ht_glsl_banner_fn)(ht_strbuf *sb, const ht_plan *plan, const char *what);

typedef struct ht_glsl_vertex_layout {
    ht_glsl_banner_fn banner;
    bool normal; /* v_normal: the shading reads N */
    bool uv;     /* v_uv: some texture is sampled */
} ht_glsl_vertex_layout;

/* v_position, v_tangent, and v_normal, v_uv, v_ao as the layout and plan
   ask; dp and cp are the direction and colour precision qualifiers ("" on
   desktop). */
void ht_glsl_varyings(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_vertex_layout *l, const char *dp,
                      const char *cp);
/* The main vertex stage (malloc'd): GLSL 1.20 with ftransform(), or ESSL
   1.00 with the MVP uniform and generic attributes. */
char *ht_glsl_main_vertex(const ht_plan *plan, const ht_glsl_vertex_layout *l, bool es);
/* The width rule per vertex (shader_interface.h) in a vertex stage: its
   declarations (a_side, u_width_rule, v_width_alpha); main's first lines,
   `vec4 position` (position widened, v_width_alpha set) from the vertex
   position expression and the MVP expression; and gl_Position from it
   (ES: the MVP uniform; desktop: ftransform() while the rule is off). */
void ht_glsl_width_rule_inputs(ht_strbuf *sb);
void ht_glsl_width_rule_position(ht_strbuf *sb, const char *position, const char *mvp);
void ht_glsl_width_rule_transform(ht_strbuf *sb, bool es);
/* The width rule's uniform and varying (shader_interface.h) and a
   fragment stage's last lines: alpha scaled by both, ES's discard against the pass's rule on
   that drawn alpha, gl_FragColor = vec4(rgb, drawn alpha). */
void ht_glsl_opacity_uniform(ht_strbuf *sb);
void ht_glsl_alpha_output(ht_strbuf *sb, const char *rgb, const char *alpha, bool es_discard);

/* The Z-prime stage (malloc'd): position only, and the albedo's alpha for
   the alpha test when the plan has alpha. */
char *ht_glsl_prime_stage(const ht_plan *plan, ht_glsl_banner_fn banner, bool fragment);

/* The ESSL 3.00 text (malloc'd) of an ESSL 1.00 one: "#version 300 es",
   attribute/varying as in/out, texture2D as texture, gl_FragColor as an
   output declared before main. One mechanical rule, so the two ES texts
   of a tier cannot drift apart; NULL when text is not ESSL 1.00. */
char *ht_glsl_essl3_from_essl1(const char *text, bool fragment);

#endif

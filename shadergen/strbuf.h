/* strbuf.h — what the emitters share (strbuf.c, emit_common.c): a growable
   string builder, locale-independent GLSL float literals, filling an
   ht_tier_output, and the shading model written out as GLSL for the full
   and vertex tiers.

   Usage:
       ht_strbuf sb;
       ht_strbuf_init(&sb);
       ht_strbuf_addf(&sb, "const float k = %s;\n", ht_glsl_float(0.25, lit));
       char *text = ht_strbuf_take(&sb);      // NULL when memory ran out
       r = ht_output_add_text(out, "full.frag", "fragment", text,
                              HT_STAGE_FRAGMENT, 120, false, err, err_size);

   Numbers never go through printf's %f/%g: those follow LC_NUMERIC and would
   write "0,5" under some locales. */
#ifndef HT_STRBUF_H
#define HT_STRBUF_H

#include <stdbool.h>
#include <stddef.h>

#include "emit.h"

typedef struct ht_strbuf {
    char *data;      /* NUL-terminated while not failed */
    size_t len, cap;
    bool failed;     /* an allocation failed; later appends are ignored */
} ht_strbuf;

void ht_strbuf_init(ht_strbuf *sb);
void ht_strbuf_add(ht_strbuf *sb, const char *s);
/* The first n bytes of s (no NUL among them). */
void ht_strbuf_addn(ht_strbuf *sb, const char *s, size_t n);
void ht_strbuf_addf(ht_strbuf *sb, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* The text, owned by the caller (free()); NULL when an allocation failed.
   Leaves sb empty either way. */
char *ht_strbuf_take(ht_strbuf *sb);
void ht_strbuf_free(ht_strbuf *sb);

#define HT_GLSL_FLOAT_SIZE 32

/* The shortest decimal that reads back as the same 32-bit float, written as
   a literal GLSL 1.10 and ESSL 1.00 both accept ("1.0", "-0.1", "0.25",
   "1.0e-06"): always a '.', never a suffix, never "-0.0". Non-finite input
   (never expected) is written as "0.0". Returns out. */
const char *ht_glsl_float(double v, char out[HT_GLSL_FLOAT_SIZE]);

/* "vec3(a, b, c)" of three such literals. */
#define HT_GLSL_VEC3_SIZE (3 * HT_GLSL_FLOAT_SIZE + 16)
const char *ht_glsl_vec3(const double v[3], char out[HT_GLSL_VEC3_SIZE]);

/* ---- ht_tier_output (emit_common.c) ---- */

/* Appends a text file, taking ownership of text (freed on failure too).
   GLSL texts (stage != HT_STAGE_NONE) are validated first; a failure is
   HT_ERR_COMPILE with "FILE: " and glslang's log in err. A NULL text is
   HT_ERR_OUT_OF_MEMORY. */
ht_result ht_output_add_text(ht_tier_output *out, const char *file, const char *role, char *text,
                             ht_stage stage, int glsl_version, bool es, char *err, size_t err_size);
/* The tier's GL ES texts from its ESSL 1.00 pair (ownership taken):
   STEM-es3.vert/.frag (ESSL 3.00, converted by ht_glsl_essl3_from_essl1)
   and STEM-es2.vert/.frag (ESSL 1.00), each validated at its ES version, and
   their two "es" entries (ES 3.0 first) with the fragment precision the
   text needs ("highp" or "mediump"). */
ht_result ht_output_add_es_pair(ht_tier_output *out, const char *stem, char *vertex100, char *fragment100,
                                const char *precision, char *err, size_t err_size);
/* One more "es" entry naming texts already added (a variant sharing a
   vertex stage, e.g. a mediump fragment text); false when the list is full. */
bool ht_output_add_es_entry(ht_tier_output *out, const char *version, const char *essl, const char *precision,
                            const char *vertex, const char *fragment);
void ht_output_add_feature(ht_tier_output *out, const char *feature);
void ht_output_add_dropped(ht_tier_output *out, const char *reason);
/* "transmission: WHY" in dropped when the plan's shading has a
   transmission lobe the tier does not draw; nothing otherwise. */
void ht_output_drop_transmission(ht_tier_output *out, const ht_plan *plan, const char *why);
/* "scheuermann", "1 directional light", "2 point lights", ...: the model and
   lights of the plan, in the order bundles list them. */
void ht_output_add_model_features(ht_tier_output *out, const ht_plan *plan);
/* Copies the plan texture called name into out->samplers; false if absent. */
bool ht_output_add_sampler(ht_tier_output *out, const ht_plan *plan, const char *name);

/* ---- the shading model as GLSL (emit_common.c) ---- */

/* What the lighting code reads: GLSL expressions of the shader it is
   written into. NULL means "not modelled here" (1 for sparkle, base and
   ao; no jitter). */
typedef struct ht_glsl_shading_inputs {
    const char *position;  /* vec3, world space */
    const char *tangent;   /* vec3, any length */
    const char *normal;    /* vec3, any length */
    const char *jitter;    /* float: shift(uv) - 0.5 */
    const char *sparkle;   /* float */
    const char *base;      /* vec3 */
    const char *ao;        /* float */
    /* Precision qualifiers with a trailing space, "" on desktop GLSL:
       direction is used for vectors and the highlight, colour for colours. */
    const char *direction_precision;
    const char *colour_precision;
    /* Squared length below which a vector has no direction; NULL →
       HT_MODEL_MIN_LENGTH2 (a mediump fallback needs a representable one). */
    const char *min_length2;
} ht_glsl_shading_inputs;

/* The uniforms u_eye, u_light_vector[n], u_light_color[n] of the plan's
   light count (nothing of the light arrays when it is 0). */
void ht_glsl_light_uniforms(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_shading_inputs *in);
/* The functions the lighting needs (normalize_or_zero, the highlights of
   the plan's lobes, the per-light term), before main(). */
void ht_glsl_shading_functions(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_shading_inputs *in);
/* ", T" when the plan draws a transmission lobe (hair_light's last
   argument, the unshifted tangent), else "": for a caller's own calls. */
const char *ht_glsl_transmission_arg(const ht_plan *plan);
/* Statements inside main() that declare and sum `rgb` over the plan's
   lights, exactly as runtime/shading/model.c does. */
void ht_glsl_shading_body(ht_strbuf *sb, const ht_plan *plan, const ht_glsl_shading_inputs *in);

#endif

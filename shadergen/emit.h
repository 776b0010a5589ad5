/* emit.h — what each tier's emitter produces: text files (shaders, the
   combiner program), images (lookup textures), requirements and the
   features it models or drops. generate.c hands these out unchanged. */
#ifndef HT_EMIT_H
#define HT_EMIT_H

#include "hairgen_internal.h"

typedef enum ht_stage {
    HT_STAGE_NONE = 0,   /* not GLSL (the combiner program) */
    HT_STAGE_VERTEX,
    HT_STAGE_FRAGMENT,
} ht_stage;

typedef struct ht_out_text {
    char file[48];       /* "full.vert", "full-es2.frag", "fixed.json" */
    char role[24];       /* manifest key: "vertex", "fragment", "prime_vertex",
                            "prime_fragment", "program"; "" for an ES text, named by an es entry */
    char *text;          /* malloc'd, NUL-terminated */
    ht_stage stage;
    int glsl_version;    /* 110, 120, 100 (ES) */
    bool es;
} ht_out_text;

typedef struct ht_out_image {
    char name[24];       /* manifest key: "fixed-lut" */
    char file[48];       /* "fixed-lut.png" */
    ht_image image;      /* a 3D texture is stored as depth slices stacked vertically */
    int depth;           /* 1 for 2D */
    char contents[96];
} ht_out_image;

/* One GL ES target of a GLSL tier: the manifest's "es" list (docs/bundle.md).
   Its texts are in texts[] with an empty role (they are not desktop files). */
typedef struct ht_out_es {
    char version[8];     /* the lowest ES version: "2.0", "3.0" */
    char essl[8];        /* "1.00", "3.00" */
    char precision[8];   /* the fragment precision the text needs: "highp", "mediump" */
    char vertex[48], fragment[48];
} ht_out_es;

#define HT_OUT_MAX_TEXTS 12
#define HT_OUT_MAX_ES 4
#define HT_OUT_MAX_IMAGES 2
#define HT_OUT_MAX_LIST 16

typedef struct ht_tier_output {
    ht_tier tier;
    struct {
        char gl[8];                        /* "2.1" */
        char glsl[8];                      /* "1.20", "" for none */
        char extensions[4][40];
        int extension_count;
        int texture_units;
    } requires;
    ht_out_text texts[HT_OUT_MAX_TEXTS];
    int text_count;
    ht_out_image images[HT_OUT_MAX_IMAGES];
    int image_count;
    ht_out_es es[HT_OUT_MAX_ES];           /* best first: ES 3.0, then ES 2.0 */
    int es_count;
    ht_plan_texture samplers[HT_MAX_UNITS]; /* plan textures this tier binds, with units */
    int sampler_count;
    char features[HT_OUT_MAX_LIST][64];
    int feature_count;
    char dropped[HT_OUT_MAX_LIST][160];
    int dropped_count;
    /* full only: its mediump fragment variant's 8-bit error as the fp16
       mirror measures it against the tier's model (mediump_measure.h);
       samples 0 when the tier has no such variant. */
    struct {
        long samples;
        int max_byte, opposite_max_byte; /* opposite: some light within HT_MP_OPPOSITE of L = -V */
    } mediump;
} ht_tier_output;

void ht_tier_output_free(ht_tier_output *out);

/* Each returns HT_OK or HT_ERR_COMPILE with glslang's log in err. Every GLSL
   text is validated with ht_glsl_validate before it is returned. */
ht_result ht_emit_full(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size);
/* Fills out->mediump (the full tier's, emitted from plan): its mediump
   variant's error under the scene's lights, with and without fp16
   subnormals (the larger), on 2048 random directions (~0.05 s; the
   generator's build runs it, ht_emit_full alone does not). */
void ht_emit_full_mediump_error(const ht_plan *plan, ht_tier_output *out);
ht_result ht_emit_vertex(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size);
ht_result ht_emit_fixed(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size);
/* HT_ERR_UNSUPPORTED (err says why) when the plan needs what the tier
   cannot do on the device (a point light among the two it lights): the
   generator then leaves the tier out of the bundle. */
ht_result ht_emit_fixed4(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size);
/* Model "marschner" only (HT_ERR_UNSUPPORTED otherwise): the fibre from
   lookup textures baked by marschner_lut.c. */
ht_result ht_emit_marschner(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size);
/* The last resort: GL 1.1, one unit, the model per vertex on the CPU. */
ht_result ht_emit_gl11(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size);

/* The fixed4 program of a plan (emit_fixed4.c): unmasked shading, the
   first two lights, LUT axes from the exponents, infinite viewer. The
   vertex tier writes the same program for the runtime to bake its LUTs. */
struct ht_fixed4_program;
void ht_fixed4_program_from_plan(const ht_plan *plan, struct ht_fixed4_program *p);

/* Texels a LUT axis holding a highlight of exponent e needs, before the
   [16, 256] clamp: next power of two of 8 sqrt(e) (emit_fixed.c). */
int ht_lut_highlight_texels(double e);

/* glslang's C API, in process: preprocess + parse at exactly this version
   and profile (es → ESSL), once per distinct text per process (a text that
   passed is remembered). log receives glslang's info log on failure.
   Thread-safe. */
ht_result ht_glsl_validate(const char *source, ht_stage stage, int version, bool es,
                           char *log, size_t log_size);
/* How many ht_glsl_validate calls in this process parsed their text and
   how many found it validated already (the same text, stage, version and
   profile): a batch parses each distinct text once. */
void ht_glsl_validate_counts(unsigned long *parsed, unsigned long *reused);
/* The textures the GLSL tiers sample, packed as the plan says:
   "albedo" = base.rgb + alpha.a, "detail" = shift.r + sparkle.g. An image
   whose plan texture is absent is left zeroed (pixels NULL). The two steps
   below, one after the other. */
ht_result ht_textures_pack(const ht_material *m, const ht_plan *plan,
                           ht_image *albedo, ht_image *detail, char *err, size_t err_size);
/* One slot's texture when the plan models it (img zeroed otherwise); a
   file's error names the material field. The slots are independent. */
ht_result ht_texture_make_slot(const ht_material *m, const ht_plan *plan, ht_texture_slot slot, ht_image *img,
                               char *err, size_t err_size);
/* The four slots' textures (made, indexed by slot; freed here) checked
   against the bundle's size limits and packed into albedo and detail. */
ht_result ht_textures_pack_made(const ht_material *m, const ht_plan *plan, ht_image made[HT_TEX_COUNT],
                                ht_image *albedo, ht_image *detail, char *err, size_t err_size);

#endif

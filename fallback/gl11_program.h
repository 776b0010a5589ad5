/* gl11_program.h — the `gl11` tier, the last resort: OpenGL 1.1, one
   texture unit, no texture_env_combine, no multitexture, no shaders, no
   buffer objects. The whole model is evaluated per vertex on the CPU and
   reaches GL as the colour array; the one unit modulates it by the albedo.

   Per vertex (ht_gl11_shade, 32-bit float, structure of arrays):
       V      = normalize(eye - position)                    local viewer
       L_l    = normalize(light vector)  or normalize(light position - position)
       colour = ao * sum over the planned lights of
                (diff_l + spec_l + tt_l) * light colour_l / albedo_scale
   with diff and spec as include/hairtier/model.h (Scheuermann: wrapped diffuse and
   two shifted highlights and, when the material has one, the transmission
   lobe tt; Kajiya-Kay: sin(T,L) and one highlight), the
   shift texture at its centre (no jitter) and the sparkle texture replaced
   by its mean (already in secondary.color), alpha 1. Where the model has a
   documented answer (model.c: zero tangent, L = -V, ...) this gives it too.
   Per pixel GL does: fragment = texture(albedo x albedo_scale) x colour
   (GL_MODULATE), so rgb = albedo x colour as the model's base x lighting;
   the per-vertex colour clamps to [0, 1] in GL (1.1 has no RGB_SCALE), so
   lighting above albedo_scale clamps. albedo_scale = the headroom the
   albedo leaves: 1 / its brightest rgb channel, in [1, 4] (the generator
   measures it), so a dark albedo keeps lighting up to albedo_scale.

   The program ("gl11.json", format "hairtier-gl11/1") holds the material
   constants: model, lights, ao, albedo_scale, diffuse, primary, secondary,
   and "transmission" (model.h's ht_transmission) only when it draws one.

   Usage (gl11.c does this):
       ht_gl11_program p;
       ht_gl11_parse(text, "gl11.json", &p, err, sizeof err);
       ht_gl11_soa soa;
       ht_gl11_soa_make(&p, vertices, n, &soa);                 // once per mesh
       float *rgba = malloc(4 * soa.padded * sizeof(float));
       ht_gl11_shade(&p, &soa, lights, light_count, eye, rgba);  // when the eye or a light changed
       ht_gl11_soa_free(&soa); */
#ifndef HT_GL11_PROGRAM_H
#define HT_GL11_PROGRAM_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include <hairtier/model.h>

#define HT_GL11_FORMAT "hairtier-gl11/1"
#define HT_GL11_MAX_SCALE 4.0
/* The shading loops run over whole blocks (the arrays are padded), so GCC's
   -O2 vectoriser needs no scalar epilogue. */
#define HT_GL11_BLOCK 8

typedef struct ht_gl11_program {
    ht_shading shading;   /* secondary.color already scaled by the sparkle mean */
    int lights;           /* 0..HT_MAX_LIGHTS: the planned lights, every one shaded */
    bool ao;              /* colour x ao, else x 1 */
    double albedo_scale;  /* [1, 4]: albedo rgb uploaded x this, vertex colours / this */
} ht_gl11_program;

ht_result ht_gl11_validate(const ht_gl11_program *p, char *err, size_t err_size);
/* JSON text (malloc'd); same program, byte-identical text. */
ht_result ht_gl11_write(const ht_gl11_program *p, char **text, char *err, size_t err_size);
/* Errors "FILE: FIELD: what is wrong". */
ht_result ht_gl11_parse(const char *json_text, const char *file_name, ht_gl11_program *out, char *err,
                        size_t err_size);

/* albedo_scale for an albedo whose brightest rgb channel is max_rgb in
   [0, 1]: 1 / max_rgb clamped to [1, HT_GL11_MAX_SCALE]. */
double ht_gl11_albedo_scale(double max_rgb);

/* Structure-of-arrays inputs, filled once per mesh: one float array per
   component, `padded` (count rounded up to HT_GL11_BLOCK) long, the
   padding zero. t1, t2 = normalize(T + shift N) per lobe (Kajiya-Kay: T
   twice), zero when T has no direction; N unit or zero; ao in [0, 1] (1
   when the program has no ao). The scratch arrays are the shading's. */
enum {
    HT_GL11_PX, HT_GL11_PY, HT_GL11_PZ,
    HT_GL11_NX, HT_GL11_NY, HT_GL11_NZ,
    HT_GL11_T1X, HT_GL11_T1Y, HT_GL11_T1Z,
    HT_GL11_T2X, HT_GL11_T2Y, HT_GL11_T2Z,
    HT_GL11_AO,
    HT_GL11_TX, HT_GL11_TY, HT_GL11_TZ, /* T unit or zero, for the transmission lobe */
    /* scratch: V, one light's H, the running sums */
    HT_GL11_VX, HT_GL11_VY, HT_GL11_VZ,
    HT_GL11_HX, HT_GL11_HY, HT_GL11_HZ,
    HT_GL11_R, HT_GL11_G, HT_GL11_B,
    HT_GL11_ARRAYS
};

typedef struct ht_gl11_soa {
    size_t count;                    /* vertices */
    size_t padded;                   /* count rounded up to HT_GL11_BLOCK (at least one block) */
    float *a[HT_GL11_ARRAYS];        /* slices of one allocation */
} ht_gl11_soa;

ht_result ht_gl11_soa_make(const ht_gl11_program *p, const ht_vertex *v, size_t count, ht_gl11_soa *out);
void ht_gl11_soa_free(ht_gl11_soa *soa);

/* The per-vertex colours: rgba (4 x soa->padded floats) = the colour
   above, not clamped (GL clamps), alpha 1. Lights: the first
   min(light_count, p->lights); a directional light's vector points towards
   it, a point light's is its position; any length (zero: no direction, as
   model.c). Always finite for finite input. */
void ht_gl11_shade(const ht_gl11_program *p, ht_gl11_soa *soa, const ht_light *lights, int light_count,
                   const float eye[3], float *rgba);
/* The same for vertices [first, first + count) only (rgba indexed as for
   the whole soa), widened to whole blocks of HT_GL11_BLOCK: a draw
   range's per-frame work. Returns how many vertices it shaded. */
size_t ht_gl11_shade_range(const ht_gl11_program *p, ht_gl11_soa *soa, size_t first, size_t count,
                           const ht_light *lights, int light_count, const float eye[3], float *rgba);

#endif

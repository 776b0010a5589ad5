/* emit_fixed.c — the fixed tier: a GL 1.3 texture-combiner program
   (fixed.json, fallback/combiner.h) and the lookup texture it reads
   (fixed-lut.png), baked from ht_model_dot_terms_d. No shader anywhere.

   LUT axes (combiner.h): Scheuermann (N.L, t1.H, t2.H) as a 3D texture,
   Kajiya-Kay (T.L, T.H) as a 2D one. Each axis is sized from what it holds:
     - a highlight S(d) = smoothstep(-1,0,d) (1-d^2)^(e/2) is a lobe of width
       ~1/sqrt(e) around d = 0; linear interpolation wants >= 4 texels per
       lobe width, so n = next power of two of 8 sqrt(e), clamped to [16,256].
       Above e ~ 1000 the clamp leaves the lobe under ~4 texels: it is
       widened and its peak, read between the two texels nearest d = 0, drops
       to S(1/255) (0.992 at e = 1000, 0.93 at e = 10000); the dropped list
       says so with the number.
     - wrapped diffuse is piecewise linear, exact under linear interpolation
       but for its one kink: 32 texels (16 when the texel budget is short).
     - Kajiya-Kay's sin(T,L) = sqrt(1 - a^2) has an infinite slope at a = +-1,
       where interpolation error falls only as sqrt(texel): 256 texels, cheap
       in a 2D texture.
     - a highlight with 0 < e < 2 has the same infinite slope at d = +-1:
       256 texels; below e ~ 0.5 the drop to 0 at d = +-1 still spans a
       texel (a known approximation at grazing t, H).
     - a term whose colour is 0 needs no resolution: 1 texel.
   Budget, a 2D LUT (Kajiya-Kay): at most 2^20 texels (4 MiB even if the
   driver widens RGB8 to RGBA8): the diffuse axis drops to 16 first, then
   the larger highlight axis halves. A 3D LUT (Scheuermann): at most 16
   depth slices (the t2.H axis) and 2^14 texels, the larger of the other
   two axes halving until it fits: a 3D fetch on a software rasteriser
   costs more the larger the LUT, mostly its slices, while the error fixed
   keeps is full's jitter and sparkle, not the LUT's resolution
   (docs/performance.md, docs/accuracy.md). Every shipped
   Scheuermann material gets 32 x 32 x 16.

   Coordinates (combiner.h): Kajiya-Kay under a directional key light gets
   "texture-matrix" (T as texture coordinate, (T.L, T.H) from the texture
   matrix, the viewer taken at infinity for H, listed as dropped); every
   other program "cpu-dots" (Scheuermann's shifted tangents, a point
   light's per-vertex L).

   Everything stored is dot_terms / scale in 8 bits, scale the smallest of
   1, 2, 4 at or above ht_model_dot_terms_max: the LUT error is at most
   0.5/255 x scale plus linear interpolation between texels. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "combiner.h"
#include "emit.h"
#include "strbuf.h"

#define LUT_NAME "fixed-lut"
#define MAX_TEXELS (1 << 20)
#define MAX_3D_TEXELS (1 << 14)
#define MAX_3D_DEPTH 16
#define MIN_AXIS 16
#define MAX_AXIS 256
#define DIFFUSE_AXIS 32
#define KAJIYA_KAY_DIFFUSE_AXIS 256
/* An extra light gets a sub-pass when its diffuse term (light colour x
   diffuse colour, brightest channel, before the base colour) can reach
   32/255: a broad term over the whole side a light faces, which at that
   size costs about the tier's 28 dB target by itself (blond's fills,
   0.20-0.27, took its fur ball to 27.7 dB and its back-lit scene to 26.6
   dB without a sub-pass). A dimmer light shows in narrow highlights only:
   dark-brown's fills (0.06-0.09) cost it 0-2.9 dB, not worth the lit
   passes' geometry a second time (1.9x full on llvmpipe).
   docs/accuracy.md and docs/performance.md have the measurements. */
#define FILL_MIN_DIFFUSE (32.0 / 255.0)

static bool is_black(const double c[3]) { return c[0] <= 0.0 && c[1] <= 0.0 && c[2] <= 0.0; }

/* Texels a highlight of exponent e needs: next power of two of 8 sqrt(e).
   For 0 < e < 2, sin^e = (1 - d^2)^(e/2) has an infinite slope at d = +-1
   (like Kajiya-Kay's diffuse) and takes the largest axis. */
int ht_lut_highlight_texels(double e) {
    if (e > 0.0 && e < 2.0) return MAX_AXIS;
    double want = 8.0 * sqrt(e > 0.0 ? e : 0.0);
    int n = 1;
    while (n < want && n < (1 << 20)) n *= 2;
    return n;
}

static int clamp_axis(int n) { return n < MIN_AXIS ? MIN_AXIS : (n > MAX_AXIS ? MAX_AXIS : n); }

static long texels(const int size[3]) { return (long)size[0] * size[1] * size[2]; }

/* What the LUT reads at d = 0 for a highlight on an axis of n texels:
   the average of the two texels nearest 0 (n is even). */
static double peak_read(double e, int n) {
    double h = ht_combiner_lut_centre(n / 2, n);
    return 0.5 * (ht_model_highlight_of_cos_d(h, e) + ht_model_highlight_of_cos_d(-h, e));
}

static void note_dropped(ht_tier_output *out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void note_dropped(ht_tier_output *out, const char *fmt, ...) {
    char line[sizeof out->dropped[0]];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    ht_output_add_dropped(out, line);
}

/* The shading the LUT holds: the plan's, without what the plan leaves out. */
static ht_shading lut_shading(const ht_plan *plan) {
    ht_shading s = ht_plan_unmasked_shading(plan);
    if (s.model == HT_MODEL_KAJIYA_KAY || !plan->secondary)
        for (int i = 0; i < 3; i++) s.secondary.color[i] = 0.0;
    return s;
}

/* The 3D LUT's budget (header): the depth axis first, then the larger of
   the other two halves (the highlight's on a tie: the diffuse axis is
   piecewise linear and wants few texels anyway). One dropped line per
   highlight axis it shrank, with the peak that axis now reads. */
static void fit_3d(const ht_shading *s, const char *const axis_names[3], ht_tier_output *out, int size[3]) {
    const int wanted[3] = { size[0], size[1], size[2] };
    if (size[2] > MAX_3D_DEPTH) size[2] = MAX_3D_DEPTH;
    while (texels(size) > MAX_3D_TEXELS) size[size[1] >= size[0] ? 1 : 0] /= 2;
    const double exponents[3] = { 0.0, s->primary.exponent, s->secondary.exponent };
    for (int i = 0; i < 3; i++) {
        if (size[i] == wanted[i]) continue;
        if (i == 0)
            note_dropped(out, "LUT axis %s: %d texels, not %d, to keep the 3D LUT within %d slices and %d texels",
                         axis_names[i], size[i], wanted[i], MAX_3D_DEPTH, MAX_3D_TEXELS);
        else
            note_dropped(out, "LUT axis %s: %d texels, not %d, to keep the 3D LUT within %d slices and %d texels: "
                         "lobe widened, peak read as %.3f", axis_names[i], size[i], wanted[i], MAX_3D_DEPTH,
                         MAX_3D_TEXELS, peak_read(exponents[i], size[i]));
    }
}

static void choose_sizes(const ht_shading *s, const char *const axis_names[3],
                         ht_tier_output *out, int size[3]) {
    const bool kk = s->model == HT_MODEL_KAJIYA_KAY;
    const ht_lobe *lobes[2] = { &s->primary, &s->secondary };
    size[0] = is_black(s->diffuse_color) ? 1 : (kk ? KAJIYA_KAY_DIFFUSE_AXIS : DIFFUSE_AXIS);
    for (int i = 0; i < 2; i++) {
        const ht_lobe *l = lobes[i];
        int *n = &size[1 + i];
        if ((kk && i == 1) || is_black(l->color)) {
            *n = 1;
            continue;
        }
        int want = ht_lut_highlight_texels(l->exponent);
        *n = clamp_axis(want);
        if (want > *n)
            note_dropped(out, "LUT axis %s: exponent %g wants %d texels, clamped to %d: lobe widened, "
                         "peak read as %.3f", axis_names[1 + i], l->exponent, want, *n,
                         peak_read(l->exponent, *n));
    }
    if (size[2] > 1) {
        fit_3d(s, axis_names, out, size);
        return;
    }
    if (texels(size) > MAX_TEXELS && size[0] > MIN_AXIS) size[0] = MIN_AXIS;
    while (texels(size) > MAX_TEXELS) {
        int i = size[1] >= size[2] ? 1 : 2;
        size[i] /= 2;
        note_dropped(out, "LUT axis %s: halved to %d texels to keep the LUT within %d texels",
                     axis_names[i], size[i], MAX_TEXELS);
    }
}

/* Which lights after the key get an additive sub-pass (combiner.h), each
   costing the lit passes' geometry again: every light whose diffuse term
   reaches FILL_MIN_DIFFUSE. Under "texture-matrix" none, since the
   infinite viewer misplaces the fill's highlight by as much as the light
   adds (Kajiya-Kay x ratboy: 33.9 dB with the sub-pass, 35.3 without),
   unless the key shines from behind (plan.key_behind): then every fill,
   whatever its diffuse, since it lights most of what the camera sees
   (Kajiya-Kay x backlit at 512², fill diffuse 0.075: 28.74 dB with it,
   26.45 without). */
static double light_diffuse(const ht_plan *plan, const ht_shading *s, int light) {
    double most = 0.0;
    for (int c = 0; c < 3; c++) most = fmax(most, plan->light_colors[light][c] * s->diffuse_color[c]);
    return most;
}

/* The most the light adds anywhere (its brightest channel times the
   model's largest sum of terms), before the base colour. */
static double light_peak(const ht_plan *plan, const ht_shading *s, int light) {
    double most = 0.0;
    for (int c = 0; c < 3; c++) most = fmax(most, plan->light_colors[light][c]);
    return most * ht_model_dot_terms_max(s);
}

static void choose_add_lights(const ht_plan *plan, const ht_shading *s, ht_combiner_coords coords,
                              ht_combiner_program *p) {
    const bool matrix = coords != HT_COORDS_CPU_DOTS;
    if (matrix && !plan->key_behind) return;
    for (int l = 1; l < plan->light_count && p->add_light_count < HT_MAX_LIGHTS - 1; l++)
        if (matrix || light_diffuse(plan, s, l) >= FILL_MIN_DIFFUSE) p->add_lights[p->add_light_count++] = l;
}

/* The light colour the LUT carries: the brightest channel of the lights
   drawn, at least 1 (combiner.h). */
static double choose_light_scale(const ht_plan *plan, const ht_combiner_program *p) {
    double most = 1.0;
    for (int sub = 0; sub < ht_combiner_sub_passes(p); sub++) {
        int l = ht_combiner_sub_pass_light(p, sub);
        for (int c = 0; c < 3 && l < plan->light_count; c++) most = fmax(most, plan->light_colors[l][c]);
    }
    return most > 4.0 ? 4.0 : most;
}

static int choose_scale(const ht_shading *s, double light_scale, ht_tier_output *out) {
    double most = ht_model_dot_terms_max(s) * light_scale;
    if (most <= 1.0) return 1;
    if (most <= 2.0) return 2;
    if (most > 4.0)
        note_dropped(out, "LUT: lighting up to %.2f clamps at 4 (GL_RGB_SCALE is at most 4)", most);
    return 4;
}

/* lround(x) for x in [0, 255] without the libm call (a third of the bake):
   x - trunc(x) is exact there, so this rounds half away from zero exactly
   as lround does, where adding 0.5 first would not (0.49999999999999994). */
static uint8_t round_to_byte(double x) {
    int r = (int)x;
    return (uint8_t)(x - (double)r >= 0.5 ? r + 1 : r);
}

/* The scaled product colour[c] * factor[i] of one axis, for every texel
   index i along it: three doubles per index. */
static double *axis_terms(const double colour[3], const double *factors, int n) {
    double *t = malloc((size_t)n * 3 * sizeof(double));
    for (int i = 0; t && i < n; i++)
        for (int c = 0; c < 3; c++) t[3 * i + c] = colour[c] * factors[i];
    return t;
}

static ht_result bake_lut(const ht_shading *s, const ht_combiner_program *p, ht_image *img) {
    const int *n = p->lut_size;
    ht_result r = ht_image_alloc(img, n[0], n[1] * n[2], 3);
    if (r != HT_OK) return r;
    /* Each axis feeds one factor (ht_model_dot_factor_d): evaluate the
       model n[0] + n[1] + n[2] times, not once per texel, and each axis's
       colour products once per index; a texel is then the sum
       ht_model_dot_combine_d forms, in its order ((a + b) + c), so the
       bytes are those of ht_model_dot_terms_d at every texel. */
    const double *colours[3] = { s->diffuse_color, s->primary.color, s->secondary.color };
    double *terms[3] = { NULL, NULL, NULL };
    bool ok = true;
    for (int axis = 0; axis < 3 && ok; axis++) {
        double *factors = malloc((size_t)n[axis] * sizeof(double));
        for (int i = 0; factors && i < n[axis]; i++)
            factors[i] = ht_model_dot_factor_d(s, axis, ht_combiner_lut_centre(i, n[axis]));
        terms[axis] = factors ? axis_terms(colours[axis], factors, n[axis]) : NULL;
        ok = terms[axis] != NULL;
        free(factors);
    }
    if (!ok) {
        for (int axis = 0; axis < 3; axis++) free(terms[axis]);
        ht_image_free(img);
        return HT_ERR_OUT_OF_MEMORY;
    }
    /* lut_scale is 1, 2 or 4: dividing by it is exact, as multiplying by
       its inverse is (light_scale 1 keeps the bytes of dot_terms / scale). */
    const double inverse_scale = p->light_scale / p->lut_scale;
    uint8_t *px = img->pixels;
    for (int z = 0; z < n[2]; z++)
        for (int y = 0; y < n[1]; y++) {
            const double *c = terms[2] + 3 * z, *b = terms[1] + 3 * y;
            for (int x = 0; x < n[0]; x++, px += 3) {
                const double *a = terms[0] + 3 * x;
                for (int i = 0; i < 3; i++) {
                    double v = (a[i] + b[i] + c[i]) * inverse_scale;
                    v = v > 0.0 ? (v < 1.0 ? v : 1.0) : 0.0;
                    px[i] = round_to_byte(v * 255.0);
                }
            }
        }
    for (int axis = 0; axis < 3; axis++) free(terms[axis]);
    return HT_OK;
}

/* The texture matrix can index the LUT when every dot product is one of
   the unshifted tangent with a vector constant per frame: Kajiya-Kay's T.L
   and T.H, L directional. */
static ht_combiner_coords coords_rule(const ht_plan *plan, ht_model_kind model) {
    bool directional = plan->light_count > 0 && plan->light_types[0] == HT_LIGHT_DIRECTIONAL;
    return model == HT_MODEL_KAJIYA_KAY && directional ? HT_COORDS_TEXTURE_MATRIX : HT_COORDS_CPU_DOTS;
}

/* Unit 0: LUT x primary colour; alpha = primary alpha (1). */
static void lut_stage(const ht_combiner_program *p, ht_combiner_coords coords, ht_combiner_stage *s) {
    ht_combiner_stage_defaults(s, 0);
    snprintf(s->texture, sizeof s->texture, "%s", LUT_NAME);
    s->target = p->lut_size[2] > 1 ? GL_TEXTURE_3D : GL_TEXTURE_2D;
    s->wrap = GL_CLAMP_TO_EDGE;
    s->coords = coords;
    s->source_rgb[0] = GL_TEXTURE;
    s->source_rgb[1] = GL_PRIMARY_COLOR;
    s->combine_alpha = GL_REPLACE;
    s->source_alpha[0] = GL_PRIMARY_COLOR;
}

/* Unit 1: albedo x previous; alpha = albedo alpha (255 when the material has
   none, docs/bundle.md). */
static void albedo_stage(ht_combiner_stage *s) {
    ht_combiner_stage_defaults(s, 1);
    snprintf(s->texture, sizeof s->texture, "albedo");
    s->source_rgb[0] = GL_TEXTURE;
    s->source_rgb[1] = GL_PREVIOUS;
    s->combine_alpha = GL_REPLACE;
    s->source_alpha[0] = GL_TEXTURE;
}

static void add_albedo_sampler(ht_tier_output *out, const ht_plan *plan) {
    if (ht_output_add_sampler(out, plan, "albedo")) {
        out->samplers[out->sampler_count - 1].unit = 1;
        return;
    }
    ht_plan_texture *t = &out->samplers[out->sampler_count++];
    memset(t, 0, sizeof *t);
    snprintf(t->name, sizeof t->name, "albedo");
    snprintf(t->contents, sizeof t->contents, "base.rgb alpha.a");
    t->unit = 1;
}

static bool drawn(const ht_combiner_program *p, int light) {
    for (int sub = 0; sub < ht_combiner_sub_passes(p); sub++)
        if (ht_combiner_sub_pass_light(p, sub) == light) return true;
    return false;
}

static void list_dropped(const ht_plan *plan, const ht_shading *shading, const ht_combiner_program *p,
                         ht_combiner_coords coords, ht_tier_output *out) {
    ht_output_drop_transmission(out, plan, "its azimuth needs L.V beside T.L and T.V, a LUT axis that moves with "
                                           "the eye; the two units hold the key's highlights and the albedo");
    if (plan->shift)
        ht_output_add_dropped(out, "shift: jitter dropped, the LUT holds the constant shifts only "
                                   "(shift texture read as 0.5)");
    if (plan->sparkle)
        note_dropped(out, "sparkle: approximated by its mean %.3f scaling the secondary highlight: "
                          "no texture unit left to read the mask", plan->sparkle_mean);
    for (int l = 1; l < plan->light_count; l++) {
        if (drawn(p, l)) continue;
        if (coords == HT_COORDS_TEXTURE_MATRIX)
            note_dropped(out, "light %d: dropped: the texture matrix's infinite viewer would misplace its "
                              "highlight", l + 1);
        else
            note_dropped(out, "light %d: dropped: diffuse %.3f < %.3f (32/255), narrow highlights only (peak "
                              "%.3f x base); a sub-pass redraws the lit passes", l + 1,
                         light_diffuse(plan, shading, l), FILL_MIN_DIFFUSE, light_peak(plan, shading, l));
    }
    if (p->add_light_count > 0)
        ht_output_add_dropped(out, "lights after the key: additive sub-passes, exact but where transparent "
                                   "layers overlap (a deeper layer's light: not attenuated, back; not added, front)");
    note_dropped(out, "light colour: channels above %g clamp (the LUT carries the brightest drawn; the primary "
                      "colour is light colour / %g)", p->light_scale, p->light_scale);
    if (coords == HT_COORDS_TEXTURE_MATRIX) {
        ht_output_add_dropped(out, "infinite viewer for H: V is the camera's view direction, constant per "
                                   "frame (the texture matrix cannot form eye - position per vertex)");
        ht_output_add_dropped(out, "dot products: T.L, T.H per vertex from the tangent by the texture "
                                   "matrix, interpolated linearly (Heidrich-Seidel); tessellate where T bends");
    } else {
        ht_output_add_dropped(out, "dot products: per vertex on the CPU, interpolated linearly across "
                                   "triangles (Heidrich-Seidel); tessellate where T bends");
    }
    ht_output_add_dropped(out, "LUT: 8-bit, texel error up to 0.5/255 x scale, linear interpolation "
                               "between texels");
}

static void list_features(const ht_plan *plan, const ht_combiner_program *p, ht_combiner_coords coords,
                          ht_tier_output *out) {
    char line[80];
    ht_output_add_feature(out, plan->shading.model == HT_MODEL_KAJIYA_KAY ? "kajiya-kay" : "scheuermann");
    for (int sub = 0; sub < ht_combiner_sub_passes(p) && plan->light_count > 0; sub++) {
        const int l = ht_combiner_sub_pass_light(p, sub);
        snprintf(line, sizeof line, "light %d %s%s", l + 1,
                 plan->light_types[l] == HT_LIGHT_POINT ? "point" : "directional",
                 sub == 0 ? "" : ", additive sub-pass");
        ht_output_add_feature(out, line);
    }
    if (plan->base) ht_output_add_feature(out, "base");
    if (plan->alpha) ht_output_add_feature(out, "alpha");
    if (plan->ao) ht_output_add_feature(out, "ao");
    snprintf(line, sizeof line, "lut %dx%dx%d rgb8 scale %d, light scale %g", p->lut_size[0], p->lut_size[1],
             p->lut_size[2], p->lut_scale, p->light_scale);
    ht_output_add_feature(out, line);
    ht_output_add_feature(out, coords == HT_COORDS_TEXTURE_MATRIX ? "coords texture-matrix" : "coords cpu-dots");
}

ht_result ht_emit_fixed(const ht_plan *plan, ht_tier_output *out, char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->tier = HT_TIER_FIXED;
    if (!plan) {
        snprintf(err, err_size, "fixed: NULL plan");
        return HT_ERR_INVALID_ARGUMENT;
    }
    const ht_shading shading = lut_shading(plan);
    const char *axis_names[3];
    ht_combiner_dot_names(shading.model, axis_names);

    ht_combiner_program p;
    memset(&p, 0, sizeof p);
    p.model = shading.model;
    p.light = 0;
    p.ao = plan->ao;
    if (shading.model == HT_MODEL_SCHEUERMANN) {
        p.shift[0] = shading.primary.shift;
        p.shift[1] = shading.secondary.shift;
    }
    snprintf(p.lut_texture, sizeof p.lut_texture, "%s", LUT_NAME);
    const ht_combiner_coords coords = coords_rule(plan, shading.model);
    choose_add_lights(plan, &shading, coords, &p);
    p.light_scale = choose_light_scale(plan, &p);
    list_dropped(plan, &shading, &p, coords, out);
    choose_sizes(&shading, axis_names, out, p.lut_size);
    p.lut_scale = choose_scale(&shading, p.light_scale, out);

    const bool albedo = plan->base || plan->alpha;
    p.stage_count = albedo ? 2 : 1;
    lut_stage(&p, coords, &p.stages[0]);
    if (albedo) albedo_stage(&p.stages[1]);
    /* The scale is restored on the last stage: each stage clamps to [0,1],
       and lighting above 1 must survive until a dark base scales it down. */
    p.stages[p.stage_count - 1].rgb_scale = p.lut_scale;

    snprintf(out->requires.gl, sizeof out->requires.gl, "1.2"); /* 3D textures, CLAMP_TO_EDGE */
    if (p.stage_count > 1)
        snprintf(out->requires.extensions[out->requires.extension_count++],
                 sizeof out->requires.extensions[0], "GL_ARB_multitexture");
    snprintf(out->requires.extensions[out->requires.extension_count++],
             sizeof out->requires.extensions[0], "GL_ARB_texture_env_combine");
    out->requires.texture_units = p.stage_count;
    if (albedo) add_albedo_sampler(out, plan);
    list_features(plan, &p, coords, out);

    char *text = NULL;
    ht_result r = ht_combiner_write(&p, &text, err, err_size);
    if (r == HT_OK)
        r = ht_output_add_text(out, "fixed.json", "program", text, HT_STAGE_NONE, 0, false, err, err_size);
    if (r == HT_OK) {
        ht_out_image *img = &out->images[out->image_count];
        snprintf(img->name, sizeof img->name, "%s", LUT_NAME);
        snprintf(img->file, sizeof img->file, "%s.png", LUT_NAME);
        img->depth = p.lut_size[2];
        if (shading.model == HT_MODEL_KAJIYA_KAY)
            snprintf(img->contents, sizeof img->contents, "rgb = dot_terms(T.L, T.H) x %g / %d", p.light_scale,
                     p.lut_scale);
        else
            snprintf(img->contents, sizeof img->contents, "rgb = dot_terms(N.L, t1.H, t2.H) x %g / %d, "
                     "slices t2.H", p.light_scale, p.lut_scale);
        r = bake_lut(&shading, &p, &img->image);
        if (r == HT_OK) out->image_count++;
        else snprintf(err, err_size, "%s.png: out of memory", LUT_NAME);
    }
    if (r != HT_OK) ht_tier_output_free(out);
    return r;
}

/* test_render_marschner — the marschner tier's pixels against the Marschner
   oracle (runtime/shading/model_marschner.c through ht_model_shade_d), on the probe
   of support_probe.h: every covered pixel within TOLERANCE per channel of
   the oracle clamped to [0,1] and rounded to 8 bits. Lights: the probe's
   first light, behind the cells (L = -V at the centre pixel: TT's glow;
   for the wide lobes theta_r reaches 80 degrees, where the parallel
   polarisation's critical angle is inside N_R and N_TT), with the viewer
   (L = V), grazing, and a point light; materials: brown hair, a light one
   that lets TT through, wide and narrow lobes, and a base texture sampled
   at texel centres, lit by the first light and the point light at once (a
   bundle planned for both: one frame and one bundle for the texture and
   both light types). Also: hairview --tier marschner
   picks the tier and the selection ranks it above full. `make test`'s
   softpipe run (support_driver.h) draws the textured fibre only: the
   front-lit fibres, the back-lit and grazing angles are the same shader
   arithmetic with other constants and angles, untextured. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "marschner_lut.h"
#include <math.h>
#include <hairtier/model.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_driver.h"
#include "support_probe.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE HT_PROBE_SIZE
#define TOLERANCE 2 /* per channel, in 1/255: the target */

static ht_test_scratch_gl fx;

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_gl_setup(&fx, "marschner", SIZE) ? 0 : -1;
}

/* Each material's lookup textures for the diagnosis of a miss, baked once
   (a bake is seconds of integrals) by the first miss that needs them;
   freed at teardown. */
enum { MAX_BAKED = 8 };
static struct baked {
    const void *material;
    ht_marschner_lut lut;
} baked[MAX_BAKED];

static int teardown(void **state) {
    (void)state;
    for (int i = 0; i < MAX_BAKED; i++)
        if (baked[i].material) ht_marschner_lut_free(&baked[i].lut);
    return ht_test_scratch_gl_teardown(&fx);
}

typedef struct fibre_material {
    const char *name;
    double absorption[3], shift, width, eta;
    bool textured; /* a base texture */
} fibre_material;

static const fibre_material brown = { "brown", { 0.42, 0.70, 1.25 }, -7, 7, 1.55, false };
static const fibre_material blond = { "blond", { 0.06, 0.10, 0.20 }, -5, 10, 1.55, false };
static const fibre_material wide = { "wide", { 0.2, 0.3, 0.5 }, -10, 30, 1.55, false };
static const fibre_material narrow = { "narrow", { 0.42, 0.70, 1.25 }, -7, 3, 1.55, false };
static const fibre_material textured = { "textured", { 0.42, 0.70, 1.25 }, -7, 7, 1.55, true };

static void write_material(const fibre_material *f, const char *path) {
    FILE *out = fopen(path, "w");
    assert_non_null(out);
    fprintf(out, "{ \"format\": \"hairtier-material/1\", \"name\": \"%s\", \"model\": \"marschner\",\n"
                 "  \"diffuse\": {\"color\": [0.06, 0.035, 0.02]},\n"
                 "  \"marschner\": {\"absorption\": [%.17g, %.17g, %.17g], \"shift\": %.17g, \"width\": %.17g, "
                 "\"eta\": %.17g}",
            f->name, f->absorption[0], f->absorption[1], f->absorption[2], f->shift, f->width, f->eta);
    if (f->textured)
        fprintf(out, ",\n  \"textures\": {\"base\": {\"procedural\": \"stretched-noise\", \"size\": %d, \"seed\": 5}}",
                HT_PROBE_TEXTURE_SIZE);
    fprintf(out, " }\n");
    fclose(out);
}

/* The dot products the fragment shader forms at P (unit T, L, V); false
   where T, L or V has no direction (the shader's and the oracle's zero). */
static bool fibre_angles(const ht_probe_cell *c, const ht_light *light, const double P[3], double *si, double *sr,
                         double *cphi, double *sin_tl) {
    ht_surface s = ht_probe_surface(c, P);
    double T[3], V[3], L[3] = { light->vector[0], light->vector[1], light->vector[2] };
    if (light->type == HT_LIGHT_POINT)
        for (int k = 0; k < 3; k++) L[k] -= P[k];
    memcpy(T, s.T, sizeof T);
    memcpy(V, s.V, sizeof V);
    if (T[0] * T[0] + T[1] * T[1] + T[2] * T[2] <= HT_MODEL_MIN_LENGTH2 ||
        L[0] * L[0] + L[1] * L[1] + L[2] * L[2] <= HT_MODEL_MIN_LENGTH2 ||
        V[0] * V[0] + V[1] * V[1] + V[2] * V[2] <= HT_MODEL_MIN_LENGTH2)
        return false;
    ht_probe_unit(T);
    ht_probe_unit(L);
    ht_probe_unit(V);
    *si = T[0] * L[0] + T[1] * L[1] + T[2] * L[2];
    *sr = T[0] * V[0] + T[1] * V[1] + T[2] * V[2];
    double lp[3], vp[3];
    for (int i = 0; i < 3; i++) lp[i] = L[i] - *si * T[i], vp[i] = V[i] - *sr * T[i];
    double ll = lp[0] * lp[0] + lp[1] * lp[1] + lp[2] * lp[2], vv = vp[0] * vp[0] + vp[1] * vp[1] + vp[2] * vp[2];
    *cphi = ll > 0 && vv > 0 ? (lp[0] * vp[0] + lp[1] * vp[1] + lp[2] * vp[2]) / sqrt(ll * vv) : 1;
    *sin_tl = sqrt(fmax(0, 1 - *si * *si));
    return true;
}

/* What the pixel would be if the device did the shader's arithmetic in
   double (marschner_lut.c): tells the textures' error from the device's.
   Untextured cells only (base 1). */
static void lut_pixel(const ht_marschner_lut *lut, const ht_material *m, const ht_probe_cell *c,
                      const ht_light *light, const double P[3], int out[3]) {
    double si, sr, cphi, sin_tl, fibre[3] = { 0, 0, 0 };
    if (!fibre_angles(c, light, P, &si, &sr, &cphi, &sin_tl)) si = sr = cphi = 1, sin_tl = 0;
    else ht_marschner_lut_fibre(lut, si, sr, cphi, fibre);
    for (int k = 0; k < 3; k++)
        out[k] = ht_probe_to_byte((sin_tl * m->shading.diffuse_color[k] + fibre[k]) * light->color[k] * c->ao);
}

static void lut_diagnosis(const ht_marschner_lut *lut, const ht_material *m, const ht_probe_cell *c,
                          const ht_light *light, const double P[3], int channel) {
    double si, sr, cphi, sin_tl, from_lut[3], oracle[3];
    fibre_angles(c, light, P, &si, &sr, &cphi, &sin_tl);
    ht_marschner_lut_fibre(lut, si, sr, cphi, from_lut);
    ht_marschner_fibre(&m->shading.marschner, si, sr, cphi, oracle);
    printf("  worst pixel, channel %d: sin(theta_i) %.4f sin(theta_r) %.4f cos(phi) %.5f: fibre %.4f, from the "
           "textures on the CPU %.4f\n", channel, si, sr, cphi, oracle[channel], from_lut[channel]);
}

/* The fibre material's textures (key: its fibre_material). */
static const ht_marschner_lut *lut_for(const void *key, const ht_material *m) {
    int i = 0;
    while (i < MAX_BAKED && baked[i].material && baked[i].material != key) i++;
    assert_true(i < MAX_BAKED);
    if (!baked[i].material) {
        assert_int_equal(ht_marschner_lut_bake(&m->shading.marschner, &baked[i].lut), HT_OK);
        baked[i].material = key;
    }
    return &baked[i].lut;
}

/* On a miss, untextured: the textures' error (the CPU lookup against the
   oracle) told from the device's (the frame against the CPU lookup). */
static void lut_split(const ht_marschner_lut *lut, const ht_material *m, const ht_light *light, const ht_image *img) {
    int textures_worst = 0, device_worst = 0;
    for (int row = 0; row < SIZE; row++)
        for (int x = 0; x < SIZE; x++) {
            double P[3];
            int ci = ht_probe_cell_at(x, SIZE - 1 - row, P);
            if (ci < 0) continue;
            const ht_probe_cell *c = &ht_probe_cells[ci];
            ht_surface s = ht_probe_surface(c, P);
            int expected[3], from_lut[3];
            ht_probe_oracle(&m->shading, &s, light, P, expected);
            lut_pixel(lut, m, c, light, P, from_lut);
            const uint8_t *got = img->pixels + ((size_t)row * SIZE + x) * 4;
            for (int k = 0; k < 3; k++) {
                if (abs(from_lut[k] - expected[k]) > textures_worst) textures_worst = abs(from_lut[k] - expected[k]);
                if (abs(from_lut[k] - got[k]) > device_worst) device_worst = abs(from_lut[k] - got[k]);
            }
        }
    printf("  textures read on the CPU vs the oracle: worst %d/255; device vs the CPU lookup: worst %d/255\n",
           textures_worst, device_worst);
}

/* A bundle depends on its scene's light types only (support_probe.h), so
   each material's bundle for a list of light types is generated once, by
   the first probe that needs it. */
static void bundle_for(const fibre_material *f, const ht_light *lights, int count, char *dir, size_t size,
                       ht_material *m) {
    char path[400], manifest[400], err[256];
    snprintf(path, sizeof path, "%s/%s.json", fx.work, f->name);
    snprintf(dir, size, "%s/probe-%s", fx.work, f->name);
    for (int i = 0; i < count; i++)
        snprintf(dir + strlen(dir), size - strlen(dir), "-%s", ht_probe_light_type(&lights[i]));
    snprintf(manifest, sizeof manifest, "%s/manifest.json", dir);
    if (ht_test_path_exists(manifest)) {
        assert_int_equal(ht_material_load(path, m, err, sizeof err), HT_OK);
        return;
    }
    write_material(f, path);
    ht_probe_make_bundle_lights(fx.work, f->name, path, lights, count, dir, size, m);
}

/* The probe of f under count lights (at most 2), every covered pixel
   within tolerance of the oracle. */
static void probe_lights(const fibre_material *f, const ht_light *lights, int count, int tolerance) {
    char dir[256], err[2048], path[400];
    ht_material m;
    bundle_for(f, lights, count, dir, sizeof dir, &m);
    ht_image albedo = { 0 };
    if (f->textured) {
        snprintf(path, sizeof path, "%s/albedo.png", dir);
        assert_int_equal(ht_image_read_png(path, &albedo, err, sizeof err), HT_OK);
    }

    ht_mesh mesh;
    ht_probe_build_mesh(&mesh);
    ht_renderer *r = NULL;
    ht_test_log_clear();
    assert_int_equal(ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, .bundle_dir = dir,
                                                             .log = ht_test_log_capture }, &r), HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_MARSCHNER); /* the best tier, unforced */
    assert_int_equal(ht_renderer_set_mesh(r, &mesh), HT_OK);
    ht_frame_desc frame = ht_probe_frame(lights);
    frame.light_count = count;
    ht_image img;
    ht_test_draw(&fx.gl, r, &frame, (const float[3]){ 0, 0, 0 }, &img);

    int pixels = 0, worst = 0, worst_cell = -1, worst_expected = 0, worst_got = 0, worst_channel = 0;
    double worst_P[3] = { 0, 0, 0 };
    for (int row = 0; row < SIZE; row++)
        for (int x = 0; x < SIZE; x++) {
            double P[3];
            int ci = ht_probe_cell_at(x, SIZE - 1 - row, P);
            if (ci < 0) continue;
            const ht_probe_cell *c = &ht_probe_cells[ci];
            ht_surface s = ht_probe_surface(c, P);
            if (albedo.pixels) ht_probe_texel(&albedo, c->uv, 3, s.base);
            int expected[3];
            ht_probe_oracle_lights(&m.shading, &s, lights, count, P, expected);
            const uint8_t *got = img.pixels + ((size_t)row * SIZE + x) * 4;
            for (int k = 0; k < 3; k++)
                if (abs(expected[k] - got[k]) > worst) {
                    worst = abs(expected[k] - got[k]);
                    worst_cell = ci;
                    worst_expected = expected[k];
                    worst_got = got[k];
                    worst_channel = k;
                    memcpy(worst_P, P, sizeof worst_P);
                }
            pixels++;
        }
    printf("marschner probe %-9s", f->name);
    for (int i = 0; i < count; i++)
        printf(" %-11s light (%5.2f %5.2f %5.2f)", ht_probe_light_type(&lights[i]), (double)lights[i].vector[0],
               (double)lights[i].vector[1], (double)lights[i].vector[2]);
    printf(": %d pixels, worst %d/255 (cell %d)\n", pixels, worst, worst_cell);
    assert_true(pixels > HT_PROBE_CELLS * 20);
    if (worst > TOLERANCE && count == 1) { /* the diagnosis reads one light */
        const ht_light light = lights[0];
        const ht_marschner_lut *lut = lut_for(f, &m);
        if (!albedo.pixels) lut_split(lut, &m, &light, &img);
        lut_diagnosis(lut, &m, &ht_probe_cells[worst_cell], &light, worst_P, worst_channel);
    }
    if (worst > tolerance)
        fail_msg("%s: cell %d: expected %d/255, got %d/255\n%s", f->name, worst_cell, worst_expected, worst_got,
                 ht_test_log_text);
    ht_image_free(&img);
    ht_image_free(&albedo);
    ht_renderer_destroy(r);
    ht_mesh_free(&mesh);
}

static void probe(const fibre_material *f, ht_light light, int tolerance) { probe_lights(f, &light, 1, tolerance); }

static ht_light first_light(void) {
    return ht_probe_directional(ht_probe_first_light[0], ht_probe_first_light[1], ht_probe_first_light[2]);
}

static void tier_matches_the_oracle_front_lit(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT(); /* the textured probe's shader, untextured, one light */
    probe(&brown, first_light(), TOLERANCE);
}

static void tier_matches_the_oracle_front_lit_on_other_fibres(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT(); /* the front-lit shader with other constants */
    probe(&blond, first_light(), TOLERANCE);
    probe(&wide, first_light(), TOLERANCE);
    probe(&narrow, first_light(), TOLERANCE);
}

static void tier_matches_the_oracle_back_lit_and_grazing(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT(); /* the front-lit shader's arithmetic at other angles */
    probe(&blond, ht_probe_directional(0, 0, -1), TOLERANCE); /* L = -V at the centre pixel: TT glows */
    probe(&brown, ht_probe_directional(0, 0, -1), TOLERANCE);
    probe(&blond, ht_probe_directional(0, 0, 1), TOLERANCE); /* L = V */
    probe(&blond, ht_probe_directional(1, 0, 0), TOLERANCE); /* grazing */
    probe(&wide, ht_probe_directional(0.2, 0.1, -1), TOLERANCE); /* theta_r 80 degrees: the critical angle */
}

static ht_light point_light(void) { return (ht_light){ HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } }; }

/* The base texture under the first light and the point light at once:
   the texture and both light types in one frame and one bundle (a bundle
   is seconds of baking and fitting); every driver's case. */
static void tier_matches_the_oracle_with_a_base_texture_and_a_point_light(void **state) {
    (void)state;
    const ht_light lights[2] = { first_light(), point_light() };
    probe_lights(&textured, lights, 2, TOLERANCE);
}

int main(void) {
    ht_probe_make_cells();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tier_matches_the_oracle_front_lit),
        cmocka_unit_test(tier_matches_the_oracle_front_lit_on_other_fibres),
        cmocka_unit_test(tier_matches_the_oracle_back_lit_and_grazing),
        cmocka_unit_test(tier_matches_the_oracle_with_a_base_texture_and_a_point_light),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

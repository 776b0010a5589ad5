/* test_render_probe — the full tier's pixels against the double-precision
   oracle (runtime/shading/model.c), on whichever Mesa driver runs it (make test
   runs it on llvmpipe and on softpipe).

   The probe (support_probe.h) is a grid of flat cells in the plane z = 0,
   facing a camera on the z axis. Every vertex of a cell carries the same T,
   N, uv and ao, so every pixel of the cell has known inputs; V and L come
   from the pixel's position, which the probe reconstructs exactly by
   casting the pixel centre's ray onto the plane. Each pixel is compared with
   ht_model_shade_d, clamped to [0,1] and rounded to 8 bits: within
   TOLERANCE per channel. Cells and bundles cover the model's extremes:
   L = -V (the centre pixel of a 129-pixel view, where V is exactly +z),
   T parallel and antiparallel to H, T parallel to N after the shift
   (shifts of +-100), T = -N with a shift of 1 (shifted tangent of zero
   length), a zero tangent, exponents 0 and 10000, Kajiya-Kay, point and
   directional lights, and the base/shift/sparkle textures sampled at texel
   centres. */
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
#include <hairtier/model.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_probe.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE HT_PROBE_SIZE
#define GRID HT_PROBE_GRID
#define TOLERANCE 2       /* per channel, in 1/255 */

static ht_test_scratch_gl fx;

static int setup(void **state) {
    (void)state;
    return ht_test_scratch_gl_setup(&fx, "probe", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_gl_teardown(&fx);
}

/* ---- the oracle, per pixel ---- */

typedef struct textures { ht_image albedo, detail; } textures;

typedef struct probe_result { int pixels, worst, worst_cell; double worst_expected, worst_got; } probe_result;

static probe_result compare(const ht_image *img, const ht_shading *shading, const ht_light *light,
                            const textures *tex) {
    probe_result res = { 0, 0, -1, 0, 0 };
    for (int row = 0; row < SIZE; row++) {
        for (int x = 0; x < SIZE; x++) {
            double P[3];
            int ci = ht_probe_cell_at(x, SIZE - 1 - row, P);
            if (ci < 0) continue;
            const ht_probe_cell *c = &ht_probe_cells[ci];
            ht_surface s = ht_probe_surface(c, P);
            if (tex->albedo.pixels) ht_probe_texel(&tex->albedo, c->uv, 3, s.base);
            if (tex->detail.pixels) {
                double d[2];
                ht_probe_texel(&tex->detail, c->uv, 2, d);
                s.shift_tex = d[0];
                s.sparkle = d[1];
            }
            int expected[3];
            ht_probe_oracle(shading, &s, light, P, expected);
            const uint8_t *got = img->pixels + ((size_t)row * SIZE + x) * 4;
            for (int k = 0; k < 3; k++) {
                int diff = abs(expected[k] - got[k]);
                if (diff > res.worst) {
                    res.worst = diff;
                    res.worst_cell = ci;
                    res.worst_expected = expected[k];
                    res.worst_got = got[k];
                }
            }
            res.pixels++;
        }
    }
    return res;
}

/* Renders the probe with one bundle's full tier under one light and
   compares every covered pixel with the oracle; the renderer's log is shown
   only when it fails. */
static void probe(const ht_probe_material *p, ht_light light) {
    char dir[256], err[2048];
    ht_material m;
    ht_probe_make_bundle(fx.work, p, &light, dir, sizeof dir, &m);

    textures tex = { 0 };
    char path[400];
    if (p->textured) {
        snprintf(path, sizeof path, "%s/albedo.png", dir);
        assert_int_equal(ht_image_read_png(path, &tex.albedo, err, sizeof err), HT_OK);
        snprintf(path, sizeof path, "%s/detail.png", dir);
        assert_int_equal(ht_image_read_png(path, &tex.detail, err, sizeof err), HT_OK);
    }

    ht_mesh mesh;
    ht_probe_build_mesh(&mesh);
    ht_renderer *r = NULL;
    ht_test_log_clear();
    assert_int_equal(ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, .bundle_dir = dir,
                                                             .tier = HT_TIER_FULL, .strict = true,
                                                             .log = ht_test_log_capture }, &r), HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL);
    assert_int_equal(ht_renderer_set_mesh(r, &mesh), HT_OK);
    ht_frame_desc frame = ht_probe_frame(&light);
    ht_image img;
    ht_test_draw(&fx.gl, r, &frame, (const float[3]){ 0, 0, 0 }, &img);

    probe_result res = compare(&img, &m.shading, &light, &tex);
    printf("probe %-14s %-11s light (%5.2f %5.2f %5.2f): %d pixels, worst %d/255", p->name,
           ht_probe_light_type(&light), (double)light.vector[0], (double)light.vector[1], (double)light.vector[2],
           res.pixels, res.worst);
    if (res.worst_cell >= 0) printf(" (cell %d)", res.worst_cell);
    printf("\n");
    assert_true(res.pixels > GRID * GRID * 20); /* the cells were drawn and found */
    if (res.worst > TOLERANCE)
        fail_msg("%s: cell %d: expected %g/255, got %g/255\n%s", p->name, res.worst_cell, res.worst_expected,
                 res.worst_got, ht_test_log_text);

    ht_image_free(&img);
    ht_image_free(&tex.albedo);
    ht_image_free(&tex.detail);
    ht_renderer_destroy(r);
    ht_mesh_free(&mesh);
}

static ht_light first_light(void) {
    return ht_probe_directional(ht_probe_first_light[0], ht_probe_first_light[1], ht_probe_first_light[2]);
}

static void test_full_tier_matches_oracle_on_generic_cells(void **state) {
    (void)state;
    probe(&ht_probe_plain, first_light());
}

static void test_full_tier_matches_oracle_when_light_is_behind_the_strand(void **state) {
    (void)state;
    probe(&ht_probe_plain, ht_probe_directional(0, 0, -1)); /* L = -V exactly at the centre pixel */
    probe(&ht_probe_plain, ht_probe_directional(0, 0, 1));  /* L = V */
    probe(&ht_probe_plain, ht_probe_directional(1, 0, 0));  /* grazing */
}

static void test_full_tier_matches_oracle_at_exponent_extremes(void **state) {
    (void)state;
    const ht_probe_material zero = { "exponent-0", "scheuermann", 0, 0.0, 0, 0.0, false };
    const ht_probe_material huge = { "exponent-10000", "scheuermann", 10000, 0.0, 10000, 0.0, false };
    probe(&zero, first_light());
    probe(&huge, first_light());
}

static void test_full_tier_matches_oracle_with_wide_shifts(void **state) {
    (void)state;
    const ht_probe_material wide = { "shift-100", "scheuermann", 80, 100.0, 24, -100.0, false };
    probe(&wide, first_light());
}

static void test_full_tier_matches_oracle_for_kajiya_kay(void **state) {
    (void)state;
    const ht_probe_material kk = { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false };
    probe(&kk, first_light());
}

static void test_full_tier_matches_oracle_with_a_point_light(void **state) {
    (void)state;
    probe(&ht_probe_plain, (ht_light){ HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } });
}

static void test_full_tier_matches_oracle_with_textures_at_texel_centres(void **state) {
    (void)state;
    const ht_probe_material textured = { "textured", "scheuermann", 80, -0.1, 24, 0.15, true };
    probe(&textured, first_light());
}

int main(void) {
    ht_probe_make_cells();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_tier_matches_oracle_on_generic_cells),
        cmocka_unit_test(test_full_tier_matches_oracle_when_light_is_behind_the_strand),
        cmocka_unit_test(test_full_tier_matches_oracle_at_exponent_extremes),
        cmocka_unit_test(test_full_tier_matches_oracle_with_wide_shifts),
        cmocka_unit_test(test_full_tier_matches_oracle_for_kajiya_kay),
        cmocka_unit_test(test_full_tier_matches_oracle_with_a_point_light),
        cmocka_unit_test(test_full_tier_matches_oracle_with_textures_at_texel_centres),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

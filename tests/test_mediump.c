/* test_mediump.c — the fp16 mirror of full-es2-mediump.frag against the
   oracle (ht_model_shade_d): on the probe grid of test_render_probe.c, on
   random directions and lengths, and at the extremes (exponent 10000, T || H,
   T || L, grazing, vectors from 2^-10 to 2^10 long). No step may overflow
   fp16, no colour may be NaN or Inf, and the 8-bit error stays within the
   bounds docs/accuracy.md reports. Every measurement runs twice: with fp16
   subnormals and flushed to zero (devices differ).

   HT_MEDIUMP_SAMPLES=N sets the random directions per material (default
   20000; docs/accuracy.md's table is the 10^6 run). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/ht_limits.h>
#include <hairtier/model.h>
#include "mediump.h"
#include "mediump_mirror.h"
#include "rng.h"
#include "support_probe.h"

typedef struct errors {
    int max_byte;   /* largest |mirror - oracle| of any channel, in 1/255 */
    long samples;
    long nonfinite; /* colours that are NaN or Inf */
    ht_mp_stats stats;
    ht_mp_inputs worst;  /* the inputs of max_byte, printed on failure */
    double worst_got[3], worst_want[3];
} errors;

/* The probe materials' colours (support_probe.c write_material). */
static ht_shading shading(ht_model_kind model, double e1, double s1, double e2, double s2) {
    return (ht_shading){ .model = model,
                         .diffuse_color = { 0.35, 0.22, 0.12 },
                         .wrap = model == HT_MODEL_KAJIYA_KAY ? 0.0 : 0.25,
                         .primary = { .color = { 0.7, 0.65, 0.6 }, .exponent = e1, .shift = s1 },
                         .secondary = { .color = { 0.4, 0.3, 0.2 }, .exponent = e2, .shift = s2 } };
}

static ht_mp_mirror *mirror_of(const ht_mp_desc *d) {
    ht_mp_program *p = malloc(sizeof *p);
    assert_non_null(p);
    ht_mp_build(d, p);
    char err[256] = "";
    ht_mp_mirror *m = ht_mp_mirror_new(p, err, sizeof err);
    if (!m) fail_msg("mirror: %s", err);
    free(p);
    return m;
}

static ht_mp_desc desc_of(const ht_shading *m, int light_count, const ht_light_type *types, bool textured) {
    ht_mp_desc d = { .shading = *m, .light_count = light_count, .ao = true };
    d.jitter = d.sparkle = textured && m->model != HT_MODEL_KAJIYA_KAY; /* Kajiya-Kay has neither */
    d.base = textured;
    for (int i = 0; i < light_count; i++) d.light_types[i] = types[i];
    return d;
}

/* |L/|L| + V/|V||: below HT_OPPOSITE the half vector is ill-conditioned
   (its direction moves by the fp16 error of L and V, ~2^-11, over this
   length), so those samples are bounded apart. */
#define HT_OPPOSITE 0.0625
static double half_length(const double L[3], const double V[3]) {
    const double l = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]), v = sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
    double h2 = 0;
    for (int k = 0; k < 3; k++) h2 += (L[k] / l + V[k] / v) * (L[k] / l + V[k] / v);
    return sqrt(h2);
}

/* One pixel: the mirror and the oracle on the same inputs, as bytes, into
   e[0], or e[1] when some light is within HT_OPPOSITE of L = -V. */
static void compare(const ht_mp_mirror *mm, const ht_mp_desc *d, const ht_mp_inputs *in, bool flush, errors e2[2]) {
    ht_surface s = { .shift_tex = d->jitter ? in->shift_texel : 0.5,
                     .sparkle = d->sparkle ? in->sparkle : 1.0,
                     .ao = in->ao };
    ht_light_ray rays[HT_MAX_LIGHTS];
    for (int k = 0; k < 3; k++) {
        s.T[k] = in->tangent[k];
        s.N[k] = in->normal[k];
        s.V[k] = in->eye[k] - in->position[k];
        s.base[k] = d->base ? in->base[k] : 1.0;
        for (int i = 0; i < d->light_count; i++) {
            rays[i].L[k] = in->light[i][k] - (d->light_types[i] == HT_LIGHT_POINT ? in->position[k] : 0.0);
            rays[i].color[k] = in->colour[i][k];
        }
    }
    double want[3], got[3];
    errors *e = &e2[0];
    for (int i = 0; i < d->light_count; i++)
        if (half_length(rays[i].L, s.V) < HT_OPPOSITE) e = &e2[1];
    ht_model_shade_d(&d->shading, &s, rays, d->light_count, want);
    ht_mp_mirror_shade(mm, in, flush, got, &e->stats);
    e->samples++;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(got[k])) {
            e->nonfinite++;
            continue;
        }
        const int diff = abs(ht_probe_to_byte(got[k]) - ht_probe_to_byte(want[k]));
        if (diff > e->max_byte) {
            e->max_byte = diff;
            e->worst = *in;
            memcpy(e->worst_got, got, sizeof got);
            memcpy(e->worst_want, want, sizeof want);
        }
    }
}

static void expect(const char *what, const errors *e, int bound) {
    if (e->samples == 0) return;
    printf("%-40s %8ld samples: max %d/255, %ld overflows, %ld subnormal results of %ld\n", what, e->samples,
           e->max_byte, e->stats.overflows, e->stats.subnormals, e->stats.results);
    assert_int_equal(e->nonfinite, 0);
    assert_int_equal(e->stats.overflows, 0);
    if (e->max_byte > bound) {
        const ht_mp_inputs *w = &e->worst;
        printf("  worst: P (%g %g %g) T (%g %g %g) N (%g %g %g) eye (%g %g %g) L0 (%g %g %g) L1 (%g %g %g)\n"
               "  mirror (%g %g %g) oracle (%g %g %g)\n",
               w->position[0], w->position[1], w->position[2], w->tangent[0], w->tangent[1], w->tangent[2],
               w->normal[0], w->normal[1], w->normal[2], w->eye[0], w->eye[1], w->eye[2], w->light[0][0],
               w->light[0][1], w->light[0][2], w->light[1][0], w->light[1][1], w->light[1][2], e->worst_got[0],
               e->worst_got[1], e->worst_got[2], e->worst_want[0], e->worst_want[1], e->worst_want[2]);
        fail_msg("%s: %d/255 > the pinned %d/255", what, e->max_byte, bound);
    }
}

/* ---- the probe grid ---- */

static void probe_with(const char *name, const ht_shading *m, ht_light light, int bound, int opposite_bound) {
    const ht_light_type type = light.type;
    const ht_mp_desc d = desc_of(m, 1, &type, false);
    ht_mp_mirror *mm = mirror_of(&d);
    for (int flush = 0; flush < 2; flush++) {
        errors e[2] = { 0 };
        for (int py = 0; py < HT_PROBE_SIZE; py++)
            for (int px = 0; px < HT_PROBE_SIZE; px++) {
                double P[3];
                const int cell = ht_probe_cell_at(px, py, P);
                if (cell < 0) continue;
                const ht_probe_cell *c = &ht_probe_cells[cell];
                ht_mp_inputs in = { .eye = { 0, 0, HT_PROBE_EYE_Z }, .ao = c->ao };
                for (int k = 0; k < 3; k++) {
                    in.position[k] = P[k];
                    in.tangent[k] = c->T[k];
                    in.normal[k] = c->N[k];
                    in.light[0][k] = light.vector[k];
                    in.colour[0][k] = light.color[k];
                }
                compare(mm, &d, &in, flush, e);
            }
        char what[96];
        snprintf(what, sizeof what, "probe %s%s", name, flush ? " (flushed)" : "");
        expect(what, &e[0], bound);
        snprintf(what, sizeof what, "probe %s, L ~ -V%s", name, flush ? " (flushed)" : "");
        expect(what, &e[1], opposite_bound);
    }
    ht_mp_mirror_free(mm);
}

static ht_light first_light(void) {
    return ht_probe_directional(ht_probe_first_light[0], ht_probe_first_light[1], ht_probe_first_light[2]);
}

static void test_probe_within_3_of_255(void **state) {
    (void)state;
    const ht_shading plain = shading(HT_MODEL_SCHEUERMANN, 80, 1.0, 24, 0.0);
    const ht_shading wide = shading(HT_MODEL_SCHEUERMANN, 80, 100.0, 24, -100.0);
    const ht_shading zero = shading(HT_MODEL_SCHEUERMANN, 0, 0, 0, 0);
    const ht_shading kk = shading(HT_MODEL_KAJIYA_KAY, 60, 0, 0, 0);
    probe_with("plain, first light", &plain, first_light(), 3, 99);
    probe_with("plain, L = -V at the centre", &plain, ht_probe_directional(0, 0, -1), 3, 99);
    probe_with("plain, L = V", &plain, ht_probe_directional(0, 0, 1), 3, 99);
    probe_with("plain, grazing light", &plain, ht_probe_directional(1, 0, 0), 3, 99);
    probe_with("plain, point light", &plain,
               (ht_light){ HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } }, 3, 99);
    probe_with("shift 100", &wide, first_light(), 3, 99);
    probe_with("exponent 0", &zero, first_light(), 3, 99);
    probe_with("kajiya-kay", &kk, first_light(), 3, 99);
}

/* Exponent 10000, the material maximum: the highlight is 0.014 wide, and
   fp16 directions carry ~5e-4 of error in c = t.h, so sin^e's exponent
   e c^2 moves by e 2 c dc ~ 0.14 at the half width (docs/accuracy.md). */
static void test_probe_at_the_maximum_exponent(void **state) {
    (void)state;
    const ht_shading huge = shading(HT_MODEL_SCHEUERMANN, HT_LIMIT_EXPONENT, 0, HT_LIMIT_EXPONENT, 0);
    probe_with("exponent 10000", &huge, first_light(), 6, 99);
}

/* ---- random directions ---- */

static void random_vector(ht_rng *r, double min_log2, double max_log2, double v[3]) {
    double len;
    do {
        for (int k = 0; k < 3; k++) v[k] = ht_rng_range(r, -1, 1);
        len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    } while (len < 1e-3 || len > 1);
    const double scale = exp2(ht_rng_range(r, min_log2, max_log2)) / len;
    for (int k = 0; k < 3; k++) v[k] *= scale;
}

static long samples(void) {
    const char *s = getenv("HT_MEDIUMP_SAMPLES");
    long n = s ? strtol(s, NULL, 10) : 20000;
    return n > 0 ? n : 20000;
}

/* Two lights (one point), textures, ao, T, N and the directional light
   2^-4 .. 2^10 long (2^20 squared: a plain dot(v, v) would overflow). */
static void random_with(const char *name, const ht_shading *m, int bound, int opposite_bound) {
    const ht_light_type types[2] = { HT_LIGHT_DIRECTIONAL, HT_LIGHT_POINT };
    const ht_mp_desc d = desc_of(m, 2, types, true);
    ht_mp_mirror *mm = mirror_of(&d);
    const long n = samples();
    for (int flush = 0; flush < 2; flush++) {
        ht_rng r = ht_rng_seed(2101);
        errors e[2] = { 0 };
        for (long i = 0; i < n; i++) {
            ht_mp_inputs in = { .shift_texel = ht_rng_unit(&r), .sparkle = ht_rng_unit(&r), .ao = ht_rng_unit(&r) };
            /* from 2^-4: a shorter vector's small components fall below
               2^-14 and flush, which no rescaling can undo */
            random_vector(&r, -4, 10, in.tangent);
            random_vector(&r, -4, 10, in.normal);
            /* positions near a unit-sized head, the eye and point light
               at least 2 units away: mediump positions carry 2^-11 of
               their size (docs/accuracy.md) */
            random_vector(&r, -4, 1, in.position);
            double view[3];
            random_vector(&r, 1, 6, view);
            random_vector(&r, -4, 10, in.light[0]);
            random_vector(&r, 1, 6, in.light[1]);
            for (int k = 0; k < 3; k++) {
                in.eye[k] = in.position[k] + view[k];
                in.light[1][k] += in.position[k];
                in.base[k] = ht_rng_unit(&r);
                in.colour[0][k] = ht_rng_range(&r, 0, 1);
                in.colour[1][k] = ht_rng_range(&r, 0, 1);
            }
            compare(mm, &d, &in, flush, e);
        }
        char what[96];
        snprintf(what, sizeof what, "random %s%s", name, flush ? " (flushed)" : "");
        expect(what, &e[0], bound);
        snprintf(what, sizeof what, "random %s, L ~ -V%s", name, flush ? " (flushed)" : "");
        expect(what, &e[1], opposite_bound);
    }
    ht_mp_mirror_free(mm);
}

static void test_random_directions(void **state) {
    (void)state;
    const ht_shading plain = shading(HT_MODEL_SCHEUERMANN, 80, -0.1, 24, 0.15);
    const ht_shading contrast = shading(HT_MODEL_SCHEUERMANN, 900, -0.05, 300, 0.2);
    const ht_shading huge = shading(HT_MODEL_SCHEUERMANN, HT_LIMIT_EXPONENT, 0, HT_LIMIT_EXPONENT, 0);
    const ht_shading small = shading(HT_MODEL_SCHEUERMANN, 0.5, 0, 0.01, 0);
    const ht_shading kk = shading(HT_MODEL_KAJIYA_KAY, 60, 0, 0, 0);
    random_with("80 / 24", &plain, 99, 99);
    random_with("900 / 300", &contrast, 99, 99);
    random_with("10000 / 10000", &huge, 99, 99);
    random_with("0.5 / 0.01", &small, 99, 99);
    random_with("kajiya-kay 60", &kk, 99, 99);
}

int main(void) {
    ht_probe_make_cells();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_probe_within_3_of_255),
        cmocka_unit_test(test_probe_at_the_maximum_exponent),
        cmocka_unit_test(test_random_directions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

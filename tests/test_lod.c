/* test_lod.c — geometry LODs (lod.h) of the three geometries a scene names
   (fur ball, patches, ratboy's strand file): every LOD keeps the covered
   fraction of a view within COVERAGE_BOUND of full detail and the summed
   ribbon area within AREA_BOUND; strands are a prefix of one permutation
   (nested levels) spread over the roots; decimation drops rows and keeps
   tangents unit, perpendicular to the normal and root to tip; components
   keep the inside-out order; the LOD choice (best with hysteresis, error:DB
   over measured cells with hysteresis) follows its rules; bad meshes are
   refused. Pure CPU: the coverage is rasterised here, not by GL. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <hairtier/lod.h>
#include <hairtier/scene.h>
#include "support_coverage.h"

/* The stated bounds (docs/lod.md): the covered fraction of an orthographic
   view (each pixel's 1 - (1 - ALPHA)^layers, ALPHA the typical strand
   opacity, support_coverage.h) and the summed area, LOD against full detail. */
#define COVERAGE_BOUND 0.10
/* A soft level (lod.h), its ribbons drawn at its opacity: wider, fainter
   ribbons pile up on more of each other (patches' 36 strips of level 2:
   +10.3 %). */
#define SOFT_COVERAGE_BOUND 0.15
#define AREA_BOUND 0.05
#define ALPHA 0.5

static double ribbon_area(const ht_mesh *m) {
    double a = 0;
    for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
        const float *p0 = m->vertices[m->indices[t]].position, *p1 = m->vertices[m->indices[t + 1]].position,
                    *p2 = m->vertices[m->indices[t + 2]].position;
        const double u[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
        const double w[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
        const double c[3] = { u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0] };
        a += 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return a;
}

static void build_scene(const char *file, ht_mesh *hair) {
    ht_scene s;
    char err[512] = "";
    if (ht_scene_load(file, &s, err, sizeof err) != HT_OK) fail_msg("%s", err);
    if (s.geometry == HT_GEOMETRY_FURBALL) s.furball.hairs = 3000; /* cheap, still dense */
    if (ht_scene_build_meshes(&s, file, hair, NULL, err, sizeof err) != HT_OK) fail_msg("%s", err);
}

static double dotf(const float a[3], const float b[3]) { return (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2]; }

/* Tangents unit, perpendicular to the normal, root to tip (along the
   centre line from each row to the next). */
static void assert_frames(const ht_mesh *m) {
    for (uint32_t c = 0; c < m->component_count; c++) {
        const uint32_t first = m->indices[m->components[c].first_index];
        const uint32_t rows = m->components[c].index_count / 6 + 1;
        for (uint32_t r = 0; r < rows; r++) {
            const ht_vertex *v = &m->vertices[first + 2 * r];
            assert_true(fabs(sqrt(dotf(v->tangent, v->tangent)) - 1) < 1e-4);
            assert_true(fabs(dotf(v->tangent, v->normal)) < 1e-4);
            if (r + 1 < rows) {
                const ht_vertex *n = v + 2;
                float d[3];
                for (int k = 0; k < 3; k++)
                    d[k] = (n[0].position[k] + n[1].position[k] - v[0].position[k] - v[1].position[k]) / 2;
                assert_true(dotf(v->tangent, d) > 0);
            }
        }
    }
}

static void check_scene_levels(const char *file) {
    ht_mesh full;
    build_scene(file, &full);
    const ht_test_view v = ht_test_view_of(&full, 2);
    const double cover0 = ht_test_covered_fraction(&full, &v, ALPHA, NULL), area0 = ribbon_area(&full);
    for (int i = 2; i <= 2 * ht_lod_max_level(&full) + 1; i++) {
        /* level i / 2, plain then soft: a soft level's ribbons drawn at its
           opacity cover what the plain level's do, area x opacity kept. */
        const int level = i / 2, soft = i % 2;
        ht_lod_desc d;
        (soft ? ht_lod_soft_level : ht_lod_level)(level, &d);
        ht_mesh lod;
        assert_int_equal(ht_mesh_build_lod(&full, &d, &lod), HT_OK);
        const double opacity = ht_lod_opacity(&d);
        assert_true(soft ? d.soften > 1 && fabs(opacity * d.soften - 1) < 1e-6 : opacity == 1);
        const double cover = ht_test_covered_fraction(&lod, &v, ALPHA * opacity, NULL), area = opacity * ribbon_area(&lod);
        printf("%s level %d%s: strands %u/%u, vertices %u/%u, coverage %.4f/%.4f (%+.1f%%), area %+.1f%%\n", file,
               level, soft ? " soft" : "", lod.component_count, full.component_count, lod.vertex_count,
               full.vertex_count, cover, cover0, 100 * (cover / cover0 - 1), 100 * (area / area0 - 1));
        assert_int_equal(lod.component_count, (full.component_count + d.strand_stride - 1) / d.strand_stride);
        assert_true(fabs(cover / cover0 - 1) <= (soft ? SOFT_COVERAGE_BOUND : COVERAGE_BOUND));
        assert_true(fabs(area / area0 - 1) <= AREA_BOUND);
        assert_frames(&lod);
        /* The inside-out order of the full mesh, kept. */
        for (uint32_t c = 1; c < lod.component_count; c++)
            assert_true(lod.components[c - 1].sort_key <= lod.components[c].sort_key);
        ht_mesh_free(&lod);
    }
    ht_mesh_free(&full);
}

static void coverage_furball(void **state) { (void)state; check_scene_levels("scenes/furball.json"); }
static void coverage_patches(void **state) { (void)state; check_scene_levels("scenes/patches.json"); }
static void coverage_strands(void **state) { (void)state; check_scene_levels("scenes/ratboy.json"); }

/* Cards of 32 strands (lod.h), baked from a material whose alpha is
   ALPHA everywhere: the covered fraction seen down x, y and z (each
   pixel's 1 - prod(1 - the atlas's alpha)), summed, against full
   detail's; frames as the strands'; inside-out order. The mohawk's cards
   lie in its sheet, seen edge on from the front (docs/lod.md): a wider
   bound. */
#define CARDS_COVERAGE_BOUND 0.10
#define CARDS_COVERAGE_BOUND_MOHAWK 0.25
#define CARDS_ATLAS 128

static void check_scene_cards(const char *file, uint32_t per_card, double bound) {
    ht_mesh full;
    build_scene(file, &full);
    ht_image material;
    assert_int_equal(ht_image_alloc(&material, 8, 8, 4), HT_OK);
    for (int i = 0; i < 8 * 8 * 4; i++) material.pixels[i] = (uint8_t)(i % 4 == 3 ? lrint(ALPHA * 255) : 255);
    const double alpha = material.pixels[3] / 255.0;
    ht_cards cards;
    assert_int_equal(ht_mesh_build_cards(&full, &(ht_cards_desc){ .strands_per_card = per_card, .strand_albedo = &material, .atlas_width = CARDS_ATLAS,
                                                                  .atlas_height = CARDS_ATLAS },
                                         &cards),
                     HT_OK);
    double sum0 = 0, sum = 0;
    for (int axis = 0; axis < 3; axis++) {
        const ht_test_view v = ht_test_view_of(&full, axis);
        const double c0 = ht_test_covered_fraction(&full, &v, alpha, NULL);
        const double c = ht_test_covered_fraction(&cards.mesh, &v, 0, &cards.albedo);
        printf("%s cards, down axis %d: coverage %.4f/%.4f (%+.1f%%)\n", file, axis, c, c0, 100 * (c / c0 - 1));
        sum0 += c0;
        sum += c;
    }
    printf("%s cards: %u cards of %u strands, %u vertices (%u), coverage %+.1f%%\n", file, cards.mesh.component_count,
           full.component_count, cards.mesh.vertex_count, full.vertex_count, 100 * (sum / sum0 - 1));
    assert_true(fabs(sum / sum0 - 1) <= bound);
    assert_true(cards.mesh.component_count <= (full.component_count + per_card - 1) / per_card);
    assert_true(cards.mesh.component_count * (uint32_t)cards.columns >= cards.mesh.component_count);
    assert_frames(&cards.mesh);
    for (uint32_t c = 1; c < cards.mesh.component_count; c++)
        assert_true(cards.mesh.components[c - 1].sort_key <= cards.mesh.components[c].sort_key);
    ht_cards_free(&cards);
    ht_image_free(&material);
    ht_mesh_free(&full);
}

static void cards_coverage_furball(void **state) { (void)state; check_scene_cards("scenes/furball.json", 32, CARDS_COVERAGE_BOUND); }
static void cards_coverage_patches(void **state) { (void)state; check_scene_cards("scenes/patches.json", 4, CARDS_COVERAGE_BOUND); }
static void cards_coverage_strands(void **state) { (void)state; check_scene_cards("scenes/ratboy.json", 16, CARDS_COVERAGE_BOUND_MOHAWK); }

/* The order is a permutation, and a prefix of an eighth of it leaves no
   eighth of the fur ball's directions (octants) without hair. */
static void order_is_spread_permutation(void **state) {
    (void)state;
    ht_mesh full;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 1000, .seed = 7 }, &full), HT_OK);
    uint32_t *rank = malloc(sizeof *rank * full.component_count);
    unsigned char *seen = calloc(full.component_count, 1);
    assert_int_equal(ht_mesh_strand_order(&full, rank), HT_OK);
    int octant_hairs[8] = { 0 };
    for (uint32_t c = 0; c < full.component_count; c++) {
        assert_true(rank[c] < full.component_count && !seen[rank[c]]);
        seen[rank[c]] = 1;
        if (rank[c] < full.component_count / 8) {
            const ht_vertex *tip = &full.vertices[full.indices[full.components[c].first_index] + 2];
            octant_hairs[(tip->position[0] > 0) | (tip->position[1] > 0) << 1 | (tip->position[2] > 0) << 2]++;
        }
    }
    /* 125 hairs, about 16 an octant: stratified, none is empty or double. */
    for (int o = 0; o < 8; o++) assert_true(octant_hairs[o] >= 8 && octant_hairs[o] <= 24);
    free(rank);
    free(seen);
    ht_mesh_free(&full);
}

/* Decimation only: every strand kept, as wide, fewer rows where the hair
   runs straight, and a straight hair keeps only its root and tip. */
static void decimation_drops_straight_rows(void **state) {
    (void)state;
    ht_mesh curved, straight, lod;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 50, .gravity = { 0, -0.2f, 0 } }, &curved), HT_OK);
    assert_int_equal(ht_mesh_build_lod(&curved, &(ht_lod_desc){ 1, 8, 0 }, &lod), HT_OK);
    assert_int_equal(lod.component_count, curved.component_count);
    assert_true(lod.vertex_count < curved.vertex_count && lod.vertex_count > 4 * curved.component_count);
    assert_true(fabs(ht_mesh_mean_width(&lod) / ht_mesh_mean_width(&curved) - 1) < 0.2);
    assert_frames(&lod);
    ht_mesh_free(&lod);
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 50 }, &straight), HT_OK);
    assert_int_equal(ht_mesh_build_lod(&straight, &(ht_lod_desc){ 1, 1, 0 }, &lod), HT_OK);
    assert_int_equal(lod.vertex_count, 4 * straight.component_count);
    ht_mesh_free(&lod);
    /* The ladder keeps bends of 4 degrees at every level: 8 costs the dense
       groom 1.5-2 dB against the truth (docs/lod.md, other ladders). */
    for (int l = 0; l < HT_LOD_LEVELS; l++) {
        ht_lod_desc d;
        ht_lod_level(l, &d);
        assert_int_equal(d.strand_stride, 1u << l);
        assert_true(d.max_turn_deg == (l ? 4.0f : 0.0f));
    }
    ht_mesh_free(&straight);
    ht_mesh_free(&curved);
}

static void bad_meshes_refused(void **state) {
    (void)state;
    ht_mesh full, lod;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 10 }, &full), HT_OK);
    assert_int_equal(ht_mesh_build_lod(&full, &(ht_lod_desc){ 2, 91, 0 }, &lod), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_mesh_build_lod(&full, &(ht_lod_desc){ 2, NAN, 0 }, &lod), HT_ERR_INVALID_ARGUMENT);
    assert_null(lod.vertices);
    static const float bad_soften[] = { NAN, -1.0f, 0.5f, HT_LOD_MAX_SOFTEN * 1.01f, INFINITY };
    for (size_t i = 0; i < sizeof bad_soften / sizeof bad_soften[0]; i++) {
        assert_int_equal(ht_mesh_build_lod(&full, &(ht_lod_desc){ 2, 0, bad_soften[i] }, &lod), HT_ERR_INVALID_ARGUMENT);
        assert_null(lod.vertices);
    }
    full.indices[full.components[3].first_index] = full.vertex_count - 1; /* not a run of rows */
    assert_int_equal(ht_mesh_build_lod(&full, &(ht_lod_desc){ 2, 0, 0 }, &lod), HT_ERR_INVALID_ARGUMENT);
    assert_null(lod.vertices);
    assert_int_equal(ht_mesh_build_lod(NULL, &(ht_lod_desc){ 2, 0, 0 }, &lod), HT_ERR_INVALID_ARGUMENT);
    ht_mesh_free(&full);
}

static void best_keeps_full_detail_to_a_pixel_with_hysteresis(void **state) {
    (void)state;
    assert_int_equal(ht_lod_pick_best(3.0, -1, 4), 0);
    assert_int_equal(ht_lod_pick_best(1.0, -1, 4), 0);
    assert_int_equal(ht_lod_pick_best(0.9, -1, 4), 1);
    assert_int_equal(ht_lod_pick_best(0.3, -1, 4), 2);
    assert_int_equal(ht_lod_pick_best(0.001, -1, 4), 4);
    /* On the 1 px boundary: level 1 holds until 2^-0.25 = 1.19 px, level 0
       until 2^0.25 ... below, i.e. it takes 0.84 px to leave it. */
    assert_int_equal(ht_lod_pick_best(1.1, 1, 4), 1);
    assert_int_equal(ht_lod_pick_best(1.25, 1, 4), 0);
    assert_int_equal(ht_lod_pick_best(0.9, 0, 4), 0);
    assert_int_equal(ht_lod_pick_best(0.8, 0, 4), 1);
    /* A size sweeping back and forth across the boundary switches twice, not on every frame. */
    int cur = -1, switches = 0;
    for (int f = 0; f < 200; f++) {
        const double px = 1.0 + 0.1 * sin(f * 0.3) + (f < 100 ? 0.3 : -0.3);
        const int next = ht_lod_pick_best(px, cur, 4);
        switches += cur >= 0 && next != cur;
        cur = next;
    }
    assert_int_equal(switches, 1);
    assert_true(ht_projected_width_px(0.01, 3.0, 40.0, 512) > 2.3 && ht_projected_width_px(0.01, 3.0, 40.0, 512) < 2.4);
}

static void error_budget_picks_cheapest_pair_with_hysteresis(void **state) {
    (void)state;
    const ht_lod_cell cells[] = {
        { 0, HT_TIER_FULL, 0.5, INFINITY, 1.00, 0 }, { 1, HT_TIER_FULL, 0.5, 34, 0.55, 0 },
        { 2, HT_TIER_FULL, 0.5, 30.5, 0.30, 0 },     { 2, HT_TIER_FIXED, 0.5, 29, 0.20, 0 },
        { 0, HT_TIER_FULL, 1.0, INFINITY, 1.00, 0 }, { 1, HT_TIER_FULL, 1.0, 27, 0.55, 0 },
        { 3, HT_TIER_FULL, 0.5, 30.8, 0.28, 0 },
    };
    const int n = (int)(sizeof cells / sizeof cells[0]);
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 30, -1), 6);  /* cheapest at >= 30 dB */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.45, 30, -1), 6); /* nearest measured size */
    assert_int_equal(ht_lod_pick_error(cells, n, 1.0, 30, -1), 4);  /* only full detail meets it */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 40, -1), 0);  /* none: the most accurate */
    /* Held: (2, full) meets 30 dB and (3, full) is cheaper but not by the margin. */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 30, 2), 2);
    /* The held pair, measured at the other size, no longer meets it. */
    assert_int_equal(ht_lod_pick_error(cells, n, 1.0, 30, 1), 4);
    /* A cheaper pair clearing the margin replaces it: the cheapest such. */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 30, 0), 1);
    assert_int_equal(ht_lod_pick_error(cells, 0, 0.5, 30, -1), -1);
}

/* Pairs of every tier: the budget picks across tiers and levels, a
   cheaper tier at a finer level beating a coarser level of the top tier. */
static void error_budget_composes_lod_and_tier(void **state) {
    (void)state;
    const ht_lod_cell cells[] = {
        { 0, HT_TIER_FULL, 0.25, INFINITY, 1.00, 0 }, { 1, HT_TIER_FULL, 0.25, 31, 0.50, 0 },
        { 2, HT_TIER_FULL, 0.25, 29, 0.25, 0 },       { 0, HT_TIER_FIXED4, 0.25, 33, 0.60, 0 },
        { 1, HT_TIER_FIXED4, 0.25, 30.2, 0.30, 0 },   { 2, HT_TIER_FIXED4, 0.25, 28, 0.15, 0 },
        { 1, HT_TIER_GL11, 0.25, 26, 0.20, 0 },
    };
    const int n = (int)(sizeof cells / sizeof cells[0]);
    assert_int_equal(ht_lod_pick_error(cells, n, 0.25, 30, -1), 4); /* (1, fixed4): 0.30x at 30.2 dB */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.25, 32, -1), 3); /* (0, fixed4) */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.25, 25, -1), 5); /* (2, fixed4): the cheapest above 25 */
    /* the tier is part of the pair: (1, full) held stays, it is not (1, fixed4) */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.25, 30, 1), 1);
}

/* frame:MS: the most accurate pair within the budget (reference 10 ms),
   none within: the cheapest; hysteresis on both sides. */
static void frame_budget_picks_most_accurate_pair_with_hysteresis(void **state) {
    (void)state;
    const ht_lod_cell cells[] = {
        { 0, HT_TIER_FULL, 0.5, INFINITY, 1.00, 0 }, { 1, HT_TIER_FULL, 0.5, 31, 0.50, 0 },
        { 2, HT_TIER_FULL, 0.5, 29, 0.25, 0 },       { 1, HT_TIER_FIXED4, 0.5, 30.5, 0.30, 0 },
        { 2, HT_TIER_FIXED4, 0.5, 28, 0.15, 0 },     { 0, HT_TIER_FULL, 1.0, INFINITY, 1.00, 0 },
        { 1, HT_TIER_FULL, 1.0, 27, 0.45, 0 },
    };
    const int n = (int)(sizeof cells / sizeof cells[0]);
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 20, 10, -1), 0);  /* everything fits: full detail */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 5, 10, -1), 1);   /* 5 ms: (1, full) at 31 dB */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 3.2, 10, -1), 3); /* 3.2 ms: (1, fixed4) beats (2, full) */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 1, 10, -1), 4);   /* none fits: the cheapest */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.6, 5, 10, -1), 1);   /* nearest measured size */
    assert_int_equal(ht_lod_pick_frame(cells, n, 1.0, 5, 10, -1), 6);
    /* Held (1, full) at 5.3 ms against a 5 ms budget: within 10 %, it stays. */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 4.9, 10, 1), 1);
    /* Past the margin it goes, to the best within. */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 4.0, 10, 1), 3);
    /* Held (2, full): (1, fixed4) is 1.5 dB better within the budget: switch;
       held (1, fixed4) and (1, full) only 0.5 dB better: stay. */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 5, 10, 2), 1);
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 5, 10, 3), 3);
    /* A budget oscillating +-8 % around (1, full)'s 5 ms switches once. */
    int cur = -1, switches = 0;
    for (int f = 0; f < 100; f++) {
        const int next = ht_lod_pick_frame(cells, n, 0.5, 5.0 * (1 + 0.08 * sin(f * 0.7)), 10, cur);
        switches += cur >= 0 && next != cur;
        cur = next;
    }
    assert_true(switches <= 1);
    /* the reference frame of a rule: its size's, else the one for every size */
    const ht_lod_reference_frame frames[] = { { 0.5, 4 }, { 0.25, 0 } };
    const ht_lod_rule rule = { .reference_ms = 10, .reference_frames = frames, .reference_frame_count = 2 };
    assert_true(ht_lod_rule_reference_ms(&rule, 0.5) == 4 && ht_lod_rule_reference_ms(&rule, 1) == 10);
    assert_true(ht_lod_rule_reference_ms(&rule, 0.25) == 10); /* not timed there */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 5, 0, -1), -1);
    assert_int_equal(ht_lod_pick_frame(cells, 0, 0.5, 5, 10, -1), -1);
}

/* Soft and plain of one (level, tier) are two pairs: a soft cell the
   cheapest at the budget is picked; held, each keeps its own hysteresis
   (a held soft level 1 is not taken for plain level 1, which would be a
   switch); the frame rule too. */
static void soft_and_plain_pairs_with_hysteresis(void **state) {
    (void)state;
    const ht_lod_cell cells[] = {
        { 0, HT_TIER_GL11, 0.5, INFINITY, 1.00, 0 }, { 2, HT_TIER_GL11, 0.5, 27.8, 0.14, 0 },
        { 2, HT_TIER_GL11, 0.5, 30.4, 0.24, 3 },     { 1, HT_TIER_GL11, 0.5, 30.9, 0.30, 0 },
        { 1, HT_TIER_GL11, 0.5, 31.6, 0.45, 3 },
    };
    const int n = (int)(sizeof cells / sizeof cells[0]);
    assert_true(ht_lod_cell_same_pair(&cells[1], &cells[1]) && !ht_lod_cell_same_pair(&cells[1], &cells[2]));
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 30, -1), 2); /* (2 soft, gl11): 0.24x at 30.4 dB */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 31, -1), 4); /* (1 soft): the only one at 31 */
    /* held plain 1: soft 2 is cheaper but 30.4 < 31, the margin: stays */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 30, 3), 3);
    /* held soft 1 stays soft 1 (plain 1 meets 30 too, but is not it) */
    assert_int_equal(ht_lod_pick_error(cells, n, 0.5, 30, 4), 4);
    /* frame: 2.8 ms of a 10 ms reference: soft 2 the most accurate within; plain 1
       held at 3 ms stays (within 10 %, soft 2 not 1 dB better); soft 1 held at 4.5 ms goes */
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 2.8, 10, -1), 2);
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 2.8, 10, 3), 3);
    assert_int_equal(ht_lod_pick_frame(cells, n, 0.5, 2.8, 10, 4), 2);
}

/* The width rule's factor: a pixel wide or up to a quarter octave more. */
static void width_rule_reaches_a_pixel(void **state) {
    (void)state;
    assert_true(ht_width_rule_widen(1.0) == 1.0 && ht_width_rule_widen(3.0) == 1.0 && ht_width_rule_widen(0) == 1.0);
    assert_true(ht_width_rule_widen(NAN) == 1.0);
    /* it applies while the strand x samples^(1/4) is under 1.5 px (lod.h) */
    assert_true(ht_width_rule_applies(1.4, 0) && ht_width_rule_applies(1.4, 1) && !ht_width_rule_applies(1.5, 1));
    assert_true(ht_width_rule_applies(1.05, 4) && !ht_width_rule_applies(1.07, 4) && !ht_width_rule_applies(1.3, 4));
    assert_true(ht_width_rule_applies(0.74, 16) && !ht_width_rule_applies(0.76, 16));
    assert_true(!ht_width_rule_applies(0, 1) && !ht_width_rule_applies(NAN, 4) && !ht_width_rule_applies(-1, 4));
    for (double px = 0.01; px < 1.0; px *= 1.07) {
        const double f = ht_width_rule_widen(px);
        assert_true(f * px >= 1.0 - 1e-9 && f * px < pow(2, 0.25) + 1e-9);
        assert_true(fabs(4 * log2(f) - round(4 * log2(f))) < 1e-9);
    }
    /* ht_mesh_widen scales every ribbon's width about its centre line */
    ht_mesh full, wide;
    assert_int_equal(ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 200 }, &full), HT_OK);
    /* a scene's strand in pixels: the mean width at the eye's distance to the target */
    const ht_camera cam = { .eye = { 1, 2, 3 }, .target = { 1, 0, 3 }, .up = { 0, 0, 1 }, .fov_y = 40 };
    assert_true(fabs(ht_mesh_projected_width_px(&full, &cam, 512) -
                     ht_projected_width_px(ht_mesh_mean_width(&full), 2.0, 40, 512)) < 1e-12);
    assert_true(ht_mesh_projected_width_px(&full, &cam, 512) > 0);
    assert_true(ht_mesh_projected_width_px(NULL, &cam, 512) == 0 && ht_mesh_projected_width_px(&full, NULL, 512) == 0);
    assert_int_equal(ht_mesh_widen(&full, 2.5, &wide), HT_OK);
    assert_int_equal(wide.component_count, full.component_count);
    assert_true(fabs(ht_mesh_mean_width(&wide) / ht_mesh_mean_width(&full) - 2.5) < 0.02);
    ht_mesh_free(&wide);
    assert_int_equal(ht_mesh_widen(&full, 0.5, &wide), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_mesh_widen(&full, NAN, &wide), HT_ERR_INVALID_ARGUMENT);
    /* widened back to front: at factor 1 (the width rule per vertex) the
       very vertices, every segment (6 indices) a component, farthest first;
       at 2 twice as wide; no eye refused */
    const float eye[3] = { 0, 0, 5 };
    for (int k = 1; k <= 2; k++) {
        assert_int_equal(ht_mesh_widen_back_to_front(&full, k, eye, &wide), HT_OK);
        assert_int_equal(wide.vertex_count, full.vertex_count);
        if (k == 1) assert_memory_equal(wide.vertices, full.vertices, sizeof *full.vertices * full.vertex_count);
        else assert_true(fabs(ht_mesh_mean_width(&wide) / ht_mesh_mean_width(&full) - 2.0) < 0.02);
        assert_int_equal(wide.component_count, full.index_count / 6);
        for (uint32_t c = 1; c < wide.component_count; c++)
            assert_true(wide.components[c - 1].sort_key <= wide.components[c].sort_key &&
                        wide.components[c].index_count == 6);
        ht_mesh_free(&wide);
    }
    assert_int_equal(ht_mesh_widen_back_to_front(&full, 1.0, NULL, &wide), HT_ERR_INVALID_ARGUMENT);
    assert_null(wide.vertices);
    /* the rule on one mesh: 0.9 px widened by a quarter octave with one
       sample; with 16 the samples resolve it and nothing changes */
    double f = 0;
    assert_int_equal(ht_mesh_width_rule(&full, 0.9, 1, eye, &wide, &f), HT_OK);
    assert_true(f == ht_width_rule_widen(0.9) && f > 1.0 && wide.vertices);
    ht_mesh_free(&wide);
    assert_int_equal(ht_mesh_width_rule(&full, 0.9, 16, eye, &wide, &f), HT_OK);
    assert_true(f == 1.0 && !wide.vertices);
    assert_int_equal(ht_mesh_width_rule(&full, 0.3, 16, eye, &wide, &f), HT_OK);
    assert_true(f == ht_width_rule_widen(0.3) && wide.vertices);
    ht_mesh_free(&wide);
    /* back to front: the farthest centroid from the eye first */
    ht_mesh_sort_back_to_front(&full, eye);
    for (uint32_t c = 1; c < full.component_count; c++)
        assert_true(full.components[c - 1].sort_key <= full.components[c].sort_key);
    assert_true(full.components[0].sort_key < full.components[full.component_count - 1].sort_key);
    ht_mesh_free(&full);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(coverage_furball),
        cmocka_unit_test(coverage_patches),
        cmocka_unit_test(coverage_strands),
        cmocka_unit_test(cards_coverage_furball),
        cmocka_unit_test(cards_coverage_patches),
        cmocka_unit_test(cards_coverage_strands),
        cmocka_unit_test(order_is_spread_permutation),
        cmocka_unit_test(decimation_drops_straight_rows),
        cmocka_unit_test(bad_meshes_refused),
        cmocka_unit_test(best_keeps_full_detail_to_a_pixel_with_hysteresis),
        cmocka_unit_test(error_budget_picks_cheapest_pair_with_hysteresis),
        cmocka_unit_test(error_budget_composes_lod_and_tier),
        cmocka_unit_test(frame_budget_picks_most_accurate_pair_with_hysteresis),
        cmocka_unit_test(soft_and_plain_pairs_with_hysteresis),
        cmocka_unit_test(width_rule_reaches_a_pixel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

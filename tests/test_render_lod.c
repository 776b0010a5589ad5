/* test_render_lod — every geometry LOD (lod.h) of the fixture's fur ball is
   drawn by the same four passes with the same state in every tier (the
   trace: only the draw range differs, and it is the LOD's whole index
   buffer), without a GL error, and still covers about as many pixels as
   full detail at a quarter of the size (the width rule on a real raster);
   a chain of levels switches with the camera's distance, with hysteresis,
   and a chain of (level, tier) pairs with an error or a frame budget. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "cards_bundle.h"
#include "support_gl_fault.h"
#include "support_render.h"

#define SIZE 48
/* Hair pixels at each LOD against full detail, at SIZE (the fixture's fur
   ball is about 1/10 of the scene's projected size here). */
#define PIXEL_BOUND 0.15
/* gl11 shades whole blocks of 8 vertices (gl11_program.h): the slack at
   each end of a level's own vertices, which the chain names
   (ht_renderer_set_draw_range_vertices). */
#define HT_TEST_BLOCK_VERTICES 8

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "render_lod", SIZE) ? 0 : -1;
}
static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

/* A full-tier renderer on the GL fault layer, which counts its uploads. */
static ht_renderer *fault_counted_renderer(void) {
    return ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true,
                                                       .getproc = ht_test_fault_getproc },
                                   fx.bundle_dir, HT_OK);
}

/* glBufferData calls since ht_fault_arm (the class counts glBufferSubData too). */
static long buffer_data_calls(void) {
    return ht_fault_state_get()->calls[HT_FAULT_BUFFER_DATA] - ht_fault_state_get()->buffer_sub_data;
}

/* glBufferSubData calls since ht_fault_arm: ht_renderer_set_mesh_order's index upload. */
static long buffer_sub_data_calls(void) { return ht_fault_state_get()->buffer_sub_data; }

static int draw_lod(ht_renderer *r, const ht_mesh *mesh, ht_trace *trace) {
    assert_int_equal(ht_renderer_set_mesh(r, mesh), HT_OK);
    const ht_frame_desc frame = ht_test_furball_frame(3.0f);
    ht_image img;
    ht_test_draw(&fx.gl, r, &frame, ht_test_background, &img);
    *trace = *ht_renderer_trace(r);
    const int changed = ht_test_pixel_stats_of(&img, ht_test_background).changed;
    ht_image_free(&img);
    return changed;
}

/* The hair's ink: each pixel's largest channel difference from the
   background, summed (a faint card edge counts as little as it shows). */
static double ink_of(ht_renderer *r, const ht_mesh *mesh) {
    assert_int_equal(ht_renderer_set_mesh(r, mesh), HT_OK);
    const ht_frame_desc frame = ht_test_furball_frame(3.0f);
    ht_image img;
    ht_test_draw(&fx.gl, r, &frame, ht_test_background, &img);
    double ink = 0;
    for (int i = 0; i < img.width * img.height; i++) {
        double d = 0;
        for (int c = 0; c < 3; c++) d = fmax(d, fabs(img.pixels[i * img.channels + c] / 255.0 - ht_test_background[c]));
        ink += d;
    }
    ht_image_free(&img);
    return ink;
}

/* t is full's passes with the same state, without a GL error, drawing
   index_count indices. */
static void assert_same_passes(const ht_trace *t, const ht_trace *full, uint32_t index_count, const char *what) {
    assert_int_equal(t->count, full->count);
    for (int i = 0; i < t->count; i++) {
        assert_int_equal(t->entries[i].gl_error, GL_NO_ERROR);
        assert_int_equal(t->entries[i].index_count, index_count);
        ht_trace_entry e = t->entries[i];
        e.index_count = full->entries[i].index_count;
        if (memcmp(&e, &full->entries[i], sizeof e) != 0) fail_msg("%s: pass %d differs from full detail's", what, i);
    }
}

static void same_passes_every_lod(ht_tier tier) {
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = tier, .strict = true }, fx.bundle_dir, HT_OK);
    ht_trace full;
    const int full_pixels = draw_lod(r, &fx.mesh, &full);
    assert_int_equal(full.count, HT_PASS_COUNT);
    for (int level = 1; level <= ht_lod_max_level(&fx.mesh); level++) {
        ht_lod_desc d;
        ht_mesh lod;
        ht_lod_level(level, &d);
        assert_int_equal(ht_mesh_build_lod(&fx.mesh, &d, &lod), HT_OK);
        ht_trace t;
        const int pixels = draw_lod(r, &lod, &t);
        printf("%s level %d: %d hair pixels, full detail %d\n", ht_tier_name(tier), level, pixels, full_pixels);
        char what[64];
        snprintf(what, sizeof what, "%s level %d", ht_tier_name(tier), level);
        assert_same_passes(&t, &full, lod.index_count, what);
        assert_true(abs(pixels - full_pixels) <= PIXEL_BOUND * full_pixels);
        ht_mesh_free(&lod);
    }
    ht_renderer_destroy(r);
}

/* A bundle storing every level (hairgen --cards: one atlas holding the
   material's texture and the cards', lods.bin the fur ball's strand
   levels and its cards of 16 strands). In the tier: level 0 drawn from it
   is full detail drawn from the material's own bundle (every channel
   within CARDS_SAME of it: the strands' uv land on the material's texels
   in the atlas); the cards are drawn by the same four passes with the
   same state (only the draw range differs), no GL error, and ink
   (ink_of) within CARDS_INK_BOUND of full detail's. */
#define CARDS_STRANDS 16
#define CARDS_ATLAS 512
#define CARDS_INK_BOUND 0.25
#define CARDS_SAME 2

/* Made once, for every test of the group (the bake is most of their cost). */
static void make_cards_bundle(char *dir, size_t size, ht_lod_file *ladder) {
    static bool made;
    char err[512] = "", path[256];
    snprintf(dir, size, "%s/cards", fx.work);
    if (!made && ht_cards_bundle_write_mesh(fx.bundle_dir, &fx.mesh, CARDS_STRANDS, CARDS_ATLAS, dir, NULL, err,
                                            sizeof err) != HT_OK)
        fail_msg("%s", err);
    made = true;
    snprintf(path, sizeof path, "%s/%s", dir, HT_LOD_FILE_NAME);
    if (ht_lod_file_read(path, ladder, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_int_equal(ladder->level_count, ht_lod_max_level(&fx.mesh) + 2);
    for (int l = 0; l < ladder->level_count; l++)
        assert_int_equal(ladder->levels[l].kind, l + 1 < ladder->level_count ? HT_LOD_KIND_STRANDS : HT_LOD_KIND_CARDS);
}

static void draw_image(ht_renderer *r, const ht_mesh *mesh, ht_image *img) {
    assert_int_equal(ht_renderer_set_mesh(r, mesh), HT_OK);
    const ht_frame_desc frame = ht_test_furball_frame(3.0f);
    ht_test_draw(&fx.gl, r, &frame, ht_test_background, img);
}

static void cards_same_passes(ht_tier tier) {
    char dir[192];
    ht_lod_file ladder;
    make_cards_bundle(dir, sizeof dir, &ladder);
    ht_mesh level0, cards;
    assert_int_equal(ht_lod_file_level_mesh(&ladder, 0, &level0), HT_OK);
    assert_int_equal(ht_lod_file_level_mesh(&ladder, ladder.level_count - 1, &cards), HT_OK);
    ht_lod_file_free(&ladder);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = tier, .strict = true }, fx.bundle_dir, HT_OK);
    ht_trace full;
    ht_image want, got;
    draw_lod(r, &fx.mesh, &full);
    const double full_ink = ink_of(r, &fx.mesh);
    draw_image(r, &fx.mesh, &want);
    ht_renderer_destroy(r);
    r = ht_test_renderer_create((ht_renderer_desc){ .tier = tier, .strict = true }, dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), tier);
    draw_image(r, &level0, &got);
    int worst = 0;
    for (int i = 0; i < want.width * want.height * want.channels; i++) {
        const int d = abs((int)want.pixels[i] - (int)got.pixels[i]);
        worst = d > worst ? d : worst;
    }
    ht_image_free(&want);
    ht_image_free(&got);
    ht_trace t;
    draw_lod(r, &cards, &t);
    const double ink = ink_of(r, &cards);
    printf("%s: stored level 0 within %d of full detail; %u cards, ink %.1f, full detail %.1f (%+.1f%%)\n",
           ht_tier_name(tier), worst, cards.component_count, ink, full_ink, 100 * (ink / full_ink - 1));
    assert_true(worst <= CARDS_SAME);
    assert_same_passes(&t, &full, cards.index_count, "cards");
    assert_true(fabs(ink / full_ink - 1) <= CARDS_INK_BOUND);
    ht_renderer_destroy(r);
    ht_mesh_free(&cards);
    ht_mesh_free(&level0);
}

/* One frame drawn; its trace, the four passes. */
static const ht_trace *draw_traced(ht_renderer *r, const ht_frame_desc *frame) {
    ht_image img;
    ht_test_draw(&fx.gl, r, frame, ht_test_background, &img);
    ht_image_free(&img);
    const ht_trace *t = ht_renderer_trace(r);
    assert_int_equal(t->count, HT_PASS_COUNT);
    return t;
}

/* One frame of the chain's renderer: the four passes, each drawing the
   chain's level `level` range. */
static void draw_expect_level(ht_renderer *r, const ht_lod_chain *chain, const ht_frame_desc *frame, int level) {
    const ht_trace *t = draw_traced(r, frame);
    for (int i = 0; i < t->count; i++) {
        assert_int_equal(t->entries[i].first_index, chain->first[level]);
        assert_int_equal(t->entries[i].index_count, chain->index_count[level]);
    }
}

/* The stored ladder as a chain (ht_lod_chain_from_file) in one renderer:
   pulled from 3 to 1000 it reaches the cards, one past the last strand
   level, and back; one upload at the first select, none at a switch, and
   each frame draws its level's range. */
static void stored_chain_reaches_the_cards(void **state) {
    (void)state;
    char dir[192];
    ht_lod_file ladder;
    make_cards_bundle(dir, sizeof dir, &ladder);
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_from_file(&ladder, &chain), HT_OK);
    ht_lod_file_free(&ladder);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true,
                                                                 .getproc = ht_test_fault_getproc },
                                             dir, HT_OK);
    const float distances[] = { 3, 1000, 3 };
    const int expect[] = { 0, chain.count - 1, 0 };
    for (int f = 0; f < 3; f++) {
        ht_frame_desc frame = ht_test_furball_frame(distances[f]);
        ht_result res;
        assert_int_equal(ht_lod_chain_select(&chain, r, &frame.camera, 512, &res), expect[f]);
        if (f == 0) ht_fault_arm(HT_FAULT_NONE, 0);
        draw_expect_level(r, &chain, &frame, expect[f]);
    }
    assert_int_equal(buffer_data_calls(), 0);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

/* A camera pulled from 3 to 40 and back, jittering by 3 %: the chain
   goes only coarser on the way out and finer on the way back (512 pixels
   high for the choice), reaching the level the rule gives at 40, each
   frame draws the chosen level's range of the one uploaded buffer in the
   four passes, and no switch uploads anything (glBufferData counted). */
static void chain_switches_with_the_distance(void **state) {
    (void)state;
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    assert_int_equal(chain.count, 4); /* 400 hairs: levels 0..3 */
    ht_renderer *r = fault_counted_renderer();
    int switches = 0, last = -1, peak = 0, steps = 120;
    long uploads_at_first = -1;
    for (int f = 0; f < 2 * steps; f++) {
        const double t = f < steps ? (double)f / (steps - 1) : (double)(2 * steps - 1 - f) / (steps - 1);
        const float d = (float)((3.0 + 37.0 * t) * (1.0 + 0.03 * ((f % 3) - 1)));
        ht_frame_desc frame = ht_test_furball_frame(d);
        ht_result res;
        const int level = ht_lod_chain_select(&chain, r, &frame.camera, 512, &res);
        assert_int_equal(res, HT_OK);
        assert_true(level >= 0 && level < chain.count);
        /* One upload, at the first select: a switch moves the draw range. */
        if (f == 0) {
            uploads_at_first = buffer_data_calls();
            ht_fault_arm(HT_FAULT_NONE, 0);
        }
        if (last >= 0 && level != last) switches++;
        /* Moving away never finer, coming back never coarser: the jitter
           does not flicker across a boundary. */
        if (last >= 0) assert_true(f < steps ? level >= last : level <= last);
        if (level > peak) peak = level;
        last = level;
        if (f % 20 == 0) {
            assert_int_equal(chain.index_count[level], ht_lod_chain_mesh(&chain, level)->index_count);
            draw_expect_level(r, &chain, &frame, level);
        }
    }
    printf("chain: %d switches over %d frames, up to level %d, back at level %d; glBufferData %ld at the first "
           "select, %ld after\n", switches, 2 * steps, peak, last, uploads_at_first,
           buffer_data_calls());
    assert_int_equal(uploads_at_first, 2); /* the vertex and the index buffer */
    assert_int_equal(buffer_data_calls(), 0);
    const ht_frame_desc far = ht_test_furball_frame(40.0f);
    double d2 = 0;
    for (int k = 0; k < 3; k++) d2 += (double)far.camera.eye[k] * far.camera.eye[k];
    assert_int_equal(peak, ht_lod_pick_best(ht_projected_width_px(chain.width, sqrt(d2), far.camera.fov_y, 512), -1, 3));
    assert_true(peak >= 2 && switches >= 2 && switches <= 2 * peak);
    assert_int_equal(last, 0);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

/* Synthetic measured cells, 4 pairs at each of 3 sizes, so the rules'
   picks are known: error:30 takes (0, gl11) at size 1, (1, fixed) at 1/2,
   (2, gl11) at 1/4; frame:7.5 ms over a 10 ms reference takes (0, gl11)
   at 1 and keeps it at 1/2 (8 ms, within its 10 % margin), (1, fixed) at
   1/4 (gl11 at level 0 is 9 ms there), and (0, gl11) again back at 1. */
static const ht_lod_cell pair_cells[] = {
    { 0, HT_TIER_FULL, 1, INFINITY, 1, 0 },    { 0, HT_TIER_GL11, 1, 38, 0.7, 0 },
    { 1, HT_TIER_FIXED, 1, 28, 0.4, 0 },       { 2, HT_TIER_GL11, 1, 25, 0.2, 0 },
    { 0, HT_TIER_FULL, 0.5, INFINITY, 1, 0 },  { 0, HT_TIER_GL11, 0.5, 38, 0.8, 0 },
    { 1, HT_TIER_FIXED, 0.5, 32, 0.4, 0 },     { 2, HT_TIER_GL11, 0.5, 27, 0.2, 0 },
    { 0, HT_TIER_FULL, 0.25, INFINITY, 1, 0 }, { 0, HT_TIER_GL11, 0.25, 38, 0.9, 0 },
    { 1, HT_TIER_FIXED, 0.25, 34, 0.4, 0 },    { 2, HT_TIER_GL11, 0.25, 31, 0.2, 0 },
};

typedef struct pair { int level; ht_tier tier; } pair;

/* One frame of a pair: the full-detail trace's four passes and state over
   the level's range of the chain's one buffer (the inside-out order of
   that level), and the GL calls of the pair's tier: a program bound only
   by the full tier, combiner stages only by fixed, neither by gl11. */
static void draw_pair(ht_renderer *r, const ht_lod_chain *chain, const ht_frame_desc *frame, const ht_trace *full,
                      pair p) {
    const long programs = ht_fault_state_get()->programs_bound, stages = ht_fault_state_get()->combiner_stages;
    draw_expect_level(r, chain, frame, p.level);
    const ht_trace *t = ht_renderer_trace(r);
    for (int i = 0; i < t->count; i++) {
        ht_trace_entry e = t->entries[i];
        e.first_index = full->entries[i].first_index;
        e.index_count = full->entries[i].index_count;
        if (memcmp(&e, &full->entries[i], sizeof e) != 0) fail_msg("%s level %d: pass %d differs from full detail's",
                                                                   ht_tier_name(p.tier), p.level, i);
    }
    assert_int_equal(ht_renderer_tier(r), p.tier);
    const long drew_programs = ht_fault_state_get()->programs_bound - programs;
    const long drew_stages = ht_fault_state_get()->combiner_stages - stages;
    assert_true(p.tier == HT_TIER_FULL ? drew_programs > 0 : drew_programs == 0);
    assert_true(p.tier == HT_TIER_FIXED ? drew_stages > 0 : drew_stages == 0);
}

/* The camera pulled from 3 to 14 units and back, jittering 3 % a frame,
   under `rule`: each frame's pair is the one `expect` lists next (never
   one back: a switch happens once across each boundary), every pair's
   frame is drawn by its tier in the four passes, glBufferData is called
   and GL objects are made only where a tier is used for the first time (its backend's own
   buffers; the chain's mesh is uploaded once), and the fixed-function
   tiers' per-frame CPU work covers the level's vertices, not the buffer's. */
static void pull_out_and_back(ht_lod_rule rule, const pair *expect, int expect_count) {
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    ht_renderer *r = fault_counted_renderer();
    ht_trace full;
    draw_lod(r, &fx.mesh, &full);
    rule.cells = pair_cells;
    rule.cell_count = (int)(sizeof pair_cells / sizeof pair_cells[0]);
    rule.size1_px = ht_projected_width_px(chain.width, 3.0, ht_test_furball_frame(3.0f).camera.fov_y, 512);
    const int steps = 30;
    int at = 0;
    unsigned used = 1u << HT_TIER_FULL;
    ht_fault_arm(HT_FAULT_NONE, 0);
    for (int f = 0; f < 2 * steps; f++) {
        const double t = f < steps ? (double)f / (steps - 1) : (double)(2 * steps - 1 - f) / (steps - 1);
        const float d = (float)((3.0 + 11.0 * t) * (1.0 + 0.03 * ((f % 3) - 1)));
        const ht_frame_desc frame = ht_test_furball_frame(d);
        const long uploads = buffer_data_calls();
        int objects = 0;
        for (int k = 0; k < HT_FAULT_OBJECT_COUNT; k++) objects += ht_fault_state_get()->created[k];
        ht_result res;
        const int level = ht_lod_chain_select_pair(&chain, r, &frame.camera, 512, &rule, &res);
        assert_int_equal(res, HT_OK);
        const pair now = { level, chain.tier };
        const bool switched = f == 0 || now.level != expect[at].level || now.tier != expect[at].tier;
        if (f > 0 && switched) at++;
        if (at >= expect_count || now.level != expect[at].level || now.tier != expect[at].tier)
            fail_msg("frame %d (distance %.2f): level %d %s, expected the pair after level %d %s", f, d, now.level,
                     ht_tier_name(now.tier), expect[at > 0 ? at - 1 : 0].level,
                     ht_tier_name(expect[at > 0 ? at - 1 : 0].tier));
        const bool first_use = !(used >> now.tier & 1u);
        used |= 1u << now.tier;
        /* the first select uploads the chain's buffers (2); a tier's first use its own */
        int objects_after = 0;
        for (int k = 0; k < HT_FAULT_OBJECT_COUNT; k++) objects_after += ht_fault_state_get()->created[k];
        if (f > 0 && !first_use) {
            assert_int_equal(buffer_data_calls(), uploads);
            assert_int_equal(objects_after, objects); /* no texture, buffer, shader or program made */
        }
        if (switched || f % 10 == 0) {
            const long before = buffer_data_calls();
            const uint64_t cpu = ht_renderer_get_stats(r).cpu_vertices;
            draw_pair(r, &chain, &frame, &full, now);
            assert_int_equal(buffer_data_calls(), before);
            const uint64_t made = ht_renderer_get_stats(r).cpu_vertices - cpu;
            const uint32_t level_vertices = ht_lod_chain_mesh(&chain, level)->vertex_count;
            /* fixed: two slots' coordinates and colours at most; the slack: a block at each end */
            if (now.tier != HT_TIER_FULL)
                assert_true(made <= 2 * (uint64_t)(level_vertices + 2 * HT_TEST_BLOCK_VERTICES) &&
                            made < chain.all.vertex_count);
        }
    }
    printf("%s %.1f: %d pairs over %d frames (%d switches), back at level %d %s; every pair drawn by its tier\n",
           rule.kind == HT_POLICY_ERROR ? "error" : "frame", rule.value, at + 1, 2 * steps, at, chain.current,
           ht_tier_name(chain.tier));
    assert_int_equal(at, expect_count - 1);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

static void chain_pairs_follow_an_error_budget(void **state) {
    (void)state;
    const pair expect[] = { { 0, HT_TIER_GL11 }, { 1, HT_TIER_FIXED }, { 2, HT_TIER_GL11 },
                            { 1, HT_TIER_FIXED }, { 0, HT_TIER_GL11 } };
    pull_out_and_back((ht_lod_rule){ .kind = HT_POLICY_ERROR, .value = 30 }, expect, 5);
}

static void chain_pairs_follow_a_frame_budget(void **state) {
    (void)state;
    const pair expect[] = { { 0, HT_TIER_GL11 }, { 1, HT_TIER_FIXED }, { 0, HT_TIER_GL11 } };
    pull_out_and_back((ht_lod_rule){ .kind = HT_POLICY_FRAME, .value = 7.5, .reference_ms = 10 }, expect, 3);
}

/* frame:7.5 with the reference frame timed per size: 10 ms at 1 and 1/2,
   6 ms at 1/4 (less hair on screen): at 1/4 full detail fits (6 ms) and
   is the most accurate, where one 10 ms reference for every size keeps
   (1, fixed) there (the case above). */
static void chain_frame_budget_reads_each_sizes_reference(void **state) {
    (void)state;
    static const ht_lod_reference_frame frames[] = { { 1, 10 }, { 0.5, 10 }, { 0.25, 6 } };
    const pair expect[] = { { 0, HT_TIER_GL11 }, { 0, HT_TIER_FULL }, { 1, HT_TIER_FIXED }, { 0, HT_TIER_GL11 } };
    pull_out_and_back((ht_lod_rule){ .kind = HT_POLICY_FRAME, .value = 7.5, .reference_ms = 10,
                                     .reference_frames = frames, .reference_frame_count = 3 },
                      expect, 4);
}

/* The width rule per draw in the chain: pulled from 3 to 300 units and
   back (512 pixels high), the coarsest level's strands go under a pixel
   past about 30; from there each frame draws that level widened by the
   rule's factor (its own mesh, the whole of it: the trace's range) with
   every fragment blended (the passes' alpha reference 1: the opacity
   scale is on), the drawn strand (level width x factor) never narrower
   while the camera moves out;
   an upload (2 glBufferData: vertices, indices) happens only when the
   factor or the level changes, and back at 3 the chain draws `all`'s
   level-0 range with the bundle's cutoff again. */
static void chain_width_rule_per_draw(void **state) {
    (void)state;
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    chain.width_rule = true;
    ht_renderer *r = fault_counted_renderer();
    const int steps = 24;
    int changes = 0, widened_frames = 0;
    double last_f = 1.0, last_drawn = 0;
    int last_level = -1;
    for (int f = 0; f < 2 * steps; f++) {
        const double t = f < steps ? (double)f / (steps - 1) : (double)(2 * steps - 1 - f) / (steps - 1);
        const ht_frame_desc frame = ht_test_furball_frame((float)(3.0 * pow(100.0, t)));
        ht_fault_arm(HT_FAULT_NONE, 0);
        ht_result res;
        const int level = ht_lod_chain_select(&chain, r, &frame.camera, 512, &res);
        assert_int_equal(res, HT_OK);
        const double wf = chain.wide_renderer == r ? chain.wide_factor : 1.0;
        const bool changed = f > 0 && (wf != last_f || (wf > 1.0 && level != last_level));
        changes += changed;
        assert_int_equal(buffer_data_calls(), f == 0 || changed ? 2 : 0);
        /* the drawn strand (the level's width x the factor) only widens going out */
        const double drawn = chain.level_width[level] * wf;
        if (f < steps && f > 0) assert_true(drawn >= last_drawn * (1 - 1e-9));
        last_drawn = drawn;
        const ht_trace *tr = draw_traced(r, &frame);
        for (int i = 0; i < tr->count; i++) {
            assert_int_equal(tr->entries[i].gl_error, GL_NO_ERROR);
            if (wf > 1.0) {
                assert_true(tr->entries[i].alpha_ref == 1.0f);
                assert_int_equal(tr->entries[i].first_index, 0);
                assert_int_equal(tr->entries[i].index_count, chain.wide.index_count);
            } else {
                assert_true(tr->entries[i].alpha_ref < 1.0f);
                assert_int_equal(tr->entries[i].first_index, chain.first[level]);
            }
        }
        widened_frames += wf > 1.0;
        last_f = wf;
        last_level = level;
    }
    printf("width rule: %d of %d frames widened (up to level %d), %d uploads of a widened level or all\n",
           widened_frames, 2 * steps, chain.count - 1, changes);
    assert_true(widened_frames >= 8 && changes >= 2 && changes <= widened_frames + 4);
    assert_int_equal(last_level, 0);
    assert_true(last_f == 1.0);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

/* Frames of a pull out from 3 to 300 units in which the chain drew its
   level with the width rule per vertex (sorted back to front), and the
   widest strand among them (pixels, the level's mean): under the
   framebuffer bound now, none of max_px or more. */
static int rule_frames(ht_renderer *r, double max_px, double *widest_px) {
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    chain.width_rule = true;
    int drawn = 0;
    *widest_px = 0;
    for (int f = 0; f < 24; f++) {
        const ht_frame_desc frame = ht_test_furball_frame((float)(3.0 * pow(100.0, f / 23.0)));
        ht_result res;
        const int level = ht_lod_chain_select(&chain, r, &frame.camera, 512, &res);
        assert_int_equal(res, HT_OK);
        assert_true(ht_renderer_width_rule_per_vertex(r));
        if (chain.ordered_level < 0) continue;
        drawn++;
        const double px = ht_mesh_projected_width_px(ht_lod_chain_mesh(&chain, level), &frame.camera, 512);
        if (px > *widest_px) *widest_px = px;
        if (px > max_px * 1.05) fail_msg("frame %d: level %d drawn with the rule at %.3f px", f, level, px);
    }
    ht_lod_chain_free(&chain);
    return drawn;
}

/* The chain's width rule reads the framebuffer's samples
   (ht_renderer_samples): per vertex, with a 4-sample framebuffer bound it
   draws a level with the rule (back to front) only while its strands are
   under 1.5 / 4^(1/4) = 1.06 px (ht_width_rule_applies; the samples
   resolve wider ones), where with one sample up to 1.5 px. */
static void chain_width_rule_reads_the_samples(void **state) {
    (void)state;
    PFNGLGENFRAMEBUFFERSPROC gen_fb = (PFNGLGENFRAMEBUFFERSPROC)ht_test_getproc("glGenFramebuffers");
    PFNGLBINDFRAMEBUFFERPROC bind_fb = (PFNGLBINDFRAMEBUFFERPROC)ht_test_getproc("glBindFramebuffer");
    PFNGLDELETEFRAMEBUFFERSPROC delete_fb = (PFNGLDELETEFRAMEBUFFERSPROC)ht_test_getproc("glDeleteFramebuffers");
    PFNGLGENRENDERBUFFERSPROC gen_rb = (PFNGLGENRENDERBUFFERSPROC)ht_test_getproc("glGenRenderbuffers");
    PFNGLBINDRENDERBUFFERPROC bind_rb = (PFNGLBINDRENDERBUFFERPROC)ht_test_getproc("glBindRenderbuffer");
    PFNGLDELETERENDERBUFFERSPROC delete_rb = (PFNGLDELETERENDERBUFFERSPROC)ht_test_getproc("glDeleteRenderbuffers");
    PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC storage =
        (PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC)ht_test_getproc("glRenderbufferStorageMultisample");
    PFNGLFRAMEBUFFERRENDERBUFFERPROC attach = (PFNGLFRAMEBUFFERRENDERBUFFERPROC)ht_test_getproc("glFramebufferRenderbuffer");
    PFNGLCHECKFRAMEBUFFERSTATUSPROC status = (PFNGLCHECKFRAMEBUFFERSTATUSPROC)ht_test_getproc("glCheckFramebufferStatus");
    if (!gen_fb || !bind_fb || !delete_fb || !gen_rb || !bind_rb || !delete_rb || !storage || !attach || !status)
        skip(); /* no framebuffer objects on this driver */
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true }, fx.bundle_dir,
                                             HT_OK);
    ht_renderer_set_width_rule(r, true);
    double widest[2];
    assert_int_equal(ht_renderer_samples(r), 1);
    const int one = rule_frames(r, HT_WIDTH_RULE_VERTEX_PX, &widest[0]);
    GLuint fb = 0, rb[2] = { 0, 0 };
    gen_fb(1, &fb);
    gen_rb(2, rb);
    const GLenum formats[2] = { GL_RGBA8, GL_DEPTH_COMPONENT24 };
    const GLenum points[2] = { GL_COLOR_ATTACHMENT0, GL_DEPTH_ATTACHMENT };
    bind_fb(GL_FRAMEBUFFER, fb);
    for (int i = 0; i < 2; i++) {
        bind_rb(GL_RENDERBUFFER, rb[i]);
        storage(GL_RENDERBUFFER, 4, formats[i], SIZE, SIZE);
        attach(GL_FRAMEBUFFER, points[i], GL_RENDERBUFFER, rb[i]);
    }
    assert_int_equal(status(GL_FRAMEBUFFER), GL_FRAMEBUFFER_COMPLETE);
    assert_int_equal(ht_renderer_samples(r), 4);
    const int four = rule_frames(r, HT_WIDTH_RULE_VERTEX_PX / sqrt(2.0), &widest[1]);
    bind_fb(GL_FRAMEBUFFER, 0);
    delete_fb(1, &fb);
    delete_rb(2, rb);
    printf("chain width rule per vertex: %d frames with 1 sample (strands up to %.3f px), %d with 4 (up to %.3f px)\n",
           one, widest[0], four, widest[1]);
    assert_true(four > 0 && four < one);
    ht_renderer_destroy(r);
}

/* The width rule per vertex in the chain (the full tier does it): the
   same pull out and back, but no level is ever widened or copied (the
   vertex stage widens each strand); past about 30 units, where the
   level's strands go under 1.5 px, the level's range of `all` is sorted
   back to front (chain.ordered_level) and drawn with the material's
   reference kept (no opacity scale) and its blended passes in the mesh's
   order (the back pass draws both faces, the front pass none). `all` is
   uploaded once, at the first frame, and never again: a level sorted
   (another level, or the distance 2x since its order was made) or put
   back as built uploads the indices alone (one glBufferSubData); per
   draw (above) uploads a widened level at every change of the factor. */
static void chain_width_rule_per_vertex(void **state) {
    (void)state;
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    chain.width_rule = true;
    ht_renderer *r = fault_counted_renderer();
    ht_renderer_set_width_rule(r, true);
    const int steps = 24;
    int sorted_frames = 0, orders = 0, last_level = -1;
    bool last_sorted = false;
    double sorted_at = 0;
    for (int f = 0; f < 2 * steps; f++) {
        const double t = f < steps ? (double)f / (steps - 1) : (double)(2 * steps - 1 - f) / (steps - 1);
        const double d = 3.0 * pow(100.0, t);
        const ht_frame_desc frame = ht_test_furball_frame((float)d);
        ht_fault_arm(HT_FAULT_NONE, 0);
        ht_result res;
        const int level = ht_lod_chain_select(&chain, r, &frame.camera, 512, &res);
        assert_int_equal(res, HT_OK);
        assert_true(ht_renderer_width_rule_per_vertex(r));
        assert_null(chain.wide_renderer);
        assert_ptr_equal(chain.uploaded, r);
        const bool sorted = chain.ordered_level >= 0;
        if (sorted) assert_int_equal(chain.ordered_level, level);
        const bool resort = sorted && last_sorted && level == last_level &&
                            (d > sorted_at * HT_LOD_RESORT_DISTANCE || d * HT_LOD_RESORT_DISTANCE < sorted_at);
        const bool order = sorted != last_sorted || (sorted && level != last_level) || resort;
        if (sorted && order) sorted_at = d;
        assert_int_equal(buffer_data_calls() > 0, f == 0);
        if (f > 0) assert_int_equal(buffer_sub_data_calls(), order);
        orders += f > 0 && order;
        const ht_trace *tr = draw_traced(r, &frame);
        for (int i = 0; i < tr->count; i++) {
            const ht_trace_entry *e = &tr->entries[i];
            assert_int_equal(e->gl_error, GL_NO_ERROR);
            assert_true(e->alpha_ref >= HT_WIDTH_RULE_VERTEX_REF && e->alpha_ref < 1.0f);
            assert_int_equal(e->first_index, chain.first[level]);
            assert_int_equal(e->index_count, chain.index_count[level]);
            if (e->pass == HT_PASS_BACK) assert_true(sorted ? !e->cull : e->cull && e->cull_face == GL_FRONT);
            if (e->pass == HT_PASS_FRONT && sorted) assert_int_equal(e->cull_face, GL_FRONT_AND_BACK);
        }
        sorted_frames += sorted;
        last_sorted = sorted;
        last_level = level;
    }
    printf("width rule per vertex: %d of %d frames a level sorted back to front in all, none widened or copied, "
           "all uploaded once, %d index-only uploads\n", sorted_frames, 2 * steps, orders);
    assert_true(sorted_frames >= 8 && orders >= 3);
    assert_int_equal(last_level, 0);
    assert_false(last_sorted);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

/* ht_renderer_set_mesh_order: the fur ball sorted back to front for one
   eye, then re-ordered for another, draws what a fresh upload of the
   second order draws (byte for byte), with one glBufferSubData and no
   glBufferData, in full and in gl11 (whose own per-vertex arrays stay);
   other counts, an index out of range, or no mesh set are refused with
   the order before kept. */
static void mesh_order_uploads_the_indices_alone(void **state) {
    (void)state;
    const float eye1[3] = { 0, 0, 6 }, eye2[3] = { 6, 0, 0 };
    ht_mesh a, b;
    assert_int_equal(ht_mesh_widen_back_to_front(&fx.mesh, 1.0, eye1, &a), HT_OK);
    assert_int_equal(ht_mesh_widen_back_to_front(&fx.mesh, 1.0, eye2, &b), HT_OK);
    assert_true(a.index_count == b.index_count &&
                memcmp(a.indices, b.indices, sizeof *a.indices * a.index_count) != 0);
    const ht_frame_desc frame = ht_test_furball_frame(3.0f);
    static const ht_tier tiers[] = { HT_TIER_FULL, HT_TIER_GL11 };
    for (size_t t = 0; t < sizeof tiers / sizeof tiers[0]; t++) {
        const ht_renderer_desc desc = { .tier = tiers[t], .strict = true, .getproc = ht_test_fault_getproc };
        ht_renderer *reordered = ht_test_renderer_create(desc, fx.bundle_dir, HT_OK),
                    *fresh = ht_test_renderer_create(desc, fx.bundle_dir, HT_OK);
        assert_int_equal(ht_renderer_set_mesh_order(reordered, &b), HT_ERR_INVALID_ARGUMENT); /* no mesh yet */
        assert_int_equal(ht_renderer_set_mesh(reordered, &a), HT_OK);
        ht_fault_arm(HT_FAULT_NONE, 0);
        assert_int_equal(ht_renderer_set_mesh_order(reordered, &b), HT_OK);
        assert_int_equal(buffer_data_calls(), 0);
        assert_int_equal(buffer_sub_data_calls(), 1);
        assert_int_equal(ht_renderer_set_mesh(fresh, &b), HT_OK);
        ht_image got, want;
        ht_test_draw(&fx.gl, reordered, &frame, ht_test_background, &got);
        ht_test_draw(&fx.gl, fresh, &frame, ht_test_background, &want);
        assert_memory_equal(got.pixels, want.pixels, (size_t)got.width * got.height * 3);
        /* refused, the order kept: a triangle short, an index past the vertices */
        ht_mesh bad = b;
        bad.index_count -= 3;
        assert_int_equal(ht_renderer_set_mesh_order(reordered, &bad), HT_ERR_INVALID_ARGUMENT);
        bad.index_count = b.index_count;
        bad.indices = malloc(sizeof *bad.indices * b.index_count);
        assert_non_null(bad.indices);
        memcpy(bad.indices, a.indices, sizeof *bad.indices * b.index_count);
        bad.indices[b.index_count - 1] = b.vertex_count;
        assert_int_equal(ht_renderer_set_mesh_order(reordered, &bad), HT_ERR_INVALID_ARGUMENT);
        free(bad.indices);
        /* a draw range's vertices named outside the mesh's, or none: refused */
        assert_int_equal(ht_renderer_set_draw_range_vertices(reordered, 0, 3, b.vertex_count, 1), HT_ERR_INVALID_ARGUMENT);
        assert_int_equal(ht_renderer_set_draw_range_vertices(reordered, 0, 3, 1, b.vertex_count), HT_ERR_INVALID_ARGUMENT);
        assert_int_equal(ht_renderer_set_draw_range_vertices(reordered, 0, 3, 0, 0), HT_ERR_INVALID_ARGUMENT);
        assert_int_equal(ht_renderer_set_draw_range_vertices(reordered, 0, b.index_count, 0, b.vertex_count), HT_OK);
        ht_image after;
        ht_test_draw(&fx.gl, reordered, &frame, ht_test_background, &after);
        assert_memory_equal(after.pixels, want.pixels, (size_t)got.width * got.height * 3);
        ht_image_free(&got);
        ht_image_free(&want);
        ht_image_free(&after);
        ht_renderer_destroy(reordered);
        ht_renderer_destroy(fresh);
    }
    ht_mesh_free(&a);
    ht_mesh_free(&b);
}

/* Soft cells beside plain ones (full tier, so the uploads counted are
   the chain's): error:30 takes (0) at size 1; at 1/2 (2 soft) at 0.24x,
   the cheapest at 30 dB, where a chain holding (1) keeps it (soft 2 is
   cheaper but not by the 1 dB margin); at 1/4 (1) at 0.30x, where a chain
   holding (2 soft) keeps it (30.3 dB, (1) 30.8 is not 1 dB clear). */
static const ht_lod_cell soft_cells[] = {
    { 0, HT_TIER_FULL, 1, INFINITY, 1, 0 },    { 1, HT_TIER_FULL, 1, 29, 0.5, 0 },
    { 2, HT_TIER_FULL, 1, 28, 0.4, 3 },
    { 0, HT_TIER_FULL, 0.5, INFINITY, 1, 0 },  { 1, HT_TIER_FULL, 0.5, 30.9, 0.30, 0 },
    { 2, HT_TIER_FULL, 0.5, 27.8, 0.14, 0 },   { 2, HT_TIER_FULL, 0.5, 30.4, 0.24, 3 },
    { 1, HT_TIER_FULL, 0.5, 31.6, 0.45, 3 },
    { 0, HT_TIER_FULL, 0.25, INFINITY, 1, 0 }, { 1, HT_TIER_FULL, 0.25, 30.8, 0.30, 0 },
    { 2, HT_TIER_FULL, 0.25, 28.5, 0.14, 0 },  { 2, HT_TIER_FULL, 0.25, 30.3, 0.35, 3 },
    { 1, HT_TIER_FULL, 0.25, 32, 0.45, 3 },
};

static ht_lod_rule soft_rule(const ht_lod_chain *chain, int viewport_h) {
    return (ht_lod_rule){ .kind = HT_POLICY_ERROR, .value = 30, .cells = soft_cells,
                          .cell_count = (int)(sizeof soft_cells / sizeof soft_cells[0]),
                          .size1_px = ht_projected_width_px(chain->width, 3.0,
                                                            ht_test_furball_frame(3.0f).camera.fov_y, viewport_h) };
}

/* m's components in the order drawn, farthest centroid from eye first. */
static void assert_back_to_front(const ht_mesh *m, const float eye[3]) {
    double last = INFINITY;
    for (uint32_t c = 0; c < m->component_count; c++) {
        const ht_component *k = &m->components[c];
        double sum[3] = { 0, 0, 0 }, d2 = 0;
        for (uint32_t i = 0; i < k->index_count; i++)
            for (int j = 0; j < 3; j++) sum[j] += m->vertices[m->indices[k->first_index + i]].position[j];
        for (int j = 0; j < 3; j++) d2 += (sum[j] / k->index_count - eye[j]) * (sum[j] / k->index_count - eye[j]);
        if (sqrt(d2) > last + 1e-4) fail_msg("component %u: %.5f from the eye, after one %.5f", c, sqrt(d2), last);
        last = sqrt(d2);
    }
}

/* One select and frame: the pair, the uploads it made, and the trace's
   four passes drawing either the soft level alone (every fragment
   blended: alpha reference 1; the opacity scale `opacity`; the whole
   drawn-alone mesh, back to front from the eye of its order) or `all`'s range of
   the level at opacity 1 and the bundle's cutoff. */
static void soft_step(ht_lod_chain *chain, ht_renderer *r, const ht_lod_rule *rule, int viewport_h,
                      const ht_frame_desc *frame, int level, bool soft, float opacity, long uploads) {
    ht_fault_arm(HT_FAULT_NONE, 0);
    ht_result res;
    assert_int_equal(ht_lod_chain_select_pair(chain, r, &frame->camera, viewport_h, rule, &res), level);
    assert_int_equal(res, HT_OK);
    assert_true((chain->soften > 1) == soft);
    assert_int_equal(buffer_data_calls(), uploads);
    const ht_trace *tr = draw_traced(r, frame);
    for (int i = 0; i < tr->count; i++) {
        const ht_trace_entry *e = &tr->entries[i];
        assert_int_equal(e->gl_error, GL_NO_ERROR);
        assert_float_equal(e->opacity_scale, soft ? opacity : 1.0f, 1e-6);
        if (soft) {
            assert_true(e->alpha_ref == 1.0f);
            assert_int_equal(e->first_index, 0);
            assert_int_equal(e->index_count, chain->wide.index_count);
        } else {
            assert_true(e->alpha_ref < 1.0f);
            assert_int_equal(e->first_index, chain->first[level]);
            assert_int_equal(e->index_count, chain->index_count[level]);
        }
    }
    if (soft) {
        assert_int_equal(chain->wide_level, level);
        assert_int_equal(chain->wide.component_count, ht_lod_chain_mesh(chain, level)->component_count);
        assert_back_to_front(&chain->wide, chain->wide_eye); /* the eye of its order: this one or one near */
    }
}

/* A soft cell the cheapest at the budget: the chain draws the level soft
   (3x wider: its mean width; opacity 1/3; back to front from this eye,
   uploaded alone: 2 glBufferData after `all`'s 2), nothing more while the eye turns less
   than HT_LOD_RESORT_DEG, sorted again past it (its indices uploaded
   alone: ht_renderer_set_mesh_order, one glBufferSubData), and back to
   plain level 0 (all uploaded again, opacity 1) close up. */
static void chain_picks_a_soft_cell(void **state) {
    (void)state;
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    ht_renderer *r = fault_counted_renderer();
    const ht_lod_rule rule = soft_rule(&chain, 512);
    ht_frame_desc f = ht_test_furball_orbit_frame(6.0f, 0);
    soft_step(&chain, r, &rule, 512, &f, 2, true, 1.0f / 3, 4); /* the first select: all, then the soft level */
    assert_memory_equal(chain.wide_eye, f.camera.eye, sizeof chain.wide_eye);
    const double width = ht_mesh_mean_width(&chain.wide) / chain.level_width[2];
    assert_true(width > 2.9 && width < 3.1);
    soft_step(&chain, r, &rule, 512, &f, 2, true, 1.0f / 3, 0); /* the same eye: nothing */
    f = ht_test_furball_orbit_frame(6.0f, 3);
    soft_step(&chain, r, &rule, 512, &f, 2, true, 1.0f / 3, 0); /* 3 degrees: the order kept */
    const ht_frame_desc turned = ht_test_furball_orbit_frame(6.0f, 8);
    ht_result res;
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(ht_lod_chain_select_pair(&chain, r, &turned.camera, 512, &rule, &res), 2);
    /* 8 degrees: sorted again for this eye, the indices alone */
    assert_int_equal(buffer_data_calls(), 0);
    assert_int_equal(buffer_sub_data_calls(), 1);
    assert_memory_equal(chain.wide_eye, turned.camera.eye, sizeof chain.wide_eye);
    assert_back_to_front(&chain.wide, turned.camera.eye);
    f = ht_test_furball_orbit_frame(3.0f, 8);
    soft_step(&chain, r, &rule, 512, &f, 0, false, 1, 2); /* plain again: all, opacity 1 */
    printf("soft: level 2 soft at 1/2 (width %.2fx the plain level's, opacity 1/3), re-sorted past %.0f degrees, "
           "plain level 0 at 1\n", width, HT_LOD_RESORT_DEG);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

/* Hysteresis across the soft/plain boundary: fresh chains pick (2 soft)
   at 1/2 and (1) at 1/4; a chain holding either keeps it at the other
   size, so a camera jumping between the two every frame switches never
   after its first pair (and uploads nothing more). With the width rule
   on a 16-pixel viewport the soft strand is under a pixel: drawn widened
   by 3 f at opacity 1 / (3 f). */
static void chain_soft_hysteresis_and_width_rule(void **state) {
    (void)state;
    const float near = 6.0f, far = 12.0f;
    for (int start = 0; start < 2; start++) {
        ht_lod_chain chain;
        assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
        ht_renderer *r = fault_counted_renderer();
        const ht_lod_rule rule = soft_rule(&chain, 512);
        const bool soft = start == 0; /* 0: begins near, soft; 1: far, plain 1 */
        for (int k = 0; k < 6; k++) {
            const ht_frame_desc f = ht_test_furball_frame((k + start) % 2 ? far : near);
            soft_step(&chain, r, &rule, 512, &f, soft ? 2 : 1, soft, 1.0f / 3, k == 0 ? (soft ? 4 : 2) : 0);
        }
        ht_renderer_destroy(r);
        ht_lod_chain_free(&chain);
    }
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    chain.width_rule = true;
    ht_renderer *r = fault_counted_renderer();
    const ht_lod_rule rule = soft_rule(&chain, 16);
    const ht_frame_desc f = ht_test_furball_frame(near);
    const double px = ht_projected_width_px(chain.width, near, f.camera.fov_y, 16);
    const double w = ht_width_rule_widen(px * 3 * chain.level_width[2] / chain.width);
    assert_true(w > 1);
    soft_step(&chain, r, &rule, 16, &f, 2, true, (float)(1 / (3 * w)), 4);
    assert_true(chain.wide_factor == 3 * w);
    printf("soft hysteresis: each start keeps its pair over 6 frames; width rule on soft level 2: f = %.3f, "
           "opacity %.4f\n", w, 1 / (3 * w));
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
}

/* A rule of more cells than a bundle holds (an application's own list):
   every one is read. HT_LOD_MAX_CELLS + 8 usable copies of (1) at 0.30x
   come before soft_cells, whose (2 soft) at 0.24x is the pick at 1/2. */
static void chain_reads_every_cell_of_a_long_rule(void **state) {
    (void)state;
    enum { COPIES = HT_LOD_MAX_CELLS + 8, SOFT = sizeof soft_cells / sizeof soft_cells[0] };
    ht_lod_cell *cells = malloc((COPIES + SOFT) * sizeof *cells);
    assert_non_null(cells);
    for (int i = 0; i < COPIES; i++) cells[i] = (ht_lod_cell){ 1, HT_TIER_FULL, 0.5, 30.9, 0.30, 0 };
    memcpy(cells + COPIES, soft_cells, sizeof soft_cells);
    ht_lod_chain chain;
    assert_int_equal(ht_lod_chain_build(&fx.mesh, &chain), HT_OK);
    ht_renderer *r = fault_counted_renderer();
    ht_lod_rule rule = soft_rule(&chain, 512);
    rule.cells = cells;
    rule.cell_count = COPIES + SOFT;
    const ht_frame_desc f = ht_test_furball_orbit_frame(6.0f, 0);
    soft_step(&chain, r, &rule, 512, &f, 2, true, 1.0f / 3, 4);
    assert_true(chain.usable_capacity >= rule.cell_count);
    ht_renderer_destroy(r);
    ht_lod_chain_free(&chain);
    assert_null(chain.usable);
    free(cells);
}

static void full_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_FULL); }
static void vertex_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_VERTEX); }
static void fixed_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_FIXED); }
static void gl11_tier(void **state) { (void)state; same_passes_every_lod(HT_TIER_GL11); }
static void cards_full(void **state) { (void)state; cards_same_passes(HT_TIER_FULL); }
static void cards_vertex(void **state) { (void)state; cards_same_passes(HT_TIER_VERTEX); }
static void cards_fixed(void **state) { (void)state; cards_same_passes(HT_TIER_FIXED); }
static void cards_gl11(void **state) { (void)state; cards_same_passes(HT_TIER_GL11); }

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(full_tier),
        cmocka_unit_test(vertex_tier),
        cmocka_unit_test(fixed_tier),
        cmocka_unit_test(gl11_tier),
        cmocka_unit_test(cards_full),
        cmocka_unit_test(cards_vertex),
        cmocka_unit_test(cards_fixed),
        cmocka_unit_test(cards_gl11),
        cmocka_unit_test(chain_switches_with_the_distance),
        cmocka_unit_test(stored_chain_reaches_the_cards),
        cmocka_unit_test(chain_pairs_follow_an_error_budget),
        cmocka_unit_test(chain_pairs_follow_a_frame_budget),
        cmocka_unit_test(chain_frame_budget_reads_each_sizes_reference),
        cmocka_unit_test(chain_width_rule_per_draw),
        cmocka_unit_test(chain_picks_a_soft_cell),
        cmocka_unit_test(chain_soft_hysteresis_and_width_rule),
        cmocka_unit_test(chain_reads_every_cell_of_a_long_rule),
        cmocka_unit_test(chain_width_rule_per_vertex),
        cmocka_unit_test(chain_width_rule_reads_the_samples),
        cmocka_unit_test(mesh_order_uploads_the_indices_alone),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_measure_lod — a bundle's stored levels and their measured cells.
   Plain hairgen --scene stores the scene's strand levels (lods.bin,
   listed in file_sums): the ladder ht_mesh_build_lod builds (indices
   exact, vertices within lods.bin's quantization bounds), level 0 not
   stored (the scene's mesh); --no-lods stores none; hairview draws a stored level, and
   builds the levels of another scene. --measure-lods (ht_measure_lods_run)
   on a cards bundle writes the manifest's "lods": every (stored level,
   tier) pair, the cards too, and every strand level past 0 soft, at 1, 1/2 and 1/4 of the scene's size,
   against (level 0, the bundle's first tier): that pair identical to
   itself (PSNR and pop null, cost 1), every other tier's level 0 finite,
   each level's strand (or card) count the ladder's, finite errors and
   costs; the runtime reads them back (ht_renderer_lod_cells through
   hairview's --lod auto --policy error:DB and frame:MS, which pick the
   pair ht_lod_pick_error / ht_lod_pick_frame pick and draw its tier and
   level, the cards where a budget only they meet, and re-pick it per
   frame while --distance A:B dollies the eye; a soft cell where a budget
   only soft cells meet, drawn soft); a bad cell is refused
   with one line naming it. Small: 600 hairs of 4 joints at 64 x 64, cards of 16 in a
   512 atlas. Runs the programs (HAIRTIER_BUILD). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hairtier/lod.h>
#include "cards_bundle.h"
#include "json_check.h"
#include "manifest.h"
#include "measure_lod.h"
#include "offscreen.h"
#include "support_lod_bound.h"
#include "support_scene.h"
#include "support_scratch.h"

#define HAIRS 600 /* 38 at level 4, above HT_LOD_MIN_STRANDS: five strand levels */
#define STRAND_LEVELS 5
#define LEVELS (STRAND_LEVELS + 1) /* and the cards */
#define SOFT_LEVELS (STRAND_LEVELS - 1) /* strand levels 1..4 soft, at each of hairgen's three factors */
#define BLOCK (LEVELS + 3 * SOFT_LEVELS) /* a (size, tier)'s cells: the plain levels, then the soft ones by factor */
static const float default_softens[] = HT_LOD_DEFAULT_SOFTENS;
#define CARDS_STRANDS 16
#define CARDS_ATLAS 512
#define JOINTS 4  /* not the scene's 16: every cell's frames a quarter of the vertices */

static char work[64], bundle[128], cards[128], scene_path[128];
static ht_mesh mesh;
static uint32_t card_count;
static double setup_warmup_ms = -1; /* the measuring's warm-up (llvmpipe here) */

/* The plain bundle (hairgen, its stored strand levels), then a cards
   bundle of it measured as hairgen --cards --measure-lods measures
   (its atlas smaller than hairgen's 1024, for time). */
static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "measure_lod")) return -1;
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    snprintf(cards, sizeof cards, "%s/cards", work);
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", work);
    if (ht_test_furball_bundle(work, 64, HAIRS, JOINTS, "--measure") != 0) return -1;
    char err[1024];
    ht_scene scene;
    ht_measure_lods *lods = malloc(sizeof *lods);
    ht_result r = lods ? ht_scene_load(scene_path, &scene, err, sizeof err) : HT_ERR_OUT_OF_MEMORY;
    if (r == HT_OK) r = ht_scene_build_meshes(&scene, scene_path, &mesh, NULL, err, sizeof err);
    if (r == HT_OK) r = ht_cards_bundle_write_mesh(bundle, &mesh, CARDS_STRANDS, CARDS_ATLAS, cards, NULL, err, sizeof err);
    if (r == HT_OK) r = ht_measure_lods_run(cards, &scene, scene_path, NULL, lods, err, sizeof err);
    if (r == HT_OK) r = ht_measure_lods_write(cards, lods, err, sizeof err);
    for (int i = 0; r == HT_OK && i < lods->count; i++)
        if (lods->cells[i].cards) card_count = lods->cells[i].strands;
    if (r == HT_OK) setup_warmup_ms = lods->warmup_ms;
    free(lods);
    if (r != HT_OK) fprintf(stderr, "%s\n", err);
    return r == HT_OK ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    ht_mesh_free(&mesh);
    return ht_test_scratch_remove(work);
}

/* A software rasterizer has no clock to raise: each cell is timed after
   one warm-up frame, and no warm-up is printed; on a GPU the print says
   how long each cell warmed up. */
static void warmup_on_a_gpu_only(void **state) {
    (void)state;
    assert_true(setup_warmup_ms == 0.0);
    ht_measure_lods *m = calloc(1, sizeof *m);
    assert_non_null(m);
    char *text = NULL, want[96];
    size_t size = 0;
    snprintf(want, sizeof want, "every cell timed after %g ms of warm-up frames", HT_TIMING_WARMUP_MS);
    for (int gpu = 0; gpu < 2; gpu++) {
        m->warmup_ms = gpu ? HT_TIMING_WARMUP_MS : 0.0;
        FILE *f = open_memstream(&text, &size);
        assert_non_null(f);
        ht_measure_lods_print(f, m);
        fclose(f);
        assert_true((strstr(text, want) != NULL) == gpu);
        free(text);
    }
    free(m);
}

/* lods.bin of a plain bundle: every strand level of the scene's ladder,
   vertex for vertex, listed in file_sums; --no-lods: none. */
static void plain_hairgen_stores_the_strand_levels(void **state) {
    (void)state;
    char path[256], err[1024];
    snprintf(path, sizeof path, "%s/%s", bundle, HT_LOD_FILE_NAME);
    ht_lod_file f;
    if (ht_lod_file_read(path, &f, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_int_equal(f.level_count, STRAND_LEVELS);
    assert_int_equal(ht_lod_max_level(&mesh) + 1, STRAND_LEVELS);
    assert_true(ht_lod_file_matches(&f, &mesh));
    ht_lod_chain chain; /* what hairgen wrote */
    assert_int_equal(ht_lod_chain_build(&mesh, &chain), HT_OK);
    for (int l = 0; l < f.level_count; l++) {
        ht_mesh stored, built;
        ht_lod_desc d;
        ht_lod_level(l, &d);
        assert_int_equal(f.levels[l].param, 1u << l);
        if (l == 0) { /* the scene's mesh: not stored */
            assert_int_equal(f.levels[0].kind, HT_LOD_KIND_SCENE);
            assert_int_equal(f.levels[0].index_count, 0);
            continue;
        }
        assert_int_equal(f.levels[l].kind, HT_LOD_KIND_STRANDS);
        assert_int_equal(ht_lod_file_level_mesh(&f, l, &stored), HT_OK);
        assert_int_equal(ht_mesh_build_lod(&mesh, &d, &built), HT_OK);
        const ht_mesh *want = &built;
        assert_int_equal(stored.vertex_count, want->vertex_count);
        assert_int_equal(stored.index_count, want->index_count);
        assert_int_equal(stored.component_count, want->component_count);
        /* the vertices within lods.bin's quantization bounds, the boxes
           those of the levels written (ht_lod_chain_build's, past 0) */
        char why[256];
        if (!ht_test_lod_within_bound(stored.vertices, want->vertices, want->vertex_count,
                                      chain.all.vertices + mesh.vertex_count, chain.all.vertex_count - mesh.vertex_count,
                                      why, sizeof why))
            fail_msg("level %d: %s", l, why);
        printf("level %d: %s\n", l, why);
        assert_memory_equal(stored.indices, want->indices, sizeof *want->indices * want->index_count);
        ht_mesh_free(&stored);
        ht_mesh_free(&built);
    }
    ht_lod_chain_free(&chain);
    ht_lod_file_free(&f);
    /* the manifest names it and lists its size */
    size_t size = 0;
    free(ht_test_read_all(path, &size));
    cJSON *root = ht_test_read_json(bundle, "manifest.json");
    assert_string_equal(cJSON_GetStringValue(cJSON_GetObjectItem(root, "lod_file")), HT_LOD_FILE_NAME);
    const cJSON *sum = cJSON_GetObjectItem(cJSON_GetObjectItem(root, "file_sums"), HT_LOD_FILE_NAME);
    assert_non_null(sum);
    assert_true(cJSON_GetNumberValue(cJSON_GetObjectItem(sum, "size")) == (double)size);
    cJSON_Delete(root);
    /* --no-lods: neither */
    char args[512], out[4096];
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --no-lods -q -o %s/none", scene_path, work);
    if (ht_test_run_program("hairgen", args, out, sizeof out) != 0) fail_msg("hairgen %s: %s", args, out);
    snprintf(path, sizeof path, "%s/none/%s", work, HT_LOD_FILE_NAME);
    assert_false(ht_test_path_exists(path));
    snprintf(path, sizeof path, "%s/none", work);
    root = ht_test_read_json(path, "manifest.json");
    assert_null(cJSON_GetObjectItem(root, "lod_file"));
    assert_null(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "file_sums"), HT_LOD_FILE_NAME));
    cJSON_Delete(root);
}

/* hairview draws the stored level; with another scene (fewer hairs) it
   says so and builds that scene's level. */
static void hairview_draws_the_stored_levels(void **state) {
    (void)state;
    char args[1024], out[8192];
    snprintf(args, sizeof args, "--bundle %s --scene %s --lod 2 --frames 1 -o %s/s.png", bundle, scene_path, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    if (!strstr(out, "lod=2 strands=150 ") || !strstr(out, "stored kind=strands param=4 "))
        fail_msg("expected the stored level 2 in:\n%s", out);
    char other[256];
    ht_test_scene_copy("scenes/furball.json", work, "other.json", 64, HAIRS / 2, false, other, sizeof other);
    snprintf(args, sizeof args, "--bundle %s --scene %s --lod 2 --frames 1 -o %s/o.png", bundle, other, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    if (!strstr(out, "is another scene's") || !strstr(out, "lod=2 strands=75 strand_px") || strstr(out, "stored kind"))
        fail_msg("expected level 2 built from %s in:\n%s", other, out);
    /* cards made from another scene's mesh are refused (stored_ladder_read), as haircompare refuses them */
    snprintf(args, sizeof args, "--bundle %s --scene %s --lod 2 --frames 1 -o %s/c.png", cards, other, work);
    assert_int_not_equal(ht_test_run_program("hairview", args, out, sizeof out), 0);
    if (!strstr(out, "these cards are another scene's")) fail_msg("expected the cards refused in:\n%s", out);
}

static void manifest_holds_every_pair_at_three_sizes(void **state) {
    (void)state;
    ht_manifest *m = malloc(sizeof *m);
    char err[1024];
    assert_non_null(m);
    if (ht_manifest_load(cards, m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_string_equal(m->lods.tier, m->tiers[0].name);
    assert_true(card_count >= HAIRS / CARDS_STRANDS / 2 && card_count <= HAIRS / CARDS_STRANDS);
    /* llvmpipe runs every tier of the bundle: size, then tier, then level */
    const int tiers = m->tier_count;
    assert_true(tiers >= 5);
    assert_int_equal(m->lods.cell_count, 3 * tiers * BLOCK);
    const double sizes[3] = { 1, 0.5, 0.25 };
    for (int i = 0; i < m->lods.cell_count; i++) {
        const ht_manifest_lod_cell *c = &m->lods.cells[i];
        const int t = i / BLOCK % tiers, j = i % BLOCK;
        const bool soft = j >= LEVELS;
        assert_int_equal(c->level, !soft ? j : (j - LEVELS) % SOFT_LEVELS + 1);
        assert_true(c->soften == (soft ? default_softens[(j - LEVELS) / SOFT_LEVELS] : 0.0f));
        assert_string_equal(c->tier, m->tiers[t].name);
        assert_true(c->size == sizes[i / (BLOCK * tiers)]);
        assert_int_equal(c->cards, !soft && c->level == STRAND_LEVELS);
        assert_int_equal(c->strands, c->cards ? card_count : (HAIRS + (1u << c->level) - 1) >> c->level);
        if (c->level == 0 && t == 0) {
            assert_true(isinf(c->psnr_db) && isinf(c->pop_psnr_db) && c->cost_ratio == 1.0);
            continue;
        }
        assert_true(c->psnr_db > 10 && c->psnr_db < 100 && c->ssim > 0 && c->ssim <= 1);
        assert_true(c->cost_ratio > 0 && c->cost_ratio < 20);
        if (c->level == 0) assert_true(isinf(c->pop_psnr_db));
        else assert_true(c->pop_psnr_db > 10 && c->pop_psnr_db < 100);
    }
    free(m);
}

/* The bundle's cells as the runtime hands them out. */
static int cells_of(ht_lod_cell *cells) {
    ht_manifest *m = malloc(sizeof *m);
    char err[1024];
    assert_non_null(m);
    if (ht_manifest_load(cards, m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    const int n = m->lods.cell_count;
    for (int i = 0; i < n; i++)
        cells[i] = (ht_lod_cell){ m->lods.cells[i].level, ht_tier_from_name(m->lods.cells[i].tier),
                                  m->lods.cells[i].size, m->lods.cells[i].psnr_db, m->lods.cells[i].cost_ratio,
                                  m->lods.cells[i].soften };
    free(m);
    return n;
}

/* hairview --lod auto --policy P at a quarter size prints and draws `pick`. */
static void expect_pair(const char *policy, const ht_lod_cell *pick) {
    char args[1024], out[8192], want[64];
    snprintf(args, sizeof args, "--bundle %s --scene %s/scene.json --size 0.25 --lod auto --policy %s --frames 1 -o %s/e.png",
             cards, work, policy, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    snprintf(want, sizeof want, "lod_pair: lod=%d tier=%s ", pick->lod, ht_tier_name(pick->tier));
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    /* a soft pick says so, and draws the stored level widened at a third the opacity */
    char soft_end[32];
    snprintf(soft_end, sizeof soft_end, " soft %g\n", (double)pick->soften);
    const char *line = strstr(out, want), *soft = strstr(line, pick->soften > 1 ? soft_end : " soft "),
               *end = strchr(line, '\n');
    if ((soft && soft < end) != (pick->soften > 1))
        fail_msg("expected the pick %s in:\n%s", pick->soften > 1 ? soft_end : "not soft", out);
    char soften[64];
    snprintf(soften, sizeof soften, "soften=%.3f opacity=%.3f\n", pick->soften, 1.0 / pick->soften);
    if ((strstr(out, soften) != NULL) != (pick->soften > 1) || (pick->soften <= 1 && strstr(out, "soften=")))
        fail_msg("expected %s%s in:\n%s", pick->soften > 1 ? "" : "no ", soften, out);
    snprintf(want, sizeof want, "lod=%d ", pick->lod);
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    /* the cards bundle stores every level: the cards past the strand levels */
    snprintf(want, sizeof want, " stored kind=%s ", pick->lod == STRAND_LEVELS ? "cards" : "strands");
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    snprintf(want, sizeof want, "\ntier=%s ", ht_tier_name(pick->tier));
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    /* cells against 4 samples were measured without the width rule: none drawn */
    if (strstr(out, "width_rule")) fail_msg("expected no width rule in:\n%s", out);
}

static void hairview_picks_the_pair_the_rules_pick(void **state) {
    (void)state;
    ht_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    const int n = cells_of(cells);
    /* error: a budget (level 1, first tier) at a quarter size meets; the
       rule picks the cheapest pair of any tier meeting it */
    const int tiers = n / (3 * BLOCK), quarter = 2 * tiers * BLOCK;
    const double db = floor(cells[quarter + 1].psnr) - 0.5;
    const int pick = ht_lod_pick_error(cells, n, 0.25, db, -1);
    assert_true(pick >= quarter && cells[pick].psnr >= db && cells[pick].cost <= cells[quarter + 1].cost);
    char policy[32];
    snprintf(policy, sizeof policy, "error:%g", db);
    expect_pair(policy, &cells[pick]);
    /* frame: every pair within 10 s, so the most accurate, the reference;
       none within 1 us, so the cheapest at a quarter size */
    expect_pair("frame:10000", &cells[quarter]);
    int cheapest = quarter;
    for (int i = quarter; i < n; i++)
        if (cells[i].cost < cells[cheapest].cost) cheapest = i;
    expect_pair("frame:0.001", &cells[cheapest]);
}

/* hairview --distance A:B dollies the eye from the scene's distance (size
   1) to 4x it (size 1/4) over 8 frames with --lod auto --policy error:DB:
   the first frame's pair is the rule's at size 1, every switch is printed
   with its frame (increasing), and the PNG's tier is the last pair's. */
static void hairview_repicks_the_pair_while_dollying(void **state) {
    (void)state;
    ht_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    const int n = cells_of(cells);
    const int tiers = n / (3 * BLOCK), quarter = 2 * tiers * BLOCK;
    const double db = floor(cells[quarter + 1].psnr) - 0.5;
    const double scene_distance = 3.3508; /* |eye - target| of scenes/furball.json's camera */
    char args[1024], out[16384], want[96];
    snprintf(args, sizeof args, "--bundle %s --scene %s/scene.json --lod auto --policy error:%g --distance %g:%g "
             "--frames 8 -o %s/d.png", cards, work, db, scene_distance, 4 * scene_distance, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    const int first = ht_lod_pick_error(cells, n, 1.0, db, -1);
    snprintf(want, sizeof want, "lod_pair: frame=0 lod=%d tier=%s ", cells[first].lod, ht_tier_name(cells[first].tier));
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    int last_frame = -1, switches = 0;
    char tier[32] = "";
    for (const char *at = strstr(out, "lod_pair: frame="); at; at = strstr(at + 1, "lod_pair: frame=")) {
        int frame = -1, lod = -1;
        assert_int_equal(sscanf(at, "lod_pair: frame=%d lod=%d tier=%31s", &frame, &lod, tier), 3);
        assert_true(frame > last_frame && frame < 8 && lod >= 0 && lod < LEVELS);
        last_frame = frame;
        switches++;
    }
    printf("dolly under error:%g: %d pairs, the last %s\n", db, switches, tier);
    snprintf(want, sizeof want, "\ntier=%s ", tier);
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    assert_non_null(strstr(out, "dolly: 8 frames"));
}

/* The manifest's soft cells of factor soften (> 1) or cards' cells (0)
   made the only ones to meet a budget: their PSNR 99 and cost 0.01, every
   other cell's 0.5 (the reference's kept). */
static void only_these_meet(float soften) {
    cJSON *root = ht_test_read_json(cards, "manifest.json");
    const cJSON *cell;
    cJSON_ArrayForEach(cell, cJSON_GetObjectItem(cJSON_GetObjectItem(root, "lods"), "cells")) {
        const bool these = soften > 1 ? cJSON_GetNumberValue(cJSON_GetObjectItem(cell, "soften")) == soften
                                      : cJSON_IsString(cJSON_GetObjectItem(cell, "kind"));
        if (cJSON_IsNull(cJSON_GetObjectItem(cell, "psnr_db"))) continue;
        cJSON_ReplaceItemInObjectCaseSensitive((cJSON *)cell, "cost_ratio", cJSON_CreateNumber(these ? 0.01 : 0.5));
        if (these) cJSON_ReplaceItemInObjectCaseSensitive((cJSON *)cell, "psnr_db", cJSON_CreateNumber(99));
    }
    char *json = cJSON_Print(root);
    ht_test_write_file(cards, "manifest.json", json);
    cJSON_free(json);
    cJSON_Delete(root);
}

/* The soft cells of one factor made the only ones to meet a budget (their
   PSNR edited in the manifest, all other cells costlier): error:DB picks
   a soft cell of that factor, which hairview draws soft by it (lod_pair
   ... soft F, soften=F), for each of hairgen's default factors, and the dolly's
   pairs are soft ones; the manifest is put back after. */
static void a_budget_only_soft_cells_meet_picks_them(void **state) {
    (void)state;
    char path[192], err[512], *saved = NULL;
    snprintf(path, sizeof path, "%s/manifest.json", cards);
    if (ht_json_read_file(path, &saved, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    for (int k = 2; k >= 0; k--) { /* 3 last: the dolly's below */
        ht_test_write_file(cards, "manifest.json", saved);
        only_these_meet(default_softens[k]);
        const int n = cells_of(cells);
        const int pick = ht_lod_pick_error(cells, n, 0.25, 90, -1);
        assert_true(pick >= 0 && cells[pick].soften == default_softens[k] && cells[pick].lod >= 1);
        expect_pair("error:90", &cells[pick]);
    }
    char args[1024], out[16384];
    snprintf(args, sizeof args, "--bundle %s --scene %s/scene.json --lod auto --policy error:90 --distance 3.3508:13.4 "
             "--frames 4 -o %s/ds.png", cards, work, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    const char *first = strstr(out, "lod_pair: frame=0 ");
    assert_non_null(first);
    if (!strstr(first, " soft 3\n") || strstr(first, " soft 3\n") > strchr(first, '\n'))
        fail_msg("expected a pair soft by 3 (the last factor made to meet) in:\n%s", out);
    ht_test_write_file(cards, "manifest.json", saved);
    free(saved);
}

/* The cards' cells made the only ones to meet a budget (their cost and
   PSNR edited in the manifest, the others costlier): error:DB and
   frame:MS pick the cards, and hairview draws the stored cards level. */
static void a_budget_only_cards_meet_picks_them(void **state) {
    (void)state;
    only_these_meet(0);
    ht_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    const int n = cells_of(cells);
    const int pick = ht_lod_pick_error(cells, n, 0.25, 90, -1), cheapest = ht_lod_pick_frame(cells, n, 0.25, 0.001, 1, -1);
    assert_true(pick >= 0 && cells[pick].lod == STRAND_LEVELS);
    assert_true(cheapest >= 0 && cells[cheapest].lod == STRAND_LEVELS);
    expect_pair("error:90", &cells[pick]);
    expect_pair("frame:0.001", &cells[cheapest]);
}

static void a_bad_cell_is_refused_naming_it(void **state) {
    (void)state;
    cJSON *root = ht_test_read_json(cards, "manifest.json");
    cJSON *cell = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "lods"), "cells"), 2);
    cJSON_ReplaceItemInObjectCaseSensitive(cell, "level", cJSON_CreateNumber(9));
    char *json = cJSON_Print(root);
    ht_manifest *m = malloc(sizeof *m);
    char err[1024] = "";
    assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.cells[2].level"));
    assert_null(strchr(err, '\n'));
    /* a kind neither strands nor cards */
    cJSON_ReplaceItemInObjectCaseSensitive(cell, "level", cJSON_CreateNumber(1));
    cJSON_AddStringToObject(cell, "kind", "ribbons");
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.cells[2].kind"));
    cJSON_DeleteItemFromObjectCaseSensitive(cell, "kind");
    /* soften: (1, 16] on a strand level past 0 (cell 2: level 2, cell 0: level 0, cell LEVELS - 1: the cards) */
    const struct { int cell; double soften; } bad[] = { { 2, 0.5 }, { 2, 1 }, { 2, 17 }, { 0, 3 }, { LEVELS - 1, 3 } };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        cJSON *c = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "lods"), "cells"), bad[k].cell);
        cJSON_AddNumberToObject(c, "soften", bad[k].soften);
        free(json);
        json = cJSON_Print(root);
        assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
        char field[64];
        snprintf(field, sizeof field, "lods.cells[%d].soften", bad[k].cell);
        if (!strstr(err, field) || strchr(err, '\n')) fail_msg("soften %g on cell %d: %s", bad[k].soften, bad[k].cell, err);
        cJSON_DeleteItemFromObjectCaseSensitive(c, "soften");
    }
    cJSON_AddStringToObject(cell, "soften", "3");
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.cells[2].soften"));
    cJSON_ReplaceItemInObjectCaseSensitive(cell, "soften", cJSON_CreateNumber(3));
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_OK);
    assert_true(m->lods.cells[2].soften == 3.0f);
    cJSON_DeleteItemFromObjectCaseSensitive(cell, "soften");
    /* the frames' samples: 2..32 when present */
    cJSON_ReplaceItemInObjectCaseSensitive(cell, "level", cJSON_CreateNumber(1));
    cJSON_AddNumberToObject(cJSON_GetObjectItem(root, "lods"), "samples", 1);
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.samples"));
    cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetObjectItem(root, "lods"), "samples", cJSON_CreateNumber(4));
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, cards, "manifest.json", m, err, sizeof err), HT_OK);
    assert_int_equal(m->lods.samples, 4);
    /* hairgen refuses a sample count it cannot draw, writing nothing */
    char args[512], out[4096];
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s/scene.json --lod-samples 1 -o %s/never", work, work);
    assert_true(ht_test_run_program("hairgen", args, out, sizeof out) != 0);
    assert_non_null(strstr(out, "--lod-samples"));
    char never[160];
    snprintf(never, sizeof never, "%s/never", work);
    assert_int_not_equal(access(never, F_OK), 0);
    free(m);
    free(json);
    cJSON_Delete(root);
}

/* hairgen --lod-reference supersample: the cells against (level 0, first
   tier) drawn at 4 x 4 the pixels and box-filtered, the 16x truth, each
   cell drawn with the width rule (this fur ball's strands are 0.06-0.23
   px): the manifest says so, the reference pair is finite against the
   truth, and a cell is the PSNR hairview measures for that drawing
   (--lod 1 --width-rule=draw --samples 4 against --supersample 4). A bad value
   is refused, by hairgen and by the manifest reader. */
static void supersample_reference_measures_the_width_rule_against_the_truth(void **state) {
    (void)state;
    char args[1024], out[4096], truth[160];
    snprintf(truth, sizeof truth, "%s/truth", work);
    snprintf(args, sizeof args, "-q materials/dark-brown.json --scene %s --no-lods --lod-samples 4 --lod-reference "
             "supersample --lod-soften 2,5 -o %s", scene_path, truth);
    if (ht_test_run_program("hairgen", args, out, sizeof out) != 0) fail_msg("hairgen: %s", out);
    cJSON *root = ht_test_read_json(truth, "manifest.json");
    const cJSON *lods = cJSON_GetObjectItem(root, "lods");
    assert_string_equal(cJSON_GetStringValue(cJSON_GetObjectItem(lods, "reference")), "supersample");
    double cell = NAN, reference = NAN;
    const cJSON *c;
    int soft_cells[2] = { 0, 0 };
    cJSON_ArrayForEach(c, cJSON_GetObjectItem(lods, "cells")) {
        /* --lod-soften 2,5: every soft cell at one of those factors, as many at each */
        const cJSON *soften = cJSON_GetObjectItem(c, "soften");
        if (soften) assert_true(cJSON_GetNumberValue(soften) == 2.0 || cJSON_GetNumberValue(soften) == 5.0);
        if (soften) soft_cells[cJSON_GetNumberValue(soften) == 5.0]++;
        if (strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(c, "tier")), "full") ||
            cJSON_GetNumberValue(cJSON_GetObjectItem(c, "size")) != 1.0 || cJSON_GetObjectItem(c, "soften"))
            continue;
        const int level = (int)cJSON_GetNumberValue(cJSON_GetObjectItem(c, "level"));
        if (level == 0) reference = cJSON_GetNumberValue(cJSON_GetObjectItem(c, "psnr_db"));
        if (level == 1) cell = cJSON_GetNumberValue(cJSON_GetObjectItem(c, "psnr_db"));
    }
    static const char *const draws[][2] = { { "truth", "--supersample 4" },
                                            { "rule1", "--lod 1 --width-rule=draw --samples 4" } };
    for (int i = 0; i < 2; i++) {
        snprintf(args, sizeof args, "--bundle %s --scene %s --tier full --strict --frames 1 %s -o %s/%s.png", truth,
                 scene_path, draws[i][1], work, draws[i][0]);
        if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview: %s", out);
    }
    snprintf(args, sizeof args, "%s/truth.png %s/rule1.png", work, work);
    assert_int_equal(ht_test_run_program("png_metrics", args, out, sizeof out), 0);
    double viewed = 0;
    assert_int_equal(sscanf(out, "psnr_db=%lf", &viewed), 1);
    printf("against the truth at size 1: level 0 %.2f dB, level 1 %.2f dB (hairview: %.2f)\n", reference, cell, viewed);
    assert_true(isfinite(reference)); /* not the reference pair itself (null) */
    assert_true(fabs(cell - viewed) < 0.05);
    assert_true(soft_cells[0] > 0 && soft_cells[0] == soft_cells[1]);
    /* --cards with no lods.bin: one line naming it */
    snprintf(args, sizeof args, "--bundle %s --scene %s --cards --frames 1 -o %s/nc.png", truth, scene_path, work);
    assert_int_not_equal(ht_test_run_program("hairview", args, out, sizeof out), 0);
    assert_non_null(strstr(out, "lods.bin: absent (make the bundle with hairgen --cards)"));
    /* hairview draws a level soft by a factor of its own; bad factors refused */
    snprintf(args, sizeof args, "--bundle %s --scene %s --lod 1 --soft=2 --frames 1 -o %s/s2.png", truth, scene_path,
             work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview: %s", out);
    assert_non_null(strstr(out, "soften=2.000 opacity=0.500\n"));
    static const char *const bad[] = { "1", "0.5", "17", "nan", "x" };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(args, sizeof args, "--bundle %s --scene %s --lod 1 --soft=%s -o %s/s3.png", truth, scene_path, bad[i],
                 work);
        assert_int_not_equal(ht_test_run_program("hairview", args, out, sizeof out), 0);
        assert_non_null(strstr(out, "--soft: expected a factor above 1, at most 16"));
    }
    /* hairgen's factors: each as hairview's, up to three, none twice */
    static const char *const bad_list[] = { "1", "0.5", "17", "nan", "x", "3,3", "2,3,4,5", "3,", ",3", "3:8", "2,17" };
    for (size_t i = 0; i < sizeof bad_list / sizeof bad_list[0]; i++) {
        snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --lod-soften %s -o %s/never3", scene_path,
                 bad_list[i], work);
        assert_int_not_equal(ht_test_run_program("hairgen", args, out, sizeof out), 0);
        if (!strstr(out, "--lod-soften: expected up to 3 factors, comma-separated, each above 1, at most 16, none twice"))
            fail_msg("--lod-soften %s: %s", bad_list[i], out);
        char never[160];
        snprintf(never, sizeof never, "%s/never3", work);
        assert_int_not_equal(access(never, F_OK), 0);
    }
    /* a pair picked from these cells is drawn as they were measured, with the
       width rule per draw (its strands are under a pixel), unless =off */
    static const char *const rules[] = { "", "--width-rule=off" };
    for (int i = 0; i < 2; i++) {
        snprintf(args, sizeof args, "--bundle %s --scene %s --size 0.5 --lod auto --policy error:10 --frames 1 %s -o %s/p.png",
                 truth, scene_path, rules[i], work);
        if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview: %s", out);
        const bool drawn = strstr(out, "width_rule=from-cells\n") && strstr(out, "\nwidth_rule=") &&
                           strstr(out, " opacity=");
        if (drawn != (i == 0) || (i == 1 && strstr(out, "width_rule")))
            fail_msg("expected the width rule %s in:\n%s", i == 0 ? "from the cells" : "off", out);
    }
    snprintf(args, sizeof args, "--bundle %s --scene %s --width-rule=sometimes -o %s/p.png", truth, scene_path, work);
    assert_int_not_equal(ht_test_run_program("hairview", args, out, sizeof out), 0);
    assert_non_null(strstr(out, "--width-rule: expected vertex, draw or off"));
    /* refused: by the reader, naming the field; by hairgen, writing nothing */
    cJSON_ReplaceItemInObjectCaseSensitive((cJSON *)lods, "reference", cJSON_CreateString("exact"));
    char *json = cJSON_Print(root), err[1024];
    ht_manifest *m = malloc(sizeof *m);
    assert_non_null(m);
    assert_int_equal(ht_manifest_parse(json, truth, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.reference"));
    free(m);
    free(json);
    cJSON_Delete(root);
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --lod-reference exact -o %s/never2", scene_path,
             work);
    assert_true(ht_test_run_program("hairgen", args, out, sizeof out) != 0);
    assert_non_null(strstr(out, "--lod-reference"));
    snprintf(truth, sizeof truth, "%s/never2", work);
    assert_int_not_equal(access(truth, F_OK), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(warmup_on_a_gpu_only),
        cmocka_unit_test(plain_hairgen_stores_the_strand_levels),
        cmocka_unit_test(hairview_draws_the_stored_levels),
        cmocka_unit_test(manifest_holds_every_pair_at_three_sizes),
        cmocka_unit_test(hairview_picks_the_pair_the_rules_pick),
        cmocka_unit_test(hairview_repicks_the_pair_while_dollying),
        cmocka_unit_test(a_bad_cell_is_refused_naming_it),
        cmocka_unit_test(a_budget_only_soft_cells_meet_picks_them),
        cmocka_unit_test(a_budget_only_cards_meet_picks_them),
        cmocka_unit_test(supersample_reference_measures_the_width_rule_against_the_truth),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_measure_lod — hairgen --measure-lods writes the manifest's "lods":
   every (LOD level, tier) pair of the scene at 1, 1/2 and 1/4 of its
   size, against (level 0, the bundle's first tier): that pair identical to
   itself (PSNR and pop null, cost 1), every other tier's level 0 finite,
   each level's strand count the ladder's, finite errors and costs; the
   runtime reads them back (ht_renderer_lod_cells through hairview's --lod
   auto --policy error:DB and frame:MS, which pick the pair
   ht_lod_pick_error / ht_lod_pick_frame pick and draw its tier); a bad
   cell is refused with one line naming it. Small: 600 hairs of 4 joints
   at 64 x 64.
   Runs the programs (HAIRTIER_BUILD). */
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
#include "manifest.h"
#include "support_scene.h"
#include "support_scratch.h"

#define HAIRS 600 /* 38 at level 4, above HT_LOD_MIN_STRANDS: five levels */
#define LEVELS 5
#define JOINTS 4  /* not the scene's 16: every tier's 75 cells of frames, a quarter of the vertices */

static char work[64], bundle[128];

static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "measure_lod")) return -1;
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    return ht_test_furball_bundle(work, 64, HAIRS, JOINTS, "--measure-lods");
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static void manifest_holds_every_pair_at_three_sizes(void **state) {
    (void)state;
    ht_manifest *m = malloc(sizeof *m);
    char err[1024];
    assert_non_null(m);
    if (ht_manifest_load(bundle, m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_string_equal(m->lods.tier, m->tiers[0].name);
    /* llvmpipe runs every tier of the bundle: size, then tier, then level */
    const int tiers = m->tier_count;
    assert_true(tiers >= 5);
    assert_int_equal(m->lods.cell_count, 3 * tiers * LEVELS);
    const double sizes[3] = { 1, 0.5, 0.25 };
    for (int i = 0; i < m->lods.cell_count; i++) {
        const ht_manifest_lod_cell *c = &m->lods.cells[i];
        const int t = i / LEVELS % tiers;
        assert_int_equal(c->level, i % LEVELS);
        assert_string_equal(c->tier, m->tiers[t].name);
        assert_true(c->size == sizes[i / (LEVELS * tiers)]);
        assert_int_equal(c->strands, (HAIRS + (1u << c->level) - 1) >> c->level);
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
    if (ht_manifest_load(bundle, m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    const int n = m->lods.cell_count;
    for (int i = 0; i < n; i++)
        cells[i] = (ht_lod_cell){ m->lods.cells[i].level, ht_tier_from_name(m->lods.cells[i].tier),
                                  m->lods.cells[i].size, m->lods.cells[i].psnr_db, m->lods.cells[i].cost_ratio };
    free(m);
    return n;
}

/* hairview --lod auto --policy P at a quarter size prints and draws `pick`. */
static void expect_pair(const char *policy, const ht_lod_cell *pick) {
    char args[1024], out[8192], want[64];
    snprintf(args, sizeof args, "--bundle %s --scene %s/scene.json --size 0.25 --lod auto --policy %s --frames 1 -o %s/e.png",
             bundle, work, policy, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    snprintf(want, sizeof want, "lod_pair: lod=%d tier=%s ", pick->lod, ht_tier_name(pick->tier));
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    snprintf(want, sizeof want, "lod=%d ", pick->lod);
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    snprintf(want, sizeof want, "\ntier=%s ", ht_tier_name(pick->tier));
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
}

static void hairview_picks_the_pair_the_rules_pick(void **state) {
    (void)state;
    ht_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    const int n = cells_of(cells);
    /* error: a budget (level 1, first tier) at a quarter size meets; the
       rule picks the cheapest pair of any tier meeting it */
    const int tiers = n / (3 * LEVELS), quarter = 2 * tiers * LEVELS;
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

static void a_bad_cell_is_refused_naming_it(void **state) {
    (void)state;
    cJSON *root = ht_test_read_json(bundle, "manifest.json");
    cJSON *cell = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetObjectItem(root, "lods"), "cells"), 2);
    cJSON_ReplaceItemInObjectCaseSensitive(cell, "level", cJSON_CreateNumber(9));
    char *json = cJSON_Print(root);
    ht_manifest *m = malloc(sizeof *m);
    char err[1024] = "";
    assert_int_equal(ht_manifest_parse(json, bundle, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.cells[2].level"));
    assert_null(strchr(err, '\n'));
    /* the frames' samples: 2..32 when present */
    cJSON_ReplaceItemInObjectCaseSensitive(cell, "level", cJSON_CreateNumber(1));
    cJSON_AddNumberToObject(cJSON_GetObjectItem(root, "lods"), "samples", 1);
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, bundle, "manifest.json", m, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "lods.samples"));
    cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetObjectItem(root, "lods"), "samples", cJSON_CreateNumber(4));
    free(json);
    json = cJSON_Print(root);
    assert_int_equal(ht_manifest_parse(json, bundle, "manifest.json", m, err, sizeof err), HT_OK);
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

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(manifest_holds_every_pair_at_three_sizes),
        cmocka_unit_test(hairview_picks_the_pair_the_rules_pick),
        cmocka_unit_test(a_bad_cell_is_refused_naming_it),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

/* test_measure_lod — hairgen --measure-lods writes the manifest's "lods":
   every LOD level of the scene at 1, 1/2 and 1/4 of its size, level 0
   identical to itself (PSNR and pop null, cost 1), each level's strand
   count the ladder's, finite errors and costs; the runtime reads them back
   (ht_renderer_lod_cells through hairview's --lod auto --policy error:DB,
   which picks the cell ht_lod_pick_error picks); a bad cell is refused with
   one line naming it. Small: 2 000 hairs at 96 x 96. Runs the programs
   (HAIRTIER_BUILD). */
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

#include <hairtier/lod.h>
#include "manifest.h"
#include "support_scene.h"
#include "support_scratch.h"

static char work[64], bundle[128];

static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "measure_lod")) return -1;
    char scene[128];
    ht_test_scene_copy("scenes/furball.json", work, "scene.json", 96, 2000, false, scene, sizeof scene);
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    char args[512], out[16384];
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s/scene.json --measure-lods -o %s", work, bundle);
    if (ht_test_run_program("hairgen", args, out, sizeof out) != 0) {
        fprintf(stderr, "%s", out);
        return -1;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static void manifest_holds_every_level_at_three_sizes(void **state) {
    (void)state;
    ht_manifest *m = malloc(sizeof *m);
    char err[1024];
    assert_non_null(m);
    if (ht_manifest_load(bundle, m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    assert_string_equal(m->lods.tier, "full");
    const int levels = 5; /* 2 000 hairs: 125 at level 4, above HT_LOD_MIN_STRANDS */
    assert_int_equal(m->lods.cell_count, 3 * levels);
    const double sizes[3] = { 1, 0.5, 0.25 };
    for (int i = 0; i < m->lods.cell_count; i++) {
        const ht_manifest_lod_cell *c = &m->lods.cells[i];
        assert_int_equal(c->level, i % levels);
        assert_true(c->size == sizes[i / levels]);
        assert_int_equal(c->strands, (2000u + (1u << c->level) - 1) >> c->level);
        if (c->level == 0) {
            assert_true(isinf(c->psnr_db) && isinf(c->pop_psnr_db) && c->cost_ratio == 1.0);
        } else {
            assert_true(c->psnr_db > 10 && c->psnr_db < 100 && c->pop_psnr_db > 10 && c->pop_psnr_db < 100);
            assert_true(c->cost_ratio > 0 && c->cost_ratio < 10 && c->ssim > 0 && c->ssim < 1);
        }
    }
    free(m);
}

static void hairview_picks_the_cell_the_error_rule_picks(void **state) {
    (void)state;
    ht_manifest *m = malloc(sizeof *m);
    char err[1024], args[1024], out[8192];
    assert_non_null(m);
    if (ht_manifest_load(bundle, m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    for (int i = 0; i < m->lods.cell_count; i++)
        cells[i] = (ht_lod_cell){ m->lods.cells[i].level, HT_TIER_FULL, m->lods.cells[i].size, m->lods.cells[i].psnr_db,
                                  m->lods.cells[i].cost_ratio };
    /* A budget level 1 at a quarter size meets: the rule picks the cheapest such. */
    const double db = floor(m->lods.cells[11].psnr_db) - 0.5;
    const int pick = ht_lod_pick_error(cells, m->lods.cell_count, 0.25, db, -1);
    assert_true(pick >= 10 && cells[pick].psnr >= db);
    snprintf(args, sizeof args, "--bundle %s --scene %s/scene.json --size 0.25 --lod auto --policy error:%g --frames 1 -o %s/e.png",
             bundle, work, db, work);
    if (ht_test_run_program("hairview", args, out, sizeof out) != 0) fail_msg("hairview %s: %s", args, out);
    char want[32];
    snprintf(want, sizeof want, "lod=%d ", cells[pick].lod);
    if (!strstr(out, want)) fail_msg("expected %s in:\n%s", want, out);
    free(m);
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
    free(m);
    free(json);
    cJSON_Delete(root);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(manifest_holds_every_level_at_three_sizes),
        cmocka_unit_test(hairview_picks_the_cell_the_error_rule_picks),
        cmocka_unit_test(a_bad_cell_is_refused_naming_it),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

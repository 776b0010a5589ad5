/* test_report_program — build/haircompare end to end on llvmpipe, on a
   small scene: a report with every tier's image and heatmap, replaced
   whole by a second run; a Marschner bundle's report naming marschner as
   its reference, with each tier's 4x crop of marschner's brightest
   highlight; the bundle's measured numbers on the page, or a sentence
   saying it has none; a cards bundle's level x tier grid drawn from its
   stored levels (lods.bin), the cards row in every tier, the manifest's
   cell numbers beside each cell's own, its tier images its stored level
   0 (as the material's bundle draws the scene); and every bad input (no
   bundle, a bundle no tier can draw, a bad scene, a hostile lods.bin or
   another scene's cards, an output it must not or cannot write, bad
   options) one line on stderr, a non-zero exit, and no report and no
   temporary directory left. The page in a browser is `make report-check`. */
#include <dirent.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cJSON.h>
#include <cmocka.h>

#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include <hairtier/lod.h>
#include <hairtier/scene.h>
#include "cards_bundle.h"
#include "support_render.h"
#include "support_scratch.h"

static char work[64], bundle[128], marschner_bundle[128], scene[128];
/* A cards bundle (few cards, a 128 atlas of a 32-texel material) for
   cards_scene, and the material's own bundle it was made from. */
static char small_bundle[128], cards_bundle[128], cards_scene[128];
#define CARDS_STRANDS 16

/* root written to DIR/NAME, then deleted. */
static void write_json(const char *dir, const char *name, cJSON *root) {
    char *text = cJSON_Print(root);
    ht_test_write_file(dir, name, text);
    free(text);
    cJSON_Delete(root);
}

/* dark-brown with 32-texel textures, so its cards fit a 128 atlas (the
   bake is per atlas texel: cheap), for the fur ball of scene.json at
   64 x 64 with 200 hairs. */
static ht_result make_cards_bundle(char *err, size_t err_size) {
    snprintf(small_bundle, sizeof small_bundle, "%s/small-bundle", work);
    snprintf(cards_bundle, sizeof cards_bundle, "%s/cards-bundle", work);
    snprintf(cards_scene, sizeof cards_scene, "%s/cards-scene.json", work);
    cJSON *root = ht_test_read_json("materials", "dark-brown.json"), *texture;
    cJSON_ArrayForEach(texture, cJSON_GetObjectItem(root, "textures"))
        cJSON_ReplaceItemInObject(texture, "size", cJSON_CreateNumber(32));
    write_json(work, "small.json", root);
    root = ht_test_read_json(work, "scene.json");
    cJSON_ReplaceItemInObject(root, "resolution", cJSON_Parse("[64, 64]"));
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(root, "geometry"), "hairs", cJSON_CreateNumber(200));
    write_json(work, "cards-scene.json", root);
    char material[128];
    snprintf(material, sizeof material, "%s/small.json", work);
    ht_scene s;
    ht_mesh hair = { 0 };
    ht_result r = ht_generate_bundle(material, cards_scene, small_bundle, NULL, err, err_size);
    if (r == HT_OK) r = ht_scene_load(cards_scene, &s, err, err_size);
    if (r == HT_OK) r = ht_scene_build_meshes(&s, cards_scene, &hair, NULL, err, err_size);
    if (r == HT_OK)
        r = ht_cards_bundle_write_mesh(small_bundle, &hair, CARDS_STRANDS, 128, cards_bundle, NULL, err, err_size);
    ht_mesh_free(&hair);
    return r;
}

static int setup(void **state) {
    (void)state;
    if (!ht_test_scratch_create(work, sizeof work, "haircompare")) return -1;
    snprintf(bundle, sizeof bundle, "%s/bundle", work);
    snprintf(scene, sizeof scene, "%s/scene.json", work);
    ht_test_write_file(work, "scene.json",
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [48, 40],\n"
        " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]},\n"
        "            {\"type\": \"directional\", \"direction\": [-0.7, 0.2, -0.6], \"color\": [0.3, 0.3, 0.3]}],\n"
        " \"background\": [0.1, 0.2, 0.3],\n"
        " \"geometry\": {\"type\": \"furball\", \"hairs\": 300, \"joints\": 6, \"length\": 0.1, \"width\": 0.02}}\n");
    char err[1024];
    snprintf(marschner_bundle, sizeof marschner_bundle, "%s/marschner-bundle", work);
    /* The Marschner bundle is the shared fixture (its bake and fit cost
       1.4 s), planned for the fur ball's two directional lights as this
       scene has; read only. */
    return ht_generate_bundle("materials/dark-brown.json", scene, bundle, NULL, err, sizeof err) == HT_OK &&
                   ht_test_bundle("materials/brown-marschner.json", "furball", "scenes/furball.json",
                                  marschner_bundle, sizeof marschner_bundle, err, sizeof err) == HT_OK &&
                   make_cards_bundle(err, sizeof err) == HT_OK
               ? 0
               : (fprintf(stderr, "%s\n", err), -1);
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* Runs build/haircompare ARGS; stdout and stderr into out/err. */
static int run(const char *args, char *out, size_t out_size, char *err, size_t err_size) {
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s/haircompare %s >%s/stdout.txt 2>%s/stderr.txt", build ? build : "build", args, work,
             work);
    int status = system(cmd);
    assert_true(WIFEXITED(status));
    snprintf(out, out_size, "%s", ht_test_read_file(work, "stdout.txt"));
    snprintf(err, err_size, "%s", ht_test_read_file(work, "stderr.txt"));
    return WEXITSTATUS(status);
}

static void assert_no_temporary(void) {
    DIR *d = opendir(work);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".tmp-")) fail_msg("%s/%s left behind", work, e->d_name);
    closedir(d);
}

static void expect_in(const char *text, const char *what) {
    if (!strstr(text, what)) fail_msg("\"%s\" not in:\n%.3000s", what, text);
}

static void test_report_has_every_tier_image_and_heatmap_and_is_replaced_whole(void **state) {
    (void)state;
    char args[1024], out[8192], err[8192], report[256], path[512];
    snprintf(report, sizeof report, "%s/report", work);
    /* a trailing slash names the same directory */
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s/'", bundle, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    expect_in(out, "haircompare: wrote");
    static const char *const tiers[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int t = 0; t < 5; t++)
        for (int heat = 0; heat < 2; heat++) {
            snprintf(path, sizeof path, "%s/%s%s.png", report, tiers[t], heat ? "-error" : "");
            if (t == 0 && heat) { /* full is the reference: no heatmap of itself */
                assert_false(ht_test_path_exists(path));
                continue;
            }
            ht_image img = { 0 };
            char e[512];
            if (ht_image_read_png(path, &img, e, sizeof e) != HT_OK) fail_msg("%s", e);
            assert_true(img.width == 48 && img.height == 40 && img.channels == 3);
            bool varied = false; /* the hair, or its errors, are there */
            for (size_t i = 3; i < (size_t)48 * 40 * 3 && !varied; i++) varied = img.pixels[i] != img.pixels[i % 3];
            if (!varied) fail_msg("%s is one colour", path);
            ht_image_free(&img);
        }
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "<img src=\"fixed-error.png\"");
    expect_in(html, "<tr><th scope=\"row\">gl11</th><td class=\"needs\">GL 1.1, 1 texture unit</td>");
    expect_in(html, "<td class=\"num\">&infin;</td>"); /* full against itself */
    expect_in(html, "light 2: dropped: diffuse"); /* dark-brown's fill: highlights only, no sub-pass */
    assert_no_temporary();

    /* Again into the same directory: replaced whole (a stray file goes). */
    ht_test_write_file(report, "stray.txt", "x");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bundle, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    snprintf(path, sizeof path, "%s/stray.txt", report);
    assert_false(ht_test_path_exists(path));
    snprintf(path, sizeof path, "%s/index.html", report);
    assert_true(ht_test_path_exists(path));
    assert_no_temporary();
}

static void read_png(const char *dir, const char *name, ht_image *img) {
    char path[512], e[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    if (ht_image_read_png(path, img, e, sizeof e) != HT_OK) fail_msg("%s", e);
}

/* A Marschner bundle is measured against its marschner tier, and the page
   says so everywhere; each tier's crop is marschner's brightest 32x32
   (as the page names it) of that tier's image, 4x, nearest neighbour. */
static void test_marschner_report_names_its_reference_and_crops_its_highlight(void **state) {
    (void)state;
    char args[1024], out[8192], err[8192], report[256];
    snprintf(report, sizeof report, "%s/marschner-report", work);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", marschner_bundle, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "reference: <b>marschner</b>");
    expect_in(html, "<h2>Measurements against marschner</h2>");
    expect_in(html, "the reference: marschner<br>no error to show");
    expect_in(html, "<img src=\"full-error.png\"");
    for (const char *const *w = (const char *const[]){ "against full", "against <b>full", "vs full", "full&#8217;s",
                                                       "reference (full)", NULL };
         *w; w++)
        if (strstr(html, *w)) fail_msg("\"%s\" in the report of a Marschner bundle", *w);
    /* hairgen without --measure: the page says the bundle has no measured numbers */
    expect_in(html, "The bundle has no measured numbers");

    int x, y, w, h;
    const char *at = strstr(html, "pixels at (");
    assert_non_null(at);
    assert_int_equal(sscanf(at, "pixels at (%d, %d)", &x, &y), 2);
    assert_int_equal(sscanf(strstr(html, "<p class=\"note\">The "), "<p class=\"note\">The %d&times;%d", &w, &h), 2);
    assert_true(w == 32 && h == 32 && x >= 0 && y >= 0 && x + w <= 48 && y + h <= 40);
    static const char *const tiers[] = { "marschner", "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int t = 0; t < 6; t++)
        for (int heat = 0; heat < 2; heat++) {
            char name[64], crop_name[64];
            snprintf(name, sizeof name, "%s%s.png", tiers[t], heat ? "-error" : "");
            snprintf(crop_name, sizeof crop_name, "%s%s-crop.png", tiers[t], heat ? "-error" : "");
            char path[512];
            snprintf(path, sizeof path, "%s/%s", report, crop_name);
            if (t == 0 && heat) { /* the reference has no heatmap, so no crop of one */
                assert_false(ht_test_path_exists(path));
                continue;
            }
            ht_image full_size = { 0 }, crop = { 0 };
            read_png(report, name, &full_size);
            read_png(report, crop_name, &crop);
            assert_true(crop.width == 128 && crop.height == 128 && crop.channels == 3);
            for (int cy = 0; cy < 128; cy++)
                for (int cx = 0; cx < 128; cx++)
                    if (memcmp(crop.pixels + 3 * ((size_t)cy * 128 + (size_t)cx),
                               full_size.pixels + 3 * ((size_t)(y + cy / 4) * 48 + (size_t)(x + cx / 4)), 3) != 0)
                        fail_msg("%s (%d, %d) is not %s (%d, %d)", crop_name, cx, cy, name, x + cx / 4, y + cy / 4);
            char tag[160];
            snprintf(tag, sizeof tag, "<img src=\"%s\" width=\"128\" height=\"128\"", crop_name);
            expect_in(html, tag);
            ht_image_free(&full_size);
            ht_image_free(&crop);
        }
    /* the window holds hair: marschner's crop is not one colour */
    ht_image ref = { 0 };
    read_png(report, "marschner-crop.png", &ref);
    bool varied = false;
    for (size_t i = 3; i < (size_t)128 * 128 * 3 && !varied; i++) varied = ref.pixels[i] != ref.pixels[i % 3];
    assert_true(varied);
    ht_image_free(&ref);
}

/* The manifest's measured numbers, as hairgen --measure writes them,
   shown beside the report's own and labelled. */
static void test_report_shows_the_bundles_measured_numbers(void **state) {
    (void)state;
    char measured[256], report[256], args[1024], out[8192], err[8192];
    snprintf(measured, sizeof measured, "%s/measured-bundle", work);
    snprintf(report, sizeof report, "%s/measured-report", work);
    ht_test_copy_dir(bundle, measured);
    cJSON *root = ht_test_read_json(measured, "manifest.json");
    cJSON *tier;
    int i = 0;
    cJSON_ArrayForEach(tier, cJSON_GetObjectItemCaseSensitive(root, "tiers")) {
        char object[256];
        snprintf(object, sizeof object, "{\"psnr_db\": %s, \"ssim\": 0.97%d1, \"delta_e00_mean\": 0.4%d3, "
                 "\"delta_e00_p95\": 2.8%d5, \"cost_ratio\": 0.6%d, \"scene\": \"elsewhere.json\", "
                 "\"driver\": \"a GPU\"}", i ? "41.23" : "null", i, i, i, i);
        cJSON_AddItemToObject(tier, "measured", cJSON_Parse(object));
        i++;
    }
    write_json(measured, "manifest.json", root);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", measured, scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "the bundle&#8217;s <code>measured</code> (manifest.json, hairgen --measure)");
    expect_in(html, "on scene <code>elsewhere.json</code> and driver <code>a GPU</code>");
    /* gl11, the fifth tier: its own numbers, then the manifest's */
    const char *row = strstr(html, "<tr><th scope=\"row\">gl11</th>");
    assert_non_null(row);
    char want[512];
    snprintf(want, sizeof want, "<td class=\"num measured\">0.64&times;</td><td class=\"num measured\">41.23</td>"
             "<td class=\"num measured\">0.9741</td><td class=\"num measured\">0.443</td>"
             "<td class=\"num measured\">2.845</td><td class=\"num measured\">");
    if (strncmp(strstr(row, "<td class=\"num measured\">"), want, strlen(want)) != 0)
        fail_msg("gl11's measured cells are not %s in:\n%.1500s", want, row);
    expect_in(strstr(html, "<tr><th scope=\"row\">full</th>"), "<td class=\"num measured\">&infin;</td>");
    assert_null(strstr(html, "has no measured numbers"));
}

/* Whether the PNG at dir/name has more than one colour. */
static bool varied_png(const char *dir, const char *name) {
    ht_image img = { 0 };
    read_png(dir, name, &img);
    bool varied = false;
    for (size_t i = 3; i < (size_t)img.width * img.height * 3 && !varied; i++) varied = img.pixels[i] != img.pixels[i % 3];
    ht_image_free(&img);
    return varied;
}

/* One manifest "lods" cell, as hairgen --measure-lods writes it. */
static cJSON *lod_cell(int level, bool cards, const char *tier, uint32_t strands, double size, double psnr_db,
                       double cost) {
    cJSON *c = cJSON_CreateObject();
    cJSON_AddNumberToObject(c, "level", level);
    if (cards) cJSON_AddStringToObject(c, "kind", "cards");
    cJSON_AddStringToObject(c, "tier", tier);
    cJSON_AddNumberToObject(c, "strands", strands);
    cJSON_AddNumberToObject(c, "size", size);
    if (isinf(psnr_db)) cJSON_AddNullToObject(c, "psnr_db");
    else cJSON_AddNumberToObject(c, "psnr_db", psnr_db);
    cJSON_AddNumberToObject(c, "ssim", 0.8);
    cJSON_AddNumberToObject(c, "delta_e00_mean", 2);
    cJSON_AddNumberToObject(c, "cost_ratio", cost);
    cJSON_AddNullToObject(c, "pop_psnr_db");
    return c;
}

/* The text of the grid cell whose image is alt ALT (to its </figure>). */
static char *grid_cell(const char *html, const char *alt) {
    char tag[128];
    snprintf(tag, sizeof tag, "alt=\"%s\">", alt);
    const char *at = strstr(html, tag);
    if (!at) fail_msg("no grid cell %s in:\n%.3000s", tag, strstr(html, "<h2>Geometry") ? strstr(html, "<h2>Geometry") : html);
    const char *end = strstr(at, "</figure>");
    assert_non_null(end);
    return strndup(at, (size_t)(end - at));
}

/* A cards bundle (hairgen --cards): the grid draws its stored levels, the
   cards a row of their own in every tier, each cell with the manifest's
   numbers for that (level, tier, size) beside its own where the manifest
   has them (a cell of other geometry left out and counted); every tier's
   image is its stored level 0, drawn as the material's own bundle draws
   the scene (the scene's mesh would sample the atlas as the material's
   texture). */
static void test_cards_bundle_grid_draws_its_stored_levels_with_the_measured_cells(void **state) {
    (void)state;
    char path[512], e[512], measured[256], report[256], plain_report[256], args[1024], out[16384], err[16384];
    snprintf(path, sizeof path, "%s/%s", cards_bundle, HT_LOD_FILE_NAME);
    ht_lod_file f;
    if (ht_lod_file_read(path, &f, e, sizeof e) != HT_OK) fail_msg("%s", e);
    const int cards = f.level_count - 1;
    assert_true(cards >= 3); /* strand levels 0..2 at least, then the cards */
    assert_int_equal(f.levels[cards].kind, HT_LOD_KIND_CARDS);
    const uint32_t card_count = f.levels[cards].component_count, hairs = f.levels[0].component_count,
                   level1 = f.levels[1].component_count, level2 = f.levels[2].component_count;
    ht_lod_file_free(&f);

    snprintf(measured, sizeof measured, "%s/measured-cards", work);
    ht_test_copy_dir(cards_bundle, measured);
    cJSON *root = ht_test_read_json(measured, "manifest.json");
    cJSON *lods = cJSON_AddObjectToObject(root, "lods"), *cells = cJSON_AddArrayToObject(lods, "cells");
    cJSON_AddStringToObject(lods, "tier", "full");
    cJSON_AddItemToArray(cells, lod_cell(0, false, "full", hairs, 0.25, INFINITY, 1));
    cJSON_AddItemToArray(cells, lod_cell(cards, true, "gl11", card_count, 0.25, 23.3, 0.25));
    cJSON_AddItemToArray(cells, lod_cell(1, false, "full", 7, 0.25, 30, 0.5));       /* another ladder's level 1 */
    cJSON_AddItemToArray(cells, lod_cell(cards, true, "full", card_count, 1, 21.1, 0.5)); /* not the grid's size */
    /* soft cells (hairgen --lod-soften 2,3): the grid's soft rows, a row per factor; a soft cell of another
       ladder's level is other geometry */
    static const struct { int level; float soften; double db; } softs[] = { { 1, 2, 31.5 }, { 2, 3, 30.5 }, { 1, 2, 29 } };
    for (int i = 0; i < 3; i++) {
        cJSON *soft = lod_cell(softs[i].level, false, "gl11", i == 2 ? 7 : softs[i].level == 1 ? level1 : level2, 0.25,
                               softs[i].db, 0.3);
        cJSON_AddNumberToObject(soft, "soften", softs[i].soften);
        cJSON_AddItemToArray(cells, soft);
    }
    write_json(measured, "manifest.json", root);

    snprintf(report, sizeof report, "%s/cards-report", work);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", measured, cards_scene, report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    char *html = ht_test_read_file(report, "index.html");
    expect_in(html, "Levels: <b>the bundle&#8217;s stored levels</b>");
    char want[256];
    snprintf(want, sizeof want, "<div class=\"lodhead\">cards<br><span>level %d: %u cards of %d strands</span></div>",
             cards, card_count, CARDS_STRANDS);
    expect_in(html, want);
    static const char *const tiers[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int t = 0; t < 5; t++) {
        char name[64], alt[64];
        snprintf(name, sizeof name, "lod%d-%s.png", cards, tiers[t]);
        if (!varied_png(report, name)) fail_msg("%s/%s is one colour", report, name);
        snprintf(alt, sizeof alt, "cards, level %d, %s", cards, tiers[t]);
        char *cell = grid_cell(html, alt);
        /* gl11's cards cell was measured; the others have only this run's numbers */
        if (t == 4) expect_in(cell, "<span class=\"measured\">bundle 23.3 dB, 0.25&#215;</span>");
        else expect_in(cell, "<span class=\"measured\">bundle: not measured</span>");
        free(cell);
    }
    char *cell = grid_cell(html, "level 0, full");
    expect_in(cell, "&#8734; dB, 1.00&#215;<br><span class=\"measured\">bundle &#8734; dB, 1.00&#215;</span>");
    free(cell);
    /* soft rows: each strand level past 0 drawn soft by each factor (wider,
       fainter: not its plain image, nor the other factor's), each soft
       cell's numbers in its factor's row; none for level 0 or cards */
    expect_in(html, "also soft by 2 and 3 (ribbons");
    for (int f = 2; f <= 3; f++) {
        snprintf(want, sizeof want, "<div class=\"lodhead\">level 1 soft<br><span>%u strands, %d&#215; wide at 1/%d",
                 level1, f, f);
        expect_in(html, want);
    }
    cell = grid_cell(html, "level 1 soft 2, gl11");
    expect_in(cell, "<span class=\"measured\">bundle 31.5 dB, 0.30&#215;</span>");
    free(cell);
    cell = grid_cell(html, "level 2 soft 3, gl11");
    expect_in(cell, "<span class=\"measured\">bundle 30.5 dB, 0.30&#215;</span>");
    free(cell);
    static const char *const unmeasured[] = { "level 1, gl11", "level 1 soft 3, gl11", "level 2 soft 2, gl11" };
    for (int i = 0; i < 3; i++) {
        cell = grid_cell(html, unmeasured[i]);
        expect_in(cell, "<span class=\"measured\">bundle: not measured</span>");
        free(cell);
    }
    assert_null(strstr(html, "level 0 soft"));
    snprintf(want, sizeof want, "cards, level %d soft", cards);
    assert_null(strstr(html, want));
    ht_image plain = { 0 }, soft2 = { 0 }, soft3 = { 0 };
    read_png(report, "lod1-gl11.png", &plain);
    read_png(report, "lod1soft2-gl11.png", &soft2);
    read_png(report, "lod1soft3-gl11.png", &soft3);
    const size_t bytes = (size_t)plain.width * plain.height * 3;
    assert_true(plain.width == soft2.width && plain.height == soft2.height && soft3.width == soft2.width);
    assert_int_not_equal(memcmp(plain.pixels, soft2.pixels, bytes), 0);
    assert_int_not_equal(memcmp(soft3.pixels, soft2.pixels, bytes), 0);
    ht_image_free(&plain);
    ht_image_free(&soft2);
    ht_image_free(&soft3);
    snprintf(want, sizeof want, "%-5d %-7s %8u %-7s", 1, "soft2", level1, "gl11");
    expect_in(out, want);
    snprintf(want, sizeof want, "%-5d %-7s %8u %-7s", 2, "soft3", level2, "gl11");
    expect_in(out, want);
    expect_in(html, "2 of its measured cells at this size are of other geometry");
    expect_in(out, "lods: the bundle's stored levels at 0.25 of the scene's size, against (level 0, full)");
    snprintf(want, sizeof want, "%-5d %-7s %8u %-7s", cards, "cards", card_count, "gl11");
    expect_in(out, want);

    /* its tiers draw stored level 0 as the material's bundle draws the scene */
    snprintf(plain_report, sizeof plain_report, "%s/small-report", work);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", small_bundle, cards_scene, plain_report);
    if (run(args, out, sizeof out, err, sizeof err) != 0) fail_msg("haircompare %s:\n%s", args, err);
    assert_null(strstr(ht_test_read_file(plain_report, "index.html"), "Geometry levels")); /* nothing stored or measured */
    for (int t = 0; t < 5; t++) {
        char name[64];
        snprintf(name, sizeof name, "%s.png", tiers[t]);
        ht_image a = { 0 }, b = { 0 };
        read_png(report, name, &a);
        read_png(plain_report, name, &b);
        assert_true(a.width == b.width && a.height == b.height);
        int worst = 0;
        for (size_t i = 0; i < (size_t)a.width * a.height * 3; i++)
            worst = abs(a.pixels[i] - b.pixels[i]) > worst ? abs(a.pixels[i] - b.pixels[i]) : worst;
        if (worst > 2) fail_msg("%s: the cards bundle's differs by %d from the material's bundle's", name, worst);
        ht_image_free(&a);
        ht_image_free(&b);
    }
}

/* Exit status, one line on stderr starting "haircompare: " and naming
   `mentions`, and no report at `report`. */
static void expect_fails(const char *args, int status, const char *mentions, const char *report) {
    char out[8192], err[8192];
    int got = run(args, out, sizeof out, err, sizeof err);
    if (got != status) fail_msg("haircompare %s: exit %d, expected %d:\n%s", args, got, status, err);
    /* the progress lines name the tiers rendered; the failure is the last line */
    size_t n = strlen(err);
    while (n && err[n - 1] == '\n') err[--n] = '\0';
    const char *line = strrchr(err, '\n') ? strrchr(err, '\n') + 1 : err;
    if (status == 2) line = err; /* usage: the reason first, then the help */
    if (strncmp(line, "haircompare: ", 13) != 0 || !strstr(line, mentions))
        fail_msg("haircompare %s: \"%.300s\" does not name %s", args, line, mentions);
    if (report && ht_test_path_exists(report)) fail_msg("haircompare %s: %s written", args, report);
    assert_no_temporary();
}

static void test_bad_input_is_one_line_and_writes_nothing(void **state) {
    (void)state;
    char args[2048], report[256], path[512], bad[256];
    snprintf(report, sizeof report, "%s/report-bad", work);

    snprintf(args, sizeof args, "--bundle '%s/no-bundle' --scene '%s' -o '%s'", work, scene, report);
    expect_fails(args, 1, "no-bundle/manifest.json: cannot read", report);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s/no-scene.json' -o '%s'", bundle, work, report);
    expect_fails(args, 1, "no-scene.json", report);

    /* every tier needs the albedo: none draws, so no report */
    snprintf(bad, sizeof bad, "%s/bad-albedo", work);
    ht_test_copy_dir(bundle, bad);
    ht_test_write_file(bad, "albedo.png", "\x89PNG\r\n\x1a\n");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bad, scene, report);
    expect_fails(args, 1, "no tier ran: ", report);

    /* a hostile lods.bin (a header alone; the real file cut in half), and
       cards made from another scene's mesh */
    snprintf(bad, sizeof bad, "%s/bad-lods", work);
    ht_test_copy_dir(cards_bundle, bad);
    ht_test_write_file(bad, HT_LOD_FILE_NAME, "HTLODS2\n\x07");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bad, cards_scene, report);
    expect_fails(args, 1, "bad-lods/" HT_LOD_FILE_NAME ": ", report);
    size_t size = 0;
    snprintf(path, sizeof path, "%s/%s", cards_bundle, HT_LOD_FILE_NAME);
    char *bytes = ht_test_read_all(path, &size);
    assert_non_null(bytes);
    snprintf(path, sizeof path, "%s/%s", bad, HT_LOD_FILE_NAME);
    FILE *half = fopen(path, "wb");
    assert_non_null(half);
    assert_int_equal(fwrite(bytes, 1, size / 2, half), size / 2);
    assert_int_equal(fclose(half), 0);
    free(bytes);
    expect_fails(args, 1, "bad-lods/" HT_LOD_FILE_NAME ": ", report);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", cards_bundle, scene, report);
    expect_fails(args, 1, "these cards are another scene's", report);

    /* outputs it cannot or must not write */
    ht_test_write_file(work, "a-file", "x");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s/a-file/report'", bundle, scene, work);
    snprintf(path, sizeof path, "%s/a-file/report", work);
    expect_fails(args, 1, "a-file/report: cannot create a temporary directory beside it", NULL);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s/a-file'", bundle, scene, work);
    expect_fails(args, 1, "a-file: exists and is not a directory", NULL);
    snprintf(path, sizeof path, "%s/mine", work);
    assert_int_equal(mkdir(path, 0755), 0);
    ht_test_write_file(path, "notes.txt", "keep me");
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 1 -o '%s'", bundle, scene, path);
    expect_fails(args, 1, "mine: exists and is not a haircompare report", NULL);
    assert_string_equal(ht_test_read_file(path, "notes.txt"), "keep me");

    /* the command line */
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames 0 -o '%s'", bundle, scene, report);
    expect_fails(args, 2, "--frames: expected an integer in 1..1000", report);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s'", bundle, scene);
    expect_fails(args, 2, "-o: required", NULL);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' -o /", bundle, scene);
    expect_fails(args, 2, "-o: not a usable directory", NULL);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_report_has_every_tier_image_and_heatmap_and_is_replaced_whole),
        cmocka_unit_test(test_marschner_report_names_its_reference_and_crops_its_highlight),
        cmocka_unit_test(test_report_shows_the_bundles_measured_numbers),
        cmocka_unit_test(test_cards_bundle_grid_draws_its_stored_levels_with_the_measured_cells),
        cmocka_unit_test(test_bad_input_is_one_line_and_writes_nothing),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

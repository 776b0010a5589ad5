/* test_parse.c — material and scene files: every shipped file parses, the
   catalogue of bad files in tests/data/bad/ fails with the right result and
   names the right field, defaults and boundaries behave as docs/materials.md
   says. Runs from the repository root. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hairtier/hairgen.h>
#include "json_check.h"

#define BAD_DIR "tests/data/bad/"
#define GOOD_DIR "tests/data/good/"

typedef enum kind { MATERIAL, SCENE } kind;

static ht_result load(kind k, const char *path, char *err, size_t err_size) {
    if (k == MATERIAL) {
        ht_material m;
        return ht_material_load(path, &m, err, err_size);
    }
    ht_scene s;
    return ht_scene_load(path, &s, err, err_size);
}

/* ---- the catalogue of bad files ---- */

typedef struct bad_case {
    const char *file;      /* under tests/data/bad/ */
    ht_result result;
    const char *field;     /* exactly the FIELD of "FILE: FIELD: what" */
    const char *says;      /* a fragment of "what" */
} bad_case;

static const bad_case bad_cases[] = {
    /* material: the document */
    { "material-empty.json", HT_ERR_PARSE, "line 1", "empty file" },
    { "material-whitespace-only.json", HT_ERR_PARSE, "line 1", "empty file" },
    { "material-malformed.json", HT_ERR_PARSE, "line 6", "malformed JSON" },
    { "material-truncated.json", HT_ERR_PARSE, "line 7", "unexpected end of file" },
    { "material-nul-in-name.json", HT_ERR_PARSE, "line 2", "(NUL) in a string" },
    { "material-raw-tab.json", HT_ERR_PARSE, "line 2", "raw control character" },
    { "material-leading-zero.json", HT_ERR_PARSE, "line 5", "leading zero" },
    { "material-bare-point.json", HT_ERR_PARSE, "line 5", "no digit after its '.'" },
    { "material-trailing-garbage.json", HT_ERR_PARSE, "line 16", "near 'x'" },
    { "material-not-object.json", HT_ERR_PARSE, "(root)", "expected a JSON object, got an array" },
    { "material-wrong-format.json", HT_ERR_PARSE, "format", "got \"hairtier-scene/1\"" },
    { "material-missing-format.json", HT_ERR_PARSE, "format", "missing" },
    { "does-not-exist.json", HT_ERR_IO, NULL, "cannot read" },
    /* material: types and non-finite numbers */
    { "material-exponent-string.json", HT_ERR_PARSE, "primary.exponent", "expected a number, got string \"80\"" },
    { "material-exponent-overflow.json", HT_ERR_PARSE, "primary.exponent", "infinity" },
    { "material-shift-negative-overflow.json", HT_ERR_PARSE, "secondary.shift", "-infinity" },
    { "material-color-null.json", HT_ERR_PARSE, "diffuse.color", "got null" },
    { "material-color-element-bool.json", HT_ERR_PARSE, "secondary.color[1]", "got true" },
    { "material-color-length.json", HT_ERR_PARSE, "primary.color", "3 numbers, got 2 elements" },
    { "material-diffuse-not-object.json", HT_ERR_PARSE, "diffuse", "expected an object" },
    { "material-textures-array.json", HT_ERR_PARSE, "textures", "expected an object" },
    /* material: ranges */
    { "material-exponent-range.json", HT_ERR_PARSE, "primary.exponent", "[0, 10000], got 20000" },
    { "material-exponent-negative.json", HT_ERR_PARSE, "secondary.exponent", "got -1" },
    { "material-color-range.json", HT_ERR_PARSE, "diffuse.color[1]", "[0, 1], got 1.5" },
    { "material-wrap-range.json", HT_ERR_PARSE, "diffuse.wrap", "got 1.5" },
    { "material-shift-range.json", HT_ERR_PARSE, "primary.shift", "[-100, 100], got 150" },
    { "material-cutoff-zero.json", HT_ERR_PARSE, "alpha.opaque_cutoff", "(0, 1], got 0" },
    { "material-cutoff-above-one.json", HT_ERR_PARSE, "alpha.opaque_cutoff", "got 1.01" },
    { "material-size-not-power-of-two.json", HT_ERR_PARSE, "textures.base.size", "power of two" },
    { "material-size-range.json", HT_ERR_PARSE, "textures.alpha.size", "[16, 2048], got 4096" },
    { "material-size-fraction.json", HT_ERR_PARSE, "textures.shift.size", "must be an integer, got 256.5" },
    { "material-seed-range.json", HT_ERR_PARSE, "textures.sparkle.seed", "got 4294967296" },
    { "material-seed-negative.json", HT_ERR_PARSE, "textures.base.seed", "got -1" },
    { "material-name-space.json", HT_ERR_PARSE, "name", "character 5" },
    { "material-name-long.json", HT_ERR_PARSE, "name", "longer than 63" },
    { "material-name-empty.json", HT_ERR_PARSE, "name", "empty" },
    /* material: required fields */
    { "material-missing-name.json", HT_ERR_PARSE, "name", "missing" },
    { "material-missing-model.json", HT_ERR_PARSE, "model", "missing" },
    { "material-missing-diffuse.json", HT_ERR_PARSE, "diffuse", "missing" },
    { "material-missing-diffuse-color.json", HT_ERR_PARSE, "diffuse.color", "missing" },
    { "material-missing-primary-exponent.json", HT_ERR_PARSE, "primary.exponent", "missing" },
    { "material-missing-secondary.json", HT_ERR_PARSE, "secondary", "missing" },
    /* material: names */
    { "material-unknown-key.json", HT_ERR_PARSE, "primary.exponnet",
      "unknown key \"exponnet\" (did you mean \"exponent\"?)" },
    { "material-unknown-root-key.json", HT_ERR_PARSE, "textrues", "did you mean \"textures\"?" },
    { "material-unknown-key-far.json", HT_ERR_PARSE, "diffuse.roughness", "known keys: \"color\", \"wrap\"" },
    { "material-duplicate-key.json", HT_ERR_PARSE, "primary.exponent", "duplicate" },
    { "material-model-unknown.json", HT_ERR_PARSE, "model", "\"phong\"" },
    { "material-model-typo.json", HT_ERR_PARSE, "model", "did you mean \"kajiya-kay\"?" },
    /* material: textures */
    { "material-texture-slot-unknown.json", HT_ERR_PARSE, "textures.glitter", "unknown key" },
    { "material-texture-wrong-generator.json", HT_ERR_PARSE, "textures.base.procedural",
      "the base slot takes \"stretched-noise\"" },
    { "material-texture-unknown-generator.json", HT_ERR_PARSE, "textures.alpha.procedural", "\"perlin\"" },
    { "material-texture-both.json", HT_ERR_PARSE, "textures.base", "both" },
    { "material-texture-neither.json", HT_ERR_PARSE, "textures.alpha", "needs \"procedural\"" },
    { "material-texture-file-with-size.json", HT_ERR_PARSE, "textures.base.size", "only procedural" },
    { "material-texture-file-empty.json", HT_ERR_PARSE, "textures.base.file", "empty" },
    /* material: Kajiya-Kay has one unshifted lobe */
    { "material-kk-secondary.json", HT_ERR_PARSE, "secondary", "kajiya-kay" },
    { "material-kk-shift-texture.json", HT_ERR_PARSE, "textures.shift", "kajiya-kay" },
    { "material-kk-sparkle-texture.json", HT_ERR_PARSE, "textures.sparkle", "kajiya-kay" },
    { "material-kk-primary-shift.json", HT_ERR_PARSE, "primary.shift", "kajiya-kay" },
    { "material-kk-wrap.json", HT_ERR_PARSE, "diffuse.wrap", "kajiya-kay" },

    /* scene: the document */
    { "scene-empty.json", HT_ERR_PARSE, "line 1", "empty file" },
    { "scene-malformed.json", HT_ERR_PARSE, "line 5", "malformed JSON" },
    { "scene-truncated.json", HT_ERR_PARSE, "line 11", "unexpected end of file" },
    { "scene-wrong-format.json", HT_ERR_PARSE, "format", "got \"hairtier-material/1\"" },
    /* scene: resolution */
    { "scene-missing-resolution.json", HT_ERR_PARSE, "resolution", "missing" },
    { "scene-resolution-range.json", HT_ERR_PARSE, "resolution[1]", "[1, 4096], got 5000" },
    { "scene-resolution-zero.json", HT_ERR_PARSE, "resolution[0]", "got 0" },
    { "scene-resolution-length.json", HT_ERR_PARSE, "resolution", "expected 2 elements, got 1" },
    { "scene-resolution-fraction.json", HT_ERR_PARSE, "resolution[0]", "integer" },
    { "scene-resolution-string.json", HT_ERR_PARSE, "resolution", "got string" },
    /* scene: camera */
    { "scene-missing-camera.json", HT_ERR_PARSE, "camera", "missing" },
    { "scene-missing-eye.json", HT_ERR_PARSE, "camera.eye", "missing" },
    { "scene-eye-overflow.json", HT_ERR_PARSE, "camera.eye[0]", "infinity" },
    { "scene-eye-length.json", HT_ERR_PARSE, "camera.eye", "got 4 elements" },
    { "scene-eye-equals-target.json", HT_ERR_PARSE, "camera.target", "equals camera.eye" },
    { "scene-up-parallel.json", HT_ERR_PARSE, "camera.up", "parallel" },
    { "scene-up-zero.json", HT_ERR_PARSE, "camera.up", "zero vector" },
    { "scene-fov-range.json", HT_ERR_PARSE, "camera.fov_y", "(0, 180), got 180" },
    { "scene-fov-underflow.json", HT_ERR_PARSE, "camera.fov_y", "32-bit float" },
    { "scene-near-range.json", HT_ERR_PARSE, "camera.near", "got 0" },
    { "scene-far-before-near.json", HT_ERR_PARSE, "camera.far", "greater than camera.near" },
    { "scene-camera-unknown-key.json", HT_ERR_PARSE, "camera.fov", "did you mean \"fov_y\"?" },
    /* scene: lights */
    { "scene-missing-lights.json", HT_ERR_PARSE, "lights", "missing" },
    { "scene-no-lights.json", HT_ERR_PARSE, "lights", "1 to 4 elements, got 0" },
    { "scene-too-many-lights.json", HT_ERR_PARSE, "lights", "1 to 4 elements, got 5" },
    { "scene-lights-object.json", HT_ERR_PARSE, "lights", "expected an array" },
    { "scene-light-not-object.json", HT_ERR_PARSE, "lights[1]", "expected an object" },
    { "scene-light-zero-direction.json", HT_ERR_PARSE, "lights[0].direction", "zero vector" },
    { "scene-light-color-range.json", HT_ERR_PARSE, "lights[1].color[2]", "[0, 4], got 5" },
    { "scene-light-type-unknown.json", HT_ERR_PARSE, "lights[0].type", "\"spot\"" },
    { "scene-light-missing-type.json", HT_ERR_PARSE, "lights[0].type", "missing" },
    { "scene-light-point-with-direction.json", HT_ERR_PARSE, "lights[1].direction", "takes \"position\"" },
    { "scene-light-directional-with-position.json", HT_ERR_PARSE, "lights[0].position", "takes \"direction\"" },
    { "scene-light-unknown-key.json", HT_ERR_PARSE, "lights[0].colour", "did you mean \"color\"?" },
    /* scene: background and geometry */
    { "scene-background-range.json", HT_ERR_PARSE, "background[0]", "got -0.1" },
    { "scene-missing-geometry.json", HT_ERR_PARSE, "geometry", "missing" },
    { "scene-geometry-type-unknown.json", HT_ERR_PARSE, "geometry.type", "\"hairball\"" },
    { "scene-geometry-missing-type.json", HT_ERR_PARSE, "geometry.type", "missing" },
    { "scene-furball-hairs-zero.json", HT_ERR_PARSE, "geometry.hairs", "[1, 1000000], got 0" },
    { "scene-furball-hairs-huge.json", HT_ERR_PARSE, "geometry.hairs", "1e+12" },
    { "scene-furball-joints-range.json", HT_ERR_PARSE, "geometry.joints", "[2, 64], got 65" },
    { "scene-furball-length-zero.json", HT_ERR_PARSE, "geometry.length", "got 0" },
    { "scene-furball-width-range.json", HT_ERR_PARSE, "geometry.width", "got 2" },
    { "scene-furball-gravity-length.json", HT_ERR_PARSE, "geometry.gravity", "got 2 elements" },
    { "scene-furball-inertia-range.json", HT_ERR_PARSE, "geometry.inertia[2]", "got 11" },
    { "scene-furball-seed-fraction.json", HT_ERR_PARSE, "geometry.seed", "integer" },
    { "scene-furball-patches-key.json", HT_ERR_PARSE, "geometry.layers", "\"patches\"" },
    { "scene-patches-layers-range.json", HT_ERR_PARSE, "geometry.layers", "[1, 8], got 9" },
    { "scene-patches-strips-range.json", HT_ERR_PARSE, "geometry.strips", "got 2000" },
    { "scene-patches-segments-zero.json", HT_ERR_PARSE, "geometry.segments", "got 0" },
    { "scene-patches-head-radius.json", HT_ERR_PARSE, "geometry.head_radius", "got -1" },
    { "scene-patches-furball-key.json", HT_ERR_PARSE, "geometry.hairs", "\"furball\"" },
};

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

static void check_error_line(const char *what, const char *err, const char *file,
                             const char *field, const char *says) {
    if (strchr(err, '\n')) fail_msg("%s: message spans lines: %s", what, err);
    size_t fl = strlen(file);
    if (strncmp(err, file, fl) != 0 || strncmp(err + fl, ": ", 2) != 0)
        fail_msg("%s: message does not start with \"%s: \": %s", what, file, err);
    const char *rest = err + fl + 2;
    if (field) {
        size_t n = strlen(field);
        if (strncmp(rest, field, n) != 0 || strncmp(rest + n, ": ", 2) != 0)
            fail_msg("%s: expected field \"%s\" in: %s", what, field, err);
        rest += n + 2;
    }
    if (!strstr(rest, says)) fail_msg("%s: expected \"%s\" in: %s", what, says, err);
}

static void test_bad_catalogue_names_the_field(void **state) {
    (void)state;
    for (size_t i = 0; i < COUNT(bad_cases); i++) {
        const bad_case *b = &bad_cases[i];
        char path[512], err[512];
        snprintf(path, sizeof path, BAD_DIR "%s", b->file);
        kind k = strncmp(b->file, "scene-", 6) == 0 ? SCENE : MATERIAL;
        memset(err, 0, sizeof err);
        ht_result r = load(k, path, err, sizeof err);
        if (r != b->result)
            fail_msg("%s: expected %s, got %s (%s)", b->file, ht_result_string(b->result),
                     ht_result_string(r), err);
        check_error_line(b->file, err, path, b->field, b->says);
    }
}

/* Both loaders report a missing file the same way, with strerror's words. */
static void test_missing_file_is_io_error_with_strerror(void **state) {
    (void)state;
    const char *path = BAD_DIR "does-not-exist.json";
    char err[256], want[256];
    snprintf(want, sizeof want, "%s: cannot read: %s", path, strerror(ENOENT));
    for (int k = MATERIAL; k <= SCENE; k++) {
        assert_int_equal(load((kind)k, path, err, sizeof err), HT_ERR_IO);
        assert_string_equal(err, want);
    }
    assert_int_equal(load(MATERIAL, "tests/data", err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, "tests/data: not a regular file (a directory)"));
}

/* Every file in tests/data/bad/ is in the table, so none goes unchecked. */
static void test_every_bad_file_is_catalogued(void **state) {
    (void)state;
    DIR *d = opendir(BAD_DIR);
    assert_non_null(d);
    int files = 0;
    for (struct dirent *e; (e = readdir(d));) {
        if (e->d_name[0] == '.') continue;
        files++;
        bool found = false;
        for (size_t i = 0; i < COUNT(bad_cases) && !found; i++)
            found = strcmp(bad_cases[i].file, e->d_name) == 0;
        if (!found) fail_msg("%s%s has no entry in bad_cases", BAD_DIR, e->d_name);
    }
    closedir(d);
    /* the table's one entry that is not a file is the missing file */
    assert_int_equal((size_t)files, COUNT(bad_cases) - 1);
}

/* ---- shipped files ---- */

/* Calls fn for every *.json in dir; returns how many. */
static int for_each_json(const char *dir, void (*fn)(const char *path, const char *stem)) {
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    for (struct dirent *e; (e = readdir(d));) {
        size_t len = strlen(e->d_name);
        if (len < 6 || strcmp(e->d_name + len - 5, ".json") != 0) continue;
        char path[512], stem[256];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        snprintf(stem, sizeof stem, "%.*s", (int)(len - 5), e->d_name);
        fn(path, stem);
        n++;
    }
    closedir(d);
    return n;
}

static void check_shipped_material(const char *path, const char *stem) {
    ht_material m;
    char err[512] = "";
    if (ht_material_load(path, &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    /* The name is what the bundle and logs call the material: keep it the file's. */
    assert_string_equal(m.name, stem);
}

static void check_shipped_scene(const char *path, const char *stem) {
    (void)stem;
    ht_scene s;
    char err[512] = "";
    if (ht_scene_load(path, &s, err, sizeof err) != HT_OK) fail_msg("%s", err);
}

static void test_every_shipped_material_parses(void **state) {
    (void)state;
    assert_true(for_each_json("materials", check_shipped_material) >= 4);
}

static void test_every_shipped_scene_parses(void **state) {
    (void)state;
    assert_true(for_each_json("scenes", check_shipped_scene) >= 2);
}

static void test_dark_brown_json_loads_every_field_as_written(void **state) {
    (void)state;
    ht_material m;
    char err[512] = "";
    assert_int_equal(ht_material_load("materials/dark-brown.json", &m, err, sizeof err), HT_OK);
    assert_int_equal(m.shading.model, HT_MODEL_SCHEUERMANN);
    const double diffuse[3] = { 0.23, 0.14, 0.08 }, p[3] = { 1.0, 0.95, 0.9 }, s[3] = { 0.55, 0.40, 0.28 };
    for (int i = 0; i < 3; i++) {
        assert_true(m.shading.diffuse_color[i] == diffuse[i]);
        assert_true(m.shading.primary.color[i] == p[i]);
        assert_true(m.shading.secondary.color[i] == s[i]);
    }
    assert_true(m.shading.wrap == 0.25);
    assert_true(m.shading.primary.exponent == 80);
    assert_true(m.shading.primary.shift == -0.1);
    assert_true(m.shading.secondary.exponent == 24);
    assert_true(m.shading.secondary.shift == 0.15);
    assert_true(m.opaque_cutoff == 0.98);
    const char *gen[HT_TEX_COUNT] = { "stretched-noise", "strand-alpha", "noise", "sparkle" };
    for (int t = 0; t < HT_TEX_COUNT; t++) {
        assert_int_equal(m.textures[t].origin, HT_TEXTURE_PROCEDURAL);
        assert_string_equal(m.textures[t].procedural, gen[t]);
        assert_int_equal(m.textures[t].size, 256);
        assert_int_equal(m.textures[t].seed, (uint32_t)t + 1);
    }
}

static void test_high_contrast_has_a_narrow_primary(void **state) {
    (void)state;
    ht_material m;
    char err[512] = "";
    assert_int_equal(ht_material_load("materials/high-contrast.json", &m, err, sizeof err), HT_OK);
    assert_true(m.shading.primary.exponent >= 500);
    double dmax = 0, pmin = 1;
    for (int i = 0; i < 3; i++) {
        dmax = fmax(dmax, m.shading.diffuse_color[i]);
        pmin = fmin(pmin, m.shading.primary.color[i]);
    }
    assert_true(pmin > 10 * dmax);
}

static void test_kajiya_kay_material_has_one_unshifted_lobe(void **state) {
    (void)state;
    ht_material m;
    char err[512] = "";
    assert_int_equal(ht_material_load("materials/kajiya-kay.json", &m, err, sizeof err), HT_OK);
    assert_int_equal(m.shading.model, HT_MODEL_KAJIYA_KAY);
    assert_true(m.shading.primary.shift == 0);
    assert_true(m.shading.secondary.exponent == 0 && m.shading.secondary.color[0] == 0);
    assert_int_equal(m.textures[HT_TEX_SHIFT].origin, HT_TEXTURE_ABSENT);
    assert_int_equal(m.textures[HT_TEX_SPARKLE].origin, HT_TEXTURE_ABSENT);
}

/* The camera of a shipped scene sees a sphere of `radius` at the origin. */
static void assert_frames_origin_sphere(const ht_scene *s, double radius) {
    const ht_camera *c = &s->camera;
    double dist = sqrt((double)c->eye[0] * c->eye[0] + (double)c->eye[1] * c->eye[1] +
                       (double)c->eye[2] * c->eye[2]);
    assert_true(dist > radius + c->z_near && dist + radius < c->z_far);
    double half_fov = c->fov_y * M_PI / 360.0;
    /* the sphere's angular radius plus the target's offset from the origin */
    double off = sqrt((double)c->target[0] * c->target[0] + (double)c->target[1] * c->target[1] +
                      (double)c->target[2] * c->target[2]);
    assert_true(asin(radius / dist) + atan(off / dist) < half_fov);
    assert_true(asin(radius / dist) > 0.5 * half_fov);   /* and fills a good part of the view */
}

static void test_furball_scene_frames_a_ball_of_about_unit_radius(void **state) {
    (void)state;
    ht_scene s;
    char err[512] = "";
    assert_int_equal(ht_scene_load("scenes/furball.json", &s, err, sizeof err), HT_OK);
    assert_int_equal(s.width, 512);
    assert_int_equal(s.height, 512);
    assert_int_equal(s.geometry, HT_GEOMETRY_FURBALL);
    assert_true(s.light_count >= 1 && s.light_count <= 2);
    for (int i = 0; i < s.light_count; i++) assert_int_equal(s.lights[i].type, HT_LIGHT_DIRECTIONAL);
    /* dense enough to read as fur, few enough for llvmpipe to draw quickly */
    assert_true(s.furball.hairs >= 3000 && s.furball.hairs <= 10000);
    assert_int_equal(s.furball.joints, 16);
    double reach = s.furball.joints * (double)s.furball.length;
    assert_true(reach > 0.8 && reach < 1.2);
    assert_frames_origin_sphere(&s, reach);
}

static void test_patches_scene_frames_a_unit_head(void **state) {
    (void)state;
    ht_scene s;
    char err[512] = "";
    assert_int_equal(ht_scene_load("scenes/patches.json", &s, err, sizeof err), HT_OK);
    assert_int_equal(s.width, 512);
    assert_int_equal(s.height, 512);
    assert_int_equal(s.geometry, HT_GEOMETRY_PATCHES);
    assert_true(s.patches.head_radius == 1.0f);
    assert_int_equal(s.patches.layers, 3);
    assert_int_equal(s.patches.strips, 48);
    assert_int_equal(s.patches.segments, 12);
    /* strips stand off the head: leave room for them */
    assert_frames_origin_sphere(&s, 1.2);
}

static void test_default_scene_is_the_documented_fur_ball(void **state) {
    (void)state;
    ht_scene s;
    memset(&s, 0xAB, sizeof s);
    ht_scene_default(&s);
    assert_int_equal(s.width, 512);
    assert_int_equal(s.height, 512);
    assert_true(s.camera.eye[0] == 0 && s.camera.eye[1] == 0 && s.camera.eye[2] == 3.2f);
    assert_true(s.camera.target[0] == 0 && s.camera.target[1] == 0 && s.camera.target[2] == 0);
    assert_int_equal(s.light_count, 1);
    assert_int_equal(s.lights[0].type, HT_LIGHT_DIRECTIONAL);
    for (int i = 0; i < 3; i++) assert_true(s.lights[0].color[i] == 1.0f);
    assert_int_equal(s.geometry, HT_GEOMETRY_FURBALL);
    assert_int_equal(s.furball.hairs, 2000);
    assert_int_equal(s.furball.joints, 16);
    assert_true(s.furball.length == 0.08f && s.furball.width == 0.01f);
    for (int i = 0; i < 3; i++) assert_true(s.furball.gravity[i] == 0 && s.furball.inertia[i] == 0);
    assert_frames_origin_sphere(&s, s.furball.joints * (double)s.furball.length);
}

/* ---- defaults ---- */

static void test_material_defaults_fill_omitted_fields(void **state) {
    (void)state;
    ht_material m;
    char err[512] = "";
    assert_int_equal(ht_material_load(GOOD_DIR "material-minimal.json", &m, err, sizeof err), HT_OK);
    assert_string_equal(m.name, "minimal");
    assert_true(m.shading.wrap == 0.25);
    assert_true(m.shading.primary.shift == 0 && m.shading.secondary.shift == 0);
    assert_true(m.opaque_cutoff == 0.98);
    for (int t = 0; t < HT_TEX_COUNT; t++) assert_int_equal(m.textures[t].origin, HT_TEXTURE_ABSENT);
}

static void test_material_textures_resolve_against_the_file_folder(void **state) {
    (void)state;
    ht_material m;
    char err[512] = "";
    assert_int_equal(ht_material_load(GOOD_DIR "material-textures.json", &m, err, sizeof err), HT_OK);
    assert_int_equal(m.textures[HT_TEX_BASE].origin, HT_TEXTURE_FILE);
    assert_string_equal(m.textures[HT_TEX_BASE].path, GOOD_DIR "textures/base.png");
    assert_int_equal(m.textures[HT_TEX_ALPHA].origin, HT_TEXTURE_FILE);
    assert_string_equal(m.textures[HT_TEX_ALPHA].path, "/abs/alpha.png");
    /* procedural defaults */
    assert_int_equal(m.textures[HT_TEX_SHIFT].origin, HT_TEXTURE_PROCEDURAL);
    assert_int_equal(m.textures[HT_TEX_SHIFT].size, 256);
    assert_int_equal(m.textures[HT_TEX_SHIFT].seed, 1);
    /* the edges of every range are inside it */
    assert_int_equal(m.textures[HT_TEX_SPARKLE].size, 2048);
    assert_int_equal(m.textures[HT_TEX_SPARKLE].seed, UINT32_MAX);
    assert_true(m.shading.primary.exponent == 10000 && m.shading.secondary.exponent == 0);
    assert_true(m.shading.primary.shift == 100 && m.shading.secondary.shift == -100);
    assert_true(m.shading.wrap == 1 && m.opaque_cutoff == 1);

    /* no folder in the name: the path stays as written */
    char *text;
    assert_int_equal(ht_json_read_file(GOOD_DIR "material-textures.json", &text, err, sizeof err), HT_OK);
    assert_int_equal(ht_material_parse(text, "m.json", &m, err, sizeof err), HT_OK);
    assert_string_equal(m.textures[HT_TEX_BASE].path, "textures/base.png");
    assert_int_equal(ht_material_parse(text, NULL, &m, err, sizeof err), HT_OK);
    assert_string_equal(m.textures[HT_TEX_BASE].path, "textures/base.png");
    free(text);
}

static void test_scene_defaults_fill_omitted_fields(void **state) {
    (void)state;
    ht_scene s, d;
    char err[512] = "";
    ht_scene_default(&d);
    assert_int_equal(ht_scene_load(GOOD_DIR "scene-minimal.json", &s, err, sizeof err), HT_OK);
    assert_int_equal(s.width, 640);
    assert_int_equal(s.height, 360);
    assert_true(s.camera.up[0] == 0 && s.camera.up[1] == 1 && s.camera.up[2] == 0);
    assert_true(s.camera.fov_y == 45.0f && s.camera.z_near == 0.05f && s.camera.z_far == 100.0f);
    assert_int_equal(s.light_count, 1);
    for (int i = 0; i < 3; i++) {
        assert_true(s.lights[0].color[i] == 1.0f);
        assert_true(s.background[i] == 0.0f);
    }
    /* the header's defaults, written out */
    assert_int_equal(s.geometry, HT_GEOMETRY_FURBALL);
    assert_int_equal(s.furball.hairs, 2000);
    assert_int_equal(s.furball.joints, 16);
    assert_true(s.furball.length == 0.08f && s.furball.width == 0.01f);
    assert_int_equal(s.furball.seed, 0);
    assert_memory_equal(&s.furball, &d.furball, sizeof s.furball);
}

static void test_scene_patches_defaults_and_four_lights(void **state) {
    (void)state;
    ht_scene s;
    char err[512] = "";
    assert_int_equal(ht_scene_load(GOOD_DIR "scene-patches-minimal.json", &s, err, sizeof err), HT_OK);
    assert_int_equal(s.width, 1);
    assert_int_equal(s.height, 4096);
    assert_int_equal(s.geometry, HT_GEOMETRY_PATCHES);
    assert_true(s.patches.head_radius == 1.0f);
    assert_int_equal(s.patches.layers, 3);
    assert_int_equal(s.patches.strips, 64);
    assert_int_equal(s.patches.segments, 12);
    assert_int_equal(s.light_count, 4);
    assert_int_equal(s.lights[0].type, HT_LIGHT_POINT);
    assert_int_equal(s.lights[2].type, HT_LIGHT_DIRECTIONAL);
    assert_true(s.lights[1].color[0] == 4.0f && s.lights[1].color[1] == 0.0f);
    assert_true(s.lights[2].vector[2] == -1e-3f);
}

/* ---- boundaries, one field at a time ---- */

static const char material_template[] =
    "{\"format\": \"hairtier-material/1\", \"name\": \"b\", \"model\": \"scheuermann\",\n"
    " \"diffuse\": {\"color\": [0.5, 0.5, 0.5], \"wrap\": %s},\n"
    " \"primary\": {\"color\": [1, 1, 1], \"exponent\": %s, \"shift\": %s},\n"
    " \"secondary\": {\"color\": [1, 1, 1], \"exponent\": 10},\n"
    " \"textures\": {\"base\": {\"procedural\": \"stretched-noise\", \"size\": %s, \"seed\": %s}},\n"
    " \"alpha\": {\"opaque_cutoff\": %s}}\n";

typedef struct boundary {
    const char *wrap, *exponent, *shift, *size, *seed, *cutoff;
    const char *field;   /* NULL: accepted */
} boundary;

static void test_material_range_edges(void **state) {
    (void)state;
    static const boundary cases[] = {
        { "0", "0", "-100", "16", "0", "1e-300", NULL },
        { "1", "10000", "100", "2048", "4294967295", "1", NULL },
        { "1.0", "1e4", "1e2", "1024.0", "4.294967295e9", "0.5", NULL },
        { "-0.0001", "80", "0", "256", "1", "0.98", "diffuse.wrap" },
        { "1.0000001", "80", "0", "256", "1", "0.98", "diffuse.wrap" },
        { "0.25", "10000.001", "0", "256", "1", "0.98", "primary.exponent" },
        { "0.25", "-1e-9", "0", "256", "1", "0.98", "primary.exponent" },
        { "0.25", "80", "100.0001", "256", "1", "0.98", "primary.shift" },
        { "0.25", "80", "-100.0001", "256", "1", "0.98", "primary.shift" },
        { "0.25", "80", "1e400", "256", "1", "0.98", "primary.shift" },
        { "0.25", "80", "0", "8", "1", "0.98", "textures.base.size" },
        { "0.25", "80", "0", "48", "1", "0.98", "textures.base.size" },
        { "0.25", "80", "0", "4096", "1", "0.98", "textures.base.size" },
        { "0.25", "80", "0", "true", "1", "0.98", "textures.base.size" },
        { "0.25", "80", "0", "256", "0.5", "0.98", "textures.base.seed" },
        { "0.25", "80", "0", "256", "1e400", "0.98", "textures.base.seed" },
        { "0.25", "80", "0", "256", "1", "-0", "alpha.opaque_cutoff" },
        { "0.25", "80", "0", "256", "1", "1.0000001", "alpha.opaque_cutoff" },
    };
    for (size_t i = 0; i < COUNT(cases); i++) {
        const boundary *b = &cases[i];
        char text[1024], err[512] = "";
        snprintf(text, sizeof text, material_template, b->wrap, b->exponent, b->shift, b->size,
                 b->seed, b->cutoff);
        ht_material m;
        ht_result r = ht_material_parse(text, "edge.json", &m, err, sizeof err);
        if (!b->field) {
            if (r != HT_OK) fail_msg("case %zu rejected: %s", i, err);
            assert_false(isnan(m.opaque_cutoff));
        } else {
            if (r != HT_ERR_PARSE) fail_msg("case %zu accepted, expected an error at %s", i, b->field);
            char what[32];
            snprintf(what, sizeof what, "case %zu", i);
            check_error_line(what, err, "edge.json", b->field, "");
        }
    }
}

/* The scene's inclusive bounds as docs/materials.md writes them are
   accepted exactly, though 0.0001 is not a float; just outside is not. */
static void test_scene_range_edges_as_documented(void **state) {
    (void)state;
    static const char scene_template[] =
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [8, 8],\n"
        " \"camera\": {\"eye\": [0, 0, 3], \"target\": [0, 0, 0], \"near\": %s, \"far\": 100},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 0]}],\n"
        " \"geometry\": {\"type\": \"%s\", %s}}\n";
    static const struct { const char *near, *type, *geometry, *field; } cases[] = {
        { "0.0001", "furball", "\"length\": 0.0001, \"width\": 0.00001", NULL },
        { "99", "furball", "\"length\": 10, \"width\": 1", NULL },
        { "0.05", "patches", "\"head_radius\": 0.001", NULL },
        { "0.05", "patches", "\"head_radius\": 100", NULL },
        { "0.000099", "furball", "\"length\": 1", "camera.near" },
        { "0.05", "furball", "\"length\": 0.000099", "geometry.length" },
        { "0.05", "furball", "\"width\": 0.0000099", "geometry.width" },
        { "0.05", "patches", "\"head_radius\": 0.00099", "geometry.head_radius" },
    };
    for (size_t i = 0; i < COUNT(cases); i++) {
        char text[1024], err[512] = "";
        snprintf(text, sizeof text, scene_template, cases[i].near, cases[i].type, cases[i].geometry);
        ht_scene s;
        ht_result r = ht_scene_parse(text, "edge.json", &s, err, sizeof err);
        if (!cases[i].field) {
            if (r != HT_OK) fail_msg("case %zu rejected: %s", i, err);
        } else {
            if (r != HT_ERR_PARSE) fail_msg("case %zu accepted, expected an error at %s", i, cases[i].field);
            char what[32];
            snprintf(what, sizeof what, "case %zu", i);
            check_error_line(what, err, "edge.json", cases[i].field, "");
        }
    }
}

/* ---- robustness ---- */

static void test_failed_parse_leaves_output_untouched(void **state) {
    (void)state;
    ht_material m, m0;
    ht_scene s, s0;
    memset(&m, 0x5A, sizeof m);
    memset(&s, 0x5A, sizeof s);
    m0 = m;
    s0 = s;
    char err[512];
    assert_int_equal(ht_material_load(BAD_DIR "material-missing-secondary.json", &m, err, sizeof err), HT_ERR_PARSE);
    assert_int_equal(ht_scene_load(BAD_DIR "scene-up-parallel.json", &s, err, sizeof err), HT_ERR_PARSE);
    assert_memory_equal(&m, &m0, sizeof m);
    assert_memory_equal(&s, &s0, sizeof s);
}

static void test_small_or_absent_error_buffer_is_safe(void **state) {
    (void)state;
    char err[16];
    memset(err, 'x', sizeof err);
    assert_int_equal(ht_material_load(BAD_DIR "material-unknown-key.json", NULL, err, sizeof err),
                     HT_ERR_INVALID_ARGUMENT);
    ht_material m;
    char small[12];
    memset(small, 'x', sizeof small);
    assert_int_equal(ht_material_load(BAD_DIR "material-unknown-key.json", &m, small, 8), HT_ERR_PARSE);
    assert_int_equal(strlen(small), 7);
    assert_int_equal(small[8], 'x');   /* nothing written past err_size */
    assert_int_equal(ht_material_load(BAD_DIR "material-unknown-key.json", &m, NULL, 0), HT_ERR_PARSE);
    assert_int_equal(ht_scene_load(BAD_DIR "does-not-exist.json", &(ht_scene){ 0 }, NULL, 0), HT_ERR_IO);
    assert_int_equal(ht_scene_parse(NULL, "x.json", &(ht_scene){ 0 }, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
}

/* Control characters in a key must not split the one-line message. */
static void test_error_is_one_line_even_for_hostile_keys(void **state) {
    (void)state;
    const char *text = "{\"format\": \"hairtier-material/1\", \"na\\nme\\r\": 1}";
    char err[512];
    ht_material m;
    assert_int_equal(ht_material_parse(text, "hostile.json", &m, err, sizeof err), HT_ERR_PARSE);
    assert_null(strchr(err, '\n'));
    assert_null(strchr(err, '\r'));
    assert_non_null(strstr(err, "unknown key"));
}

static void test_nul_byte_and_deep_nesting_are_rejected(void **state) {
    (void)state;
    char path[] = "/tmp/ht-test-parse-XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    static const char bytes[] = "{\"format\": \"hairtier-scene/1\",\n\"x\": 1\0}";
    assert_int_equal(write(fd, bytes, sizeof bytes - 1), (ssize_t)(sizeof bytes - 1));
    close(fd);
    char err[512];
    ht_scene s;
    assert_int_equal(ht_scene_load(path, &s, err, sizeof err), HT_ERR_PARSE);
    unlink(path);
    assert_non_null(strstr(err, ": line 2: NUL byte"));

    enum { DEPTH = 5000 };
    char *deep = malloc(2 * DEPTH + 1);
    assert_non_null(deep);
    memset(deep, '[', DEPTH);
    memset(deep + DEPTH, ']', DEPTH);
    deep[2 * DEPTH] = '\0';
    assert_int_equal(ht_scene_parse(deep, "deep.json", &s, err, sizeof err), HT_ERR_PARSE);
    free(deep);
}

static void test_edit_distance_counts_a_swap_as_one(void **state) {
    (void)state;
    assert_int_equal(ht_json_edit_distance("exponnet", "exponent"), 1);
    assert_int_equal(ht_json_edit_distance("", "abc"), 3);
    assert_int_equal(ht_json_edit_distance("kitten", "sitting"), 3);
    assert_int_equal(ht_json_edit_distance("color", "color"), 0);
}

static void test_slot_names(void **state) {
    (void)state;
    assert_string_equal(ht_texture_slot_name(HT_TEX_BASE), "base");
    assert_string_equal(ht_texture_slot_name(HT_TEX_SPARKLE), "sparkle");
    assert_string_equal(ht_texture_slot_name(HT_TEX_COUNT), "unknown");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_catalogue_names_the_field),
        cmocka_unit_test(test_missing_file_is_io_error_with_strerror),
        cmocka_unit_test(test_every_bad_file_is_catalogued),
        cmocka_unit_test(test_every_shipped_material_parses),
        cmocka_unit_test(test_every_shipped_scene_parses),
        cmocka_unit_test(test_dark_brown_json_loads_every_field_as_written),
        cmocka_unit_test(test_high_contrast_has_a_narrow_primary),
        cmocka_unit_test(test_kajiya_kay_material_has_one_unshifted_lobe),
        cmocka_unit_test(test_furball_scene_frames_a_ball_of_about_unit_radius),
        cmocka_unit_test(test_patches_scene_frames_a_unit_head),
        cmocka_unit_test(test_default_scene_is_the_documented_fur_ball),
        cmocka_unit_test(test_material_defaults_fill_omitted_fields),
        cmocka_unit_test(test_material_textures_resolve_against_the_file_folder),
        cmocka_unit_test(test_scene_defaults_fill_omitted_fields),
        cmocka_unit_test(test_scene_patches_defaults_and_four_lights),
        cmocka_unit_test(test_material_range_edges),
        cmocka_unit_test(test_scene_range_edges_as_documented),
        cmocka_unit_test(test_failed_parse_leaves_output_untouched),
        cmocka_unit_test(test_small_or_absent_error_buffer_is_safe),
        cmocka_unit_test(test_error_is_one_line_even_for_hostile_keys),
        cmocka_unit_test(test_nul_byte_and_deep_nesting_are_rejected),
        cmocka_unit_test(test_edit_distance_counts_a_swap_as_one),
        cmocka_unit_test(test_slot_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* test_render_robustness — bad input to the runtime and the programs, on
   OSMesa: broken bundle textures and manifest fields, frames with NaN,
   infinite or degenerate cameras and lights, meshes with NaN or
   out-of-range data, a driver that refuses a shader stage, and hairview,
   tier_sheet and benchmark runs that cannot succeed. Each gets a result
   code and one line naming the file or field, or a documented finite
   behaviour; programs exit non-zero and leave no output (or scratch
   directory) behind.

   Frames are drawn into a float colour buffer: GL clamps only fixed-point
   buffers, so a NaN or Inf a shader computes stays visible there and every
   pixel can be checked. (Compile failures of broken shader text and missing
   shader files are covered by test_render_passes.c; bad manifest JSON at
   the parser by test_select.c.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <dirent.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <GL/osmesa.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE 64

static ht_test_furball fx;
static OSMesaContext float_context;
static float float_buffer[SIZE * SIZE * 4];

static const ht_tier every_tier[] = { HT_TIER_FULL, HT_TIER_VERTEX, HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
#define EVERY_TIER (int)(sizeof every_tier / sizeof every_tier[0])

/* ---- fixture ---- */

static int setup(void **state) {
    (void)state;
    if (!ht_test_furball_setup(&fx, "robust", SIZE)) return -1;
    static const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                                   OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0 };
    float_context = OSMesaCreateContextAttribs(attribs, NULL);
    if (!float_context || !OSMesaMakeCurrent(float_context, float_buffer, GL_FLOAT, SIZE, SIZE)) {
        fprintf(stderr, "setup: no float OSMesa context\n");
        return -1;
    }
    glViewport(0, 0, SIZE, SIZE);
    return 0;
}

static int teardown(void **state) {
    (void)state;
    OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
    if (float_context) OSMesaDestroyContext(float_context);
    return ht_test_furball_teardown(&fx);
}

static ht_frame_desc frame(void) { return ht_test_furball_frame(2.4f); }

/* A renderer on the fixture's mesh (no mesh when expect is not HT_OK). */
static ht_renderer *create(ht_renderer_desc desc, const char *dir, ht_result expect) {
    ht_renderer *r = ht_test_renderer_create(desc, dir ? dir : fx.bundle_dir, expect);
    if (r) assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    return r;
}

static ht_renderer *create_tier(ht_tier tier) {
    return create((ht_renderer_desc){ .tier = tier, .strict = true }, NULL, HT_OK);
}

/* Clears to the test background, draws f expecting `expect`, and checks
   what every draw owes: no GL error left, every channel of every pixel
   finite. Returns how many pixels differ from the background. */
static int draw(ht_renderer *r, const ht_frame_desc *f, ht_result expect) {
    glClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_result res = ht_renderer_draw(r, f);
    if (res != expect)
        fail_msg("ht_renderer_draw: %s, expected %s; log:\n%s", ht_result_string(res), ht_result_string(expect),
                 ht_test_log_text);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    glFinish();
    int changed = 0, not_finite = 0;
    for (int i = 0; i < SIZE * SIZE; i++) {
        const float *p = float_buffer + 4 * i;
        bool differs = false;
        for (int k = 0; k < 4; k++) {
            if (!isfinite(p[k])) not_finite++;
            if (k < 3 && fabsf(p[k] - ht_test_background[k]) > 1.0f / 255) differs = true;
        }
        changed += differs;
    }
    if (not_finite) fail_msg("%d channels are NaN or Inf; log:\n%s", not_finite, ht_test_log_text);
    return changed;
}

static void snapshot(float *out) { memcpy(out, float_buffer, sizeof float_buffer); }

/* Pixels whose colour sums to more than the background's: lit hair (black
   hair sums to less). */
static int brighter_than_background(const float *pixels) {
    const float bg = ht_test_background[0] + ht_test_background[1] + ht_test_background[2];
    int n = 0;
    for (int i = 0; i < SIZE * SIZE; i++) n += pixels[4 * i] + pixels[4 * i + 1] + pixels[4 * i + 2] > bg + 0.05f;
    return n;
}

/* The one log line that starts with `what`; fails unless there is exactly
   one (a reason may recur inside other lines, e.g. the chosen tier's). */
static const char *logged_once(const char *what) {
    const char *found = NULL;
    size_t n = strlen(what);
    for (const char *line = ht_test_log_text; *line; line += strcspn(line, "\n") + 1) {
        if (strncmp(line, what, n) != 0) continue;
        if (found) fail_msg("\"%s\" logged more than once:\n%s", what, ht_test_log_text);
        found = line;
        if (!line[strcspn(line, "\n")]) break;
    }
    if (!found) fail_msg("no line starts \"%s\"; log:\n%s", what, ht_test_log_text);
    return found;
}

/* ---- bundle files ---- */

static void path_of(const char *dir, const char *name, char *out, size_t size) {
    snprintf(out, size, "%s/%s", dir, name);
}

static void write_bytes(const char *dir, const char *name, const void *data, size_t n) {
    char path[512];
    path_of(dir, name, path, sizeof path);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, n, f), n);
    fclose(f);
}

/* The bytes of DIR/NAME (malloc'd). */
static unsigned char *read_bytes(const char *dir, const char *name, size_t *n) {
    char path[512];
    path_of(dir, name, path, sizeof path);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    assert_true(size > 0);
    unsigned char *data = malloc((size_t)size);
    assert_non_null(data);
    assert_int_equal(fread(data, 1, (size_t)size, f), (size_t)size);
    fclose(f);
    *n = (size_t)size;
    return data;
}

/* A copy of the fixture's bundle whose manifest has `path` (keys and array
   indices separated by '/') set to the JSON `value`; a last key starting
   with '+' adds a second member of that name. */
static void copy_with_manifest_value(const char *name, const char *path, const char *value, char *dir, size_t size) {
    ht_test_furball_copy_bundle(&fx, name, dir, size);
    cJSON *root = cJSON_Parse(ht_test_read_file(dir, "manifest.json"));
    cJSON *v = cJSON_Parse(value);
    assert_non_null(root);
    assert_non_null(v);
    char keys[256];
    snprintf(keys, sizeof keys, "%s", path);
    cJSON *node = root;
    char *save = NULL, *key = strtok_r(keys, "/", &save);
    while (key) {
        char *next = strtok_r(NULL, "/", &save);
        bool is_index = key[0] >= '0' && key[0] <= '9';
        if (!next) {
            if (key[0] == '+') cJSON_AddItemToObject(node, key + 1, v);
            else if (is_index) assert_true(cJSON_ReplaceItemInArray(node, atoi(key), v));
            else if (cJSON_GetObjectItemCaseSensitive(node, key)) assert_true(cJSON_ReplaceItemInObjectCaseSensitive(node, key, v));
            else cJSON_AddItemToObject(node, key, v);
        } else {
            node = is_index ? cJSON_GetArrayItem(node, atoi(key)) : cJSON_GetObjectItemCaseSensitive(node, key);
            if (!node) fail_msg("manifest has no %s", path);
        }
        key = next;
    }
    char *text = cJSON_Print(root);
    ht_test_write_file(dir, "manifest.json", text);
    free(text);
    cJSON_Delete(root);
}

/* ---- textures ---- */

static void test_missing_detail_texture_drops_full_to_vertex_naming_the_file(void **state) {
    (void)state;
    char dir[256], path[512], want[600];
    ht_test_furball_copy_bundle(&fx, "no-detail", dir, sizeof dir);
    path_of(dir, "detail.png", path, sizeof path);
    assert_int_equal(unlink(path), 0);

    ht_renderer *r = create((ht_renderer_desc){ 0 }, dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX); /* the vertex tier never reads detail */
    snprintf(want, sizeof want, "hairtier: skipped full: %s: cannot read: No such file or directory", path);
    logged_once(want);
    assert_non_null(strstr(ht_renderer_reason(r), "detail.png"));
    ht_frame_desc f = frame();
    assert_true(draw(r, &f, HT_OK) > SIZE * SIZE / 20);
    ht_renderer_destroy(r);

    /* Strict: the downgrade is the error, with the same reason. */
    assert_null(create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true }, dir, HT_ERR_UNSUPPORTED));
    snprintf(want, sizeof want, "hairtier: full: %s: cannot read: No such file or directory", path);
    logged_once(want);
}

/* The bundle's albedo replaced by `bytes`: every tier samples it, so none
   runs, and the one error line gives each tier's reason naming the file. */
static void expect_albedo_fails_every_tier(const char *name, const void *bytes, size_t n, const char *why) {
    char dir[256], path[512], want[600];
    ht_test_furball_copy_bundle(&fx, name, dir, sizeof dir);
    path_of(dir, "albedo.png", path, sizeof path);
    if (bytes) write_bytes(dir, "albedo.png", bytes, n);
    else assert_int_equal(unlink(path), 0);

    assert_null(create((ht_renderer_desc){ 0 }, dir, HT_ERR_NO_TIER));
    snprintf(want, sizeof want, "hairtier: %s/manifest.json: tiers: none runs here: ", dir);
    const char *line = logged_once(want);
    size_t len = strcspn(line, "\n");
    for (int t = 0; t < EVERY_TIER; t++) {
        snprintf(want, sizeof want, "%s: %s: ", ht_tier_name(every_tier[t]), path);
        const char *at = strstr(line, want);
        if (!at || (size_t)(at - line) > len) fail_msg("%s: no \"%s\" in: %.*s", name, want, (int)len, line);
    }
    snprintf(want, sizeof want, "full: %s: %s", path, why);
    if (!strstr(line, want)) fail_msg("%s: no \"%s\" in: %.*s", name, want, (int)len, line);

    assert_null(create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true }, dir, HT_ERR_UNSUPPORTED));
    snprintf(want, sizeof want, "hairtier: full: %s: %s", path, why);
    logged_once(want);
}

static void test_broken_albedo_leaves_no_tier_and_names_the_file(void **state) {
    (void)state;
    size_t n;
    unsigned char *png = read_bytes(fx.bundle_dir, "albedo.png", &n);
    expect_albedo_fails_every_tier("albedo-missing", NULL, 0, "cannot read: No such file or directory");
    expect_albedo_fails_every_tier("albedo-empty", "", 0, "file is empty");
    expect_albedo_fails_every_tier("albedo-text", "not a png at all", 16, "not a PNG file");
    expect_albedo_fails_every_tier("albedo-truncated", png, n / 2, "file is truncated");
    /* Bytes flipped inside the compressed data: libpng's CRC check. */
    unsigned char *corrupt = malloc(n);
    assert_non_null(corrupt);
    memcpy(corrupt, png, n);
    for (size_t i = n / 2; i < n / 2 + 16; i++) corrupt[i] ^= 0x5a;
    expect_albedo_fails_every_tier("albedo-corrupt", corrupt, n, "");
    free(corrupt);
    free(png);

    /* A valid PNG of another size than the manifest lists. */
    char err[256];
    ht_image small = { 0 };
    assert_int_equal(ht_image_alloc(&small, 8, 8, 4), HT_OK);
    char dir[256], path[512];
    snprintf(dir, sizeof dir, "%s/small-albedo-source", fx.work);
    assert_int_equal(mkdir(dir, 0755), 0);
    path_of(dir, "small.png", path, sizeof path);
    assert_int_equal(ht_image_write_png(path, &small, err, sizeof err), HT_OK);
    ht_image_free(&small);
    png = read_bytes(dir, "small.png", &n);
    expect_albedo_fails_every_tier("albedo-8x8", png, n, "8x8, manifest says 256x256");
    free(png);
}

static void test_texture_header_claiming_a_huge_size_is_refused_before_decoding(void **state) {
    (void)state;
    /* A PNG signature, a well-formed IHDR (its CRC right) claiming
       100000 x 100000 RGBA, 40 GB decoded, and the start of an IDAT: what
       a decoder allocates the image for. Refused from the header. */
    static const unsigned char bomb[41] = {
        0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
        0x00, 0x01, 0x86, 0xa0, 0x00, 0x01, 0x86, 0xa0, 8, 6, 0, 0, 0, 0xa8, 0x52, 0x0b, 0xc8,
        0, 0, 0, 64, 'I', 'D', 'A', 'T',
    };
    char dir[256], path[512], want[600];
    ht_test_furball_copy_bundle(&fx, "albedo-bomb", dir, sizeof dir);
    write_bytes(dir, "albedo.png", bomb, sizeof bomb);
    path_of(dir, "albedo.png", path, sizeof path);
    /* The GLSL tiers only: see the report on the fixed backend. */
    for (int t = 0; t < 2; t++) {
        assert_null(create((ht_renderer_desc){ .tier = every_tier[t], .strict = true }, dir, HT_ERR_UNSUPPORTED));
        snprintf(want, sizeof want, "hairtier: %s: %s: 100000x100000, manifest says 256x256",
                 ht_tier_name(every_tier[t]), path);
        logged_once(want);
    }
}

/* ---- manifest fields ---- */

static void test_bad_manifest_fields_fail_creation_naming_file_and_field(void **state) {
    (void)state;
    static const struct { const char *path, *value, *field; } cases[] = {
        { "textures/albedo/width", "\"wide\"", "textures.albedo.width: expected an integer, got string \"wide\"" },
        { "textures/albedo/width", "1.5", "textures.albedo.width: must be an integer, got 1.5" },
        { "textures/detail/height", "0", "textures.detail.height: must be an integer in [1, 16384], got 0" },
        { "textures/detail/height", "1e9", "textures.detail.height: must be an integer in [1, 16384], got 1e+09" },
        { "textures/albedo/file", "\"../albedo.png\"", "textures.albedo.file: " },
        { "textures/+albedo", "{\"file\": \"albedo.png\", \"width\": 256, \"height\": 256}",
          "textures.albedo: listed twice" },
        { "tiers/0/name", "7", "tiers[0].name: expected a string" },
        { "tiers/1/name", "\"full\"", "tiers[1].name: \"full\" already listed as tiers[0]" },
        { "tiers/2/name", "\"auto\"", "tiers[2].name: " },
        { "tiers/0/requires", "\"2.1\"", "tiers[0].requires: expected an object" },
        { "tiers/0/requires/extensions", "[3]", "tiers[0].requires.extensions[0]: " },
        { "tiers/2/requires/texture_units", "65", "tiers[2].requires.texture_units: must be an integer in [0, 64], got 65" },
        { "tiers/0/files/vertex", "\"\"", "tiers[0].files.vertex: empty string" },
        { "tiers/0/files/+vertex", "\"other.vert\"", "tiers[0].files.vertex: listed twice" },
        { "tiers/0/samplers/1/unit", "32", "tiers[0].samplers[1].unit: must be an integer in [0, 31], got 32" },
        { "tiers/0/samplers/1/unit", "\"1\"", "tiers[0].samplers[1].unit: expected an integer" },
        { "tiers/0/samplers/1/unit", "0", "tiers[0].samplers[1].unit: unit 0 already used" },
        { "tiers/0/samplers/1/uniform", "\"u_albedo\"", "tiers[0].samplers[1].uniform: \"u_albedo\" already bound" },
        /* another tier's own texture is not this tier's */
        { "tiers/0/samplers/1/texture", "\"fixed-lut\"", "tiers[0].samplers[1].texture: \"fixed-lut\" is not listed" },
        { "lights", "[\"point\", \"point\", \"point\", \"point\", \"point\"]", "lights: expected 1 to 4 elements, got 5" },
        { "lights", "\"directional\"", "lights: expected an array" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char name[32], dir[256], want[600];
        snprintf(name, sizeof name, "field-%zu", i);
        copy_with_manifest_value(name, cases[i].path, cases[i].value, dir, sizeof dir);
        assert_null(create((ht_renderer_desc){ 0 }, dir, HT_ERR_PARSE));
        snprintf(want, sizeof want, "hairtier: %s/manifest.json: %s", dir, cases[i].field);
        if (!strstr(ht_test_log_text, want)) fail_msg("case %zu: no \"%s\" in:\n%s", i, want, ht_test_log_text);
    }
}

static void test_unknown_tier_is_skipped_by_name(void **state) {
    (void)state;
    char dir[256];
    ht_test_furball_copy_bundle(&fx, "unknown-tier", dir, sizeof dir);
    cJSON *root = cJSON_Parse(ht_test_read_file(dir, "manifest.json"));
    assert_non_null(root);
    cJSON *tiers = cJSON_GetObjectItem(root, "tiers");
    cJSON *future = cJSON_Duplicate(cJSON_GetArrayItem(tiers, 0), true);
    cJSON_ReplaceItemInObject(future, "name", cJSON_CreateString("pathtraced"));
    assert_true(cJSON_InsertItemInArray(tiers, 0, future));
    char *text = cJSON_Print(root);
    ht_test_write_file(dir, "manifest.json", text);
    free(text);
    cJSON_Delete(root);

    ht_renderer *r = create((ht_renderer_desc){ 0 }, dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL);
    logged_once("hairtier: skipped pathtraced: unknown to this runtime");
    ht_renderer_destroy(r);
}

static void test_sampler_units_the_device_lacks_drop_the_tier(void **state) {
    (void)state;
    char dir[256], want[600];
    ht_renderer *probe = create((ht_renderer_desc){ .flat = true }, NULL, HT_OK);
    int units = ht_renderer_caps(probe)->texture_units;
    ht_renderer_destroy(probe);
    assert_true(units < 31);

    copy_with_manifest_value("unit-31", "tiers/0/samplers/1/unit", "31", dir, sizeof dir);
    ht_renderer *r = create((ht_renderer_desc){ 0 }, dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    snprintf(want, sizeof want, "hairtier: skipped full: %s/manifest.json: tiers[0].samplers[1].unit: 31, device has %d units",
             dir, units);
    logged_once(want);
    ht_renderer_destroy(r);

    /* A manifest understating the units a tier needs: the device's own
       count (here a profile's) still refuses the sampler. */
    copy_with_manifest_value("understated-units", "tiers/0/samplers/1/unit", "4", dir, sizeof dir);
    r = create((ht_renderer_desc){ .profile = { .texture_units = 4 } }, dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    snprintf(want, sizeof want, "hairtier: skipped full: %s/manifest.json: tiers[0].samplers[1].unit: 4, device has 4 units", dir);
    logged_once(want);
    /* The tier it falls to draws on its four units what it draws on all of them:
       lit hair, not the black of an ao or tangent read from a coordinate
       set the device does not have. */
    static float all_units[SIZE * SIZE * 4];
    const ht_frame_desc f = frame();
    ht_renderer *every_unit = create((ht_renderer_desc){ .tier = HT_TIER_VERTEX, .strict = true }, dir, HT_OK);
    assert_true(draw(every_unit, &f, HT_OK) > SIZE * SIZE / 20);
    snapshot(all_units);
    assert_true(brighter_than_background(all_units) > SIZE * SIZE / 40);
    ht_renderer_destroy(every_unit);
    assert_true(draw(r, &f, HT_OK) > SIZE * SIZE / 20);
    if (memcmp(all_units, float_buffer, sizeof all_units) != 0)
        fail_msg("vertex tier on four units: %d pixels brighter than the background, %d on every unit",
                 brighter_than_background(float_buffer), brighter_than_background(all_units));
    ht_renderer_destroy(r);

    /* The vertex tier's combiner stages read the albedo after the LUTs (unit 2). */
    copy_with_manifest_value("vertex-unit-0", "tiers/1/samplers/0/unit", "0", dir, sizeof dir);
    assert_null(create((ht_renderer_desc){ .tier = HT_TIER_VERTEX, .strict = true }, dir, HT_ERR_UNSUPPORTED));
    snprintf(want, sizeof want, "hairtier: vertex: %s/manifest.json: tiers[1].samplers[0].unit: 0, the vertex tier's", dir);
    logged_once(want);
}

/* ---- frames ---- */

/* f is refused with one line naming field; nothing is drawn. */
static void expect_frame_rejected(ht_renderer *r, const ht_frame_desc *f, const char *field) {
    char want[256];
    ht_test_log_clear();
    assert_int_equal(draw(r, f, HT_ERR_INVALID_ARGUMENT), 0);
    snprintf(want, sizeof want, "hairtier: ht_frame_desc: %s: ", field);
    logged_once(want);
    /* one call, one line */
    assert_int_equal(strchr(ht_test_log_text, '\n') - ht_test_log_text + 1, (long)strlen(ht_test_log_text));
}

static void test_draw_refuses_non_finite_and_degenerate_cameras_naming_the_field(void **state) {
    (void)state;
    const float nan = NAN, inf = INFINITY;
    for (int t = 0; t < EVERY_TIER; t++) {
        ht_renderer *r = create_tier(every_tier[t]);
        ht_frame_desc f = frame();
        f.camera.eye[1] = nan;
        expect_frame_rejected(r, &f, "camera.eye");
        f = frame();
        f.camera.target[0] = inf;
        expect_frame_rejected(r, &f, "camera.target");
        f = frame();
        f.camera.up[2] = -inf;
        expect_frame_rejected(r, &f, "camera.up");
        f = frame();
        memset(f.camera.up, 0, sizeof f.camera.up);
        expect_frame_rejected(r, &f, "camera.up");
        f = frame();
        memcpy(f.camera.target, f.camera.eye, sizeof f.camera.eye);
        expect_frame_rejected(r, &f, "camera.target");
        f = frame();
        for (int k = 0; k < 3; k++) f.camera.up[k] = -3 * (f.camera.target[k] - f.camera.eye[k]);
        expect_frame_rejected(r, &f, "camera.up");
        const float bad_fov[] = { 0, -10, 180, 720, nan, inf };
        for (size_t i = 0; i < sizeof bad_fov / sizeof bad_fov[0]; i++) {
            f = frame();
            f.camera.fov_y = bad_fov[i];
            expect_frame_rejected(r, &f, "camera.fov_y");
        }
        f = frame();
        f.camera.z_near = -1;
        expect_frame_rejected(r, &f, "camera.z_near");
        f = frame();
        f.camera.z_near = nan;
        expect_frame_rejected(r, &f, "camera.z_near");
        f = frame();
        f.camera.z_near = 5;
        f.camera.z_far = 1;
        expect_frame_rejected(r, &f, "camera.z_far");
        f = frame();
        f.camera.z_far = inf;
        expect_frame_rejected(r, &f, "camera.z_far");
        f = frame();
        f.aspect = -1;
        expect_frame_rejected(r, &f, "aspect");
        f = frame();
        f.aspect = nan;
        expect_frame_rejected(r, &f, "aspect");
        /* Finite input whose matrices are not. */
        f = frame();
        f.camera.fov_y = 1e-40f;
        expect_frame_rejected(r, &f, "camera");
        f = frame();
        f.camera.z_far = 3e38f;
        expect_frame_rejected(r, &f, "camera");

        /* Extreme but finite: a camera 1e20 away sees nothing, a 0.01
           degree one a few hairs; both draw finite pixels. */
        ht_test_log_clear();
        f = frame();
        f.camera.eye[2] = 1e20f;
        assert_int_equal(draw(r, &f, HT_OK), 0);
        f = frame();
        f.camera.fov_y = 0.01f;
        draw(r, &f, HT_OK);
        ht_renderer_destroy(r);
    }
}

static void test_draw_refuses_bad_lights_naming_the_field(void **state) {
    (void)state;
    ht_renderer *r = create_tier(HT_TIER_FULL);
    ht_light lights[HT_MAX_LIGHTS + 1];
    const ht_frame_desc base = frame();
    memcpy(lights, base.lights, 2 * sizeof *lights);
    lights[2] = lights[3] = lights[4] = lights[0];
    ht_frame_desc f = base;
    f.lights = lights;

    f.light_count = -1;
    expect_frame_rejected(r, &f, "light_count");
    f.light_count = HT_MAX_LIGHTS + 1;
    expect_frame_rejected(r, &f, "light_count");
    f.light_count = 1;
    f.lights = NULL;
    expect_frame_rejected(r, &f, "lights");
    f.lights = lights;
    f.light_count = 2;

    const struct { int light, member, k; float value; const char *field; } cases[] = {
        { 1, 0, 0, NAN, "lights[1].vector" }, { 0, 0, 2, -INFINITY, "lights[0].vector" },
        { 0, 1, 1, NAN, "lights[0].color" },  { 1, 1, 0, INFINITY, "lights[1].color" },
        { 0, 1, 2, -0.5f, "lights[0].color" }, { 1, 1, 1, 4.5f, "lights[1].color" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        memcpy(lights, base.lights, 2 * sizeof *lights);
        float *v = cases[i].member == 0 ? lights[cases[i].light].vector : lights[cases[i].light].color;
        v[cases[i].k] = cases[i].value;
        expect_frame_rejected(r, &f, cases[i].field);
    }
    memcpy(lights, base.lights, 2 * sizeof *lights);
    lights[0].type = (ht_light_type)7;
    expect_frame_rejected(r, &f, "lights[0].type");
    ht_renderer_destroy(r);
}

static void test_degenerate_lights_draw_finite_pixels_in_every_tier(void **state) {
    (void)state;
    static float reference[SIZE * SIZE * 4];
    for (int t = 0; t < EVERY_TIER; t++) {
        ht_renderer *r = create_tier(every_tier[t]);
        const ht_frame_desc base = frame();
        ht_light lights[2] = { base.lights[0], base.lights[0] };
        lights[1].color[0] = lights[1].color[1] = lights[1].color[2] = 0.3f;
        ht_frame_desc f = base;
        f.lights = lights;
        f.light_count = 2;
        assert_true(draw(r, &f, HT_OK) > SIZE * SIZE / 20);
        snapshot(reference);

        /* A directional vector too long for float's dot product is still
           a direction: the same image. */
        ht_light scaled[2] = { lights[0], lights[1] };
        for (int k = 0; k < 3; k++) scaled[0].vector[k] = ldexpf(lights[0].vector[k], 100);
        f.lights = scaled;
        draw(r, &f, HT_OK);
        if (memcmp(reference, float_buffer, sizeof reference) != 0)
            fail_msg("%s: a 2^100 times longer light vector changed the image", ht_tier_name(every_tier[t]));

        /* No direction (zero vector), no light at all: the model's
           documented finite answers, still drawn. */
        memset(scaled[0].vector, 0, sizeof scaled[0].vector);
        assert_true(draw(r, &f, HT_OK) > SIZE * SIZE / 20);
        f.lights = lights;
        f.light_count = 0;
        assert_true(draw(r, &f, HT_OK) > SIZE * SIZE / 20);
        ht_renderer_destroy(r);
    }
}

static void test_lights_beyond_the_plan_are_ignored_with_one_log_line(void **state) {
    (void)state;
    static float two[SIZE * SIZE * 4];
    const ht_frame_desc base = frame();
    ht_light lights[HT_MAX_LIGHTS] = { base.lights[0], base.lights[0], base.lights[0], base.lights[0] };
    lights[1].color[0] = 0.2f;
    for (int i = 2; i < HT_MAX_LIGHTS; i++) {
        lights[i].vector[0] = -lights[i].vector[0];
        lights[i].color[0] = lights[i].color[1] = lights[i].color[2] = 4;
    }
    for (int t = 0; t < EVERY_TIER; t++) {
        ht_renderer *r = create_tier(every_tier[t]);
        ht_frame_desc f = base;
        f.lights = lights;
        f.light_count = 2; /* what the bundle plans */
        draw(r, &f, HT_OK);
        snapshot(two);
        ht_test_log_clear();
        f.light_count = HT_MAX_LIGHTS;
        draw(r, &f, HT_OK);
        draw(r, &f, HT_OK);
        logged_once("hairtier: ht_frame_desc: light_count: 4, the bundle plans 2; lights[2..3] are not drawn");
        if (memcmp(two, float_buffer, sizeof two) != 0)
            fail_msg("%s: lights beyond the plan changed the image", ht_tier_name(every_tier[t]));

        /* A point light where the bundle plans a directional one is shaded
           as planned, said once. */
        ht_test_log_clear();
        f.light_count = 2;
        lights[1].type = HT_LIGHT_POINT;
        draw(r, &f, HT_OK);
        draw(r, &f, HT_OK);
        lights[1].type = HT_LIGHT_DIRECTIONAL;
        logged_once("hairtier: ht_frame_desc: lights[1].type: point, the bundle plans directional; shaded as directional");
        if (memcmp(two, float_buffer, sizeof two) != 0)
            fail_msg("%s: the light type changed the image", ht_tier_name(every_tier[t]));
        ht_renderer_destroy(r);
    }
}

/* ---- meshes ---- */

static void copy_mesh(const ht_mesh *from, ht_mesh *to) {
    *to = *from;
    to->vertices = malloc(from->vertex_count * sizeof *to->vertices);
    to->indices = malloc(from->index_count * sizeof *to->indices);
    to->components = malloc(from->component_count * sizeof *to->components);
    assert_true(to->vertices && to->indices && to->components);
    memcpy(to->vertices, from->vertices, from->vertex_count * sizeof *to->vertices);
    memcpy(to->indices, from->indices, from->index_count * sizeof *to->indices);
    memcpy(to->components, from->components, from->component_count * sizeof *to->components);
}

static void expect_mesh_rejected(ht_renderer *r, const ht_mesh *m, const char *field) {
    char want[256];
    ht_test_log_clear();
    assert_int_equal(ht_renderer_set_mesh(r, m), HT_ERR_INVALID_ARGUMENT);
    snprintf(want, sizeof want, "hairtier: ht_renderer_set_mesh: mesh: %s: ", field);
    logged_once(want);
}

static void test_set_mesh_refuses_bad_meshes_and_keeps_the_previous_one(void **state) {
    (void)state;
    static float before[SIZE * SIZE * 4];
    ht_renderer *r = create_tier(HT_TIER_FULL);
    ht_frame_desc f = frame();
    draw(r, &f, HT_OK);
    snapshot(before);

    ht_mesh m;
    copy_mesh(&fx.mesh, &m);
    m.indices[7] = m.vertex_count;
    expect_mesh_rejected(r, &m, "indices[7]");
    m.indices[7] = fx.mesh.indices[7];
    m.index_count = 4;
    expect_mesh_rejected(r, &m, "index_count");
    m.index_count = fx.mesh.index_count;
    uint32_t *indices = m.indices;
    m.indices = NULL;
    expect_mesh_rejected(r, &m, "indices");
    m.indices = indices;
    ht_vertex *vertices = m.vertices;
    m.vertices = NULL;
    m.index_count = 0;
    expect_mesh_rejected(r, &m, "vertices");
    m.vertices = vertices;
    m.index_count = fx.mesh.index_count;

    const struct { uint32_t v; size_t offset; int k; float value; const char *field; } cases[] = {
        { 1, offsetof(ht_vertex, position), 2, NAN, "vertices[1].position[2]" },
        { 5, offsetof(ht_vertex, normal), 0, INFINITY, "vertices[5].normal[0]" },
        { 9, offsetof(ht_vertex, tangent), 1, -INFINITY, "vertices[9].tangent[1]" },
        { 2, offsetof(ht_vertex, uv), 1, NAN, "vertices[2].uv[1]" },
        { 3, offsetof(ht_vertex, ao), 0, NAN, "vertices[3].ao" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        float *x = (float *)((char *)&m.vertices[cases[i].v] + cases[i].offset) + cases[i].k;
        float saved = *x;
        *x = cases[i].value;
        expect_mesh_rejected(r, &m, cases[i].field);
        *x = saved;
    }
    ht_test_log_clear();
    assert_int_equal(ht_renderer_set_mesh(r, NULL), HT_ERR_INVALID_ARGUMENT);
    logged_once("hairtier: ht_renderer_set_mesh: mesh: NULL");

    /* Every refusal left the fixture's mesh in place. */
    draw(r, &f, HT_OK);
    assert_memory_equal(before, float_buffer, sizeof before);
    ht_mesh_free(&m);
    ht_renderer_destroy(r);
}

static void test_degenerate_meshes_draw_finite_pixels_in_every_tier(void **state) {
    (void)state;
    static float reference[SIZE * SIZE * 4];
    ht_frame_desc f = frame();
    for (int t = 0; t < EVERY_TIER; t++) {
        ht_renderer *r = create_tier(every_tier[t]);
        draw(r, &f, HT_OK);
        snapshot(reference);
        ht_mesh m;
        copy_mesh(&fx.mesh, &m);

        /* The renderer draws the sorted index buffer whole: components are
           the sort's, not the draw's. */
        ht_mesh no_components = m;
        no_components.components = NULL;
        no_components.component_count = 0;
        assert_int_equal(ht_renderer_set_mesh(r, &no_components), HT_OK);
        draw(r, &f, HT_OK);
        assert_memory_equal(reference, float_buffer, sizeof reference);

        /* Zero normals (N.L = 0), zero tangents (no highlight), zero ao
           (black), one point-sized triangle: documented finite answers. */
        for (int which = 0; which < 3; which++) {
            ht_mesh z;
            copy_mesh(&fx.mesh, &z);
            for (uint32_t v = 0; v < z.vertex_count; v++) {
                if (which == 0) memset(z.vertices[v].normal, 0, sizeof z.vertices[v].normal);
                if (which == 1) memset(z.vertices[v].tangent, 0, sizeof z.vertices[v].tangent);
                if (which == 2) z.vertices[v].ao = 0;
            }
            assert_int_equal(ht_renderer_set_mesh(r, &z), HT_OK);
            assert_true(draw(r, &f, HT_OK) > SIZE * SIZE / 20);
            ht_mesh_free(&z);
        }
        ht_mesh point = m;
        point.index_count = 3;
        point.indices[0] = point.indices[1] = point.indices[2] = 0;
        assert_int_equal(ht_renderer_set_mesh(r, &point), HT_OK);
        assert_int_equal(draw(r, &f, HT_OK), 0);

        ht_mesh empty = { 0 };
        assert_int_equal(ht_renderer_set_mesh(r, &empty), HT_OK);
        assert_int_equal(draw(r, &f, HT_OK), 0);
        ht_mesh_free(&m);
        ht_renderer_destroy(r);
    }
}

static void test_draw_refuses_a_bad_opaque_mesh(void **state) {
    (void)state;
    ht_mesh hair = { 0 }, head = { 0 };
    assert_int_equal(ht_mesh_build_patches(&(ht_patches_desc){ .layers = 1, .strips = 8, .segments = 4, .seed = 1 },
                                           &hair, &head), HT_OK);
    ht_renderer *r = create_tier(HT_TIER_FULL);
    ht_frame_desc f = frame();
    f.camera.eye[2] = 4;
    f.opaque = &head;
    assert_true(draw(r, &f, HT_OK) > 0);
    head.indices[4] = head.vertex_count + 10;
    expect_frame_rejected(r, &f, "opaque: indices[4]");
    head.indices[4] = 0;
    head.vertices[0].normal[1] = NAN;
    expect_frame_rejected(r, &f, "opaque: vertices[0].normal[1]");
    ht_renderer_destroy(r);
    ht_mesh_free(&hair);
    ht_mesh_free(&head);
}

/* ---- a driver that refuses a shader stage (fresh process) ---- */

/* Child mode: argv = exe --child BUNDLE under Mesa overrides. Prints the
   log, the result and tier, and one frame's GL error and coverage. */
static int child_main(const char *bundle) {
    ht_test_gl gl;
    ht_renderer *r;
    if (!ht_test_child_renderer(bundle, 32, &gl, &r)) return 1;
    ht_mesh mesh;
    if (r && ht_test_furball_mesh(&mesh) == HT_OK) {
        ht_frame_desc f = ht_test_furball_frame(2.4f);
        glViewport(0, 0, 32, 32);
        glClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        ht_result set = ht_renderer_set_mesh(r, &mesh);
        ht_result drawn = ht_renderer_draw(r, &f);
        ht_image img;
        if (ht_test_gl_read(&gl, &img) == HT_OK) {
            ht_test_pixel_stats s = ht_test_pixel_stats_of(&img, ht_test_background);
            printf("draw=%s/%s gl_error=0x%04x changed=%d magenta=%d\n", ht_result_string(set),
                   ht_result_string(drawn), glGetError(), s.changed, s.magenta);
            ht_image_free(&img);
        }
        ht_mesh_free(&mesh);
    }
    ht_renderer_destroy(r);
    ht_test_gl_destroy(&gl);
    return 0;
}

static void run_child_refusing(const char *extensions, char *out, size_t size) {
    setenv("MESA_EXTENSION_OVERRIDE", extensions, 1);
    ht_test_run_child("2.1", fx.bundle_dir, out, size);
    unsetenv("MESA_EXTENSION_OVERRIDE");
}

static void expect_in(const char *out, const char *what) {
    if (!strstr(out, what)) fail_msg("no \"%s\" in the child's output:\n%s", what, out);
}

static void test_driver_refusing_fragment_shaders_drops_full_with_the_reason(void **state) {
    (void)state;
    char out[8192];
    run_child_refusing("-GL_ARB_fragment_shader", out, sizeof out);
    expect_in(out, "hairtier: device GL 2.1");
    expect_in(out, "skipped full: compile failed: full.frag: glCreateShader(GL_FRAGMENT_SHADER) refused");
    expect_in(out, "result=ok tier=vertex");
    expect_in(out, "draw=ok/ok gl_error=0x0000");
    assert_null(strstr(out, "changed=0 "));
    expect_in(out, "magenta=0");
}

static void test_driver_refusing_every_shader_stage_falls_to_fixed(void **state) {
    (void)state;
    char out[8192];
    run_child_refusing("-GL_ARB_vertex_shader -GL_ARB_fragment_shader", out, sizeof out);
    expect_in(out, "skipped full: compile failed: full.vert: glCreateShader(GL_VERTEX_SHADER) refused");
    /* each skipped tier said once, though selection ran three times */
    assert_null(strstr(strstr(out, "hairtier: skipped full: ") + 1, "hairtier: skipped full: "));
    expect_in(out, "skipped vertex: compile failed: vertex.vert: glCreateShader(GL_VERTEX_SHADER) refused");
    expect_in(out, "result=ok tier=fixed");
    expect_in(out, "draw=ok/ok gl_error=0x0000");
    assert_null(strstr(out, "changed=0 "));
}

/* ---- the programs ---- */

/* No "NAME.tmp-*" left beside an output that failed. */
static void assert_no_temporary_in(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strstr(e->d_name, ".tmp-")) fail_msg("%s/%s left behind", dir, e->d_name);
    closedir(d);
}

/* Runs build/PROGRAM ARGS with stderr captured; returns the exit status. */
static int run_program(const char *program, const char *args, char *err, size_t size) {
    char cmd[4096], err_path[256];
    snprintf(err_path, sizeof err_path, "%s/stderr.txt", fx.work);
    snprintf(cmd, sizeof cmd, "%s/%s %s >/dev/null 2>%s", ht_test_build_dir(), program, args, err_path);
    int status = system(cmd);
    assert_true(WIFEXITED(status));
    FILE *f = fopen(err_path, "rb");
    assert_non_null(f);
    size_t n = fread(err, 1, size - 1, f);
    err[n] = '\0';
    fclose(f);
    return WEXITSTATUS(status);
}

/* The last line of text (without its newline), in a static buffer. */
static const char *last_line(const char *text) {
    static char line[1024];
    size_t n = strlen(text);
    while (n && text[n - 1] == '\n') n--;
    size_t start = n;
    while (start && text[start - 1] != '\n') start--;
    snprintf(line, sizeof line, "%.*s", (int)(n - start), text + start);
    return line;
}

static void expect_hairview_fails(const char *args, const char *out_png, int status, const char *line_start,
                                  const char *mentions) {
    char err[8192], cmd[3072];
    snprintf(cmd, sizeof cmd, "%s -o '%s'", args, out_png);
    int got = run_program("hairview", cmd, err, sizeof err);
    if (got != status) fail_msg("hairview %s: exit %d, expected %d; stderr:\n%s", cmd, got, status, err);
    /* usage errors: the reason, then the usage line; others: the last line */
    const char *line = status == 2 ? err : last_line(err);
    if (strncmp(line, line_start, strlen(line_start)) != 0)
        fail_msg("hairview %s: line \"%.200s\" does not start \"%s\"", cmd, line, line_start);
    size_t len = strcspn(line, "\n");
    const char *at = strstr(line, mentions);
    if (!at || (size_t)(at - line) >= len) fail_msg("hairview %s: \"%.*s\" does not name %s", cmd, (int)len, line, mentions);
    if (ht_test_path_exists(out_png)) fail_msg("hairview %s: %s left behind", cmd, out_png);
}

static void test_hairview_fails_cleanly_on_bad_input(void **state) {
    (void)state;
    char scene[256], bundle_arg[512], args[2048], png[256], path[512], dir[256];
    snprintf(scene, sizeof scene, "%s/scene.json", fx.work);
    ht_test_write_file(fx.work, "scene.json",
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [48, 48],\n"
        " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]},\n"
        "            {\"type\": \"directional\", \"direction\": [-0.7, 0.2, -0.6], \"color\": [0.3, 0.3, 0.3]}],\n"
        " \"background\": [0.1, 0.2, 0.3],\n"
        " \"geometry\": {\"type\": \"furball\", \"hairs\": 200, \"joints\": 6, \"length\": 0.1, \"width\": 0.02}}\n");
    snprintf(bundle_arg, sizeof bundle_arg, "--bundle '%s' --frames 1", fx.bundle_dir);
    snprintf(png, sizeof png, "%s/view.png", fx.work);

    /* The control: these arguments work. */
    char err[8192];
    snprintf(args, sizeof args, "%s --scene '%s' -o '%s'", bundle_arg, scene, png);
    if (run_program("hairview", args, err, sizeof err) != 0) fail_msg("hairview %s failed:\n%s", args, err);
    assert_true(ht_test_path_exists(png));
    assert_int_equal(unlink(png), 0);

    /* --policy: the choice and its reason are logged; frame:MS times every
       tier (no time is asserted); error:DB without measured numbers fails. */
    snprintf(args, sizeof args, "%s --policy fastest --scene '%s' -o '%s'", bundle_arg, scene, png);
    if (run_program("hairview", args, err, sizeof err) != 0) fail_msg("hairview %s failed:\n%s", args, err);
    if (!strstr(err, "hairtier: tier gl11 (fastest: ")) fail_msg("hairview %s:\n%s", args, err);
    snprintf(args, sizeof args, "%s --policy frame:100000 --scene '%s' -o '%s'", bundle_arg, scene, png);
    if (run_program("hairview", args, err, sizeof err) != 0) fail_msg("hairview %s failed:\n%s", args, err);
    if (!strstr(err, "hairtier: timed gl11: ") || !strstr(err, "hairtier: tier full (frame:100000: "))
        fail_msg("hairview %s:\n%s", args, err);
    assert_int_equal(unlink(png), 0);
    snprintf(args, sizeof args, "%s --policy error:30 --scene '%s'", bundle_arg, scene);
    expect_hairview_fails(args, png, 1, "hairview: ", "no tier has measured numbers");
    snprintf(args, sizeof args, "%s --policy soon --scene '%s'", bundle_arg, scene);
    expect_hairview_fails(args, png, 2, "hairview: ", "--policy");

    /* The scene: missing, malformed, a field out of range. */
    snprintf(args, sizeof args, "%s --scene '%s/no-scene.json'", bundle_arg, fx.work);
    expect_hairview_fails(args, png, 1, "hairview: ", "no-scene.json");
    ht_test_write_file(fx.work, "broken-scene.json", "{\"format\": \"hairtier-scene/1\", \"resolution\": [48,");
    snprintf(args, sizeof args, "%s --scene '%s/broken-scene.json'", bundle_arg, fx.work);
    expect_hairview_fails(args, png, 1, "hairview: ", "broken-scene.json");
    char *text = ht_test_read_file(fx.work, "scene.json");
    char *fov = strstr(text, "\"fov_y\": 45");
    assert_non_null(fov);
    memcpy(fov, "\"fov_y\": 0 ", 11);
    ht_test_write_file(fx.work, "fov-scene.json", text);
    snprintf(args, sizeof args, "%s --scene '%s/fov-scene.json'", bundle_arg, fx.work);
    expect_hairview_fails(args, png, 1, "hairview: ", "camera.fov_y");

    /* The bundle: absent, or its albedo corrupt with the tier forced. */
    snprintf(args, sizeof args, "--bundle '%s/no-bundle' --scene '%s'", fx.work, scene);
    expect_hairview_fails(args, png, 1, "hairview: ", "no-bundle/manifest.json: cannot read");
    ht_test_furball_copy_bundle(&fx, "view-bad-albedo", dir, sizeof dir);
    write_bytes(dir, "albedo.png", "\x89PNG\r\n\x1a\n", 8);
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --tier full --strict", dir, scene);
    expect_hairview_fails(args, png, 1, "hairview: full: ", "albedo.png");

    /* The output: a missing directory, a file where a directory should
       be, an existing directory. Nothing half-written stays. */
    snprintf(args, sizeof args, "%s --scene '%s'", bundle_arg, scene);
    snprintf(path, sizeof path, "%s/no-dir/view.png", fx.work);
    expect_hairview_fails(args, path, 1, "hairview: ", path);
    ht_test_write_file(fx.work, "a-file", "x");
    snprintf(path, sizeof path, "%s/a-file/view.png", fx.work);
    expect_hairview_fails(args, path, 1, "hairview: ", path);
    snprintf(dir, sizeof dir, "%s/out-dir", fx.work);
    assert_int_equal(mkdir(dir, 0755), 0);
    char e2[8192], cmd[3072];
    snprintf(cmd, sizeof cmd, "%s -o '%s'", args, dir);
    assert_int_equal(run_program("hairview", cmd, e2, sizeof e2), 1);
    assert_non_null(strstr(last_line(e2), dir));
    assert_no_temporary_in(fx.work);

    /* The command line. */
    snprintf(args, sizeof args, "%s --scene '%s' --tier bogus", bundle_arg, scene);
    expect_hairview_fails(args, png, 2, "hairview: --tier: ", "auto, marschner, full, vertex, fixed4, fixed or gl11");
    const char *frames[] = { "0", "-1", "ten", "100001" };
    for (int i = 0; i < 4; i++) {
        snprintf(args, sizeof args, "--bundle '%s' --scene '%s' --frames %s", fx.bundle_dir, scene, frames[i]);
        expect_hairview_fails(args, png, 2, "hairview: --frames: ", "1..100000");
    }
    assert_no_temporary_in(fx.work);
}

static void test_tier_sheet_without_a_bundle_writes_no_sheet(void **state) {
    (void)state;
    char args[1024], err[8192], sheet[256];
    snprintf(sheet, sizeof sheet, "%s/sheet.png", fx.work);
    ht_test_write_file(fx.work, "sheet-scene.json",
        "{\"format\": \"hairtier-scene/1\", \"resolution\": [32, 32],\n"
        " \"camera\": {\"eye\": [0, 0.3, 2.4], \"target\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y\": 45},\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 1, 1]}],\n"
        " \"geometry\": {\"type\": \"furball\", \"hairs\": 50, \"joints\": 4}}\n");
    snprintf(args, sizeof args, "--bundle '%s/no-bundle' --scene '%s/sheet-scene.json' --frames 1 -o '%s'", fx.work,
             fx.work, sheet);
    assert_int_equal(run_program("tier_sheet", args, err, sizeof err), 1);
    assert_non_null(strstr(last_line(err), "tier_sheet: no tier ran: "));
    assert_non_null(strstr(last_line(err), "no-bundle/manifest.json: cannot read"));
    assert_false(ht_test_path_exists(sheet));
    snprintf(args, sizeof args, "--bundle '%s' --scene '%s/sheet-scene.json' --frames 0 -o '%s'", fx.bundle_dir,
             fx.work, sheet);
    assert_int_equal(run_program("tier_sheet", args, err, sizeof err), 2);
    assert_false(ht_test_path_exists(sheet));
}

/* The entries of /tmp whose names start with prefix, one per line. */
static void tmp_entries(const char *prefix, char *out, size_t size) {
    out[0] = '\0';
    DIR *d = opendir("/tmp");
    assert_non_null(d);
    struct dirent *e;
    size_t used = 0;
    while ((e = readdir(d)))
        if (strncmp(e->d_name, prefix, strlen(prefix)) == 0 && used < size)
            used += (size_t)snprintf(out + used, size - used, "%s\n", e->d_name);
    closedir(d);
}

/* Run where there are no materials/ or scenes/, the benchmarks stop at
   their first step; the scratch directory each made goes with them. */
static void test_benchmarks_failing_early_leave_no_scratch_directory(void **state) {
    (void)state;
    char build[PATH_MAX], before[8192], after[8192], cmd[PATH_MAX * 2 + 256];
    assert_non_null(realpath(ht_test_build_dir(), build));
    const char *benches[2] = { "bench_frame", "bench_hairgen" };
    for (int i = 0; i < 2; i++) {
        tmp_entries("hairtier-bench-", before, sizeof before);
        snprintf(cmd, sizeof cmd, "cd '%s' && '%s/%s' >/dev/null 2>&1", fx.work, build, benches[i]);
        int status = system(cmd);
        assert_true(WIFEXITED(status));
        assert_int_equal(WEXITSTATUS(status), 1);
        tmp_entries("hairtier-bench-", after, sizeof after);
        for (const char *line = after; *line; line += strcspn(line, "\n") + 1) {
            char name[256];
            snprintf(name, sizeof name, "%.*s\n", (int)strcspn(line, "\n"), line);
            if (!strstr(before, name)) fail_msg("%s left /tmp/%.*s behind", benches[i], (int)strlen(name) - 1, name);
        }
    }
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "--child") == 0) return child_main(argv[2]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_missing_detail_texture_drops_full_to_vertex_naming_the_file),
        cmocka_unit_test(test_broken_albedo_leaves_no_tier_and_names_the_file),
        cmocka_unit_test(test_texture_header_claiming_a_huge_size_is_refused_before_decoding),
        cmocka_unit_test(test_bad_manifest_fields_fail_creation_naming_file_and_field),
        cmocka_unit_test(test_unknown_tier_is_skipped_by_name),
        cmocka_unit_test(test_sampler_units_the_device_lacks_drop_the_tier),
        cmocka_unit_test(test_draw_refuses_non_finite_and_degenerate_cameras_naming_the_field),
        cmocka_unit_test(test_draw_refuses_bad_lights_naming_the_field),
        cmocka_unit_test(test_degenerate_lights_draw_finite_pixels_in_every_tier),
        cmocka_unit_test(test_lights_beyond_the_plan_are_ignored_with_one_log_line),
        cmocka_unit_test(test_set_mesh_refuses_bad_meshes_and_keeps_the_previous_one),
        cmocka_unit_test(test_degenerate_meshes_draw_finite_pixels_in_every_tier),
        cmocka_unit_test(test_draw_refuses_a_bad_opaque_mesh),
        cmocka_unit_test(test_driver_refusing_fragment_shaders_drops_full_with_the_reason),
        cmocka_unit_test(test_driver_refusing_every_shader_stage_falls_to_fixed),
        cmocka_unit_test(test_hairview_fails_cleanly_on_bad_input),
        cmocka_unit_test(test_tier_sheet_without_a_bundle_writes_no_sheet),
        cmocka_unit_test(test_benchmarks_failing_early_leave_no_scratch_directory),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

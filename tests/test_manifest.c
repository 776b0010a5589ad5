/* test_manifest.c — the manifest reader (runtime/io/manifest_read.c) against
   the generator that writes it (shadergen/generate.c): a round trip over
   every field, and the reader's refusals that no generated bundle exercises. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairgen.h>
#include "manifest.h"
#include "support_scratch.h"

static char work[64];

static int make_work_dir(void **state) {
    (void)state;
    return ht_test_scratch_create(work, sizeof work, "manifest") ? 0 : -1;
}

static int remove_work_dir(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static const char *str(const cJSON *obj, const char *key) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsString(v) ? v->valuestring : NULL;
}

static int num(const cJSON *obj, const char *key) {
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    assert_true(cJSON_IsNumber(v));
    return (int)v->valuedouble;
}

static void check_textures(const cJSON *json, const ht_manifest_texture *tex, int count) {
    assert_int_equal(cJSON_GetArraySize(json), count);
    const cJSON *t;
    int i = 0;
    cJSON_ArrayForEach(t, json) {
        assert_string_equal(tex[i].name, t->string);
        assert_string_equal(tex[i].file, str(t, "file"));
        assert_int_equal(tex[i].width, num(t, "width"));
        assert_int_equal(tex[i].height, num(t, "height"));
        assert_int_equal(tex[i].depth, num(t, "depth"));
        i++;
    }
}

/* What the generator writes, the reader reads back field by field (both
   materials: one with every texture and two lobes, one Kajiya-Kay). */
static void round_trip(const char *material, const char *scene, const char *name) {
    char dir[256], err[2048] = "";
    snprintf(dir, sizeof dir, "%s/%s", work, name);
    if (ht_generate_bundle(material, scene, dir, NULL, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_manifest m;
    if (ht_manifest_load(dir, &m, err, sizeof err) != HT_OK) fail_msg("%s", err);

    char path[320];
    snprintf(path, sizeof path, "%s/" HT_MANIFEST_FILE, dir);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static char text[1 << 16];
    text[fread(text, 1, sizeof text - 1, f)] = '\0';
    fclose(f);
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);

    assert_string_equal(str(root, "format"), HT_MANIFEST_FORMAT);
    assert_string_equal(m.dir, dir);
    assert_string_equal(m.material, str(root, "material"));
    assert_string_equal(m.model, str(root, "model"));
    assert_float_equal(m.opaque_cutoff, cJSON_GetObjectItem(root, "opaque_cutoff")->valuedouble, 1e-6);
    const cJSON *lights = cJSON_GetObjectItem(root, "lights");
    assert_int_equal(m.light_count, cJSON_GetArraySize(lights));
    for (int i = 0; i < m.light_count; i++)
        assert_string_equal(m.lights[i] == HT_LIGHT_POINT ? "point" : "directional",
                            cJSON_GetArrayItem(lights, i)->valuestring);
    check_textures(cJSON_GetObjectItem(root, "textures"), m.textures, m.texture_count);

    const cJSON *tiers = cJSON_GetObjectItem(root, "tiers");
    assert_int_equal(m.tier_count, cJSON_GetArraySize(tiers));
    for (int i = 0; i < m.tier_count; i++) {
        const cJSON *t = cJSON_GetArrayItem(tiers, i);
        const ht_manifest_tier *mt = &m.tiers[i];
        assert_string_equal(mt->name, str(t, "name"));
        assert_ptr_equal(ht_manifest_find_tier(&m, mt->tier), mt);
        const cJSON *req = cJSON_GetObjectItem(t, "requires");
        char version[16];
        snprintf(version, sizeof version, "%d.%d", mt->gl_major, mt->gl_minor);
        assert_string_equal(version, str(req, "gl"));
        if (str(req, "glsl")) {
            snprintf(version, sizeof version, "%d.%02d", mt->glsl_major, mt->glsl_minor);
            assert_string_equal(version, str(req, "glsl"));
        } else {
            assert_int_equal(mt->glsl_major, 0);
        }
        assert_int_equal(mt->texture_units, num(req, "texture_units"));
        const cJSON *ext = cJSON_GetObjectItem(req, "extensions");
        assert_int_equal(mt->extension_count, cJSON_GetArraySize(ext));
        for (int e = 0; e < mt->extension_count; e++)
            assert_string_equal(mt->extensions[e], cJSON_GetArrayItem(ext, e)->valuestring);
        const cJSON *files = cJSON_GetObjectItem(t, "files"), *fi;
        assert_int_equal(mt->file_count, cJSON_GetArraySize(files));
        cJSON_ArrayForEach(fi, files) assert_string_equal(ht_manifest_tier_file(mt, fi->string), fi->valuestring);
        const cJSON *samplers = cJSON_GetObjectItem(t, "samplers");
        assert_int_equal(mt->sampler_count, cJSON_GetArraySize(samplers));
        for (int s = 0; s < mt->sampler_count; s++) {
            const cJSON *js = cJSON_GetArrayItem(samplers, s);
            assert_string_equal(mt->samplers[s].uniform, str(js, "uniform"));
            assert_string_equal(mt->samplers[s].texture, str(js, "texture"));
            assert_int_equal(mt->samplers[s].unit, num(js, "unit"));
            assert_non_null(ht_manifest_find_texture(&m, mt, mt->samplers[s].texture));
        }
        const cJSON *own = cJSON_GetObjectItem(t, "textures");
        if (own) check_textures(own, mt->textures, mt->texture_count);
        else assert_int_equal(mt->texture_count, 0);
    }
    cJSON_Delete(root);
}

static void test_manifest_round_trips_every_field_the_generator_writes(void **state) {
    (void)state;
    round_trip("materials/dark-brown.json", "scenes/furball.json", "dark");
    round_trip("materials/dark-brown.json", "scenes/patches.json", "patches");
}

/* A file name must name a file inside the bundle: "." and ".." name
   directories (the bundle itself, its parent). */
static void test_manifest_refuses_dot_and_dot_dot_file_names(void **state) {
    (void)state;
    static const char *const names[] = { ".", ".." };
    for (int i = 0; i < 2; i++) {
        char text[1024], err[512] = "";
        snprintf(text, sizeof text,
                 "{\"format\": \"" HT_MANIFEST_FORMAT "\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"directional\"],"
                 " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\", \"glsl\": \"1.20\"},"
                 " \"files\": {\"vertex\": \"%s\"}}]}", names[i]);
        ht_manifest m;
        assert_int_equal(ht_manifest_parse(text, "/b", "/b/manifest.json", &m, err, sizeof err), HT_ERR_PARSE);
        char want[128];
        snprintf(want, sizeof want, "/b/manifest.json: tiers[0].files.vertex: \"%s\" is not a plain file name",
                 names[i]);
        if (strncmp(err, want, strlen(want)) != 0) fail_msg("got \"%s\", want \"%s...\"", err, want);
        assert_null(strchr(err, '\n'));

        snprintf(text, sizeof text,
                 "{\"format\": \"" HT_MANIFEST_FORMAT "\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"opaque_cutoff\": 0.5, \"lights\": [\"directional\"],"
                 " \"textures\": {\"albedo\": {\"file\": \"%s\", \"width\": 4, \"height\": 4}},"
                 " \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\"}, \"files\": {}}]}", names[i]);
        assert_int_equal(ht_manifest_parse(text, "/b", "/b/manifest.json", &m, err, sizeof err), HT_ERR_PARSE);
        snprintf(want, sizeof want, "/b/manifest.json: textures.albedo.file: \"%s\" is not a plain file name",
                 names[i]);
        if (strncmp(err, want, strlen(want)) != 0) fail_msg("got \"%s\", want \"%s...\"", err, want);
    }
}

/* A bundle of another generator version is refused before any other field,
   with one line naming the manifest, its version and the one to regenerate
   with; so is one that records none. */
static void test_manifest_refuses_another_generator_version(void **state) {
    (void)state;
    static const char *const versions[] = { "\"hairgen 2\"", "\"hairgen 9\"", "null", "4" };
    static const char *const echoed[] = { "\"hairgen 2\", ", "\"hairgen 9\", ", "not a string, ", "not a string, " };
    for (int i = 0; i < 4; i++) {
        char text[1024], err[512] = "";
        snprintf(text, sizeof text,
                 "{\"format\": \"" HT_MANIFEST_FORMAT "\", \"generator\": %s, \"opaque_cutoff\": 0.5,"
                 " \"lights\": [\"directional\"], \"tiers\": [{\"name\": \"full\", \"requires\": {\"api\": \"gl\", \"gl\": \"2.1\"},"
                 " \"files\": {}}]}", versions[i]);
        ht_manifest m;
        assert_int_equal(ht_manifest_parse(text, "/b", "/b/manifest.json", &m, err, sizeof err), HT_ERR_PARSE);
        char want[256];
        snprintf(want, sizeof want, "/b/manifest.json: generator: %sthis runtime reads " HT_MANIFEST_GENERATOR
                 " bundles: regenerate with " HT_MANIFEST_GENERATOR, echoed[i]);
        assert_string_equal(err, want);
    }
    char err[512] = "";
    ht_manifest m;
    assert_int_equal(ht_manifest_parse("{\"format\": \"" HT_MANIFEST_FORMAT "\"}", "/b", "/b/manifest.json", &m, err,
                                       sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "generator: missing, this runtime reads " HT_MANIFEST_GENERATOR " bundles"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_manifest_round_trips_every_field_the_generator_writes),
        cmocka_unit_test(test_manifest_refuses_dot_and_dot_dot_file_names),
        cmocka_unit_test(test_manifest_refuses_another_generator_version),
    };
    return cmocka_run_group_tests(tests, make_work_dir, remove_work_dir);
}

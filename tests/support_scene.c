/* support_scene.c — see support_scene.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cJSON.h>
#include <cmocka.h>

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "support_render.h"
#include "support_scene.h"
#include "support_scratch.h"

void ht_test_run_command(const char *cmd) {
    int status = system(cmd);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail_msg("command failed: %s", cmd);
}

void ht_test_keep_strand_file(cJSON *root, const char *shipped_scene) {
    cJSON *file = cJSON_GetObjectItem(cJSON_GetObjectItem(root, "geometry"), "file");
    if (!cJSON_IsString(file) || file->valuestring[0] == '/') return;
    char joined[1024], resolved[PATH_MAX];
    const char *slash = strrchr(shipped_scene, '/');
    snprintf(joined, sizeof joined, "%.*s%s", slash ? (int)(slash - shipped_scene) + 1 : 0, shipped_scene,
             file->valuestring);
    assert_non_null(realpath(joined, resolved));
    cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetObjectItem(root, "geometry"), "file",
                                           cJSON_CreateString(resolved));
}

const char *ht_test_scene_copy(const char *shipped_scene, const char *dir, const char *name, int side, int hairs,
                               bool no_head, char *out, size_t out_size) {
    cJSON *root = cJSON_Parse(ht_test_read_file(".", shipped_scene));
    assert_non_null(root);
    if (side > 0)
        cJSON_ReplaceItemInObjectCaseSensitive(root, "resolution", cJSON_CreateIntArray((const int[]){ side, side }, 2));
    ht_test_keep_strand_file(root, shipped_scene);
    cJSON *geometry = cJSON_GetObjectItem(root, "geometry");
    if (hairs > 0 && cJSON_GetObjectItem(geometry, "hairs"))
        cJSON_ReplaceItemInObjectCaseSensitive(geometry, "hairs", cJSON_CreateNumber(hairs));
    if (no_head) cJSON_DeleteItemFromObjectCaseSensitive(geometry, "head");
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    ht_test_write_file(dir, name, text);
    cJSON_free(text);
    snprintf(out, out_size, "%s/%s", dir, name);
    return out;
}

/* The TressFX 4.0 header (runtime/io/strands_tfx.c): version, strands,
   points per strand, then five block offsets; 160 bytes. */
enum { TFX_HEADER = 160, TFX_STRANDS = 4, TFX_POINTS = 8, TFX_POSITIONS = 12 };

static uint32_t get_u32(const char *p) {
    uint32_t v;
    memcpy(&v, p, sizeof v);
    return v;
}

int ht_test_furball_bundle(const char *dir, int side, int hairs, int joints, const char *options) {
    char scene[512], args[2048], out[16384];
    ht_test_scene_copy("scenes/furball.json", dir, "scene.json", side, hairs, false, scene, sizeof scene);
    if (joints > 0) {
        cJSON *root = ht_test_read_json(dir, "scene.json");
        cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetObjectItem(root, "geometry"), "joints", cJSON_CreateNumber(joints));
        char *text = cJSON_Print(root);
        cJSON_Delete(root);
        ht_test_write_file(dir, "scene.json", text);
        cJSON_free(text);
    }
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s %s -o %s/bundle", scene, options, dir);
    if (ht_test_run_program("hairgen", args, out, sizeof out) != 0) {
        fprintf(stderr, "%s", out);
        return -1;
    }
    return 0;
}

void ht_test_scene_thin_strands(const char *dir, const char *name, int every) {
    cJSON *root = ht_test_read_json(dir, name);
    cJSON *file = cJSON_GetObjectItem(cJSON_GetObjectItem(root, "geometry"), "file");
    size_t n = cJSON_IsString(file) ? strlen(file->valuestring) : 0;
    if (n < 4 || strcmp(file->valuestring + n - 4, ".tfx") != 0) {
        cJSON_Delete(root);
        return;
    }
    size_t size = 0;
    char *in = ht_test_read_all(file->valuestring, &size);
    assert_non_null(in);
    assert_true(size >= TFX_HEADER);
    uint32_t strands = get_u32(in + TFX_STRANDS), points = get_u32(in + TFX_POINTS), at = get_u32(in + TFX_POSITIONS);
    size_t strand_bytes = (size_t)points * 16, kept = (strands + every - 1) / every;
    assert_true(at >= TFX_HEADER && at <= size && (size - at) / strand_bytes >= strands);
    char *out = calloc(1, TFX_HEADER + kept * strand_bytes);
    assert_non_null(out);
    memcpy(out, in, TFX_POSITIONS);
    uint32_t header[2] = { (uint32_t)kept, TFX_HEADER };
    memcpy(out + TFX_STRANDS, &header[0], 4);
    memcpy(out + TFX_POSITIONS, &header[1], 4); /* the other blocks: absent (offsets 0) */
    for (size_t s = 0; s < kept; s++)
        memcpy(out + TFX_HEADER + s * strand_bytes, in + at + s * every * strand_bytes, strand_bytes);
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.tfx", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(out, 1, TFX_HEADER + kept * strand_bytes, f), TFX_HEADER + kept * strand_bytes);
    assert_int_equal(fclose(f), 0);
    free(out);
    free(in);
    cJSON_ReplaceItemInObjectCaseSensitive(cJSON_GetObjectItem(root, "geometry"), "file", cJSON_CreateString(path));
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    ht_test_write_file(dir, name, text);
    cJSON_free(text);
}

int ht_test_bundle_tiers(const char *bundle, char names[HT_TIER_COUNT][16], const char *first) {
    cJSON *root = cJSON_Parse(ht_test_read_file(bundle, "manifest.json"));
    assert_non_null(root);
    int n = 0;
    const cJSON *t;
    cJSON_ArrayForEach(t, cJSON_GetObjectItem(root, "tiers")) {
        if (n == HT_TIER_COUNT) break;
        snprintf(names[n++], 16, "%s", cJSON_GetObjectItem(t, "name")->valuestring);
    }
    cJSON_Delete(root);
    assert_true(n >= 2);
    assert_string_equal(names[0], first);
    return n;
}

void ht_test_view_scene_load(const char *path, ht_test_view_scene *out) {
    char err[1024];
    *out = (ht_test_view_scene){ 0 };
    snprintf(out->path, sizeof out->path, "%s", path);
    if (ht_scene_load(path, &out->scene, err, sizeof err) != HT_OK) fail_msg("%s", err);
    if (ht_scene_build_meshes(&out->scene, path, &out->hair, &out->head, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
}

void ht_test_view_scene_free(ht_test_view_scene *s) {
    ht_mesh_free(&s->hair);
    ht_mesh_free(&s->head);
}

void ht_test_view_draw(ht_test_gl *gl, const char *bundle, const ht_test_view_scene *s, const char *tier, bool device,
                       ht_image *img) {
    const ht_scene *sc = &s->scene;
    if (!gl->context || gl->width != sc->width || gl->height != sc->height) {
        char err[256];
        if (gl->context) ht_test_gl_destroy(gl);
        if (!ht_test_gl_create(gl, sc->width, sc->height, NULL, err, sizeof err)) fail_msg("context: %s", err);
    }
    ht_renderer *r = ht_test_renderer_create(
        (ht_renderer_desc){ .tier = ht_tier_from_name(tier), .strict = true,
                            .variant = device ? HT_VARIANT_DEVICE : HT_VARIANT_EXACT },
        bundle, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &s->hair), HT_OK);
    const ht_frame_desc frame = { .camera = sc->camera, .lights = sc->lights, .light_count = sc->light_count,
                                  .aspect = (float)sc->width / (float)sc->height,
                                  .opaque = s->head.index_count ? &s->head : NULL };
    ht_test_draw(gl, r, &frame, sc->background, img);
    ht_renderer_destroy(r);
}

/* A frame as RGBA8, what ht_metrics_compare reads (hairview may write RGB). */
static uint8_t *as_rgba(const ht_image *img) {
    size_t n = (size_t)img->width * img->height;
    uint8_t *rgba = malloc(n * 4);
    assert_non_null(rgba);
    for (size_t i = 0; i < n; i++) {
        const uint8_t *p = img->pixels + i * img->channels;
        for (int c = 0; c < 3; c++) rgba[i * 4 + c] = p[img->channels >= 3 ? c : 0];
        rgba[i * 4 + 3] = 255;
    }
    return rgba;
}

ht_metrics ht_test_whole_frame_metrics(const ht_image *reference, const ht_image *test) {
    uint8_t *a = as_rgba(reference), *b = as_rgba(test);
    ht_metrics whole;
    char err[256];
    assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = a, .test = b, .width = reference->width,
                                                            .height = reference->height },
                                        &whole, NULL, err, sizeof err),
                     HT_OK);
    free(a);
    free(b);
    return whole;
}

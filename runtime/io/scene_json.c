/* scene_json.c — reads "hairtier-scene/1" files into ht_scene, and the
   default scene. Every rule is listed in docs/materials.md; keep the two in
   step. Geometry defaults are written out (not left 0) so a parsed scene
   says exactly what will be built. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/scene.h>
#include "json_check.h"
#include <hairtier/model.h>

#define SCENE_FORMAT "hairtier-scene/1"

/* Positions and directions: far beyond any hair scene, yet products of two
   of them stay well inside float range. */
static const ht_jrange COORD_RANGE = { -10000, 10000, false, false };

static const ht_furball_desc furball_defaults = {
    .hairs = 2000, .joints = 16, .length = 0.08f, .width = 0.01f,
};
static const ht_patches_desc patches_defaults = {
    .head_radius = 1.0f, .layers = 3, .strips = 64, .segments = 12,
};
static const ht_strands_scene strands_defaults = {
    .ribbon = { .scale = 1.0f, .width = 0.01f, .tip_width = 0.25f, .ao = 0.3f },
};

void ht_scene_default(ht_scene *out) {
    memset(out, 0, sizeof *out);
    out->width = 512;
    out->height = 512;
    /* 50 degrees, not the file default of 45: the default fur reaches
       joints * length = 1.28 from the origin, which 45 degrees at 3.2 clips. */
    out->camera = (ht_camera){
        .eye = { 0, 0, 3.2f }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 },
        .fov_y = 50, .z_near = 0.05f, .z_far = 100,
    };
    out->lights[0] = (ht_light){
        .type = HT_LIGHT_DIRECTIONAL, .vector = { 0.5f, 0.7f, 1.0f }, .color = { 1, 1, 1 },
    };
    out->light_count = 1;
    out->geometry = HT_GEOMETRY_FURBALL;
    out->furball = furball_defaults;
    out->patches = patches_defaults;
    out->strands = strands_defaults;
}

static double length2(const float v[3]) {
    return (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2];
}

static ht_result parse_resolution(const ht_jctx *c, const cJSON *root, ht_scene *s) {
    const cJSON *arr;
    int n;
    ht_result r = ht_json_array(c, root, "", "resolution", true, 2, 2, &arr, &n);
    if (r != HT_OK) return r;
    int64_t v[2];
    for (int i = 0; i < 2; i++) {
        char field[HT_JSON_PATH_MAX];
        ht_json_path_index(field, "resolution", i);
        r = ht_json_int_item(c, cJSON_GetArrayItem(arr, i), field, 1, 4096, &v[i]);
        if (r != HT_OK) return r;
    }
    s->width = (int)v[0];
    s->height = (int)v[1];
    return HT_OK;
}

static ht_result parse_camera(const ht_jctx *c, const cJSON *root, ht_camera *cam) {
    static const char *const keys[] = { "eye", "target", "up", "fov_y", "near", "far", NULL };
    const cJSON *obj;
    ht_result r = ht_json_object(c, root, "", "camera", true, &obj);
    if (r == HT_OK) r = ht_json_keys(c, obj, "camera", keys);
    if (r == HT_OK) r = ht_json_vec3f(c, obj, "camera", "eye", NULL, COORD_RANGE, cam->eye);
    if (r == HT_OK) r = ht_json_vec3f(c, obj, "camera", "target", NULL, COORD_RANGE, cam->target);
    if (r == HT_OK)
        r = ht_json_vec3f(c, obj, "camera", "up", (const float[3]){ 0, 1, 0 }, COORD_RANGE, cam->up);
    if (r == HT_OK)
        r = ht_json_float(c, obj, "camera", "fov_y", &(float){ 45 }, HT_JRANGE_OPEN(0, 180), &cam->fov_y);
    if (r == HT_OK)
        r = ht_json_float(c, obj, "camera", "near", &(float){ 0.05f }, HT_JRANGE(0.0001, 10000), &cam->z_near);
    if (r == HT_OK)
        r = ht_json_float(c, obj, "camera", "far", &(float){ 100 }, HT_JRANGE_LO_OPEN(0, 1000000), &cam->z_far);
    if (r != HT_OK) return r;
    if (!(cam->z_far > cam->z_near))
        return ht_json_fail(c, "camera.far", "must be greater than camera.near (%g), got %g",
                            (double)cam->z_near, (double)cam->z_far);
    float d[3] = { cam->target[0] - cam->eye[0], cam->target[1] - cam->eye[1], cam->target[2] - cam->eye[2] };
    double d2 = length2(d);
    if (d2 < HT_MODEL_MIN_LENGTH2)
        return ht_json_fail(c, "camera.target", "equals camera.eye; the camera needs a direction to look in");
    double u2 = length2(cam->up);
    if (u2 < HT_MODEL_MIN_LENGTH2) return ht_json_fail(c, "camera.up", "zero vector");
    double x[3] = {
        (double)cam->up[1] * d[2] - (double)cam->up[2] * d[1],
        (double)cam->up[2] * d[0] - (double)cam->up[0] * d[2],
        (double)cam->up[0] * d[1] - (double)cam->up[1] * d[0],
    };
    /* sin of the angle between up and the view below ~0.06 degrees leaves
       the camera's roll to rounding. */
    double sin2 = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / (u2 * d2);
    if (sin2 < 1e-6)
        return ht_json_fail(c, "camera.up", "parallel to the view direction (target - eye); the roll is undefined");
    return HT_OK;
}

static ht_result parse_light(const ht_jctx *c, const cJSON *obj, const char *path, ht_light *l) {
    static const char *const keys[] = { "type", "direction", "position", "color", NULL };
    static const char *const types[] = { "directional", "point", NULL };
    ht_result r = ht_json_keys(c, obj, path, keys);
    int type = 0;
    if (r == HT_OK) r = ht_json_enum(c, obj, path, "type", -1, types, &type);
    if (r != HT_OK) return r;
    l->type = type == 1 ? HT_LIGHT_POINT : HT_LIGHT_DIRECTIONAL;
    const char *vec_key = type == 1 ? "position" : "direction";
    r = ht_json_forbid(c, obj, path, type == 1 ? "direction" : "position",
                       type == 1 ? "a point light takes \"position\", not \"direction\""
                                 : "a directional light takes \"direction\" (towards the light), not \"position\"");
    if (r == HT_OK) r = ht_json_vec3f(c, obj, path, vec_key, NULL, COORD_RANGE, l->vector);
    if (r == HT_OK && type == 0 && length2(l->vector) < HT_MODEL_MIN_LENGTH2) {
        char field[HT_JSON_PATH_MAX];
        ht_json_path_key(field, path, "direction");
        return ht_json_fail(c, field, "zero vector; a directional light needs a direction towards the light");
    }
    if (r == HT_OK)
        r = ht_json_vec3f(c, obj, path, "color", (const float[3]){ 1, 1, 1 }, HT_JRANGE(0, 4), l->color);
    return r;
}

static ht_result parse_lights(const ht_jctx *c, const cJSON *root, ht_scene *s) {
    const cJSON *arr;
    int n;
    ht_result r = ht_json_array(c, root, "", "lights", true, 1, HT_MAX_LIGHTS, &arr, &n);
    if (r != HT_OK) return r;
    int i = 0;
    for (const cJSON *it = arr->child; it && i < n; it = it->next, i++) {
        char path[HT_JSON_PATH_MAX];
        ht_json_path_index(path, "lights", i);
        r = parse_light(c, it, path, &s->lights[i]);
        if (r != HT_OK) return r;
    }
    s->light_count = n;
    return HT_OK;
}

/* A key of the other geometry type gets a better message than "unknown". */
static ht_result other_kind_keys(const ht_jctx *c, const cJSON *g, const char *const own[],
                                 const char *const other[], const char *why) {
    for (int i = 0; other[i]; i++) {
        bool shared = false;
        for (int j = 0; own[j]; j++) shared = shared || strcmp(own[j], other[i]) == 0;
        ht_result r = shared ? HT_OK : ht_json_forbid(c, g, "geometry", other[i], why);
        if (r != HT_OK) return r;
    }
    return HT_OK;
}

static const char *const furball_keys[] = {
    "type", "hairs", "joints", "length", "gravity", "inertia", "width", "seed", NULL,
};
static const char *const patches_keys[] = {
    "type", "head_radius", "layers", "strips", "segments", "seed", NULL,
};
static const char *const strands_keys[] = {
    "type", "file", "scale", "center", "width", "tip_width", "thickness", "ao", "facing", "head", NULL,
};

static ht_result parse_furball(const ht_jctx *c, const cJSON *g, ht_furball_desc *f) {
    const ht_furball_desc *d = &furball_defaults;
    int64_t hairs, joints, seed;
    ht_result r = other_kind_keys(c, g, furball_keys, patches_keys,
                                  "belongs to \"type\": \"patches\", not \"furball\"");
    if (r == HT_OK)
        r = other_kind_keys(c, g, furball_keys, strands_keys, "belongs to \"type\": \"strands\", not \"furball\"");
    if (r == HT_OK) r = ht_json_keys(c, g, "geometry", furball_keys);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "hairs", &(int64_t){ d->hairs }, 1, 1000000, &hairs);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "joints", &(int64_t){ d->joints }, 2, 64, &joints);
    if (r == HT_OK) r = ht_json_float(c, g, "geometry", "length", &d->length, HT_JRANGE(0.0001, 10), &f->length);
    if (r == HT_OK) r = ht_json_vec3f(c, g, "geometry", "gravity", d->gravity, HT_JRANGE(-10, 10), f->gravity);
    if (r == HT_OK) r = ht_json_vec3f(c, g, "geometry", "inertia", d->inertia, HT_JRANGE(-10, 10), f->inertia);
    if (r == HT_OK) r = ht_json_float(c, g, "geometry", "width", &d->width, HT_JRANGE(0.00001, 1), &f->width);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "seed", &(int64_t){ d->seed }, 0, UINT32_MAX, &seed);
    if (r != HT_OK) return r;
    f->hairs = (int)hairs;
    f->joints = (int)joints;
    f->seed = (uint32_t)seed;
    return HT_OK;
}

static ht_result parse_patches(const ht_jctx *c, const cJSON *g, ht_patches_desc *p) {
    const ht_patches_desc *d = &patches_defaults;
    int64_t layers, strips, segments, seed;
    ht_result r = other_kind_keys(c, g, patches_keys, furball_keys,
                                  "belongs to \"type\": \"furball\", not \"patches\"");
    if (r == HT_OK)
        r = other_kind_keys(c, g, patches_keys, strands_keys, "belongs to \"type\": \"strands\", not \"patches\"");
    if (r == HT_OK) r = ht_json_keys(c, g, "geometry", patches_keys);
    if (r == HT_OK)
        r = ht_json_float(c, g, "geometry", "head_radius", &d->head_radius, HT_JRANGE(0.001, 100), &p->head_radius);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "layers", &(int64_t){ d->layers }, 1, 8, &layers);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "strips", &(int64_t){ d->strips }, 1, 1024, &strips);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "segments", &(int64_t){ d->segments }, 1, 256, &segments);
    if (r == HT_OK) r = ht_json_int(c, g, "geometry", "seed", &(int64_t){ d->seed }, 0, UINT32_MAX, &seed);
    if (r != HT_OK) return r;
    p->layers = (int)layers;
    p->strips = (int)strips;
    p->segments = (int)segments;
    p->seed = (uint32_t)seed;
    return HT_OK;
}

/* The strand file's path: the scene file's folder + rel, unless rel is
   absolute or the scene has no folder. */
static ht_result resolve_strands_path(const ht_jctx *c, const char *rel, char out[HT_LIMIT_STRANDS_PATH + 1]) {
    size_t dir_len = 0;
    if (rel[0] != '/' && c->file) {
        const char *slash = strrchr(c->file, '/');
        if (slash) dir_len = (size_t)(slash - c->file) + 1;
    }
    int n = snprintf(out, HT_LIMIT_STRANDS_PATH + 1, "%.*s%s", (int)dir_len, c->file ? c->file : "", rel);
    if (n < 0 || n > HT_LIMIT_STRANDS_PATH)
        return ht_json_fail(c, "geometry.file", "path longer than %d bytes once resolved", HT_LIMIT_STRANDS_PATH);
    return HT_OK;
}

static ht_result parse_strands(const ht_jctx *c, const cJSON *g, ht_strands_scene *st) {
    const ht_strands_ribbon_desc *d = &strands_defaults.ribbon;
    static const char *const head_keys[] = { "radius", "center", NULL };
    static const ht_jrange FILE_COORD_RANGE = { -1e7, 1e7, false, false }; /* HT_LIMIT_STRANDS_COORD */
    char rel[HT_LIMIT_STRANDS_PATH + 1];
    const cJSON *head = NULL;
    ht_strands_ribbon_desc *rb = &st->ribbon;
    ht_result r = other_kind_keys(c, g, strands_keys, furball_keys,
                                  "belongs to \"type\": \"furball\", not \"strands\"");
    if (r == HT_OK)
        r = other_kind_keys(c, g, strands_keys, patches_keys, "belongs to \"type\": \"patches\", not \"strands\"");
    if (r == HT_OK) r = ht_json_keys(c, g, "geometry", strands_keys);
    if (r == HT_OK) r = ht_json_string(c, g, "geometry", "file", NULL, rel, sizeof rel);
    if (r == HT_OK) r = resolve_strands_path(c, rel, st->file);
    if (r == HT_OK) r = ht_json_float(c, g, "geometry", "scale", &d->scale, HT_JRANGE(1e-6, 1e4), &rb->scale);
    if (r == HT_OK) r = ht_json_vec3f(c, g, "geometry", "center", d->center, FILE_COORD_RANGE, rb->center);
    if (r == HT_OK) r = ht_json_float(c, g, "geometry", "width", &d->width, HT_JRANGE(0.00001, 1), &rb->width);
    if (r == HT_OK)
        r = ht_json_float(c, g, "geometry", "tip_width", &d->tip_width, HT_JRANGE(0, 1), &rb->tip_width);
    if (r == HT_OK) r = ht_json_bool(c, g, "geometry", "thickness", &d->use_thickness, &rb->use_thickness);
    if (r == HT_OK) r = ht_json_float(c, g, "geometry", "ao", &d->ao, HT_JRANGE(0, 10), &rb->ao);
    if (r == HT_OK) r = ht_json_vec3f(c, g, "geometry", "facing", d->facing, HT_JRANGE(-1, 1), rb->facing);
    if (r == HT_OK) r = ht_json_object(c, g, "geometry", "head", false, &head);
    if (r != HT_OK) return r;
    st->head_radius = 0;
    memset(rb->head_center, 0, sizeof rb->head_center);
    if (!head) return HT_OK;
    r = ht_json_keys(c, head, "geometry.head", head_keys);
    if (r == HT_OK)
        r = ht_json_float(c, head, "geometry.head", "radius", &(float){ 0 }, HT_JRANGE(0, 100), &st->head_radius);
    if (r == HT_OK)
        r = ht_json_vec3f(c, head, "geometry.head", "center", (const float[3]){ 0, 0, 0 }, COORD_RANGE,
                          rb->head_center);
    return r;
}

static ht_result parse_geometry(const ht_jctx *c, const cJSON *root, ht_scene *s) {
    static const char *const kinds[] = { "furball", "patches", "strands", NULL };
    const cJSON *g;
    int kind = 0;
    ht_result r = ht_json_object(c, root, "", "geometry", true, &g);
    /* The type decides which keys are known, so it is read first. */
    if (r == HT_OK) r = ht_json_enum(c, g, "geometry", "type", -1, kinds, &kind);
    if (r != HT_OK) return r;
    s->geometry = kind == 2 ? HT_GEOMETRY_STRANDS : kind == 1 ? HT_GEOMETRY_PATCHES : HT_GEOMETRY_FURBALL;
    if (kind == 2) return parse_strands(c, g, &s->strands);
    return kind == 1 ? parse_patches(c, g, &s->patches) : parse_furball(c, g, &s->furball);
}

static ht_result parse_scene(const ht_jctx *c, const cJSON *root, ht_scene *s) {
    static const char *const keys[] = {
        "format", "resolution", "camera", "lights", "background", "geometry", NULL,
    };
    ht_result r = ht_json_format(c, root, SCENE_FORMAT, "scene file");
    if (r == HT_OK) r = ht_json_keys(c, root, "", keys);
    if (r == HT_OK) r = parse_resolution(c, root, s);
    if (r == HT_OK) r = parse_camera(c, root, &s->camera);
    if (r == HT_OK) r = parse_lights(c, root, s);
    if (r == HT_OK)
        r = ht_json_vec3f(c, root, "", "background", (const float[3]){ 0, 0, 0 }, HT_JRANGE(0, 1), s->background);
    if (r == HT_OK) r = parse_geometry(c, root, s);
    return r;
}

ht_result ht_scene_parse(const char *json_text, const char *file_name,
                         ht_scene *out, char *err, size_t err_size) {
    ht_jctx c = { file_name ? file_name : "<input>", err, err_size };
    cJSON *root;
    ht_result r = ht_json_parse_entry(&c, json_text, out, &root);
    if (r != HT_OK) return r;
    /* Built aside so a failed parse leaves *out untouched; the geometry not
       chosen keeps its defaults. */
    ht_scene s;
    memset(&s, 0, sizeof s);
    s.furball = furball_defaults;
    s.patches = patches_defaults;
    s.strands = strands_defaults;
    r = parse_scene(&c, root, &s);
    cJSON_Delete(root);
    if (r == HT_OK) r = ht_scene_check_budget(&s, c.file, err, err_size);
    if (r == HT_OK) {
        *out = s;
        if (err && err_size) err[0] = '\0';
    }
    return r;
}

ht_result ht_scene_load(const char *path, ht_scene *out, char *err, size_t err_size) {
    char *text;
    ht_result r = ht_json_load_entry(path, out, &text, err, err_size);
    if (r != HT_OK) return r;
    r = ht_scene_parse(text, path, out, err, err_size);
    free(text);
    return r;
}

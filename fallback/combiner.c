/* combiner.c — the fixed tier's combiner program: validation, JSON write
   and parse (cJSON). */
#include "combiner.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_check.h"

/* ---- names ---- */

typedef struct gl_name { GLenum value; const char *name; } gl_name;

static const gl_name combine_names[] = {
    { GL_REPLACE, "GL_REPLACE" },       { GL_MODULATE, "GL_MODULATE" },
    { GL_ADD, "GL_ADD" },               { GL_ADD_SIGNED, "GL_ADD_SIGNED" },
    { GL_INTERPOLATE, "GL_INTERPOLATE" }, { GL_SUBTRACT, "GL_SUBTRACT" },
    { 0, NULL },
};
static const gl_name source_names[] = {
    { GL_TEXTURE, "GL_TEXTURE" },       { GL_CONSTANT, "GL_CONSTANT" },
    { GL_PRIMARY_COLOR, "GL_PRIMARY_COLOR" }, { GL_PREVIOUS, "GL_PREVIOUS" },
    { 0, NULL },
};
static const gl_name operand_rgb_names[] = {
    { GL_SRC_COLOR, "GL_SRC_COLOR" },   { GL_ONE_MINUS_SRC_COLOR, "GL_ONE_MINUS_SRC_COLOR" },
    { GL_SRC_ALPHA, "GL_SRC_ALPHA" },   { GL_ONE_MINUS_SRC_ALPHA, "GL_ONE_MINUS_SRC_ALPHA" },
    { 0, NULL },
};
static const gl_name operand_alpha_names[] = {
    { GL_SRC_ALPHA, "GL_SRC_ALPHA" },   { GL_ONE_MINUS_SRC_ALPHA, "GL_ONE_MINUS_SRC_ALPHA" },
    { 0, NULL },
};
static const gl_name filter_names[] = {
    { GL_LINEAR, "GL_LINEAR" }, { GL_NEAREST, "GL_NEAREST" }, { 0, NULL },
};
static const gl_name wrap_names[] = {
    { GL_CLAMP_TO_EDGE, "GL_CLAMP_TO_EDGE" }, { GL_REPEAT, "GL_REPEAT" }, { 0, NULL },
};
static const gl_name target_names[] = {
    { GL_TEXTURE_2D, "2d" }, { GL_TEXTURE_3D, "3d" }, { 0, NULL },
};

static const char *name_of(const gl_name *table, GLenum value) {
    for (; table->name; table++)
        if (table->value == value) return table->name;
    return NULL;
}

static bool value_of(const gl_name *table, const char *name, GLenum *out) {
    for (; table->name; table++)
        if (strcmp(table->name, name) == 0) {
            *out = table->value;
            return true;
        }
    return false;
}

static const char *const model_names[] = { "scheuermann", "kajiya-kay" };
static const char *const coords_names[] = { "uv", "cpu-dots", "texture-matrix" };
#define COORDS_COUNT 3

static const GLenum default_source[3] = { GL_TEXTURE, GL_PREVIOUS, GL_CONSTANT };
static const GLenum default_operand_rgb[3] = { GL_SRC_COLOR, GL_SRC_COLOR, GL_SRC_ALPHA };
static const GLenum default_operand_alpha[3] = { GL_SRC_ALPHA, GL_SRC_ALPHA, GL_SRC_ALPHA };

/* How many arguments a combiner function reads. */
static int argument_count(GLenum combine) {
    switch (combine) {
    case GL_REPLACE: return 1;
    case GL_INTERPOLATE: return 3;
    default: return 2;
    }
}

/* ---- public helpers ---- */

void ht_combiner_stage_defaults(ht_combiner_stage *s, int unit) {
    memset(s, 0, sizeof *s);
    s->unit = unit;
    s->target = GL_TEXTURE_2D;
    s->filter = GL_LINEAR;
    s->wrap = GL_REPEAT;
    s->coords = HT_COORDS_UV;
    s->combine_rgb = s->combine_alpha = GL_MODULATE;
    for (int i = 0; i < 3; i++) {
        s->source_rgb[i] = s->source_alpha[i] = default_source[i];
        s->operand_rgb[i] = default_operand_rgb[i];
        s->operand_alpha[i] = default_operand_alpha[i];
    }
    s->rgb_scale = s->alpha_scale = 1;
}

double ht_combiner_lut_centre(int x, int size) {
    if (size <= 1) return 0.0;
    return 2.0 * (double)x / (double)(size - 1) - 1.0;
}

float ht_combiner_lut_coord(double d, int size) {
    if (size <= 1) return 0.5f;
    if (!(d >= -1.0)) d = -1.0; /* also NaN */
    if (d > 1.0) d = 1.0;
    return (float)((0.5 + (d + 1.0) * 0.5 * (double)(size - 1)) / (double)size);
}

ht_combiner_coords ht_combiner_lut_coords(const ht_combiner_program *p) {
    for (int i = 0; p && i < p->stage_count && i < HT_COMBINER_MAX_STAGES; i++)
        if (strcmp(p->stages[i].texture, p->lut_texture) == 0) return p->stages[i].coords;
    return HT_COORDS_UV;
}

int ht_combiner_dot_names(ht_model_kind model, const char *names[3]) {
    if (model == HT_MODEL_KAJIYA_KAY) {
        names[0] = "T.L";
        names[1] = "T.H";
        names[2] = NULL;
        return 2;
    }
    names[0] = "N.L";
    names[1] = "t1.H";
    names[2] = "t2.H";
    return 3;
}

/* ---- validation ---- */

/* ht_json_fail() for a caller's mistake rather than bad input. */
static ht_result fail_argument(const ht_jctx *c, const char *field, const char *what) {
    ht_json_fail(c, field, "%s", what);
    return HT_ERR_INVALID_ARGUMENT;
}

static bool is_scale(int s) { return s == 1 || s == 2 || s == 4; }

static bool is_pow2(int n) { return n >= 1 && (n & (n - 1)) == 0; }

static ht_result check_arguments(const ht_jctx *c, const char *stage_path, const char *what,
                                 GLenum combine, const GLenum source[3], const GLenum operand[3],
                                 const gl_name *operand_table, const GLenum default_operand[3]) {
    char field[HT_JSON_PATH_MAX];
    int used = argument_count(combine);
    for (int i = 0; i < 3; i++) {
        snprintf(field, sizeof field, "%s.source_%s[%d]", stage_path, what, i);
        if (i < used && !name_of(source_names, source[i]))
            return ht_json_fail(c, field, "0x%X is not a source ARB_texture_env_combine offers "
                        "(GL_TEXTURE, GL_CONSTANT, GL_PRIMARY_COLOR, GL_PREVIOUS)", source[i]);
        if (i >= used && source[i] != default_source[i])
            return ht_json_fail(c, field, "unused by %s, must keep GL's default %s",
                        name_of(combine_names, combine), name_of(source_names, default_source[i]));
        snprintf(field, sizeof field, "%s.operand_%s[%d]", stage_path, what, i);
        if (i < used && !name_of(operand_table, operand[i]))
            return ht_json_fail(c, field, "0x%X is not a valid %s operand", operand[i], what);
        if (i >= used && operand[i] != default_operand[i])
            return ht_json_fail(c, field, "unused by %s, must keep GL's default %s",
                        name_of(combine_names, combine), name_of(operand_rgb_names, default_operand[i]));
    }
    return HT_OK;
}

static ht_result check_stage(const ht_jctx *c, const ht_combiner_program *p, int index) {
    const ht_combiner_stage *s = &p->stages[index];
    char path[32], field[96];
    snprintf(path, sizeof path, "stages[%d]", index);
#define FIELD(name) (snprintf(field, sizeof field, "%s." name, path), field)
    if (s->unit != index)
        return ht_json_fail(c, FIELD("unit"), "%d: stage %d must be on unit %d (GL combines units in order)",
                    s->unit, index, index);
    if (!s->texture[0]) return ht_json_fail(c, FIELD("texture"), "empty texture name");
    if (!name_of(target_names, s->target)) return ht_json_fail(c, FIELD("target"), "must be 2d or 3d");
    if (!name_of(filter_names, s->filter))
        return ht_json_fail(c, FIELD("filter"), "must be GL_LINEAR or GL_NEAREST");
    if (!name_of(wrap_names, s->wrap))
        return ht_json_fail(c, FIELD("wrap"), "must be GL_CLAMP_TO_EDGE or GL_REPEAT");
    if ((unsigned)s->coords >= COORDS_COUNT)
        return ht_json_fail(c, FIELD("coords"), "unknown rule %d", (int)s->coords);
    const bool reads_lut = strcmp(s->texture, p->lut_texture) == 0;
    if (reads_lut) {
        if (s->coords == HT_COORDS_UV)
            return ht_json_fail(c, FIELD("coords"), "the LUT is indexed by cpu-dots or texture-matrix, not uv");
        if (s->coords == HT_COORDS_TEXTURE_MATRIX && p->model != HT_MODEL_KAJIYA_KAY)
            return ht_json_fail(c, FIELD("coords"), "texture-matrix needs kajiya-kay: the t1.H and t2.H of %s "
                        "need two shifted tangents, one matrix row each cannot make them",
                        model_names[p->model]);
        GLenum want = p->lut_size[2] > 1 ? GL_TEXTURE_3D : GL_TEXTURE_2D;
        if (s->target != want)
            return ht_json_fail(c, FIELD("target"), "the LUT of depth %d is %s", p->lut_size[2],
                        name_of(target_names, want));
    } else {
        if (s->coords != HT_COORDS_UV)
            return ht_json_fail(c, FIELD("coords"), "%s index the LUT \"%s\" only", coords_names[s->coords],
                        p->lut_texture);
        if (s->target != GL_TEXTURE_2D)
            return ht_json_fail(c, FIELD("target"), "textures other than the LUT are 2d");
    }
    if (!name_of(combine_names, s->combine_rgb))
        return ht_json_fail(c, FIELD("combine_rgb"), "0x%X is not a GL 1.3 combiner function", s->combine_rgb);
    if (!name_of(combine_names, s->combine_alpha))
        return ht_json_fail(c, FIELD("combine_alpha"), "0x%X is not a GL 1.3 combiner function",
                    s->combine_alpha);
    ht_result r = check_arguments(c, path, "rgb", s->combine_rgb, s->source_rgb, s->operand_rgb,
                                  operand_rgb_names, default_operand_rgb);
    if (r == HT_OK)
        r = check_arguments(c, path, "alpha", s->combine_alpha, s->source_alpha, s->operand_alpha,
                            operand_alpha_names, default_operand_alpha);
    if (r != HT_OK) return r;
    if (!is_scale(s->rgb_scale)) return ht_json_fail(c, FIELD("rgb_scale"), "%d is not 1, 2 or 4", s->rgb_scale);
    if (!is_scale(s->alpha_scale))
        return ht_json_fail(c, FIELD("alpha_scale"), "%d is not 1, 2 or 4", s->alpha_scale);
    for (int i = 0; i < 4; i++)
        if (!(s->constant[i] >= 0.0f && s->constant[i] <= 1.0f)) {
            snprintf(field, sizeof field, "%s.constant[%d]", path, i);
            return ht_json_fail(c, field, "must be in [0,1]");
        }
#undef FIELD
    return HT_OK;
}

static ht_result check_program(const ht_jctx *c, const ht_combiner_program *p) {
    if (p->model != HT_MODEL_SCHEUERMANN && p->model != HT_MODEL_KAJIYA_KAY)
        return ht_json_fail(c, "model", "unknown model %d", (int)p->model);
    if (p->light < 0 || p->light >= HT_MAX_LIGHTS)
        return ht_json_fail(c, "primary_color", "light %d is outside 0..%d", p->light, HT_MAX_LIGHTS - 1);
    for (int i = 0; i < 2; i++)
        if (!(fabs(p->shift[i]) <= 100.0)) {
            char field[32];
            snprintf(field, sizeof field, "shifts[%d]", i);
            return ht_json_fail(c, field, "must be a finite number in [-100,100]");
        }
    if (!p->lut_texture[0]) return ht_json_fail(c, "lut.texture", "empty texture name");
    for (int i = 0; i < 3; i++)
        if (!is_pow2(p->lut_size[i]) || p->lut_size[i] > HT_COMBINER_MAX_LUT_SIZE) {
            char field[32];
            snprintf(field, sizeof field, "lut.size[%d]", i);
            return ht_json_fail(c, field, "%d is not a power of two in 1..%d (GL 1.x textures)",
                        p->lut_size[i], HT_COMBINER_MAX_LUT_SIZE);
        }
    if (p->model == HT_MODEL_KAJIYA_KAY && p->lut_size[2] != 1)
        return ht_json_fail(c, "lut.size[2]", "kajiya-kay has two dot products: depth must be 1");
    if (!is_scale(p->lut_scale)) return ht_json_fail(c, "lut.scale", "%d is not 1, 2 or 4", p->lut_scale);
    if (p->stage_count < 1 || p->stage_count > HT_COMBINER_MAX_STAGES)
        return ht_json_fail(c, "stages", "%d stages, expected 1..%d", p->stage_count, HT_COMBINER_MAX_STAGES);
    bool lut_read = false;
    for (int i = 0; i < p->stage_count; i++) {
        ht_result r = check_stage(c, p, i);
        if (r != HT_OK) return r;
        lut_read = lut_read || strcmp(p->stages[i].texture, p->lut_texture) == 0;
    }
    if (!lut_read) return ht_json_fail(c, "stages", "no stage reads the LUT \"%s\"", p->lut_texture);
    return HT_OK;
}

ht_result ht_combiner_validate(const ht_combiner_program *p, char *err, size_t err_size) {
    ht_jctx c = { "program", err, err_size };
    if (!p) return fail_argument(&c, "program", "NULL");
    return check_program(&c, p);
}

/* ---- write ---- */

static cJSON *name_array(const gl_name *table, const GLenum *values, int n) {
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < n; i++) cJSON_AddItemToArray(a, cJSON_CreateString(name_of(table, values[i])));
    return a;
}

static cJSON *stage_json(const ht_combiner_stage *s) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "unit", s->unit);
    cJSON_AddStringToObject(o, "texture", s->texture);
    cJSON_AddStringToObject(o, "target", name_of(target_names, s->target));
    cJSON_AddStringToObject(o, "filter", name_of(filter_names, s->filter));
    cJSON_AddStringToObject(o, "wrap", name_of(wrap_names, s->wrap));
    cJSON_AddStringToObject(o, "coords", coords_names[s->coords]);
    int n = argument_count(s->combine_rgb);
    cJSON_AddStringToObject(o, "combine_rgb", name_of(combine_names, s->combine_rgb));
    cJSON_AddItemToObject(o, "source_rgb", name_array(source_names, s->source_rgb, n));
    cJSON_AddItemToObject(o, "operand_rgb", name_array(operand_rgb_names, s->operand_rgb, n));
    n = argument_count(s->combine_alpha);
    cJSON_AddStringToObject(o, "combine_alpha", name_of(combine_names, s->combine_alpha));
    cJSON_AddItemToObject(o, "source_alpha", name_array(source_names, s->source_alpha, n));
    cJSON_AddItemToObject(o, "operand_alpha", name_array(operand_alpha_names, s->operand_alpha, n));
    cJSON_AddNumberToObject(o, "rgb_scale", s->rgb_scale);
    cJSON_AddNumberToObject(o, "alpha_scale", s->alpha_scale);
    cJSON *k = cJSON_AddArrayToObject(o, "constant");
    for (int i = 0; i < 4; i++) cJSON_AddItemToArray(k, cJSON_CreateNumber(s->constant[i]));
    return o;
}

ht_result ht_combiner_write(const ht_combiner_program *p, char **text, char *err, size_t err_size) {
    if (!p || !text) {
        snprintf(err, err_size, "program: NULL argument");
        return HT_ERR_INVALID_ARGUMENT;
    }
    *text = NULL;
    ht_result r = ht_combiner_validate(p, err, err_size);
    if (r != HT_OK) return r;

    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "format", HT_COMBINER_FORMAT);
    cJSON_AddStringToObject(root, "model", model_names[p->model]);
    char primary[32];
    snprintf(primary, sizeof primary, p->ao ? "light%d.color*ao" : "light%d.color", p->light);
    cJSON_AddStringToObject(root, "primary_color", primary);
    const char *dots[3];
    int dot_count = ht_combiner_dot_names(p->model, dots);
    cJSON_AddItemToObject(root, "dots", cJSON_CreateStringArray(dots, dot_count));
    cJSON *shifts = cJSON_AddArrayToObject(root, "shifts");
    for (int i = 0; i < 2; i++) cJSON_AddItemToArray(shifts, cJSON_CreateNumber(p->shift[i]));
    cJSON *lut = cJSON_AddObjectToObject(root, "lut");
    cJSON_AddStringToObject(lut, "texture", p->lut_texture);
    cJSON_AddItemToObject(lut, "size", cJSON_CreateIntArray(p->lut_size, 3));
    cJSON_AddNumberToObject(lut, "scale", p->lut_scale);
    cJSON_AddStringToObject(lut, "centres", "endpoints");
    cJSON *stages = cJSON_AddArrayToObject(root, "stages");
    for (int i = 0; i < p->stage_count; i++) cJSON_AddItemToArray(stages, stage_json(&p->stages[i]));

    char *printed = cJSON_Print(root);
    cJSON_Delete(root);
    /* cJSON's allocator may be hooked; the caller free()s what we return. */
    char *copy = printed ? malloc(strlen(printed) + 2) : NULL;
    if (copy) {
        strcpy(copy, printed);
        strcat(copy, "\n");
    }
    if (printed) cJSON_free(printed);
    if (!copy) {
        snprintf(err, err_size, "program: out of memory");
        return HT_ERR_OUT_OF_MEMORY;
    }
    *text = copy;
    return HT_OK;
}

/* ---- parse ---- */

static ht_result check_keys(const ht_jctx *c, const cJSON *obj, const char *path, const char *const known[]) {
    for (const cJSON *item = obj->child; item; item = item->next) {
        bool ok = false;
        for (int i = 0; known[i]; i++) ok = ok || strcmp(item->string, known[i]) == 0;
        char field[HT_JSON_PATH_MAX];
        ht_json_path_key(field, path, item->string);
        if (!ok) return ht_json_fail(c, field, "unknown field");
        for (const cJSON *other = item->next; other; other = other->next)
            if (strcmp(other->string, item->string) == 0) return ht_json_fail(c, field, "appears twice");
    }
    return HT_OK;
}

/* The field `key` of obj, which must exist and have `type`. */
static ht_result member(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                        int type, const char *type_name, const cJSON **out) {
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, key);
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!item) return ht_json_fail(c, field, "missing");
    if ((item->type & 0xFF) != type) return ht_json_fail(c, field, "must be %s", type_name);
    *out = item;
    return HT_OK;
}

static ht_result int_item(const ht_jctx *c, const cJSON *item, const char *field, int lo, int hi, int *out) {
    if (!cJSON_IsNumber(item)) return ht_json_fail(c, field, "must be a number");
    double v = item->valuedouble;
    if (!(v >= lo && v <= hi) || v != floor(v))
        return ht_json_fail(c, field, "must be an integer in %d..%d", lo, hi);
    *out = (int)v;
    return HT_OK;
}

static ht_result get_int(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                         int lo, int hi, int *out) {
    const cJSON *item = NULL;
    ht_result r = member(c, obj, path, key, cJSON_Number, "a number", &item);
    if (r != HT_OK) return r;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, key);
    return int_item(c, item, field, lo, hi, out);
}

static ht_result get_string(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                            char *out, size_t out_size) {
    const cJSON *item = NULL;
    ht_result r = member(c, obj, path, key, cJSON_String, "a string", &item);
    if (r != HT_OK) return r;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, key);
    size_t len = strlen(item->valuestring);
    if (len == 0 || len >= out_size)
        return ht_json_fail(c, field, "must be 1..%zu characters", out_size - 1);
    memcpy(out, item->valuestring, len + 1);
    return HT_OK;
}

static ht_result get_choice(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                            const char *const names[], int count, int *out) {
    const cJSON *item = NULL;
    ht_result r = member(c, obj, path, key, cJSON_String, "a string", &item);
    if (r != HT_OK) return r;
    for (int i = 0; i < count; i++)
        if (strcmp(item->valuestring, names[i]) == 0) {
            *out = i;
            return HT_OK;
        }
    char field[HT_JSON_PATH_MAX], expected[160] = "";
    ht_json_path_key(field, path, key);
    for (int i = 0; i < count; i++)
        snprintf(expected + strlen(expected), sizeof expected - strlen(expected), "%s\"%s\"",
                 i ? ", " : "", names[i]);
    return ht_json_fail(c, field, "\"%.40s\" is unknown, expected one of %s", item->valuestring, expected);
}

static ht_result gl_item(const ht_jctx *c, const cJSON *item, const char *field, const gl_name *table,
                         const char *what, GLenum *out) {
    if (!cJSON_IsString(item)) return ht_json_fail(c, field, "must be a string naming a GL enum");
    if (value_of(table, item->valuestring, out)) return HT_OK;
    char expected[200] = "";
    for (int i = 0; table[i].name; i++)
        snprintf(expected + strlen(expected), sizeof expected - strlen(expected), "%s%s",
                 i ? ", " : "", table[i].name);
    return ht_json_fail(c, field, "\"%.40s\" is not a %s (expected %s)", item->valuestring, what, expected);
}

static ht_result get_gl(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                        const gl_name *table, const char *what, GLenum *out) {
    const cJSON *item = NULL;
    ht_result r = member(c, obj, path, key, cJSON_String, "a string naming a GL enum", &item);
    if (r != HT_OK) return r;
    char field[HT_JSON_PATH_MAX];
    ht_json_path_key(field, path, key);
    return gl_item(c, item, field, table, what, out);
}

/* source_WHAT / operand_WHAT: as many entries as the function reads. */
static ht_result get_arguments(const ht_jctx *c, const cJSON *obj, const char *path, const char *what,
                               GLenum combine, const gl_name *operand_table,
                               GLenum source[3], GLenum operand[3]) {
    char key[32], field[HT_JSON_PATH_MAX];
    const int used = argument_count(combine);
    const gl_name *tables[2] = { source_names, operand_table };
    const char *kinds[2] = { "source", "operand" };
    const char *descr[2] = { "combiner source", "combiner operand" };
    GLenum *outs[2] = { source, operand };
    for (int k = 0; k < 2; k++) {
        snprintf(key, sizeof key, "%s_%s", kinds[k], what);
        const cJSON *arr = NULL;
        ht_result r = member(c, obj, path, key, cJSON_Array, "an array", &arr);
        if (r != HT_OK) return r;
        ht_json_path_key(field, path, key);
        int n = cJSON_GetArraySize(arr);
        if (n != used)
            return ht_json_fail(c, field, "%d entries, %s reads %d", n, name_of(combine_names, combine), used);
        for (int i = 0; i < n; i++) {
            char item_field[HT_JSON_PATH_MAX];
            ht_json_path_index(item_field, field, i);
            r = gl_item(c, cJSON_GetArrayItem(arr, i), item_field, tables[k], descr[k], &outs[k][i]);
            if (r != HT_OK) return r;
        }
    }
    return HT_OK;
}

/* "lightN.color*ao" or "lightN.color". */
static bool primary_rule(const char *text, int *light, bool *ao) {
    if (strncmp(text, "light", 5) != 0) return false;
    const char *q = text + 5;
    if (!(*q >= '0' && *q <= '9')) return false;
    int n = 0;
    while (*q >= '0' && *q <= '9' && n < 1000) n = n * 10 + (*q++ - '0');
    if (strcmp(q, ".color*ao") == 0) *ao = true;
    else if (strcmp(q, ".color") == 0) *ao = false;
    else return false;
    *light = n;
    return true;
}

static ht_result parse_stage(const ht_jctx *c, const cJSON *o, int index, ht_combiner_stage *s) {
    static const char *const keys[] = {
        "unit", "texture", "target", "filter", "wrap", "coords", "combine_rgb", "source_rgb",
        "operand_rgb", "combine_alpha", "source_alpha", "operand_alpha", "rgb_scale",
        "alpha_scale", "constant", NULL,
    };
    char path[32];
    snprintf(path, sizeof path, "stages[%d]", index);
    if (!cJSON_IsObject(o)) return ht_json_fail(c, path, "must be an object");
    ht_combiner_stage_defaults(s, index);
    int coords = 0;
    ht_result r = check_keys(c, o, path, keys);
    if (r == HT_OK) r = get_int(c, o, path, "unit", 0, HT_COMBINER_MAX_STAGES - 1, &s->unit);
    if (r == HT_OK) r = get_string(c, o, path, "texture", s->texture, sizeof s->texture);
    if (r == HT_OK) r = get_gl(c, o, path, "target", target_names, "texture target", &s->target);
    if (r == HT_OK) r = get_gl(c, o, path, "filter", filter_names, "filter", &s->filter);
    if (r == HT_OK) r = get_gl(c, o, path, "wrap", wrap_names, "wrap mode", &s->wrap);
    if (r == HT_OK) r = get_choice(c, o, path, "coords", coords_names, COORDS_COUNT, &coords);
    s->coords = (ht_combiner_coords)coords;
    if (r == HT_OK)
        r = get_gl(c, o, path, "combine_rgb", combine_names, "GL 1.3 combiner function", &s->combine_rgb);
    if (r == HT_OK)
        r = get_arguments(c, o, path, "rgb", s->combine_rgb, operand_rgb_names, s->source_rgb,
                          s->operand_rgb);
    if (r == HT_OK)
        r = get_gl(c, o, path, "combine_alpha", combine_names, "GL 1.3 combiner function",
                   &s->combine_alpha);
    if (r == HT_OK)
        r = get_arguments(c, o, path, "alpha", s->combine_alpha, operand_alpha_names, s->source_alpha,
                          s->operand_alpha);
    if (r == HT_OK) r = get_int(c, o, path, "rgb_scale", 1, 4, &s->rgb_scale);
    if (r == HT_OK) r = get_int(c, o, path, "alpha_scale", 1, 4, &s->alpha_scale);
    const cJSON *k = NULL;
    if (r == HT_OK) r = member(c, o, path, "constant", cJSON_Array, "an array of 4 numbers", &k);
    if (r == HT_OK && cJSON_GetArraySize(k) != 4) {
        char field[64];
        snprintf(field, sizeof field, "%s.constant", path);
        r = ht_json_fail(c, field, "must hold 4 numbers");
    }
    for (int i = 0; r == HT_OK && i < 4; i++) {
        const cJSON *v = cJSON_GetArrayItem(k, i);
        if (!cJSON_IsNumber(v) || !(v->valuedouble >= 0.0 && v->valuedouble <= 1.0)) {
            char field[64];
            snprintf(field, sizeof field, "%s.constant[%d]", path, i);
            r = ht_json_fail(c, field, "must be a number in [0,1]");
        } else {
            s->constant[i] = (float)v->valuedouble;
        }
    }
    return r;
}

ht_result ht_combiner_parse(const char *json_text, const char *file_name, ht_combiner_program *out,
                            char *err, size_t err_size) {
    ht_jctx c = { file_name ? file_name : "<program>", err, err_size };
    if (!json_text || !out) return fail_argument(&c, "program", "NULL argument");
    memset(out, 0, sizeof *out);
    cJSON *root = cJSON_Parse(json_text);
    if (!root) {
        const char *at = cJSON_GetErrorPtr();
        int line = 1;
        for (const char *q = json_text; at && q < at && *q; q++) line += *q == '\n';
        char where[32];
        snprintf(where, sizeof where, "line %d", line);
        return ht_json_fail(&c, where, "malformed JSON near \"%.20s\"", at ? at : "");
    }
    static const char *const keys[] = { "format", "model", "primary_color", "dots", "shifts",
                                        "lut", "stages", NULL };
    static const char *const lut_keys[] = { "texture", "size", "scale", "centres", NULL };
    ht_result r = HT_OK;
    const cJSON *item = NULL;
    char text[48];
    if (!cJSON_IsObject(root)) r = ht_json_fail(&c, "(root)", "must be an object");
    if (r == HT_OK) r = check_keys(&c, root, "", keys);
    if (r == HT_OK) r = get_string(&c, root, "", "format", text, sizeof text);
    if (r == HT_OK && strcmp(text, HT_COMBINER_FORMAT) != 0)
        r = ht_json_fail(&c, "format", "\"%s\", expected \"%s\"", text, HT_COMBINER_FORMAT);
    int model = 0;
    if (r == HT_OK) r = get_choice(&c, root, "", "model", model_names, 2, &model);
    out->model = (ht_model_kind)model;

    if (r == HT_OK) r = get_string(&c, root, "", "primary_color", text, sizeof text);
    if (r == HT_OK && !primary_rule(text, &out->light, &out->ao))
        r = ht_json_fail(&c, "primary_color", "\"%s\", expected \"lightN.color*ao\" or \"lightN.color\"", text);

    const char *want[3];
    int want_count = ht_combiner_dot_names(out->model, want);
    if (r == HT_OK) r = member(&c, root, "", "dots", cJSON_Array, "an array of strings", &item);
    if (r == HT_OK) {
        bool same = cJSON_GetArraySize(item) == want_count;
        for (int i = 0; same && i < want_count; i++) {
            const cJSON *d = cJSON_GetArrayItem(item, i);
            same = cJSON_IsString(d) && strcmp(d->valuestring, want[i]) == 0;
        }
        if (!same)
            r = ht_json_fail(&c, "dots", "must be [\"%s\", \"%s\"%s%s%s] for %s", want[0], want[1],
                     want_count > 2 ? ", \"" : "", want_count > 2 ? want[2] : "",
                     want_count > 2 ? "\"" : "", model_names[out->model]);
    }
    if (r == HT_OK) r = member(&c, root, "", "shifts", cJSON_Array, "an array of 2 numbers", &item);
    if (r == HT_OK && cJSON_GetArraySize(item) != 2) r = ht_json_fail(&c, "shifts", "must hold 2 numbers");
    for (int i = 0; r == HT_OK && i < 2; i++) {
        const cJSON *v = cJSON_GetArrayItem(item, i);
        if (!cJSON_IsNumber(v) || !(fabs(v->valuedouble) <= 100.0)) {
            char field[32];
            snprintf(field, sizeof field, "shifts[%d]", i);
            r = ht_json_fail(&c, field, "must be a number in [-100,100]");
        } else {
            out->shift[i] = v->valuedouble;
        }
    }

    const cJSON *lut = NULL;
    if (r == HT_OK) r = member(&c, root, "", "lut", cJSON_Object, "an object", &lut);
    if (r == HT_OK) r = check_keys(&c, lut, "lut", lut_keys);
    if (r == HT_OK) r = get_string(&c, lut, "lut", "texture", out->lut_texture, sizeof out->lut_texture);
    if (r == HT_OK) r = member(&c, lut, "lut", "size", cJSON_Array, "an array of 3 integers", &item);
    if (r == HT_OK && cJSON_GetArraySize(item) != 3) r = ht_json_fail(&c, "lut.size", "must hold 3 integers");
    for (int i = 0; r == HT_OK && i < 3; i++) {
        char field[32];
        snprintf(field, sizeof field, "lut.size[%d]", i);
        r = int_item(&c, cJSON_GetArrayItem(item, i), field, 1, HT_COMBINER_MAX_LUT_SIZE, &out->lut_size[i]);
    }
    if (r == HT_OK) r = get_int(&c, lut, "lut", "scale", 1, 4, &out->lut_scale);
    if (r == HT_OK) r = get_string(&c, lut, "lut", "centres", text, sizeof text);
    if (r == HT_OK && strcmp(text, "endpoints") != 0)
        r = ht_json_fail(&c, "lut.centres", "\"%s\", expected \"endpoints\" (texel centres from d = -1 to d = 1)",
                 text);

    const cJSON *stages = NULL;
    if (r == HT_OK) r = member(&c, root, "", "stages", cJSON_Array, "an array", &stages);
    if (r == HT_OK) {
        int n = cJSON_GetArraySize(stages);
        if (n < 1 || n > HT_COMBINER_MAX_STAGES)
            r = ht_json_fail(&c, "stages", "%d stages, expected 1..%d", n, HT_COMBINER_MAX_STAGES);
        out->stage_count = n;
    }
    for (int i = 0; r == HT_OK && i < out->stage_count; i++)
        r = parse_stage(&c, cJSON_GetArrayItem(stages, i), i, &out->stages[i]);
    cJSON_Delete(root);
    if (r == HT_OK) r = check_program(&c, out);
    return r;
}

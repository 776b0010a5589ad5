/* combiner.c — the fixed tier's combiner program: validation, JSON write
   (cJSON) and parse (runtime/io/json_check.h's getters, so its messages read
   like every other format's). */
#include "combiner.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/ht_limits.h>
#include "json_check.h"

/* ---- names ---- */

/* A GL enum's names in the file (NULL-terminated, for ht_json_enum) and
   their values, index for index. */
enum { GL_NAMES_MAX = 6 };
typedef struct gl_names { const char *name[GL_NAMES_MAX + 1]; GLenum value[GL_NAMES_MAX]; } gl_names;

static const gl_names combine_names = {
    { "GL_REPLACE", "GL_MODULATE", "GL_ADD", "GL_ADD_SIGNED", "GL_INTERPOLATE", "GL_SUBTRACT", NULL },
    { GL_REPLACE, GL_MODULATE, GL_ADD, GL_ADD_SIGNED, GL_INTERPOLATE, GL_SUBTRACT },
};
static const gl_names source_names = {
    { "GL_TEXTURE", "GL_CONSTANT", "GL_PRIMARY_COLOR", "GL_PREVIOUS", NULL },
    { GL_TEXTURE, GL_CONSTANT, GL_PRIMARY_COLOR, GL_PREVIOUS },
};
static const gl_names operand_rgb_names = {
    { "GL_SRC_COLOR", "GL_ONE_MINUS_SRC_COLOR", "GL_SRC_ALPHA", "GL_ONE_MINUS_SRC_ALPHA", NULL },
    { GL_SRC_COLOR, GL_ONE_MINUS_SRC_COLOR, GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA },
};
static const gl_names operand_alpha_names = {
    { "GL_SRC_ALPHA", "GL_ONE_MINUS_SRC_ALPHA", NULL },
    { GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA },
};
static const gl_names filter_names = { { "GL_LINEAR", "GL_NEAREST", NULL }, { GL_LINEAR, GL_NEAREST } };
static const gl_names wrap_names = {
    { "GL_CLAMP_TO_EDGE", "GL_REPEAT", NULL }, { GL_CLAMP_TO_EDGE, GL_REPEAT },
};
static const gl_names target_names = { { "2d", "3d", NULL }, { GL_TEXTURE_2D, GL_TEXTURE_3D } };

static const char *name_of(const gl_names *table, GLenum value) {
    for (int i = 0; table->name[i]; i++)
        if (table->value[i] == value) return table->name[i];
    return NULL;
}

static const char *const model_names[] = { "scheuermann", "kajiya-kay", NULL };
static const char *const coords_names[] = { "uv", "cpu-dots", "texture-matrix", NULL };
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

bool ht_combiner_stage_scale_alpha(const ht_combiner_stage *in, float opacity, ht_combiner_stage *out) {
    if (in->combine_alpha != GL_REPLACE) return false;
    for (int a = 0; a < argument_count(in->combine_rgb); a++)
        if (in->source_rgb[a] == GL_CONSTANT &&
            (in->operand_rgb[a] == GL_SRC_ALPHA || in->operand_rgb[a] == GL_ONE_MINUS_SRC_ALPHA))
            return false;
    *out = *in;
    out->combine_alpha = GL_MODULATE;
    out->source_alpha[1] = GL_CONSTANT;
    out->operand_alpha[1] = GL_SRC_ALPHA;
    out->constant[3] = opacity;
    return true;
}

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

int ht_combiner_sub_passes(const ht_combiner_program *p) { return p ? 1 + p->add_light_count : 1; }

int ht_combiner_sub_pass_light(const ht_combiner_program *p, int sub) {
    if (!p || sub < 0 || sub > p->add_light_count) return -1;
    return sub == 0 ? p->light : p->add_lights[sub - 1];
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
                                 const gl_names *operand_table, const GLenum default_operand[3]) {
    char field[HT_JSON_PATH_MAX];
    int used = argument_count(combine);
    for (int i = 0; i < 3; i++) {
        snprintf(field, sizeof field, "%s.source_%s[%d]", stage_path, what, i);
        if (i < used && !name_of(&source_names, source[i]))
            return ht_json_fail(c, field, "0x%X is not a source ARB_texture_env_combine offers "
                        "(GL_TEXTURE, GL_CONSTANT, GL_PRIMARY_COLOR, GL_PREVIOUS)", source[i]);
        if (i >= used && source[i] != default_source[i])
            return ht_json_fail(c, field, "unused by %s, must keep GL's default %s",
                        name_of(&combine_names, combine), name_of(&source_names, default_source[i]));
        snprintf(field, sizeof field, "%s.operand_%s[%d]", stage_path, what, i);
        if (i < used && !name_of(operand_table, operand[i]))
            return ht_json_fail(c, field, "0x%X is not a valid %s operand", operand[i], what);
        if (i >= used && operand[i] != default_operand[i])
            return ht_json_fail(c, field, "unused by %s, must keep GL's default %s",
                        name_of(&combine_names, combine), name_of(&operand_rgb_names, default_operand[i]));
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
    if (!name_of(&target_names, s->target)) return ht_json_fail(c, FIELD("target"), "must be 2d or 3d");
    if (!name_of(&filter_names, s->filter))
        return ht_json_fail(c, FIELD("filter"), "must be GL_LINEAR or GL_NEAREST");
    if (!name_of(&wrap_names, s->wrap))
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
                        name_of(&target_names, want));
    } else {
        if (s->coords != HT_COORDS_UV)
            return ht_json_fail(c, FIELD("coords"), "%s index the LUT \"%s\" only", coords_names[s->coords],
                        p->lut_texture);
        if (s->target != GL_TEXTURE_2D)
            return ht_json_fail(c, FIELD("target"), "textures other than the LUT are 2d");
    }
    if (!name_of(&combine_names, s->combine_rgb))
        return ht_json_fail(c, FIELD("combine_rgb"), "0x%X is not a GL 1.3 combiner function", s->combine_rgb);
    if (!name_of(&combine_names, s->combine_alpha))
        return ht_json_fail(c, FIELD("combine_alpha"), "0x%X is not a GL 1.3 combiner function",
                    s->combine_alpha);
    ht_result r = check_arguments(c, path, "rgb", s->combine_rgb, s->source_rgb, s->operand_rgb,
                                  &operand_rgb_names, default_operand_rgb);
    if (r == HT_OK)
        r = check_arguments(c, path, "alpha", s->combine_alpha, s->source_alpha, s->operand_alpha,
                            &operand_alpha_names, default_operand_alpha);
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
    if (p->add_light_count < 0 || p->add_light_count > HT_MAX_LIGHTS - 1)
        return ht_json_fail(c, "add_lights", "%d lights, expected 0..%d", p->add_light_count, HT_MAX_LIGHTS - 1);
    for (int i = 0; i < p->add_light_count; i++) {
        char field[32];
        snprintf(field, sizeof field, "add_lights[%d]", i);
        const int l = p->add_lights[i];
        if (l < 0 || l >= HT_MAX_LIGHTS)
            return ht_json_fail(c, field, "light %d is outside 0..%d", l, HT_MAX_LIGHTS - 1);
        if (l == p->light) return ht_json_fail(c, field, "light %d is the key light (primary_color)", l);
        for (int j = 0; j < i; j++)
            if (p->add_lights[j] == l) return ht_json_fail(c, field, "light %d is listed twice", l);
    }
    if (!(p->light_scale >= 1.0 && p->light_scale <= 4.0))
        return ht_json_fail(c, "lut.light_scale", "must be a number in [1,4]");
    for (int i = 0; i < 2; i++)
        if (!(fabs(p->shift[i]) <= HT_LIMIT_SHIFT)) {
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

static cJSON *name_array(const gl_names *table, const GLenum *values, int n) {
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; i < n; i++) cJSON_AddItemToArray(a, cJSON_CreateString(name_of(table, values[i])));
    return a;
}

static cJSON *stage_json(const ht_combiner_stage *s) {
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "unit", s->unit);
    cJSON_AddStringToObject(o, "texture", s->texture);
    cJSON_AddStringToObject(o, "target", name_of(&target_names, s->target));
    cJSON_AddStringToObject(o, "filter", name_of(&filter_names, s->filter));
    cJSON_AddStringToObject(o, "wrap", name_of(&wrap_names, s->wrap));
    cJSON_AddStringToObject(o, "coords", coords_names[s->coords]);
    int n = argument_count(s->combine_rgb);
    cJSON_AddStringToObject(o, "combine_rgb", name_of(&combine_names, s->combine_rgb));
    cJSON_AddItemToObject(o, "source_rgb", name_array(&source_names, s->source_rgb, n));
    cJSON_AddItemToObject(o, "operand_rgb", name_array(&operand_rgb_names, s->operand_rgb, n));
    n = argument_count(s->combine_alpha);
    cJSON_AddStringToObject(o, "combine_alpha", name_of(&combine_names, s->combine_alpha));
    cJSON_AddItemToObject(o, "source_alpha", name_array(&source_names, s->source_alpha, n));
    cJSON_AddItemToObject(o, "operand_alpha", name_array(&operand_alpha_names, s->operand_alpha, n));
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
    cJSON_AddItemToObject(root, "add_lights", cJSON_CreateIntArray(p->add_lights, p->add_light_count));
    const char *dots[3];
    int dot_count = ht_combiner_dot_names(p->model, dots);
    cJSON_AddItemToObject(root, "dots", cJSON_CreateStringArray(dots, dot_count));
    cJSON *shifts = cJSON_AddArrayToObject(root, "shifts");
    for (int i = 0; i < 2; i++) cJSON_AddItemToArray(shifts, cJSON_CreateNumber(p->shift[i]));
    cJSON *lut = cJSON_AddObjectToObject(root, "lut");
    cJSON_AddStringToObject(lut, "texture", p->lut_texture);
    cJSON_AddItemToObject(lut, "size", cJSON_CreateIntArray(p->lut_size, 3));
    cJSON_AddNumberToObject(lut, "scale", p->lut_scale);
    cJSON_AddNumberToObject(lut, "light_scale", p->light_scale);
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

/* A GL enum named in the file: the array element `item` at `field`, or the
   field `key` of obj. */
static ht_result gl_item(const ht_jctx *c, const cJSON *item, const char *field, const gl_names *table,
                         GLenum *out) {
    int i = 0;
    ht_result r = ht_json_enum_item(c, item, field, table->name, &i);
    if (r == HT_OK) *out = table->value[i];
    return r;
}

static ht_result get_gl(const ht_jctx *c, const cJSON *obj, const char *path, const char *key,
                        const gl_names *table, GLenum *out) {
    int i = 0;
    ht_result r = ht_json_enum(c, obj, path, key, -1, table->name, &i);
    if (r == HT_OK) *out = table->value[i];
    return r;
}

/* source_WHAT / operand_WHAT: as many entries as the function reads. */
static ht_result get_arguments(const ht_jctx *c, const cJSON *obj, const char *path, const char *what,
                               GLenum combine, const gl_names *operand_table,
                               GLenum source[3], GLenum operand[3]) {
    char key[32], field[HT_JSON_PATH_MAX], item_field[HT_JSON_PATH_MAX];
    const int used = argument_count(combine);
    const gl_names *tables[2] = { &source_names, operand_table };
    const char *kinds[2] = { "source", "operand" };
    GLenum *outs[2] = { source, operand };
    for (int k = 0; k < 2; k++) {
        snprintf(key, sizeof key, "%s_%s", kinds[k], what);
        ht_json_path_key(field, path, key);
        const cJSON *arr = NULL;
        int n = 0;
        ht_result r = ht_json_array(c, obj, path, key, true, 0, 3, &arr, &n);
        if (r != HT_OK) return r;
        if (n != used)
            return ht_json_fail(c, field, "%d entries, %s reads %d", n, name_of(&combine_names, combine), used);
        for (int i = 0; i < n; i++) {
            ht_json_path_index(item_field, field, i);
            r = gl_item(c, cJSON_GetArrayItem(arr, i), item_field, tables[k], &outs[k][i]);
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
    char path[HT_JSON_PATH_MAX];
    ht_json_path_index(path, "stages", index);
    ht_combiner_stage_defaults(s, index);
    int coords = 0;
    double constant[4] = { 0 };
    ht_result r = ht_json_keys(c, o, path, keys);
    if (r == HT_OK) r = ht_json_int32(c, o, path, "unit", NULL, 0, HT_COMBINER_MAX_STAGES - 1, &s->unit);
    if (r == HT_OK) r = ht_json_string(c, o, path, "texture", NULL, s->texture, sizeof s->texture);
    if (r == HT_OK) r = get_gl(c, o, path, "target", &target_names, &s->target);
    if (r == HT_OK) r = get_gl(c, o, path, "filter", &filter_names, &s->filter);
    if (r == HT_OK) r = get_gl(c, o, path, "wrap", &wrap_names, &s->wrap);
    if (r == HT_OK) r = ht_json_enum(c, o, path, "coords", -1, coords_names, &coords);
    s->coords = (ht_combiner_coords)coords;
    if (r == HT_OK) r = get_gl(c, o, path, "combine_rgb", &combine_names, &s->combine_rgb);
    if (r == HT_OK)
        r = get_arguments(c, o, path, "rgb", s->combine_rgb, &operand_rgb_names, s->source_rgb,
                          s->operand_rgb);
    if (r == HT_OK) r = get_gl(c, o, path, "combine_alpha", &combine_names, &s->combine_alpha);
    if (r == HT_OK)
        r = get_arguments(c, o, path, "alpha", s->combine_alpha, &operand_alpha_names, s->source_alpha,
                          s->operand_alpha);
    if (r == HT_OK) r = ht_json_int32(c, o, path, "rgb_scale", NULL, 1, 4, &s->rgb_scale);
    if (r == HT_OK) r = ht_json_int32(c, o, path, "alpha_scale", NULL, 1, 4, &s->alpha_scale);
    if (r == HT_OK) r = ht_json_vec(c, o, path, "constant", NULL, 4, HT_JRANGE(0, 1), constant);
    for (int i = 0; i < 4; i++) s->constant[i] = (float)constant[i];
    return r;
}

ht_result ht_combiner_parse(const char *json_text, const char *file_name, ht_combiner_program *out,
                            char *err, size_t err_size) {
    static const char *const keys[] = { "format", "model", "primary_color", "add_lights", "dots", "shifts",
                                        "lut", "stages", NULL };
    static const char *const lut_keys[] = { "texture", "size", "scale", "light_scale", "centres", NULL };
    ht_jctx c = { file_name ? file_name : "<program>", err, err_size };
    cJSON *root = NULL;
    ht_result r = ht_json_parse_entry(&c, json_text, out, &root);
    if (r != HT_OK) return r;
    memset(out, 0, sizeof *out);
    const cJSON *item = NULL, *lut = NULL, *stages = NULL;
    int model = 0, n = 0;
    char text[48];
    r = ht_json_keys(&c, root, "", keys);
    if (r == HT_OK) r = ht_json_format(&c, root, HT_COMBINER_FORMAT, "combiner program");
    if (r == HT_OK) r = ht_json_enum(&c, root, "", "model", -1, model_names, &model);
    out->model = (ht_model_kind)model;

    if (r == HT_OK) r = ht_json_string(&c, root, "", "primary_color", NULL, text, sizeof text);
    if (r == HT_OK && !primary_rule(text, &out->light, &out->ao))
        r = ht_json_fail(&c, "primary_color", "\"%s\", expected \"lightN.color*ao\" or \"lightN.color\"", text);

    /* optional (programs written before sub-passes): none */
    if (r == HT_OK) r = ht_json_array(&c, root, "", "add_lights", false, 0, HT_MAX_LIGHTS - 1, &item, &n);
    if (r == HT_OK) out->add_light_count = item ? n : 0;
    for (int i = 0; r == HT_OK && i < out->add_light_count; i++) {
        char field[HT_JSON_PATH_MAX];
        int64_t light = 0;
        ht_json_path_index(field, "add_lights", i);
        r = ht_json_int_item(&c, cJSON_GetArrayItem(item, i), field, 0, HT_MAX_LIGHTS - 1, &light);
        out->add_lights[i] = (int)light;
    }

    const char *want[3];
    int want_count = ht_combiner_dot_names(out->model, want);
    if (r == HT_OK) r = ht_json_array(&c, root, "", "dots", true, 0, 3, &item, &n);
    if (r == HT_OK) {
        bool same = n == want_count;
        for (int i = 0; same && i < want_count; i++) {
            const cJSON *d = cJSON_GetArrayItem(item, i);
            same = cJSON_IsString(d) && strcmp(d->valuestring, want[i]) == 0;
        }
        if (!same)
            r = ht_json_fail(&c, "dots", "must be [\"%s\", \"%s\"%s%s%s] for %s", want[0], want[1],
                     want_count > 2 ? ", \"" : "", want_count > 2 ? want[2] : "",
                     want_count > 2 ? "\"" : "", model_names[out->model]);
    }
    if (r == HT_OK) r = ht_json_vec(&c, root, "", "shifts", NULL, 2, HT_JRANGE(-HT_LIMIT_SHIFT, HT_LIMIT_SHIFT), out->shift);

    if (r == HT_OK) r = ht_json_object(&c, root, "", "lut", true, &lut);
    if (r == HT_OK) r = ht_json_keys(&c, lut, "lut", lut_keys);
    if (r == HT_OK) r = ht_json_string(&c, lut, "lut", "texture", NULL, out->lut_texture, sizeof out->lut_texture);
    if (r == HT_OK) r = ht_json_array(&c, lut, "lut", "size", true, 3, 3, &item, &n);
    for (int i = 0; r == HT_OK && i < 3; i++) {
        char field[HT_JSON_PATH_MAX];
        int64_t size = 0;
        ht_json_path_index(field, "lut.size", i);
        r = ht_json_int_item(&c, cJSON_GetArrayItem(item, i), field, 1, HT_COMBINER_MAX_LUT_SIZE, &size);
        out->lut_size[i] = (int)size;
    }
    if (r == HT_OK) r = ht_json_int32(&c, lut, "lut", "scale", NULL, 1, 4, &out->lut_scale);
    /* optional (programs written before it): light colours up to 1 */
    const double unit_light = 1.0;
    if (r == HT_OK) r = ht_json_number(&c, lut, "lut", "light_scale", &unit_light, HT_JRANGE(1, 4), &out->light_scale);
    if (r == HT_OK) r = ht_json_string(&c, lut, "lut", "centres", NULL, text, sizeof text);
    if (r == HT_OK && strcmp(text, "endpoints") != 0)
        r = ht_json_fail(&c, "lut.centres", "\"%s\", expected \"endpoints\" (texel centres from d = -1 to d = 1)",
                 text);

    if (r == HT_OK) r = ht_json_array(&c, root, "", "stages", true, 1, HT_COMBINER_MAX_STAGES, &stages, &n);
    if (r == HT_OK) out->stage_count = n;
    for (int i = 0; r == HT_OK && i < out->stage_count; i++)
        r = parse_stage(&c, cJSON_GetArrayItem(stages, i), i, &out->stages[i]);
    cJSON_Delete(root);
    if (r == HT_OK) r = check_program(&c, out);
    return r;
}

/* support_combiner_eval.c — the combiner program's CPU emulator (see
   support_combiner_eval.h). */
#include "support_combiner_eval.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_check.h"

/* ht_json_fail() for a caller's mistake rather than bad input. */
static ht_result fail_argument(const ht_jctx *c, const char *field, const char *what) {
    ht_json_fail(c, field, "%s", what);
    return HT_ERR_INVALID_ARGUMENT;
}

/* ---- CPU emulation ---- */

typedef struct rgba { float v[4]; } rgba;

static float clamp01(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

/* Texel index along an axis of n after wrapping. */
static int wrap_index(int i, int n, GLenum wrap) {
    if (wrap == GL_REPEAT) {
        i %= n;
        return i < 0 ? i + n : i;
    }
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

static rgba texel(const ht_image *img, int x, int y) {
    const uint8_t *p = img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
    rgba c;
    switch (img->channels) {
    case 1: c = (rgba){ { p[0], p[0], p[0], 255 } }; break;
    case 2: c = (rgba){ { p[0], p[0], p[0], p[1] } }; break;
    case 3: c = (rgba){ { p[0], p[1], p[2], 255 } }; break;
    default: c = (rgba){ { p[0], p[1], p[2], p[3] } }; break;
    }
    for (int i = 0; i < 4; i++) c.v[i] /= 255.0f;
    return c;
}

/* Texels and weights along one axis for coordinate s. */
static void axis_taps(float s, int n, GLenum filter, GLenum wrap, int idx[2], float w[2]) {
    if (!isfinite(s)) s = 0.0f;
    if (filter == GL_NEAREST) {
        idx[0] = idx[1] = wrap_index((int)floorf(s * (float)n), n, wrap);
        w[0] = 1.0f;
        w[1] = 0.0f;
        return;
    }
    float u = s * (float)n - 0.5f;
    float i0 = floorf(u);
    w[1] = u - i0;
    w[0] = 1.0f - w[1];
    idx[0] = wrap_index((int)i0, n, wrap);
    idx[1] = wrap_index((int)i0 + 1, n, wrap);
}

static rgba sample(const ht_combiner_stage *s, const ht_image *img, int depth, const float coord[3]) {
    const int dims[3] = { img->width, img->height / depth, depth };
    const int axes = s->target == GL_TEXTURE_3D ? 3 : 2;
    int idx[3][2] = { { 0, 0 }, { 0, 0 }, { 0, 0 } };
    float w[3][2] = { { 1, 0 }, { 1, 0 }, { 1, 0 } };
    for (int a = 0; a < axes; a++) axis_taps(coord[a], dims[a], s->filter, s->wrap, idx[a], w[a]);
    rgba out = { { 0, 0, 0, 0 } };
    for (int k = 0; k < 8; k++) {
        float weight = w[0][k & 1] * w[1][(k >> 1) & 1] * w[2][(k >> 2) & 1];
        if (weight == 0.0f) continue;
        int z = idx[2][(k >> 2) & 1];
        rgba t = texel(img, idx[0][k & 1], z * dims[1] + idx[1][(k >> 1) & 1]);
        for (int i = 0; i < 4; i++) out.v[i] += weight * t.v[i];
    }
    return out;
}

static float combine(GLenum fn, const float arg[3]) {
    switch (fn) {
    case GL_REPLACE: return arg[0];
    case GL_MODULATE: return arg[0] * arg[1];
    case GL_ADD: return arg[0] + arg[1];
    case GL_ADD_SIGNED: return arg[0] + arg[1] - 0.5f;
    case GL_INTERPOLATE: return arg[0] * arg[2] + arg[1] * (1.0f - arg[2]);
    case GL_SUBTRACT: return arg[0] - arg[1];
    }
    return 0.0f;
}

static const rgba *source(GLenum src, const rgba *tex, const rgba *constant, const rgba *primary,
                          const rgba *previous) {
    switch (src) {
    case GL_TEXTURE: return tex;
    case GL_CONSTANT: return constant;
    case GL_PRIMARY_COLOR: return primary;
    default: return previous;
    }
}

static const ht_combiner_texture *find_texture(const ht_combiner_texture *t, int n, const char *name) {
    for (int i = 0; i < n; i++)
        if (t[i].name && strcmp(t[i].name, name) == 0) return &t[i];
    return NULL;
}

static ht_result check_texture(const ht_jctx *c, const ht_combiner_program *p, int stage,
                               const ht_combiner_texture *t) {
    const ht_combiner_stage *s = &p->stages[stage];
    char field[48];
    snprintf(field, sizeof field, "stages[%d].texture", stage);
    char what[160];
    if (!t) {
        snprintf(what, sizeof what, "texture \"%s\" was not supplied", s->texture);
        return fail_argument(c, field, what);
    }
    const ht_image *img = t->image;
    if (!img || !img->pixels || img->width < 1 || img->channels < 1 || img->channels > 4 ||
        t->depth < 1 || img->height < t->depth || img->height % t->depth != 0) {
        snprintf(what, sizeof what, "texture \"%s\" is empty or not a stack of %d slices",
                 s->texture, t->depth);
        return fail_argument(c, field, what);
    }
    if (strcmp(s->texture, p->lut_texture) == 0 &&
        (img->width != p->lut_size[0] || img->height / t->depth != p->lut_size[1] ||
         t->depth != p->lut_size[2])) {
        snprintf(what, sizeof what, "LUT image is %dx%dx%d, the program says %dx%dx%d", img->width,
                 img->height / t->depth, t->depth, p->lut_size[0], p->lut_size[1], p->lut_size[2]);
        return fail_argument(c, field, what);
    }
    return HT_OK;
}

/* GL's texture-coordinate transform: (s,t,r,q) = M (T,1), then the divide
   by q. False when q is not positive or a coordinate is not finite. */
static bool texture_matrix_coord(const float m[16], const float T[3], float out[3]) {
    const float in[4] = { T[0], T[1], T[2], 1.0f };
    float v[4];
    for (int row = 0; row < 4; row++)
        v[row] = m[row] * in[0] + m[4 + row] * in[1] + m[8 + row] * in[2] + m[12 + row] * in[3];
    if (!(v[3] > 0.0f) || !isfinite(v[3])) return false;
    for (int i = 0; i < 3; i++) {
        out[i] = v[i] / v[3];
        if (!isfinite(out[i])) return false;
    }
    return true;
}

ht_result ht_combiner_eval(const ht_combiner_program *p, const ht_combiner_texture *textures,
                           int texture_count, const ht_combiner_fragment *frag, float out[4],
                           char *err, size_t err_size) {
    ht_jctx c = { "combiner", err, err_size };
    if (!p || !frag || !out || (texture_count > 0 && !textures))
        return fail_argument(&c, "eval", "NULL argument");
    rgba primary, previous;
    for (int i = 0; i < 4; i++) primary.v[i] = clamp01(isfinite(frag->primary[i]) ? frag->primary[i] : 0.0f);
    previous = primary;
    for (int si = 0; si < p->stage_count; si++) {
        const ht_combiner_stage *s = &p->stages[si];
        const ht_combiner_texture *t = find_texture(textures, texture_count, s->texture);
        ht_result r = check_texture(&c, p, si, t);
        if (r != HT_OK) return r;
        float coord[3] = { frag->uv[0], frag->uv[1], 0.0f };
        if (s->coords == HT_COORDS_CPU_DOTS) {
            memcpy(coord, frag->lut_coord, sizeof coord);
        } else if (s->coords == HT_COORDS_TEXTURE_MATRIX &&
                   !texture_matrix_coord(frag->texture_matrix, frag->tangent, coord)) {
            char field[48];
            snprintf(field, sizeof field, "stages[%d].coords", si);
            return fail_argument(&c, field, "the texture matrix gives q <= 0 or a non-finite coordinate");
        }
        rgba tex = sample(s, t->image, t->depth, coord);
        rgba constant = { { s->constant[0], s->constant[1], s->constant[2], s->constant[3] } };
        rgba next;
        for (int ch = 0; ch < 3; ch++) {
            float arg[3];
            for (int a = 0; a < 3; a++) {
                const rgba *src = source(s->source_rgb[a], &tex, &constant, &primary, &previous);
                switch (s->operand_rgb[a]) {
                case GL_SRC_COLOR: arg[a] = src->v[ch]; break;
                case GL_ONE_MINUS_SRC_COLOR: arg[a] = 1.0f - src->v[ch]; break;
                case GL_SRC_ALPHA: arg[a] = src->v[3]; break;
                default: arg[a] = 1.0f - src->v[3]; break;
                }
            }
            next.v[ch] = clamp01(combine(s->combine_rgb, arg) * (float)s->rgb_scale);
        }
        float arg[3];
        for (int a = 0; a < 3; a++) {
            const rgba *src = source(s->source_alpha[a], &tex, &constant, &primary, &previous);
            arg[a] = s->operand_alpha[a] == GL_SRC_ALPHA ? src->v[3] : 1.0f - src->v[3];
        }
        next.v[3] = clamp01(combine(s->combine_alpha, arg) * (float)s->alpha_scale);
        previous = next;
    }
    for (int i = 0; i < 4; i++) out[i] = previous.v[i];
    return HT_OK;
}

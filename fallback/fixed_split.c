/* fixed_split.c — see fixed_split.h. */
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "fixed_split.h"

int ht_fixed_split_lut_stage(const ht_combiner_program *p) {
    for (int i = 0; i < p->stage_count; i++)
        if (p->stages[i].target == GL_TEXTURE_3D) return i;
    return -1;
}

static bool colour_operand(GLenum op) { return op == GL_SRC_COLOR || op == GL_ONE_MINUS_SRC_COLOR; }

ht_result ht_fixed_split_program(ht_combiner_program *p, int k, char *err, size_t err_size) {
    const ht_combiner_stage lut = p->stages[k];
    for (int a = 0; a < 3; a++)
        if (lut.source_rgb[a] == GL_PREVIOUS)
            return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "LUT stage %d reads the previous stage's colour: no "
                           "room for the 2D split of its 3D LUT (no 3D textures)", k);
    if (p->stage_count + 2 > HT_COMBINER_MAX_STAGES)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "%d stages and 2 more for the 2D split of the 3D LUT "
                       "(no 3D textures) exceed %d", p->stage_count, HT_COMBINER_MAX_STAGES);
    ht_combiner_program out = *p;
    out.stage_count = p->stage_count + 2;
    for (int i = k + 1; i < p->stage_count; i++) {
        out.stages[i + 2] = p->stages[i];
        out.stages[i + 2].unit = i + 2;
    }
    ht_combiner_stage *c = &out.stages[k], *a = &out.stages[k + 1], *sum = &out.stages[k + 2];
    for (int i = 0; i < 2; i++) {
        ht_combiner_stage *st = i == 0 ? c : a;
        ht_combiner_stage_defaults(st, k + i);
        memcpy(st->texture, lut.texture, sizeof st->texture);
        st->target = GL_TEXTURE_2D;
        st->filter = lut.filter;
        st->wrap = GL_CLAMP_TO_EDGE;
        st->coords = lut.coords;
        st->combine_rgb = i == 0 ? GL_REPLACE : GL_ADD;
        st->source_rgb[0] = GL_TEXTURE;
        st->source_rgb[1] = GL_PREVIOUS;
        st->combine_alpha = GL_REPLACE;
        st->source_alpha[0] = GL_PREVIOUS;
    }
    *sum = lut;
    sum->unit = k + 2;
    sum->target = GL_TEXTURE_2D;
    sum->texture[0] = '\0'; /* the white texel */
    for (int i = 0; i < 3; i++)
        if (sum->source_rgb[i] == GL_TEXTURE && colour_operand(sum->operand_rgb[i])) sum->source_rgb[i] = GL_PREVIOUS;
    *p = out;
    return HT_OK;
}

ht_result ht_fixed_split_lut(const int n[3], const ht_image *lut3d, ht_image *a, ht_image *c, int *max_error) {
    *a = *c = (ht_image){ 0 };
    if (!lut3d || lut3d->width != n[0] || lut3d->height != n[1] * n[2] || lut3d->channels < 3)
        return HT_ERR_INVALID_ARGUMENT;
    ht_result r = ht_image_alloc(a, n[0], n[1], 3);
    if (r == HT_OK) r = ht_image_alloc(c, n[2], 1, 3);
    if (r != HT_OK) {
        ht_image_free(a);
        return r;
    }
    const size_t ch = (size_t)lut3d->channels, slice = (size_t)n[0] * (size_t)n[1];
    for (size_t i = 0; i < slice; i++)
        for (int k = 0; k < 3; k++) a->pixels[i * 3 + (size_t)k] = lut3d->pixels[i * ch + (size_t)k];
    for (int z = 0; z < n[2]; z++)
        for (int k = 0; k < 3; k++) {
            long sum = 0, count = 0;
            for (size_t i = 0; i < slice; i++) {
                const int v = lut3d->pixels[((size_t)z * slice + i) * ch + (size_t)k];
                if (v == 255) continue; /* clipped by the 8-bit range: not L - A */
                sum += v - a->pixels[i * 3 + (size_t)k];
                count++;
            }
            long mean = count ? (2 * sum + count) / (2 * count) : 0;
            c->pixels[(size_t)z * 3 + (size_t)k] = (uint8_t)(mean < 0 ? 0 : mean > 255 ? 255 : mean);
        }
    int worst = 0;
    for (int z = 0; z < n[2]; z++)
        for (size_t i = 0; i < slice; i++)
            for (int k = 0; k < 3; k++) {
                int sum = a->pixels[i * 3 + (size_t)k] + c->pixels[(size_t)z * 3 + (size_t)k];
                int e = abs((sum > 255 ? 255 : sum) - lut3d->pixels[((size_t)z * slice + i) * ch + (size_t)k]);
                if (e > worst) worst = e;
            }
    *max_error = worst;
    return HT_OK;
}

void ht_fixed_split_matrix(float m[16]) {
    memset(m, 0, 16 * sizeof *m);
    m[8] = 1.0f;   /* s' = r */
    m[13] = 0.5f;  /* t' = q / 2 */
    m[15] = 1.0f;  /* q' = q */
}

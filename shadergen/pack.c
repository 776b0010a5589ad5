/* pack.c — the material's textures packed into the two RGBA images the GLSL
   tiers sample (docs/bundle.md):
     albedo = base.r base.g base.b alpha   (base 255 and alpha 255 when absent)
     detail = shift sparkle 0 255          (shift 128 and sparkle 255 when absent)
   An image exists iff the plan models one of its sources.

   Two sources of different sizes pack at the larger width and the larger
   height, the smaller one resampled nearest-neighbour at texel centres. When
   the sizes agree that is a texel-exact copy, which the LUT and texel tests
   rely on; filtering would change texels even then. */
#include "emit.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "manifest.h"

/* The runtime refuses a bundle texture over manifest.h's limits, so the
   generator refuses it first, naming the material field(s) it came from,
   and before allocating (two thin sources can pack into a huge image). */
static ht_result check_size(const ht_material *m, const char *fields, const char *what,
                            int w, int h, char *err, size_t err_size) {
    const char *file = m->file[0] ? m->file : "<material>";
    if (w > HT_MANIFEST_MAX_TEXTURE_SIZE || h > HT_MANIFEST_MAX_TEXTURE_SIZE) {
        ht_set_error(err, err_size, "%s: %s: %s %dx%d texels; a bundle texture has at most %d per side",
                     file, fields, what, w, h, HT_MANIFEST_MAX_TEXTURE_SIZE);
        return HT_ERR_UNSUPPORTED;
    }
    if ((uint64_t)w * (uint64_t)h > HT_MANIFEST_MAX_TEXTURE_PIXELS) {
        ht_set_error(err, err_size, "%s: %s: %s %dx%d texels; a bundle texture has at most %u in all",
                     file, fields, what, w, h, (unsigned)HT_MANIFEST_MAX_TEXTURE_PIXELS);
        return HT_ERR_UNSUPPORTED;
    }
    return HT_OK;
}

/* The size pack_two() makes from a and b: the larger of each side. */
static void packed_size(const ht_image *a, const ht_image *b, int *w, int *h) {
    *w = a->pixels ? a->width : 0;
    *h = a->pixels ? a->height : 0;
    if (b->pixels && b->width > *w) *w = b->width;
    if (b->pixels && b->height > *h) *h = b->height;
}

/* The index along a source side of src_n texels nearest to the centre of
   texel i of a side of n texels. */
static int nearest_index(int i, int src_n, int n) {
    return (int)(((int64_t)2 * i + 1) * src_n / (2 * (int64_t)n));
}

/* For each column x of a w-wide image, the offset of src's nearest column
   (in bytes): computed once per column, not twice per texel (the 64-bit
   divisions made packing 5% of one material's instructions). */
static size_t *column_offsets(const ht_image *src, int w) {
    size_t *at = malloc((size_t)w * sizeof *at);
    for (int x = 0; at && x < w; x++) at[x] = (size_t)nearest_index(x, src->width, w) * (size_t)src->channels;
    return at;
}

/* Packs up to two sources into RGBA. a fills channels [0, a_channels) from
   a's channels, b fills channel b_at; missing sources leave `fill`. */
static ht_result pack_two(const ht_image *a, int a_channels, const ht_image *b, int b_at,
                          const uint8_t fill[4], ht_image *out) {
    int w = 0, h = 0;
    if (a->pixels) { w = a->width; h = a->height; }
    if (b->pixels) {
        if (b->width > w) w = b->width;
        if (b->height > h) h = b->height;
    }
    ht_result r = ht_image_alloc(out, w, h, 4);
    if (r != HT_OK) return r;
    size_t *a_at = a->pixels ? column_offsets(a, w) : NULL, *b_at_x = b->pixels ? column_offsets(b, w) : NULL;
    if ((a->pixels && !a_at) || (b->pixels && !b_at_x)) {
        free(a_at);
        free(b_at_x);
        ht_image_free(out);
        return HT_ERR_OUT_OF_MEMORY;
    }
    for (int y = 0; y < h; y++) {
        const uint8_t *a_row = a->pixels ? a->pixels + (size_t)nearest_index(y, a->height, h) * a->width * a->channels
                                         : NULL;
        const uint8_t *b_row = b->pixels ? b->pixels + (size_t)nearest_index(y, b->height, h) * b->width * b->channels
                                         : NULL;
        uint8_t *px = out->pixels + 4 * (size_t)y * w;
        for (int x = 0; x < w; x++) memcpy(px + 4 * x, fill, 4);
        if (a_row && a_channels == 3)
            for (int x = 0; x < w; x++) memcpy(px + 4 * x, a_row + a_at[x], 3);
        else if (a_row)
            for (int x = 0; x < w; x++)
                for (int c = 0; c < a_channels; c++) px[4 * x + c] = a_row[a_at[x] + c];
        if (b_row)
            for (int x = 0; x < w; x++) px[4 * x + b_at] = b_row[b_at_x[x]];
    }
    free(a_at);
    free(b_at_x);
    return HT_OK;
}

static bool modelled(const ht_plan *plan, ht_texture_slot slot) {
    const bool modelled[HT_TEX_COUNT] = { plan->base, plan->alpha, plan->shift, plan->sparkle };
    return slot >= 0 && slot < HT_TEX_COUNT && modelled[slot];
}

ht_result ht_texture_make_slot(const ht_material *m, const ht_plan *plan, ht_texture_slot slot, ht_image *img,
                               char *err, size_t err_size) {
    static const char *const slots[HT_TEX_COUNT] = { "base", "alpha", "shift", "sparkle" };
    *img = (ht_image){ 0 };
    if (!modelled(plan, slot)) return HT_OK;
    char why[1200];
    ht_result r = ht_texture_make(&m->textures[slot], slot, img, why, sizeof why);
    if (r == HT_OK) return HT_OK;
    /* A file's error names the PNG; say which material field named it. */
    if (m->textures[slot].origin == HT_TEXTURE_FILE)
        ht_set_error(err, err_size, "%s: textures.%s.file: %s", m->file[0] ? m->file : "<material>", slots[slot],
                     why);
    else
        ht_set_error(err, err_size, "%s", why);
    return r;
}

ht_result ht_textures_pack_made(const ht_material *m, const ht_plan *plan, ht_image made[HT_TEX_COUNT],
                                ht_image *albedo, ht_image *detail, char *err, size_t err_size) {
    *albedo = (ht_image){ 0 };
    *detail = (ht_image){ 0 };
    ht_image *base = &made[HT_TEX_BASE], *alpha = &made[HT_TEX_ALPHA];
    ht_image *shift = &made[HT_TEX_SHIFT], *sparkle = &made[HT_TEX_SPARKLE];
    static const char *const sources[HT_TEX_COUNT] = {
        "textures.base", "textures.alpha", "textures.shift", "textures.sparkle",
    };
    ht_result r = HT_OK;
    for (int i = 0; i < HT_TEX_COUNT && r == HT_OK; i++)
        if (made[i].pixels)
            r = check_size(m, sources[i], "the texture is", made[i].width, made[i].height, err, err_size);
    int w, h;
    packed_size(base, alpha, &w, &h);
    if (r == HT_OK && base->pixels && alpha->pixels)
        r = check_size(m, "textures.base, textures.alpha", "they pack into an albedo of", w, h, err, err_size);
    packed_size(shift, sparkle, &w, &h);
    if (r == HT_OK && shift->pixels && sparkle->pixels)
        r = check_size(m, "textures.shift, textures.sparkle", "they pack into a detail texture of", w, h,
                       err, err_size);
    if (r != HT_OK) goto done;

    if (plan->base || plan->alpha)
        r = pack_two(base, 3, alpha, 3, (const uint8_t[4]){ 255, 255, 255, 255 }, albedo);
    if (r == HT_OK && (plan->shift || plan->sparkle))
        r = pack_two(shift, 1, sparkle, 1, (const uint8_t[4]){ 128, 255, 0, 255 }, detail);
    if (r != HT_OK)
        ht_set_error(err, err_size, "%s: textures: out of memory packing the albedo and detail textures",
                     m->file[0] ? m->file : "<material>");

done:
    for (int i = 0; i < HT_TEX_COUNT; i++) ht_image_free(&made[i]);
    if (r != HT_OK) {
        ht_image_free(albedo);
        ht_image_free(detail);
    }
    return r;
}

ht_result ht_textures_pack(const ht_material *m, const ht_plan *plan,
                           ht_image *albedo, ht_image *detail, char *err, size_t err_size) {
    if (!m || !plan || !albedo || !detail) {
        ht_set_error(err, err_size, "ht_textures_pack: material, plan and both images are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    /* One slot after another; the first failure in slot order is the
       error (generate.c makes the slots as jobs of their own). */
    ht_image made[HT_TEX_COUNT] = { { 0 } };
    ht_result r = HT_OK;
    for (int i = 0; i < HT_TEX_COUNT && r == HT_OK; i++)
        r = ht_texture_make_slot(m, plan, (ht_texture_slot)i, &made[i], err, err_size);
    if (r == HT_OK) return ht_textures_pack_made(m, plan, made, albedo, detail, err, err_size);
    for (int i = 0; i < HT_TEX_COUNT; i++) ht_image_free(&made[i]);
    *albedo = (ht_image){ 0 };
    *detail = (ht_image){ 0 };
    return r;
}

/* texture.c — a material's textures: procedural ones generated from (size,
   seed), file ones read from PNG; both reduced to what the slot holds.

   Coordinates: u runs along image x (across strands), v along image y, row 0
   is v = 0, the root; strands grow down the image towards the tip at v = 1.

   Procedural textures are the same bytes on every machine: all arithmetic is
   integer (16.16 fixed point), randomness comes from runtime/mesh/rng.h only, and
   no libm function (whose last bits differ between C libraries) or floating
   point expression (which a compiler may contract into FMA) touches a texel.
   They tile: every lattice and strand pattern has a period dividing the size.
     stretched-noise  3 ch  grey in [0.55, 1]: value noise, fine across u
                            (a lattice cell every 2 texels), cells 32 times
                            longer along v (one cell at sizes up to 64)
     strand-alpha     1 ch  a comb of strands along v, one per size/8 columns
                            (2..64 strands): opaque cores (45..70% of the
                            half width) near the root, soft edges, tips
                            fading to 0 at a random length in [0.75, 1],
                            the fade starting at 60..85% of that length
     noise            1 ch  per-strand shift jitter in [0.38, 0.62] around
                            0.5 (a tangent shift of at most ±0.12: strands
                            break the highlight band up without scattering
                            it), 2 cells along v
     sparkle          1 ch  the secondary highlight's mask: 0 but for glints
                            1 texel wide, elongated along v, on about a fifth
                            of the texels at every size
   Procedural sizes are powers of two in 16..2048 (hairgen.h); a file may be
   any size at least 1 x 1, square or not: GL 2.0 and the GLSL tiers sample
   any size; what a tier needs beyond that is the packer's and emitters' call.

   Slots: base holds 3 channels (grey expands to rgb), the others 1 channel:
   alpha takes a file's alpha channel when it has one, else its luminance;
   shift and sparkle take luminance. */
#include "hairgen_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "rng.h"

#define ONE 65536 /* 1.0 in 16.16 fixed point */

static const char *const slot_names[HT_TEX_COUNT] = { "base", "alpha", "shift", "sparkle" };

/* ---- fixed-point helpers ---- */

/* smoothstep on a 16.16 fraction f in [0, ONE] */
static int64_t smooth16(int64_t f) {
    return f * f / ONE * (3 * ONE - 2 * f) / ONE;
}

/* ONE at x <= lo, 0 at x >= hi, smooth in between (16.16 arguments). */
static int64_t falloff16(int64_t x, int64_t lo, int64_t hi) {
    if (x <= lo) return ONE;
    if (x >= hi) return 0;
    return ONE - smooth16((x - lo) * ONE / (hi - lo));
}

static uint8_t to_byte(int64_t f16) {
    if (f16 <= 0) return 0;
    if (f16 >= ONE) return 255;
    return (uint8_t)((f16 * 255 + ONE / 2) / ONE);
}

/* A 16-bit random value at lattice point (i, j), fixed by key. */
static int64_t lattice(uint64_t key, int i, int j) {
    ht_rng r = ht_rng_seed(key ^ ((uint64_t)(uint32_t)i << 32 | (uint32_t)j));
    return (int64_t)(ht_rng_next(&r) >> 48);
}

#define MAX_PROCEDURAL_SIZE 2048

/* Where each texel column's centre falls on a lattice of `cells` cells
   across `size` texels (position = (x + 0.5) * cells / size, in halves):
   its cell, the next one (wrapping) and the smoothed weight between them.
   The same for every row, so computed once per image, not per row (three
   64-bit divisions a texel were most of the noise's instructions). */
typedef struct noise_columns {
    int cells;
    int cell[MAX_PROCEDURAL_SIZE], next[MAX_PROCEDURAL_SIZE];
    int64_t weight[MAX_PROCEDURAL_SIZE];
} noise_columns;

static void noise_columns_init(noise_columns *c, int size, int cells) {
    int64_t span = 2 * (int64_t)size;
    c->cells = cells;
    for (int x = 0; x < size; x++) {
        int64_t pu = (int64_t)(2 * x + 1) * cells;
        c->cell[x] = (int)(pu / span);
        c->next[x] = (c->cell[x] + 1) % cells;
        c->weight[x] = smooth16(pu % span * ONE / span);
    }
}

/* One value-noise lattice across a size x size image: cols->cells x
   cells_v cells that wrap around the image (cols->cells at most size / 2),
   and the row of lattice cells the last row fell in, interpolated across
   every column (top: the cell row above, bottom: the one below). Rows of
   one lattice row share those: a row is then one blend per texel, the same
   integers as blending the four corners at every texel. On the heap (64
   KiB): made once per texture. */
typedef struct noise_lattice {
    uint64_t key;
    int cells_v;
    int row;                       /* the lattice row top and bottom hold; -1 none yet */
    noise_columns cols;
    int64_t top[MAX_PROCEDURAL_SIZE], bottom[MAX_PROCEDURAL_SIZE];
} noise_lattice;

static void noise_lattice_init(noise_lattice *n, uint64_t key, int size, int cells_u, int cells_v) {
    n->key = key;
    n->cells_v = cells_v;
    n->row = -1;
    noise_columns_init(&n->cols, size, cells_u);
}

/* Value noise in [0, 65535] along row y of a size x size image. */
static void value_noise_row(noise_lattice *n, int y, int size, int64_t *row) {
    int64_t span = 2 * (int64_t)size;
    int64_t pv = (int64_t)(2 * y + 1) * n->cells_v;
    int j = (int)(pv / span), j1 = (j + 1) % n->cells_v;
    int64_t wv = smooth16(pv % span * ONE / span);
    if (j != n->row) {
        const noise_columns *cols = &n->cols;
        int64_t above[MAX_PROCEDURAL_SIZE / 2], below[MAX_PROCEDURAL_SIZE / 2];
        for (int i = 0; i < cols->cells; i++) {
            above[i] = lattice(n->key, i, j);
            below[i] = lattice(n->key, i, j1);
        }
        for (int x = 0; x < size; x++) {
            int i = cols->cell[x], i1 = cols->next[x];
            int64_t wu = cols->weight[x];
            n->top[x] = above[i] + (above[i1] - above[i]) * wu / ONE;
            n->bottom[x] = below[i] + (below[i1] - below[i]) * wu / ONE;
        }
        n->row = j;
    }
    for (int x = 0; x < size; x++) row[x] = n->top[x] + (n->bottom[x] - n->top[x]) * wv / ONE;
}

static int at_least_one(int n) { return n < 1 ? 1 : n; }

/* A uniform integer in [lo, hi]. */
static int64_t rng_int(ht_rng *r, int64_t lo, int64_t hi) {
    return lo + (int64_t)(ht_rng_next(r) % (uint64_t)(hi - lo + 1));
}

/* ---- generators: out is allocated by the caller ---- */

/* The generators' scratch memory (make_procedural allocates it): two
   noise lattices. */
typedef struct noise_scratch {
    noise_lattice a, b;
} noise_scratch;

static void stretched_noise(ht_image *out, ht_rng *keys, noise_scratch *scratch) {
    int size = out->width;
    uint64_t fine_key = ht_rng_next(keys), broad_key = ht_rng_next(keys);
    int64_t fine[MAX_PROCEDURAL_SIZE], broad[MAX_PROCEDURAL_SIZE];
    noise_lattice_init(&scratch->a, fine_key, size, size / 2, at_least_one(size / 64));
    noise_lattice_init(&scratch->b, broad_key, size, size / 16, at_least_one(size / 128));
    for (int y = 0; y < size; y++) {
        value_noise_row(&scratch->a, y, size, fine);
        value_noise_row(&scratch->b, y, size, broad);
        for (int x = 0; x < size; x++) {
            int64_t n = (fine[x] * 13 + broad[x] * 7) / 20; /* [0, 65535] */
            /* 0.55 + 0.45 n, in 16.16 */
            uint8_t grey = to_byte(ONE * 55 / 100 + n * 45 / 100);
            uint8_t *px = out->pixels + 3 * ((size_t)y * size + x);
            px[0] = px[1] = px[2] = grey;
        }
    }
}

static void strand_alpha(ht_image *out, ht_rng *keys, noise_scratch *scratch) {
    (void)scratch;
    int size = out->width;
    int strands = size / 8 < 2 ? 2 : (size / 8 > 64 ? 64 : size / 8);
    int width = size / strands;
    ht_rng r = ht_rng_seed(ht_rng_next(keys));
    for (int k = 0; k < strands; k++) {
        /* per strand, as 16.16 fractions: its length (of the image height),
           where its tip starts fading (of its length), its opaque core
           (of its half width) */
        int64_t length = rng_int(&r, ONE * 75 / 100, ONE);
        int64_t fade_from = length * rng_int(&r, ONE * 60 / 100, ONE * 85 / 100) / ONE;
        int64_t core = rng_int(&r, ONE * 45 / 100, ONE * 70 / 100);
        const int64_t edge = ONE * 95 / 100;
        for (int c = 0; c < width; c++) {
            int x = k * width + c;
            /* distance of the column centre from the strand's axis, 0..1 */
            int64_t d = (int64_t)(2 * c + 1 - width) * ONE / width;
            if (d < 0) d = -d;
            int64_t across = falloff16(d, core, edge);
            for (int y = 0; y < size; y++) {
                int64_t v = (int64_t)(2 * y + 1) * ONE / (2 * size);
                int64_t along = falloff16(v, fade_from, length);
                out->pixels[(size_t)y * size + x] = to_byte(across * along / ONE);
            }
        }
    }
}

static void shift_noise(ht_image *out, ht_rng *keys, noise_scratch *scratch) {
    int size = out->width;
    uint64_t key = ht_rng_next(keys);
    int64_t n[MAX_PROCEDURAL_SIZE];
    noise_lattice_init(&scratch->a, key, size, at_least_one(size / 2), 2);
    for (int y = 0; y < size; y++) {
        value_noise_row(&scratch->a, y, size, n);
        for (int x = 0; x < size; x++) out->pixels[(size_t)y * size + x] = to_byte(ONE * 38 / 100 + n[x] * 24 / 100);
    }
}

static void sparkle(ht_image *out, ht_rng *keys, noise_scratch *scratch) {
    (void)scratch;
    int size = out->width;
    int shortest = size / 64 < 2 ? 2 : size / 64, longest = size / 16 < 3 ? 3 : size / 16;
    /* A glint is shortest + longest + 1 texels long on average: this many
       would cover a quarter of the image if none overlapped, at any size. */
    int glints = at_least_one(size * size / (4 * (shortest + longest + 1)));
    ht_rng r = ht_rng_seed(ht_rng_next(keys));
    for (int g = 0; g < glints; g++) {
        int x = (int)rng_int(&r, 0, size - 1), y = (int)rng_int(&r, 0, size - 1);
        int half = (int)rng_int(&r, shortest, longest);
        int64_t peak = rng_int(&r, ONE * 7 / 10, ONE);
        for (int dy = -half; dy <= half; dy++) {
            /* 1 - (dy / (half + 1))^2: bright along most of its length */
            int64_t t = (int64_t)dy * ONE / (half + 1);
            uint8_t value = to_byte(peak * (ONE - t * t / ONE) / ONE);
            uint8_t *px = out->pixels + (size_t)((y + dy + size) % size) * size + x;
            if (value > *px) *px = value;
        }
    }
}

typedef struct generator {
    const char *name;
    int channels;
    void (*make)(ht_image *out, ht_rng *keys, noise_scratch *scratch);
} generator;

static const generator generators[] = {
    { "stretched-noise", 3, stretched_noise },
    { "strand-alpha", 1, strand_alpha },
    { "noise", 1, shift_noise },
    { "sparkle", 1, sparkle },
};

/* ---- channel reduction ---- */

/* Rec. 601 weights in 1/256 (77 + 150 + 29 = 256: white stays 255). */
static uint8_t luminance(const uint8_t *px, int channels) {
    if (channels < 3) return px[0];
    return (uint8_t)((77 * px[0] + 150 * px[1] + 29 * px[2] + 128) >> 8);
}

/* in reduced to the slot's channels in out; in is taken (freed or moved). */
static ht_result reduce_to_slot(ht_image *in, ht_texture_slot slot, ht_image *out) {
    int channels = slot == HT_TEX_BASE ? 3 : 1;
    /* Already the slot's channels (every procedural texture): what the
       loop below would copy texel by texel (a 1-channel texel is its own
       luminance), so the image itself. */
    if (in->channels == channels) {
        *out = *in;
        *in = (ht_image){ 0 };
        return HT_OK;
    }
    ht_result r = ht_image_alloc(out, in->width, in->height, channels);
    if (r != HT_OK) {
        ht_image_free(in);
        return r;
    }
    size_t count = (size_t)in->width * in->height;
    for (size_t i = 0; i < count; i++) {
        const uint8_t *src = in->pixels + i * in->channels;
        uint8_t *dst = out->pixels + i * channels;
        if (slot == HT_TEX_BASE) {
            for (int c = 0; c < 3; c++) dst[c] = in->channels >= 3 ? src[c] : src[0];
        } else if (slot == HT_TEX_ALPHA && (in->channels == 2 || in->channels == 4)) {
            dst[0] = src[in->channels - 1];
        } else {
            dst[0] = luminance(src, in->channels);
        }
    }
    ht_image_free(in);
    return HT_OK;
}

/* ---- the entry point ---- */

static ht_result make_procedural(const ht_texture_source *src, const char *slot_name,
                                 ht_image *native, char *err, size_t err_size) {
    const generator *gen = NULL;
    for (size_t i = 0; i < sizeof generators / sizeof generators[0]; i++)
        if (strcmp(src->procedural, generators[i].name) == 0) gen = &generators[i];
    if (!gen) {
        ht_set_error(err, err_size,
                "texture %s: procedural \"%.32s\" is not one of stretched-noise, strand-alpha, "
                "noise, sparkle", slot_name, src->procedural);
        return HT_ERR_PARSE;
    }
    if (src->size < 16 || src->size > MAX_PROCEDURAL_SIZE || (src->size & (src->size - 1)) != 0) {
        ht_set_error(err, err_size, "texture %s: size %d is not a power of two in 16..2048",
                slot_name, src->size);
        return HT_ERR_PARSE;
    }
    noise_scratch *scratch = malloc(sizeof *scratch);
    ht_result r = scratch ? ht_image_alloc(native, src->size, src->size, gen->channels) : HT_ERR_OUT_OF_MEMORY;
    if (r != HT_OK) {
        free(scratch);
        ht_set_error(err, err_size, "texture %s: out of memory", slot_name);
        return r;
    }
    /* Each generator draws its own stream: the same seed in two slots
       still gives unrelated patterns. */
    ht_rng keys = ht_rng_seed((uint64_t)src->seed ^ (uint64_t)(gen - generators + 1) << 32);
    gen->make(native, &keys, scratch);
    free(scratch);
    return HT_OK;
}

ht_result ht_texture_make(const ht_texture_source *src, ht_texture_slot slot,
                          ht_image *out, char *err, size_t err_size) {
    if (!src || !out || slot < 0 || slot >= HT_TEX_COUNT) {
        ht_set_error(err, err_size, "ht_texture_make: src, out and a valid slot are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    *out = (ht_image){ 0 };
    const char *slot_name = slot_names[slot];
    ht_image native = { 0 };
    ht_result r;
    switch (src->origin) {
    case HT_TEXTURE_PROCEDURAL:
        r = make_procedural(src, slot_name, &native, err, err_size);
        break;
    case HT_TEXTURE_FILE:
        r = ht_image_read_png(src->path, &native, err, err_size);
        break;
    default:
        ht_set_error(err, err_size, "texture %s: no texture to make (the slot is absent)", slot_name);
        return HT_ERR_INVALID_ARGUMENT;
    }
    if (r != HT_OK) return r;
    r = reduce_to_slot(&native, slot, out);
    ht_image_free(&native);
    if (r != HT_OK)
        ht_set_error(err, err_size, "texture %s: out of memory", slot_name);
    return r;
}

/* cards_bundle.c — a bundle whose albedo and detail are one atlas of the
   material's own textures and a scene's cards, and whose lods.bin holds
   every level, strands and cards (cards_bundle.h). Every other file is
   copied byte for byte: the tiers' programs and LUTs do not depend on the
   textures' contents, only on their names (and the manifest's sizes). */
#include "cards_bundle.h"

#include <cJSON.h>
#include <dirent.h>
#include <math.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bundle_sums.h"
#include "errfmt.h"
#include "file_open.h"
#include "lods_store.h"
#include "mesh_internal.h"
#include <hairtier/image.h>
#include <hairtier/lod.h>
#include <hairtier/scene.h>

#define MAX_BUNDLE_FILE (256u << 20)

static bool is_replaced(const char *name) {
    return !strcmp(name, "albedo.png") || !strcmp(name, "detail.png") || !strcmp(name, "manifest.json") ||
           !strcmp(name, HT_LOD_FILE_NAME);
}

/* The files the cards bundle writes itself, their bytes for file_sums. */
typedef struct written {
    const char *name;
    unsigned char *data;
    size_t size;
} written;
#define WRITTEN_MAX 3

static ht_result write_bytes(const char *dir, const written *w, char *err, size_t err_size) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, w->name);
    FILE *f = fopen(path, "wb");
    const bool ok = f && fwrite(w->data, 1, w->size, f) == w->size;
    const bool closed = f && fclose(f) == 0;
    return ok && closed ? HT_OK : ht_fail(err, err_size, HT_ERR_IO, "%s: %s", path, strerror(errno));
}

static ht_result copy_file(const char *from, const char *to, char *err, size_t err_size) {
    size_t size = 0;
    void *data = ht_file_read_bytes(from, MAX_BUNDLE_FILE, &size, err, err_size);
    if (!data) return HT_ERR_IO;
    FILE *f = fopen(to, "wb");
    const bool ok = f && fwrite(data, 1, size, f) == size;
    const bool closed = f && fclose(f) == 0;
    free(data);
    if (!ok || !closed) return ht_fail(err, err_size, HT_ERR_IO, "%s: %s", to, strerror(errno));
    return HT_OK;
}

/* Every regular file of `from` but the two textures, into `to`. */
static ht_result copy_bundle(const char *from, const char *to, char *err, size_t err_size) {
    DIR *d = opendir(from);
    if (!d) return ht_fail(err, err_size, HT_ERR_IO, "%s: %s", from, strerror(errno));
    ht_result r = HT_OK;
    struct dirent *e;
    while (r == HT_OK && (e = readdir(d))) {
        char src[4096], dst[4096];
        struct stat st;
        if (e->d_name[0] == '.' || is_replaced(e->d_name)) continue;
        snprintf(src, sizeof src, "%s/%s", from, e->d_name);
        snprintf(dst, sizeof dst, "%s/%s", to, e->d_name);
        if (stat(src, &st) != 0 || !S_ISREG(st.st_mode)) {
            r = ht_fail(err, err_size, HT_ERR_IO, "%s: not a regular file; a bundle holds only files", src);
            break;
        }
        r = copy_file(src, dst, err, err_size);
    }
    closedir(d);
    return r;
}

static void remove_dir(const char *dir) {
    DIR *d = opendir(dir);
    if (!d) return;
    struct dirent *e;
    while ((e = readdir(d))) {
        char p[4096];
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
        snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
        unlink(p);
    }
    closedir(d);
    rmdir(dir);
}

/* The fraction of the covered texels (alpha > 0) of rows [y0, y1) of an
   RGBA image whose alpha is at least a (0..255). */
static double opaque_fraction(const ht_image *img, int y0, int y1, int a) {
    size_t covered = 0, opaque = 0;
    for (size_t i = (size_t)y0 * img->width; i < (size_t)y1 * img->width; i++) {
        covered += img->pixels[4 * i + 3] > 0;
        opaque += img->pixels[4 * i + 3] >= a && img->pixels[4 * i + 3] > 0;
    }
    return covered ? (double)opaque / covered : 0;
}

/* The bundle keeps one opaque cutoff, the material's. Baked coverage is
   smooth and reaches it less often than the material's opaque cores, so
   less of a card would prime depth and more would blend in inside-out
   order, far side over near (docs/lod.md). The cards' alpha is remapped
   so that their own cutoff c (the alpha above which as large a part of
   their coverage lies as of the material's above its cutoff) lands on
   the material's m: unchanged below 0.9 c, stretched from there to c onto
   [0.9 c, m], [c, 1] onto [m, 1]. Returns c. */
static double match_cutoff(const ht_image *material, ht_image *atlas, int first_row, double m) {
    const double target = opaque_fraction(material, 0, material->height, (int)ceil(m * 255));
    int a = 255;
    while (a > 1 && opaque_fraction(atlas, first_row, atlas->height, a) < target) a--;
    const double c = a / 255.0, a0 = 0.9 * c;
    if (c >= m) return c;
    for (size_t i = (size_t)first_row * atlas->width; i < (size_t)atlas->height * atlas->width; i++) {
        const double x = atlas->pixels[4 * i + 3] / 255.0;
        const double y = x <= a0 ? x : x < c ? a0 + (x - a0) * (m - a0) / (c - a0) : m + (x - c) * (1 - m) / (1 - c);
        atlas->pixels[4 * i + 3] = (uint8_t)lrint(ht_clamp01(y) * 255);
    }
    return c;
}

/* The material's opaque cutoff, from BUNDLE's manifest. */
static ht_result read_cutoff(const char *dir, double *cutoff, char *err, size_t err_size) {
    char path[4096], *text;
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    if (!(text = ht_file_read_text(path, MAX_BUNDLE_FILE, err, err_size))) return HT_ERR_IO;
    cJSON *root = cJSON_Parse(text);
    free(text);
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(root, "opaque_cutoff");
    const bool ok = cJSON_IsNumber(c) && c->valuedouble > 0 && c->valuedouble <= 1;
    if (ok) *cutoff = c->valuedouble;
    cJSON_Delete(root);
    return ok ? HT_OK : ht_fail(err, err_size, HT_ERR_PARSE, "%s: opaque_cutoff: expected a number in (0, 1]", path);
}

/* The manifest with textures.albedo and .detail the atlas's size (the
   runtime checks each texture against its entry), the new files' sums
   and "lod_file". */
static ht_result write_manifest(const char *from, const char *to, int w, int h, const written *files,
                                int file_count, char *err, size_t err_size) {
    char path[4096], *text = NULL;
    snprintf(path, sizeof path, "%s/manifest.json", from);
    if (!(text = ht_file_read_text(path, MAX_BUNDLE_FILE, err, err_size))) return HT_ERR_IO;
    cJSON *root = cJSON_Parse(text);
    free(text);
    cJSON *textures = cJSON_GetObjectItemCaseSensitive(root, "textures");
    ht_result r = HT_OK;
    for (int i = 0; r == HT_OK && i < 2; i++) {
        cJSON *t = cJSON_GetObjectItemCaseSensitive(textures, i ? "detail" : "albedo");
        if (!t && i) continue;
        if (!cJSON_IsObject(t) || !cJSON_GetObjectItemCaseSensitive(t, "width") ||
            !cJSON_GetObjectItemCaseSensitive(t, "height"))
            r = ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: textures.%s: expected an object with width and height",
                        path, i ? "detail" : "albedo");
        else {
            cJSON_SetNumberValue(cJSON_GetObjectItemCaseSensitive(t, "width"), w);
            cJSON_SetNumberValue(cJSON_GetObjectItemCaseSensitive(t, "height"), h);
        }
    }
    cJSON *sums = cJSON_GetObjectItemCaseSensitive(root, "file_sums");
    for (int i = 0; r == HT_OK && i < file_count; i++) {
        const bool lods = !strcmp(files[i].name, HT_LOD_FILE_NAME);
        if (lods ? !ht_lods_manifest_add(root, files[i].data, files[i].size)
                 : cJSON_IsObject(sums) && !ht_bundle_sums_set(sums, files[i].name, files[i].data, files[i].size))
            r = ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: file_sums: out of memory", path);
    }
    char *out = r == HT_OK ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (r != HT_OK) return r;
    if (!out) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s/manifest.json: out of memory", to);
    snprintf(path, sizeof path, "%s/manifest.json", to);
    FILE *f = fopen(path, "wb");
    const bool ok = f && fputs(out, f) >= 0 && fputc('\n', f) != EOF;
    const bool closed = f && fclose(f) == 0;
    cJSON_free(out);
    return ok && closed ? HT_OK : ht_fail(err, err_size, HT_ERR_IO, "%s: %s", path, strerror(errno));
}

/* The bundle's texture NAME.png, RGBA; absent: *img zeroed, HT_OK unless required. */
static ht_result read_texture(const char *dir, const char *name, bool required, ht_image *img, char *err,
                              size_t err_size) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    memset(img, 0, sizeof *img);
    if (access(path, F_OK) != 0)
        return required ? ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT,
                                  "%s: absent; cards need the material's alpha (an albedo texture)", path)
                        : HT_OK;
    ht_result r = ht_image_read_png(path, img, err, err_size);
    if (r == HT_OK && img->channels != 4) {
        ht_image_free(img);
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: %d channels, expected RGBA", path, img->channels);
    }
    return r;
}

/* The material's texture into the atlas's top left, with a one-texel
   border of its wrapped-around texels: a strand's uv, mapped there
   (strand_uv), samples what it sampled in the material's own texture. */
static void place_material(const ht_image *material, ht_image *atlas) {
    const int mw = material->width, mh = material->height;
    for (int y = 0; y < mh + 2; y++)
        for (int x = 0; x < mw + 2; x++) {
            const int sx = (x - 1 + mw) % mw, sy = (y - 1 + mh) % mh;
            memcpy(atlas->pixels + ((size_t)y * atlas->width + x) * 4, material->pixels + ((size_t)sy * mw + sx) * 4, 4);
        }
}

static void strand_uv(ht_mesh *m, int mw, int mh, int W, int H) {
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        m->vertices[v].uv[0] = (float)((1.0 + m->vertices[v].uv[0] * mw) / W);
        m->vertices[v].uv[1] = (float)((1.0 + m->vertices[v].uv[1] * mh) / H);
    }
}

ht_result ht_cards_bundle_write_mesh(const char *bundle_dir, const ht_mesh *hair, uint32_t strands_per_card,
                                     int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size) {
    ht_image albedo = { 0 }, detail = { 0 };
    ht_cards cards = { 0 };
    ht_lod_chain chain = { 0 };
    ht_lod_file ladder = { 0 };
    bool made_dir = false;
    ht_result r = read_texture(bundle_dir, "albedo.png", true, &albedo, err, err_size);
    if (r == HT_OK) r = read_texture(bundle_dir, "detail.png", false, &detail, err, err_size);
    if (r == HT_OK && detail.pixels && (detail.width != albedo.width || detail.height != albedo.height))
        r = ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "%s/detail.png: %dx%d, albedo.png is %dx%d; cards share one atlas grid",
                    bundle_dir, detail.width, detail.height, albedo.width, albedo.height);
    if (r == HT_OK && (albedo.width + 2 > atlas_size || albedo.height + 2 >= atlas_size))
        r = ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "%s/albedo.png: %dx%d does not fit a %dx%d atlas with a border",
                    bundle_dir, albedo.width, albedo.height, atlas_size, atlas_size);
    if (r == HT_OK) {
        r = ht_mesh_build_cards(hair, &(ht_cards_desc){ .strands_per_card = strands_per_card, .strand_albedo = &albedo,
                                                        .atlas_width = atlas_size, .atlas_height = atlas_size,
                                                        .strand_detail = detail.pixels ? &detail : NULL,
                                                        .reserve_rows = albedo.height + 2 },
                                &cards);
        if (r != HT_OK)
            ht_fail(err, err_size, r, "%s: cards of %u strands: %u strands do not make cards in a %dx%d atlas (%s)",
                    out_dir, strands_per_card, hair->component_count, atlas_size, atlas_size, ht_result_string(r));
    }
    if (r == HT_OK && (r = ht_lod_chain_build(hair, &chain)) != HT_OK)
        ht_fail(err, err_size, r, "%s: the strand levels: %s", out_dir, ht_result_string(r));
    double cutoff = 1, cards_cutoff = 1;
    if (r == HT_OK) r = read_cutoff(bundle_dir, &cutoff, err, err_size);
    if (r == HT_OK) {
        cards_cutoff = match_cutoff(&albedo, &cards.albedo, cards.first_row, cutoff);
        place_material(&albedo, &cards.albedo);
        if (detail.pixels) place_material(&detail, &cards.detail);
        strand_uv(&chain.all, albedo.width, albedo.height, atlas_size, atlas_size);
        if ((r = ht_lods_ladder(&chain, true, &cards.mesh, strands_per_card, &ladder)) != HT_OK)
            ht_fail(err, err_size, r, "%s: the ladder: %s", out_dir, ht_result_string(r));
    }
    if (r == HT_OK) {
        if (mkdir(out_dir, 0755) != 0) r = ht_fail(err, err_size, HT_ERR_IO, "%s: %s", out_dir, strerror(errno));
        else made_dir = true;
    }
    if (r == HT_OK) r = copy_bundle(bundle_dir, out_dir, err, err_size);
    /* The atlas and every level (lods.bin). */
    written files[WRITTEN_MAX] = { { "albedo.png", NULL, 0 }, { HT_LOD_FILE_NAME, NULL, 0 }, { "detail.png", NULL, 0 } };
    if (r == HT_OK) r = ht_image_encode_png(&cards.albedo, &files[0].data, &files[0].size, err, err_size);
    if (r == HT_OK && (r = ht_lod_file_encode(&ladder, &files[1].data, &files[1].size)) != HT_OK)
        ht_fail(err, err_size, r, "%s/%s: cannot encode the ladder (%s)", out_dir, HT_LOD_FILE_NAME, ht_result_string(r));
    if (r == HT_OK && detail.pixels) r = ht_image_encode_png(&cards.detail, &files[2].data, &files[2].size, err, err_size);
    const int count = detail.pixels ? 3 : 2;
    for (int i = 0; r == HT_OK && i < count; i++) r = write_bytes(out_dir, &files[i], err, err_size);
    if (r == HT_OK) r = write_manifest(bundle_dir, out_dir, atlas_size, atlas_size, files, count, err, err_size);
    for (int i = 0; i < WRITTEN_MAX; i++) free(files[i].data);
    if (r == HT_OK && summary)
        fprintf(summary, "cards: %u cards of %u strands (%u strands), %d strand levels, atlas %dx%d in %dx%d cells, "
                "alpha %.3f mapped to the cutoff %.3f -> %s\n", cards.mesh.component_count, strands_per_card,
                hair->component_count, chain.count, cards.albedo.width, cards.albedo.height, cards.columns, cards.rows,
                cards_cutoff, cutoff, out_dir);
    if (r != HT_OK && made_dir) remove_dir(out_dir);
    ht_lod_file_free(&ladder);
    ht_lod_chain_free(&chain);
    ht_cards_free(&cards);
    ht_image_free(&albedo);
    ht_image_free(&detail);
    return r;
}

ht_result ht_cards_bundle_write(const char *bundle_dir, const char *scene_path, uint32_t strands_per_card,
                                int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size) {
    ht_scene scene;
    ht_mesh hair = { 0 };
    ht_result r = ht_scene_load(scene_path, &scene, err, err_size);
    if (r == HT_OK) r = ht_scene_build_meshes(&scene, scene_path, &hair, NULL, err, err_size);
    if (r == HT_OK)
        r = ht_cards_bundle_write_mesh(bundle_dir, &hair, strands_per_card, atlas_size, out_dir, summary, err, err_size);
    ht_mesh_free(&hair);
    return r;
}

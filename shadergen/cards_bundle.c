/* cards_bundle.c — a bundle whose albedo and detail are a scene's cards
   atlas (cards_bundle.h). Every other file is copied byte for byte: the
   tiers' programs and LUTs do not depend on the textures' contents, only
   on their names and sizes, which the atlas keeps. */
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

/* The fraction of an RGBA image's covered texels (alpha > 0) whose alpha
   is at least a (0..255). */
static double opaque_fraction(const ht_image *img, int a) {
    size_t covered = 0, opaque = 0;
    for (size_t i = 0; i < (size_t)img->width * img->height; i++) {
        covered += img->pixels[4 * i + 3] > 0;
        opaque += img->pixels[4 * i + 3] >= a && img->pixels[4 * i + 3] > 0;
    }
    return covered ? (double)opaque / covered : 0;
}

/* The cards' opaque cutoff: the alpha above which as large a part of the
   atlas's coverage lies as of the material's above its own cutoff. Drawn
   with the material's, the smooth baked coverage would rarely reach it:
   nothing would write depth in the prime-Z pass and every card would
   blend in inside-out order, far side over near side (docs/lod.md). */
static double cards_cutoff(const ht_image *material, const ht_image *atlas, double cutoff) {
    const double target = opaque_fraction(material, (int)ceil(cutoff * 255));
    int a = 255;
    while (a > 1 && opaque_fraction(atlas, a) < target) a--;
    return a / 255.0 < cutoff ? a / 255.0 : cutoff;
}

/* The manifest with textures.albedo and .detail the atlas's size (the
   runtime checks each texture against its entry) and the cards' opaque
   cutoff. */
static ht_result write_manifest(const char *from, const char *to, int w, int h, const ht_image *material,
                                const ht_image *atlas, const written *files, int file_count, double *cutoff_out,
                                char *err, size_t err_size) {
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
    cJSON *cutoff = cJSON_GetObjectItemCaseSensitive(root, "opaque_cutoff");
    if (r == HT_OK && !cJSON_IsNumber(cutoff))
        r = ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: opaque_cutoff: expected a number", path);
    if (r == HT_OK) {
        *cutoff_out = cards_cutoff(material, atlas, cutoff->valuedouble);
        cJSON_SetNumberValue(cutoff, *cutoff_out);
    }
    cJSON *sums = cJSON_GetObjectItemCaseSensitive(root, "file_sums");
    for (int i = 0; r == HT_OK && i < file_count; i++)
        if (cJSON_IsObject(sums) && !ht_bundle_sums_set(sums, files[i].name, files[i].data, files[i].size))
            r = ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: file_sums: out of memory", path);
    cJSON_DeleteItemFromObjectCaseSensitive(root, "lod_file");
    if (r == HT_OK && !cJSON_AddStringToObject(root, "lod_file", HT_LOD_FILE_NAME))
        r = ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: lod_file: out of memory", path);
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

ht_result ht_cards_bundle_write_mesh(const char *bundle_dir, const ht_mesh *hair, uint32_t strands_per_card,
                                     int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size) {
    ht_image albedo = { 0 }, detail = { 0 };
    ht_cards cards = { 0 };
    bool made_dir = false;
    ht_result r = read_texture(bundle_dir, "albedo.png", true, &albedo, err, err_size);
    if (r == HT_OK) r = read_texture(bundle_dir, "detail.png", false, &detail, err, err_size);
    if (r == HT_OK && detail.pixels && (detail.width != albedo.width || detail.height != albedo.height))
        r = ht_fail(err, err_size, HT_ERR_UNSUPPORTED, "%s/detail.png: %dx%d, albedo.png is %dx%d; cards share one atlas grid",
                    bundle_dir, detail.width, detail.height, albedo.width, albedo.height);
    if (r == HT_OK) {
        r = ht_mesh_build_cards(hair, &(ht_cards_desc){ .strands_per_card = strands_per_card, .strand_albedo = &albedo,
                                                        .atlas_width = atlas_size, .atlas_height = atlas_size,
                                                        .strand_detail = detail.pixels ? &detail : NULL },
                                &cards);
        if (r != HT_OK)
            ht_fail(err, err_size, r, "%s: cards of %u strands: %u strands do not make cards in a %dx%d atlas (%s)",
                    out_dir, strands_per_card, hair->component_count, atlas_size, atlas_size, ht_result_string(r));
    }
    if (r == HT_OK) {
        if (mkdir(out_dir, 0755) != 0) r = ht_fail(err, err_size, HT_ERR_IO, "%s: %s", out_dir, strerror(errno));
        else made_dir = true;
    }
    if (r == HT_OK) r = copy_bundle(bundle_dir, out_dir, err, err_size);
    /* The atlas and the cards' geometry (lods.bin, one cards level). */
    written files[WRITTEN_MAX] = { { "albedo.png", NULL, 0 }, { "detail.png", NULL, 0 }, { HT_LOD_FILE_NAME, NULL, 0 } };
    const ht_lod_file ladder = { .mesh = cards.mesh, .level_count = 1,
                                 .levels = { { HT_LOD_KIND_CARDS, strands_per_card, 0, cards.mesh.index_count, 0,
                                               cards.mesh.component_count } } };
    if (r == HT_OK) r = ht_image_encode_png(&cards.albedo, &files[0].data, &files[0].size, err, err_size);
    if (r == HT_OK && detail.pixels) r = ht_image_encode_png(&cards.detail, &files[1].data, &files[1].size, err, err_size);
    if (r == HT_OK && (r = ht_lod_file_encode(&ladder, &files[2].data, &files[2].size)) != HT_OK)
        ht_fail(err, err_size, r, "%s/%s: cannot encode the cards (%s)", out_dir, HT_LOD_FILE_NAME, ht_result_string(r));
    for (int i = 0; r == HT_OK && i < WRITTEN_MAX; i++)
        if (files[i].data) r = write_bytes(out_dir, &files[i], err, err_size);
    const written listed[WRITTEN_MAX] = { files[0], detail.pixels ? files[1] : files[2], files[2] };
    double cutoff = 0;
    if (r == HT_OK)
        r = write_manifest(bundle_dir, out_dir, atlas_size, atlas_size, &albedo, &cards.albedo, listed,
                           detail.pixels ? 3 : 2, &cutoff, err, err_size);
    for (int i = 0; i < WRITTEN_MAX; i++) free(files[i].data);
    if (r == HT_OK && summary)
        fprintf(summary, "cards: %u cards of %u strands (%u strands), atlas %dx%d in %dx%d cells, opaque cutoff %.3f -> %s\n",
                cards.mesh.component_count, strands_per_card, hair->component_count, cards.albedo.width,
                cards.albedo.height, cards.columns, cards.rows, cutoff, out_dir);
    if (r != HT_OK && made_dir) remove_dir(out_dir);
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

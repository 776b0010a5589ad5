/* lods_store.c — a bundle's stored levels, lods.bin (lods_store.h). */
#include "lods_store.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bundle_sums.h"
#include "errfmt.h"
#include "file_open.h"
#include "manifest.h"
#include "mesh_internal.h"

ht_result ht_lods_ladder(const ht_lod_chain *chain, bool store_level0, const ht_mesh *cards, uint32_t strands_per_card,
                         ht_lod_file *out) {
    memset(out, 0, sizeof *out);
    static const ht_mesh none = { 0 };
    if (!cards) cards = &none;
    const ht_mesh *all = &chain->all, *full = chain->full;
    /* Level 0 is the first full->vertex_count vertices, chain->index_count[0]
       indices and full->component_count components of all. */
    const uint32_t skip_v = store_level0 ? 0 : full->vertex_count, skip_i = store_level0 ? 0 : chain->index_count[0];
    const uint32_t skip_c = store_level0 ? 0 : full->component_count;
    const uint32_t nv = all->vertex_count - skip_v, ni = all->index_count - skip_i, nc = all->component_count - skip_c;
    ht_result r = ht_mesh_alloc(&out->mesh, (uint64_t)nv + cards->vertex_count, (uint64_t)ni + cards->index_count,
                                (uint64_t)nc + cards->component_count);
    if (r != HT_OK) return r;
    ht_mesh *m = &out->mesh;
    memcpy(m->center, all->center, sizeof m->center);
    memcpy(m->vertices, all->vertices + skip_v, sizeof *m->vertices * nv);
    if (cards->vertex_count) memcpy(m->vertices + nv, cards->vertices, sizeof *m->vertices * cards->vertex_count);
    for (uint32_t i = 0; i < ni; i++) m->indices[i] = all->indices[skip_i + i] - skip_v;
    for (uint32_t i = 0; i < cards->index_count; i++) m->indices[ni + i] = cards->indices[i] + nv;
    for (uint32_t c = 0; c < nc; c++) {
        m->components[c] = all->components[skip_c + c];
        m->components[c].first_index -= skip_i;
    }
    for (uint32_t c = 0; c < cards->component_count; c++) {
        m->components[nc + c] = cards->components[c];
        m->components[nc + c].first_index += ni;
    }
    uint32_t component = 0;
    for (int l = 0; l < chain->count; l++) {
        const uint32_t n = ht_lod_chain_mesh(chain, l)->component_count;
        out->levels[l] = l || store_level0 ? (ht_lod_range){ HT_LOD_KIND_STRANDS, 1u << l, chain->first[l] - skip_i,
                                                             chain->index_count[l], component, n }
                                           : (ht_lod_range){ HT_LOD_KIND_SCENE, 1, 0, 0, 0, 0 };
        component += l || store_level0 ? n : 0;
    }
    out->level_count = chain->count;
    if (cards->component_count)
        out->levels[out->level_count++] = (ht_lod_range){ HT_LOD_KIND_CARDS, strands_per_card, ni, cards->index_count,
                                                          nc, cards->component_count };
    ht_lod_file_set_scene(out, full);
    return HT_OK;
}

bool ht_lods_manifest_add(cJSON *manifest, const void *lods, size_t size) {
    cJSON *sums = cJSON_GetObjectItemCaseSensitive(manifest, HT_MANIFEST_KEY_FILE_SUMS);
    if (cJSON_IsObject(sums) && !ht_bundle_sums_set(sums, HT_LOD_FILE_NAME, lods, size)) return false;
    cJSON_DeleteItemFromObjectCaseSensitive(manifest, HT_MANIFEST_KEY_LOD_FILE);
    return cJSON_AddStringToObject(manifest, HT_MANIFEST_KEY_LOD_FILE, HT_LOD_FILE_NAME) != NULL;
}

static ht_result write_file(const char *dir, const char *name, const void *data, size_t size, char *err,
                            size_t err_size) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    const bool ok = f && fwrite(data, 1, size, f) == size;
    const bool closed = f && fclose(f) == 0;
    return ok && closed ? HT_OK : ht_fail(err, err_size, HT_ERR_IO, "%s: %s", path, strerror(errno));
}

/* dir's manifest with lods.bin listed (ht_lods_manifest_add). */
static ht_result add_to_manifest(const char *dir, const void *lods, size_t size, char *err, size_t err_size) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, HT_MANIFEST_FILE);
    char *text = ht_file_read_text(path, HT_FILE_MAX_JSON, err, err_size);
    if (!text) return HT_ERR_IO;
    cJSON *root = cJSON_Parse(text);
    free(text);
    char *out = root && ht_lods_manifest_add(root, lods, size) ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!out) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "%s: " HT_MANIFEST_KEY_LOD_FILE ": out of memory", path);
    FILE *f = fopen(path, "wb");
    /* as the generator writes it: cJSON_Print's text, no newline after */
    const bool ok = f && fputs(out, f) >= 0;
    const bool closed = f && fclose(f) == 0;
    const ht_result r = ok && closed ? HT_OK : ht_fail(err, err_size, HT_ERR_IO, "%s: %s", path, strerror(errno));
    cJSON_free(out);
    return r;
}

/* lods.bin's bytes for the scene: the strand levels past 0. */
static ht_result encode_levels(const ht_scene *scene, const char *scene_path, unsigned char **bytes, size_t *size,
                               char *err, size_t err_size) {
    ht_mesh hair = { 0 };
    ht_lod_chain chain = { 0 };
    ht_lod_file ladder = { 0 };
    char why[1024];
    ht_result r = ht_scene_build_meshes(scene, scene_path ? scene_path : "<scene>", &hair, NULL, why, sizeof why);
    if (r != HT_OK) ht_set_error(err, err_size, "%s: %s", HT_LOD_FILE_NAME, why);
    if (r == HT_OK && (r = ht_lod_chain_build(&hair, &chain)) != HT_OK)
        ht_fail(err, err_size, r, "%s: the strand levels: %s", HT_LOD_FILE_NAME, ht_result_string(r));
    if (r == HT_OK && (r = ht_lods_ladder(&chain, false, NULL, 0, &ladder)) == HT_OK &&
        (r = ht_lod_file_encode(&ladder, bytes, size)) != HT_OK)
        ht_fail(err, err_size, r, "%s: cannot encode the levels (%s)", HT_LOD_FILE_NAME, ht_result_string(r));
    ht_lod_file_free(&ladder);
    ht_lod_chain_free(&chain);
    ht_mesh_free(&hair);
    return r;
}

void ht_lods_cache_init(ht_lods_cache *c) {
    memset(c, 0, sizeof *c);
    pthread_mutex_init(&c->lock, NULL);
}

void ht_lods_cache_free(ht_lods_cache *c) {
    pthread_mutex_destroy(&c->lock);
    free(c->bytes);
    memset(c, 0, sizeof *c);
}

ht_result ht_lods_store(const char *dir, const ht_scene *scene, const char *scene_path, ht_lods_cache *cache,
                        char *err, size_t err_size) {
    unsigned char *own = NULL;
    const unsigned char *bytes = NULL;
    size_t size = 0;
    ht_result r;
    if (cache) {
        pthread_mutex_lock(&cache->lock);
        if (!cache->made)
            cache->result = encode_levels(scene, scene_path, &cache->bytes, &cache->size, cache->err, sizeof cache->err);
        cache->made = true;
        pthread_mutex_unlock(&cache->lock);
        if ((r = cache->result) != HT_OK) ht_set_error(err, err_size, "%s", cache->err);
        bytes = cache->bytes;
        size = cache->size;
    } else {
        r = encode_levels(scene, scene_path, &own, &size, err, err_size);
        bytes = own;
    }
    if (r == HT_OK) r = write_file(dir, HT_LOD_FILE_NAME, bytes, size, err, err_size);
    if (r == HT_OK) r = add_to_manifest(dir, bytes, size, err, err_size);
    free(own);
    return r;
}

/* lods_store.h — a bundle's stored geometry levels, lods.bin (lod.h's
   ht_lod_file; docs/bundle.md): what plain `hairgen --scene S` writes
   (the scene's strand levels) and `hairgen --cards` (the strand levels,
   then the cards). Internal to libhairgen.

   Usage (a step on the written, unpublished bundle):
       char err[512];
       if (ht_lods_store(tmp_dir, &scene, "scenes/furball.json", NULL, err, sizeof err) != HT_OK)
           puts(err);   // one line naming the file and what is wrong
*/
#ifndef HT_LODS_STORE_H
#define HT_LODS_STORE_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#include <cJSON.h>
#include <hairtier/lod.h>
#include <hairtier/scene.h>

/* Every strand level of chain (ht_lod_chain_build's), then, when cards is
   not NULL, the cards (one component a card, strands_per_card their
   param), in one buffer, with the scene's fingerprint (chain->full's).
   store_level0 false: level 0 is not stored (HT_LOD_KIND_SCENE: the
   reader has the scene's mesh; 66-80 % of a shipped scene's bytes). */
ht_result ht_lods_ladder(const ht_lod_chain *chain, bool store_level0, const ht_mesh *cards, uint32_t strands_per_card,
                         ht_lod_file *out);

/* manifest's file_sums gain lods.bin's bytes and the top level
   "lod_file": "lods.bin"; false when out of memory. */
bool ht_lods_manifest_add(cJSON *manifest, const void *lods, size_t size);

/* lods.bin's bytes for one scene, made once for every bundle of a batch
   (the scene is theirs alike) by the first that needs them; zero it, and
   ht_lods_cache_free it after the batch. */
typedef struct ht_lods_cache {
    pthread_mutex_t lock;
    bool made;
    ht_result result;
    char err[1024];
    unsigned char *bytes;
    size_t size;
} ht_lods_cache;
void ht_lods_cache_init(ht_lods_cache *c);
void ht_lods_cache_free(ht_lods_cache *c);

/* The scene's strand levels (1 + ht_lod_max_level of its hair mesh,
   built as ht_scene_build_meshes builds it; level 0 not stored) into
   dir/lods.bin, listed in dir/manifest.json. scene_path resolves a
   strands scene's file. cache: NULL, made here; else the batch's. */
ht_result ht_lods_store(const char *dir, const ht_scene *scene, const char *scene_path, ht_lods_cache *cache,
                        char *err, size_t err_size);

#endif

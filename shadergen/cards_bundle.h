/* cards_bundle.h — a bundle for drawing cards (lod.h's ht_cards): the
   same tiers, programs and LUTs, with the material's albedo and detail
   textures replaced by the cards' atlas baked from them (hairgen --cards;
   docs/lod.md). Internal to libhairgen.

   Usage:
       char err[512];
       if (ht_cards_bundle_write("out/furball-bundle", "scenes/furball.json", 32, 1024,
                                 "out/furball-bundle-cards", stdout, err, sizeof err) != HT_OK)
           puts(err);   // one line naming the file and what is wrong
*/
#ifndef HT_CARDS_BUNDLE_H
#define HT_CARDS_BUNDLE_H

#include <stdint.h>
#include <stdio.h>

#include <hairtier/hairtier.h>

/* out_dir must not exist; it is made, filled and, on any failure, removed
   again. The bundle needs an albedo texture (the cards' coverage is its
   alpha); detail, when present, must be albedo's size. The atlas is
   atlas_size square (a power of two: the fixed-function tiers' GL 1.x
   takes no other), the manifest's textures.albedo and .detail say so;
   the manifest's file_sums are the source bundle's. summary (may be
   NULL) gets one line: cards, strands per card, atlas grid. */
ht_result ht_cards_bundle_write(const char *bundle_dir, const char *scene_path, uint32_t strands_per_card,
                                int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size);

/* The same from a mesh already built (sorted inside out, as
   ht_scene_build_meshes leaves it); hairview's --cards must build the same
   cards: ht_mesh_build_cards with this strands_per_card and atlas size. */
ht_result ht_cards_bundle_write_mesh(const char *bundle_dir, const ht_mesh *hair, uint32_t strands_per_card,
                                     int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size);

#endif

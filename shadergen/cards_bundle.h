/* cards_bundle.h — a bundle carrying every geometry level of a scene,
   strands and cards (lod.h; hairgen --cards; docs/lod.md): the same
   tiers, programs and LUTs; albedo and detail one atlas, the material's
   own texture in its top left (with a one-texel wrapped border) and the
   cards' cells baked from it below; lods.bin the strand levels (their uv
   mapped onto the material's part) and the cards in one buffer. Internal
   to libhairgen.

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
   alpha); detail, when present, must be albedo's size, and it fits the
   atlas with a one-texel border and room for the cards' cells below. The atlas is atlas_size square (a
   power of two: the fixed-function tiers' GL 1.x takes no other), the
   manifest's textures.albedo and .detail say so, its file_sums list the
   new files. summary (may be
   NULL) gets one line: cards, strands per card, atlas grid. */
ht_result ht_cards_bundle_write(const char *bundle_dir, const char *scene_path, uint32_t strands_per_card,
                                int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size);

/* The same from a mesh already built (sorted inside out, as
   ht_scene_build_meshes leaves it). */
ht_result ht_cards_bundle_write_mesh(const char *bundle_dir, const ht_mesh *hair, uint32_t strands_per_card,
                                     int atlas_size, const char *out_dir, FILE *summary, char *err, size_t err_size);

#endif

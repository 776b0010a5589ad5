/* grid_levels.h — the geometry levels haircompare draws (its level x tier
   grid, and level 0 for every tier's image): the bundle's stored ones
   (lods.bin, hairgen --scene or --cards) when they were made from this
   scene's mesh, else the ladder lod.h builds from that mesh.

   Usage:
       grid_levels lv;
       if (grid_levels_open("out/fb-cards", "scenes/furball.json", &hair, &lv, err, sizeof err) != HT_OK)
           puts(err);    // one line: a hostile lods.bin, another scene's cards
       for (int l = 0; l < lv.count; l++) {
           ht_mesh m;
           bool borrowed;
           if (grid_levels_mesh(&lv, &hair, l, &m, &borrowed) == HT_OK) {
               ... draw m (lv.cards[l]: a cards level) ...
               if (!borrowed) ht_mesh_free(&m);
           }
       }
       grid_levels_close(&lv); */
#ifndef HT_EXAMPLES_GRID_LEVELS_H
#define HT_EXAMPLES_GRID_LEVELS_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/lod.h>

typedef struct grid_levels {
    bool stored;                   /* the bundle's lods.bin is this scene's: its levels are drawn */
    bool other_scene;              /* the bundle has a lods.bin of another scene's (strand levels only) */
    ht_lod_file file;              /* when stored */
    int count;                     /* levels: the file's, else 1 + ht_lod_max_level */
    bool cards[HT_LOD_FILE_MAX_LEVELS];
    uint32_t param[HT_LOD_FILE_MAX_LEVELS]; /* the strand stride, or strands per card */
} grid_levels;

/* Which stored ladder BUNDLE has for a scene's mesh (hairview and
   haircompare read it alike). */
typedef enum stored_ladder { STORED_NONE, STORED_THIS_SCENE, STORED_OTHER_SCENE } stored_ladder;
/* BUNDLE/lods.bin into *file when it is made from hair (THIS_SCENE; free
   it with ht_lod_file_free); absent: NONE; another scene's strand levels:
   OTHER_SCENE (not kept). A file the reader refuses, or cards made from
   another mesh (their atlas is the bundle's textures, which this scene's
   mesh would sample wrongly), is an error: one line naming the file in
   err. path receives the file's path. */
ht_result stored_ladder_read(const char *bundle, const char *scene_name, const ht_mesh *hair, ht_lod_file *file,
                             stored_ladder *kind, char *path, size_t path_size, char *err, size_t err_size);

/* Reads BUNDLE/lods.bin when there is one. A file the reader refuses (a
   hostile one), or one holding cards made from another mesh than hair
   (their atlas is the bundle's textures, which the scene's own mesh
   would sample wrongly), is an error: one line naming the file. */
ht_result grid_levels_open(const char *bundle, const char *scene_name, const ht_mesh *hair, grid_levels *out,
                           char *err, size_t err_size);
/* Level `level`: the stored level (a copy), hair itself for a level 0 not
   stored or not built (*borrowed), else ht_mesh_build_lod of hair. */
ht_result grid_levels_mesh(const grid_levels *lv, const ht_mesh *hair, int level, ht_mesh *out, bool *borrowed);
void grid_levels_close(grid_levels *lv);

#endif

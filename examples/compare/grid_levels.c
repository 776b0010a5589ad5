/* grid_levels.c — the levels haircompare draws (grid_levels.h). */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "grid_levels.h"

ht_result stored_ladder_read(const char *bundle, const char *scene_name, const ht_mesh *hair, ht_lod_file *file,
                             stored_ladder *kind, char *path, size_t path_size, char *err, size_t err_size) {
    memset(file, 0, sizeof *file);
    *kind = STORED_NONE;
    snprintf(path, path_size, "%s/%s", bundle, HT_LOD_FILE_NAME);
    if (access(path, F_OK) != 0) return HT_OK;
    ht_result r = ht_lod_file_read(path, file, err, err_size);
    if (r != HT_OK) return r;
    if (ht_lod_file_matches(file, hair)) {
        *kind = STORED_THIS_SCENE;
        return HT_OK;
    }
    bool cards = false;
    for (int l = 0; l < file->level_count; l++) cards = cards || file->levels[l].kind == HT_LOD_KIND_CARDS;
    ht_lod_file_free(file);
    if (cards) {
        snprintf(err, err_size, "%s: its level 0 is not %s's mesh: these cards are another scene's", path, scene_name);
        return HT_ERR_INVALID_ARGUMENT;
    }
    *kind = STORED_OTHER_SCENE;
    return HT_OK;
}

ht_result grid_levels_open(const char *bundle, const char *scene_name, const ht_mesh *hair, grid_levels *out,
                           char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    out->count = ht_lod_max_level(hair) + 1;
    if (out->count > HT_LOD_FILE_MAX_LEVELS) out->count = HT_LOD_FILE_MAX_LEVELS;
    for (int l = 0; l < out->count; l++) {
        ht_lod_desc d;
        ht_lod_level(l, &d);
        out->param[l] = d.strand_stride;
    }
    char path[4200];
    stored_ladder kind;
    ht_result r = stored_ladder_read(bundle, scene_name, hair, &out->file, &kind, path, sizeof path, err, err_size);
    if (r != HT_OK || kind == STORED_NONE) return r;
    out->other_scene = kind == STORED_OTHER_SCENE;
    if (out->other_scene) return HT_OK;
    const ht_lod_file *f = &out->file;
    out->stored = true;
    out->count = f->level_count;
    for (int l = 0; l < f->level_count; l++) {
        out->cards[l] = f->levels[l].kind == HT_LOD_KIND_CARDS;
        out->param[l] = f->levels[l].param;
    }
    return HT_OK;
}

ht_result grid_levels_mesh(const grid_levels *lv, const ht_mesh *hair, int level, ht_mesh *out, bool *borrowed) {
    *borrowed = false;
    if (lv->stored && lv->file.levels[level].kind != HT_LOD_KIND_SCENE)
        return ht_lod_file_level_mesh(&lv->file, level, out);
    if (level == 0) {
        *borrowed = true;
        *out = *hair;
        return HT_OK;
    }
    ht_lod_desc d;
    ht_lod_level(level, &d);
    return ht_mesh_build_lod(hair, &d, out);
}

void grid_levels_close(grid_levels *lv) {
    ht_lod_file_free(&lv->file);
}

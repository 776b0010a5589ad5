/* scene_mesh.c — a scene's hair and head meshes, whatever the geometry:
   what hairview, tier_sheet and the tests build from a scene file. */
#include <string.h>

#include "errfmt.h"
#include "mesh_internal.h"
#include <hairtier/scene.h>

static ht_result build_strands(const ht_scene *s, const char *scene_file, ht_mesh *hair, ht_mesh *head, char *err,
                               size_t err_size) {
    ht_strands strands;
    ht_result r = ht_strands_load(s->strands.file, &strands, err, err_size);
    if (r != HT_OK) return r;
    char why[256];
    r = ht_mesh_build_strands(&strands, &s->strands.ribbon, hair, why, sizeof why);
    ht_strands_free(&strands);
    if (r != HT_OK)
        return ht_fail(err, err_size, r, "%s: geometry.%s (strand file %s)", scene_file, why, s->strands.file);
    if (head && s->strands.head_radius > 0) {
        r = ht_mesh_build_head(s->strands.head_radius, s->strands.ribbon.head_center, false, head);
        if (r != HT_OK) {
            ht_mesh_free(hair);
            return ht_fail(err, err_size, r, "%s: geometry.head: %s", scene_file, ht_result_string(r));
        }
    }
    return HT_OK;
}

ht_result ht_scene_build_meshes(const ht_scene *s, const char *scene_file, ht_mesh *hair, ht_mesh *head,
                                char *err, size_t err_size) {
    const char *file = scene_file ? scene_file : "<scene>";
    if (!s || !hair) return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: no scene or no mesh", file);
    memset(hair, 0, sizeof *hair);
    if (head) memset(head, 0, sizeof *head);
    if (s->geometry == HT_GEOMETRY_STRANDS) return build_strands(s, file, hair, head, err, err_size);
    ht_result r = s->geometry == HT_GEOMETRY_PATCHES ? ht_mesh_build_patches(&s->patches, hair, head)
                                                     : ht_mesh_build_furball(&s->furball, hair);
    if (r != HT_OK)
        return ht_fail(err, err_size, r, "%s: geometry: cannot build the mesh: %s", file, ht_result_string(r));
    ht_mesh_sort_inside_out(hair);
    return HT_OK;
}

/* scene_check.c — a strands scene's strand file read by the runtime's own
   reader (strands.h) before a bundle is made from it: hairgen hashes the
   file as an input, but a file the runtime refuses (a bad header, a NaN
   point, a wrong extension) would give a bundle hairview cannot draw. */
#include <stdio.h>

#include "errfmt.h"
#include "hairgen_internal.h"
#include <hairtier/strands.h>

ht_result ht_scene_check_strands(const ht_scene *scene, const char *scene_path, char *err, size_t err_size) {
    if (!scene || scene->geometry != HT_GEOMETRY_STRANDS) return HT_OK;
    ht_strands strands;
    char why[1024];
    ht_result r = ht_strands_load(scene->strands.file, &strands, why, sizeof why);
    /* The ribbons' one demand on the file's contents (mesh_strands.c). */
    if (r == HT_OK && scene->strands.ribbon.use_thickness && !strands.thickness) {
        snprintf(why, sizeof why, "%.900s: thickness: the file has none, and the scene's use_thickness needs it",
                 scene->strands.file);
        r = HT_ERR_PARSE;
    }
    ht_strands_free(&strands);
    if (r == HT_OK) return HT_OK;
    return ht_fail(err, err_size, r, "%s: geometry.file: %s", scene_path ? scene_path : "<scene>", why);
}

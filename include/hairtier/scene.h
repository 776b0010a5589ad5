/* scene.h — a scene to draw hair in: image size, camera, lights, which hair
   geometry to build; read from "hairtier-scene/1" files (docs/materials.md).
   Not needed to draw hair (hairtier.h is): the generator plans a material
   for a scene, and the examples and tests build and render one. The reader
   (runtime/io/scene_json.c) needs only cJSON, so hairview links it without the
   generator or glslang.

   Usage:
       ht_scene s;
       char err[512];
       if (ht_scene_load("scenes/furball.json", &s, err, sizeof err) != HT_OK) puts(err);
       ht_mesh hair, head;
       if (ht_scene_build_meshes(&s, "scenes/furball.json", &hair, &head, err, sizeof err) != HT_OK)
           puts(err);
       // ... draw hair (and head, when it has triangles) with s.camera and s.lights ...
       ht_mesh_free(&hair);
       ht_mesh_free(&head);

   Errors are one line "FILE: FIELD: what is wrong".

   Public: installed beside hairtier.h (hairgen.h plans for an ht_scene);
   it includes only hairtier.h. */
#ifndef HT_SCENE_H
#define HT_SCENE_H

#include "export.h"

#include <stddef.h>
#include <stdint.h>

#include "hairtier.h"
#include "ht_limits.h"
#include "strands.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum ht_geometry_kind {
    HT_GEOMETRY_FURBALL = 0,
    HT_GEOMETRY_PATCHES = 1,
    HT_GEOMETRY_STRANDS = 2,
} ht_geometry_kind;

/* "type": "strands": a strand file drawn as ribbons (mesh_strands.c). */
typedef struct ht_strands_scene {
    char file[HT_LIMIT_STRANDS_PATH + 1]; /* resolved against the scene file's folder */
    ht_strands_ribbon_desc ribbon;
    float head_radius;                    /* scene units; 0: no head drawn */
} ht_strands_scene;

typedef struct ht_scene {
    int width, height;          /* pixels */
    ht_camera camera;
    ht_light lights[HT_MAX_LIGHTS];
    int light_count;            /* 1..4 */
    float background[3];
    ht_geometry_kind geometry;
    ht_furball_desc furball;
    ht_patches_desc patches;
    ht_strands_scene strands;
} ht_scene;

HT_API ht_result ht_scene_load(const char *path, ht_scene *out, char *err, size_t err_size);
HT_API ht_result ht_scene_parse(const char *json_text, const char *file_name,
                         ht_scene *out, char *err, size_t err_size);
/* Bytes the scene's hair needs, every copy together (ht_limits.h), and the
   check every parse runs: above HT_LIMIT_SCENE_BYTES it fails with
   "FILE: geometry.hairs: needs about N GB ...". A strands scene counts the
   most points a strand file may hold (its file is read later, by
   ht_scene_build_meshes), which fits by construction. */
HT_API uint64_t ht_scene_memory_estimate(const ht_scene *s);
HT_API ht_result ht_scene_check_budget(const ht_scene *s, const char *file_name, char *err, size_t err_size);
/* The scene's hair, sorted inside out, and its opaque head (zeroed when
   the geometry has none; head may be NULL). A strands scene reads its file
   here: its errors name that file and field; the others say
   "FILE: geometry: cannot build the mesh: why". On failure both are zeroed. */
HT_API ht_result ht_scene_build_meshes(const ht_scene *s, const char *scene_file, ht_mesh *hair, ht_mesh *head,
                                char *err, size_t err_size);
/* The scene a material is planned for when none is given: one white
   directional light, the fur ball. */
HT_API void ht_scene_default(ht_scene *out);

#ifdef __cplusplus
}
#endif

#endif

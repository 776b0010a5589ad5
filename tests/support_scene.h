/* support_scene.h — what the tests that run the programs on shipped scenes
   share (test_render_scenes.c, test_render_accuracy.c, test_render_drivers.c,
   test_render_mediump.c, test_measure_lod.c, test_thin_strands.c): a command
   that must succeed, a scene copied elsewhere (smaller) that still finds its
   strand file, a bundle's tier names, and two frames' whole-frame metrics.

   Helpers that check fail the running cmocka test. */
#ifndef HT_SUPPORT_SCENE_H
#define HT_SUPPORT_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include <hairtier/scene.h>
#include "metrics.h"
#include "support_osmesa.h"

struct cJSON;

/* system(cmd); fails the test unless it exits 0. */
void ht_test_run_command(const char *cmd);
/* A scene's strand file path made absolute against the shipped scene's
   folder, so a copy of root written elsewhere draws the same file. */
void ht_test_keep_strand_file(struct cJSON *root, const char *shipped_scene);
/* The shipped scene copied to DIR/NAME at side² (0: as shipped), its strand
   file kept, with `hairs` fur-ball hairs (0: as shipped), without its head
   when asked; its path in out. */
const char *ht_test_scene_copy(const char *shipped_scene, const char *dir, const char *name, int side, int hairs,
                               bool no_head, char *out, size_t out_size);
/* For a group setup: the fur-ball scene copied to DIR/scene.json (side²,
   `hairs` hairs of `joints` joints, 0: as shipped) and `build/hairgen
   materials/dark-brown.json --scene DIR/scene.json OPTIONS -o DIR/bundle`
   run; 0, or -1 with hairgen's output on stderr. */
int ht_test_furball_bundle(const char *dir, int side, int hairs, int joints, const char *options);
/* The scene copy DIR/NAME, if it draws a TressFX strand file, made to draw
   every `every`-th strand of it instead: the positions of those strands
   written to DIR/NAME.tfx (the rest of that file is not drawn). */
void ht_test_scene_thin_strands(const char *dir, const char *name, int every);
/* The bundle's tiers, best first; the first must be `first`, and there are
   at least two. Returns how many. */
int ht_test_bundle_tiers(const char *bundle, char names[HT_TIER_COUNT][16], const char *first);

/* A scene file loaded and its meshes built (hair, and head when it has
   one), for drawing it in this process the way hairview does. */
typedef struct ht_test_view_scene {
    char path[600];
    ht_scene scene;
    ht_mesh hair, head;
} ht_test_view_scene;
void ht_test_view_scene_load(const char *path, ht_test_view_scene *out);
void ht_test_view_scene_free(ht_test_view_scene *s);
/* What `hairview --bundle BUNDLE --scene S --tier TIER --strict` draws
   (HAIRTIER_VARIANT=device when device, else exact), in this process: a
   renderer with the tier forced and strict (support_render.h's
   ht_test_renderer_create), the scene's hair and head, camera, lights and
   aspect, on its background, read back as RGBA. gl is made (or remade) at
   the scene's size when it is not already; ht_test_gl_destroy it after. */
void ht_test_view_draw(ht_test_gl *gl, const char *bundle, const ht_test_view_scene *s, const char *tier, bool device,
                       ht_image *img);

/* PSNR, SSIM and CIEDE2000 of test against reference over the whole frame
   (shadergen/metrics.h), from images of any channel count. */
ht_metrics ht_test_whole_frame_metrics(const ht_image *reference, const ht_image *test);

#endif

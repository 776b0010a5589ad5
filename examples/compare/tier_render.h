/* tier_render.h — what tier_sheet and haircompare share: a scene file's
   hair (and head) mesh built once, and one tier of a bundle rendered into
   it on a fresh offscreen context (platform/offscreen.h, the one place the
   programs make contexts), forced and strict, with its median frame time.

   Usage:
       tier_scene s;
       if (tier_scene_load("scenes/furball.json", &s, err, sizeof err) != HT_OK) puts(err);
       tier_frame f;
       tier_render("out/bundle", &s, HT_TIER_FIXED, 5, &f);
       if (f.ran) ... f.rgba (GL rows, bottom-up), f.frame_ms ...
       else puts(f.reason);
       tier_frame_free(&f);
       tier_scene_free(&s); */
#ifndef HT_EXAMPLES_TIER_RENDER_H
#define HT_EXAMPLES_TIER_RENDER_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include "offscreen.h"
#include <hairtier/scene.h>

typedef struct tier_scene {
    ht_scene scene;
    ht_mesh hair;   /* sorted inside out */
    ht_mesh head;   /* empty unless the geometry is patches */
    float opacity;  /* the hair's opacity scale (lod.h): 0 or 1 as the material has it, a soft level's 1/3 */
} tier_scene;

/* Reads the scene and builds its meshes; errors are one line naming the
   file ("SCENE: geometry: cannot build the mesh: out of memory"). */
ht_result tier_scene_load(const char *path, tier_scene *out, char *err, size_t err_size);
void tier_scene_free(tier_scene *s);

typedef struct tier_frame {
    bool ran;
    char reason[512];      /* the renderer's reason, or why the tier did not run */
    unsigned char *rgba;   /* width * height * 4, GL rows (bottom-up); NULL when it did not run */
    double frame_ms;       /* median of the timed frames, each ended by glFinish */
    char driver[128];      /* GL_RENDERER of the context, "" when none was made */
} tier_frame;

/* Renders `tier` of the bundle with one warm-up frame, then `frames` (>= 1)
   timed ones. A tier the device cannot run (strict: no fall to the next)
   leaves ran false and the log's reason in `reason`. */
void tier_render(const char *bundle, const tier_scene *s, ht_tier tier, int frames, tier_frame *out);
/* How tier_render makes its contexts from now on (--context, --egl-device;
   offscreen.h): OFFSCREEN_AUTO and -1 until a program says otherwise. */
void tier_render_use_context(offscreen_kind kind, int egl_device, offscreen_api api);
void tier_frame_free(tier_frame *f);

#endif

/* support_render.h — what the renderer tests share around ht_renderer:
   the fur-ball fixture (a scratch directory holding the dark-brown fur-ball
   bundle, an OSMesa context, the fur-ball mesh sorted inside out, its two
   lights), a renderer factory that records the trace and captures the log
   (support_log.h), one frame drawn and read back, coverage counts, and
   re-running the test binary under MESA_GL_VERSION_OVERRIDE.

   Helpers that check fail the running cmocka test. */
#ifndef HT_SUPPORT_RENDER_H
#define HT_SUPPORT_RENDER_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include "support_osmesa.h"

typedef struct ht_test_furball {
    char work[64];          /* scratch directory */
    char bundle_dir[128];   /* materials/dark-brown.json x scenes/furball.json (ht_test_bundle: make's fixture, else work/bundle); read only */
    ht_test_gl gl;          /* size x size, current */
    ht_mesh mesh;           /* 400 hairs (support_driver.h: fewer on softpipe), sorted inside out */
} ht_test_furball;

/* For cmocka group setup/teardown: false (with the reason on stderr) when
   anything cannot be made; name tells the scratch directory apart. */
bool ht_test_furball_setup(ht_test_furball *f, const char *name, int size);
int ht_test_furball_teardown(ht_test_furball *f);
/* A scratch directory and a current size x size context, for tests that
   write their own bundles; the same contract as the fur-ball fixture. */
typedef struct ht_test_scratch_gl {
    char work[64];
    ht_test_gl gl;
} ht_test_scratch_gl;
bool ht_test_scratch_gl_setup(ht_test_scratch_gl *f, const char *name, int size);
int ht_test_scratch_gl_teardown(ht_test_scratch_gl *f);
/* The fixture's mesh on its own (for a child process). */
ht_result ht_test_furball_mesh(ht_mesh *out);
/* The two lights (directional key, point fill), looked at from (0, 0.3, eye_z). */
ht_frame_desc ht_test_furball_frame(float eye_z);
/* The same camera d from the target, turned deg about the vertical. */
ht_frame_desc ht_test_furball_orbit_frame(float d, double deg);
/* The bundle of material_path (materials/NAME.json) for scenes/SCENE.json:
   the one make builds once for the render tests to share (Makefile,
   FIXTURE_BUNDLES, build/fixtures/NAME/SCENE: a Marschner material's bake
   and fit cost about 2 s a bundle) where it is there, else generated from
   scene_path (SCENE.json or a copy of it at another size or hair count,
   which gives the same bundle but for its input_hash) into dir. On HT_OK
   dir holds the bundle's path. Read only: a test that edits a bundle
   copies it. */
ht_result ht_test_bundle(const char *material_path, const char *scene, const char *scene_path, char *dir,
                         size_t size, char *err, size_t err_size);
/* A copy of the fixture's bundle at work/NAME, to break. */
void ht_test_furball_copy_bundle(const ht_test_furball *f, const char *name, char *out, size_t size);

extern const float ht_test_background[3];   /* the clear colour of the coverage tests */

/* ht_renderer_create with getproc (unless set), the log capture and the
   trace; bundle_dir unless desc sets one. Fails the test, showing the log,
   unless the result is expect. */
ht_renderer *ht_test_renderer_create(ht_renderer_desc desc, const char *bundle_dir, ht_result expect);
/* Clears the whole context to clear (depth too), draws f without error,
   reads it back. */
void ht_test_draw(const ht_test_gl *gl, ht_renderer *r, const ht_frame_desc *f, const float clear[3],
                  ht_image *img);

typedef struct ht_test_pixel_stats {
    int changed;    /* more than 2/255 from background in some channel */
    int magenta;    /* what a failed shader looks like */
} ht_test_pixel_stats;

ht_test_pixel_stats ht_test_pixel_stats_of(const ht_image *img, const float background[3]);

/* The child side: a size x size context and a renderer on bundle_dir,
   printing the renderer's log and "result=RESULT tier=TIER" on stdout for
   the parent to read. *r is NULL unless the result is HT_OK. False when no
   context could be made (the reason printed). */
bool ht_test_child_renderer(const char *bundle_dir, int size, ht_test_gl *gl, ht_renderer **r);
/* The whole child side when a test only needs the selection: a 16 x 16
   context and a renderer (ht_test_child_renderer), then nothing. The exit
   status for main. */
int ht_test_child_select_only(const char *bundle_dir);
/* One line per trace entry ("trace pass P.S cull ... range F+N error E"),
   so traces of two tiers or two processes compare as text. */
void ht_test_format_trace(const ht_trace *t, char *out, size_t size);
/* Runs this test binary as `EXE --child BUNDLE_DIR` with
   MESA_GL_VERSION_OVERRIDE=version (Mesa reads it once per process);
   out receives its stdout and stderr. The child must exit 0. */
void ht_test_run_child(const char *version, const char *bundle_dir, char *out, size_t size);

#endif

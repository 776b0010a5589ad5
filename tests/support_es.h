/* support_es.h — the GL ES render tests' shared work (test_render_es1,
   test_render_es2, test_render_es3): every shipped scene, small, drawn with
   each tier of its bundle the API runs forced and with auto, on a real EGL GL ES context and on a
   desktop GL context of the same driver, compared in PSNR.

   Usage:
       ht_test_es_scenes(OFFSCREEN_API_GLES3, NULL, &(ht_test_es_result){0});
   The bundles are generated once per process into a scratch folder
   (ht_test_es_bundles / ht_test_es_cleanup). */
#ifndef HT_SUPPORT_ES_H
#define HT_SUPPORT_ES_H

#include <stdbool.h>
#include <stdint.h>

#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "offscreen.h"

/* The side of the test images, and the fur balls' hairs (of 8000 shipped). */
#define HT_TEST_ES_SIZE 96
#define HT_TEST_ES_FURBALL_HAIRS 1500
/* Against the same tier on desktop GL (issue 21). */
#define HT_TEST_ES_MIN_PSNR_DB 40.0

typedef struct ht_test_es_draw {
    ht_image image;            /* RGBA, rows top to bottom */
    ht_tier tier;              /* the tier that drew */
    ht_trace trace;
    uint32_t index_count;      /* the hair mesh's */
    bool uploads_order;        /* HT_TEST_ES_REORDERED: ht_renderer_set_mesh_order returned HT_OK */
    bool width_rule_vertex;    /* HT_TEST_ES_WIDTH_RULE: ht_renderer_width_rule_per_vertex */
    char log[1024];            /* the renderer's lines, newline-separated (cut) */
} ht_test_es_draw;

/* One frame of a shipped scene (scenes/NAME.json) with bundle on a fresh
   context of api, the tier forced (strict), HT_TIER_AUTO, or flat mode
   (HT_TIER_COUNT: the geometry floor, no bundle), the profile
   applied (NULL: none). False with why in out->log when any step fails. */
bool ht_test_es_draw_scene(const char *bundle, const char *scene, offscreen_api api, ht_tier tier,
                           const ht_device_profile *profile, ht_test_es_draw *out);
/* The same with furball_hairs hairs on a fur ball scene. */
bool ht_test_es_draw_scene_hairs(const char *bundle, const char *scene, offscreen_api api, ht_tier tier,
                                 const ht_device_profile *profile, int furball_hairs, ht_test_es_draw *out);
/* The hair's order in a draw: as built (inside out); sorted back to front
   from the camera's eye (ht_mesh_sort_back_to_front) before its upload;
   or uploaded as built and then given that order by
   ht_renderer_set_mesh_order (out->uploads_order: it returned HT_OK). */
/* HT_TEST_ES_WIDTH_RULE: back to front with the width rule per vertex
   (ht_renderer_set_width_rule, ht_renderer_set_back_to_front), as
   hairview --width-rule draws strands under 1.5 px (out->width_rule_vertex:
   the renderer did it per vertex). */
typedef enum ht_test_es_order {
    HT_TEST_ES_INSIDE_OUT,
    HT_TEST_ES_BACK_TO_FRONT,
    HT_TEST_ES_REORDERED,
    HT_TEST_ES_WIDTH_RULE
} ht_test_es_order;
bool ht_test_es_draw_scene_ordered(const char *bundle, const char *scene, offscreen_api api, ht_tier tier,
                                   const ht_device_profile *profile, int furball_hairs, ht_test_es_order order,
                                   ht_test_es_draw *out);
void ht_test_es_draw_free(ht_test_es_draw *d);
/* Whole-frame PSNR of two draws. */
double ht_test_es_psnr(const ht_test_es_draw *a, const ht_test_es_draw *b);

/* The shipped scenes and their bundles (generated once per process). The
   first HT_TEST_ES_TEXT_SCENES carry every distinct GLSL text: dark-brown's
   furball, patches and ratboy bundles emit byte-identical .vert/.frag (the
   scene changes uniforms and LUT contents only), brown-marschner's backlit
   adds the marschner tier and its own full and vertex texts. */
#define HT_TEST_ES_SCENES 4
#define HT_TEST_ES_TEXT_SCENES 2
enum { HT_TEST_ES_FURBALL, HT_TEST_ES_BACKLIT, HT_TEST_ES_PATCHES, HT_TEST_ES_RATBOY };
extern const char *const ht_test_es_scene_names[HT_TEST_ES_SCENES];
const char *ht_test_es_bundle(int scene);
void ht_test_es_cleanup(void);
/* The ES tests' group teardown: ht_test_es_cleanup. */
int ht_test_es_teardown(void **state);

/* The same passes, fixed state, ranges and no GL error in both traces (the
   ES 2.0+ alpha test is the texts' discard, recorded from the one rule). */
void ht_test_es_assert_same_passes(const ht_test_es_draw *desk, const ht_test_es_draw *es);

/* Every scene, each tier of its bundle that api runs (ES 1.x: fixed4, fixed,
   gl11; ES 2.0+: the GLSL tiers) forced, and auto on the first scene: api against desktop GL
   at HT_TEST_ES_MIN_PSNR_DB, the same tier drawn on both, the same passes;
   prints one line per draw (scene, tier, dB). Fails the cmocka test. The
   first `scenes` of ht_test_es_scene_names (HT_TEST_ES_SCENES: all). */
void ht_test_es_scenes_match_desktop(offscreen_api api, const ht_device_profile *profile, int scenes);

#endif

/* support_es.c — see support_es.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairgen.h>
#include <hairtier/lod.h>
#include <hairtier/scene.h>
#include "metrics.h"
#include "support_driver.h"
#include "support_es.h"
#include "support_render.h"
#include "support_scratch.h"

const char *const ht_test_es_scene_names[HT_TEST_ES_SCENES] = { "furball", "backlit", "patches", "ratboy" };
static const char *const materials[HT_TEST_ES_SCENES] = { "dark-brown", "brown-marschner", "dark-brown", "dark-brown" };

static char work[64];
static char bundles[HT_TEST_ES_SCENES][128];
/* One context per API for the whole process: a fresh one per draw costs
   llvmpipe its shader compiles again, and every frame restores the state
   it found (hairtier.h), which the next draw then relies on. */
static offscreen *contexts[OFFSCREEN_API_GLES3 + 1];

static offscreen *context_of(offscreen_api api, char *err, size_t err_size) {
    if (contexts[api]) return offscreen_make_current(contexts[api]) ? contexts[api] : NULL;
    contexts[api] = offscreen_open(&(offscreen_desc){ .kind = OFFSCREEN_EGL, .api = api, .width = HT_TEST_ES_SIZE,
                                                      .height = HT_TEST_ES_SIZE, .egl_device = -1 },
                                   err, err_size);
    return contexts[api];
}

const char *ht_test_es_bundle(int i) {
    if (!work[0] && !ht_test_scratch_create(work, sizeof work, "es")) return NULL;
    if (!bundles[i][0]) {
        char material[96], scene[96], dir[128], err[1024];
        snprintf(material, sizeof material, "materials/%s.json", materials[i]);
        snprintf(scene, sizeof scene, "scenes/%s.json", ht_test_es_scene_names[i]);
        snprintf(dir, sizeof dir, "%s/%s", work, ht_test_es_scene_names[i]);
        if (ht_test_bundle(material, ht_test_es_scene_names[i], scene, dir, sizeof dir, err, sizeof err) != HT_OK) {
            print_error("%s\n", err);
            return NULL;
        }
        snprintf(bundles[i], sizeof bundles[i], "%s", dir);
    }
    return bundles[i];
}

void ht_test_es_cleanup(void) {
    for (size_t i = 0; i < sizeof contexts / sizeof contexts[0]; i++) {
        offscreen_close(contexts[i]);
        contexts[i] = NULL;
    }
    if (work[0]) ht_test_scratch_remove(work);
    work[0] = '\0';
    memset(bundles, 0, sizeof bundles);
}

int ht_test_es_teardown(void **state) {
    (void)state;
    ht_test_es_cleanup();
    return 0;
}

static void keep_log(void *user, const char *line) {
    ht_test_es_draw *d = user;
    size_t n = strlen(d->log);
    snprintf(d->log + n, sizeof d->log - n, "%s\n", line);
}

bool ht_test_es_draw_scene(const char *bundle, const char *scene_name, offscreen_api api, ht_tier tier,
                           const ht_device_profile *profile, ht_test_es_draw *out) {
    return ht_test_es_draw_scene_hairs(bundle, scene_name, api, tier, profile, HT_TEST_ES_FURBALL_HAIRS, out);
}

bool ht_test_es_draw_scene_hairs(const char *bundle, const char *scene_name, offscreen_api api, ht_tier tier,
                                 const ht_device_profile *profile, int furball_hairs, ht_test_es_draw *out) {
    return ht_test_es_draw_scene_ordered(bundle, scene_name, api, tier, profile, furball_hairs, HT_TEST_ES_INSIDE_OUT,
                                         out);
}

bool ht_test_es_draw_scene_ordered(const char *bundle, const char *scene_name, offscreen_api api, ht_tier tier,
                                   const ht_device_profile *profile, int furball_hairs, ht_test_es_order order,
                                   ht_test_es_draw *out) {
    memset(out, 0, sizeof *out);
    char path[96], err[1024];
    snprintf(path, sizeof path, "scenes/%s.json", scene_name);
    ht_scene s;
    ht_mesh hair = { 0 }, head = { 0 };
    if (ht_scene_load(path, &s, err, sizeof err) != HT_OK) {
        snprintf(out->log, sizeof out->log, "%s", err);
        return false;
    }
    /* Small and cheap: the same camera and lights, fewer pixels and hairs
       (fewer again on the softpipe run: support_driver.h). */
    s.width = s.height = HT_TEST_ES_SIZE;
    if (s.geometry == HT_GEOMETRY_FURBALL) s.furball.hairs = ht_test_driver_hairs(furball_hairs);
    if (ht_scene_build_meshes(&s, path, &hair, &head, err, sizeof err) != HT_OK) {
        snprintf(out->log, sizeof out->log, "%s", err);
        return false;
    }
    bool ok = false;
    offscreen *gl = context_of(api, err, sizeof err);
    ht_renderer *r = NULL;
    if (!gl) {
        snprintf(out->log, sizeof out->log, "%s", err);
        goto done;
    }
    const bool flat = tier == HT_TIER_COUNT;
    ht_renderer_desc desc = { .getproc = offscreen_getproc, .bundle_dir = flat ? NULL : bundle,
                              .tier = flat ? HT_TIER_AUTO : tier, .strict = tier != HT_TIER_AUTO && !flat,
                              .log = keep_log, .log_user = out, .record_trace = true, .flat = flat };
    if (profile) desc.profile = *profile;
    if (order == HT_TEST_ES_BACK_TO_FRONT || order == HT_TEST_ES_WIDTH_RULE)
        ht_mesh_sort_back_to_front(&hair, s.camera.eye);
    if (ht_renderer_create(&desc, &r) != HT_OK) goto done;
    if (order == HT_TEST_ES_WIDTH_RULE) {
        ht_renderer_set_width_rule(r, true);
        ht_renderer_set_back_to_front(r, true);
    }
    if (ht_renderer_set_mesh(r, &hair) != HT_OK) goto done;
    out->width_rule_vertex = ht_renderer_width_rule_per_vertex(r);
    if (order == HT_TEST_ES_REORDERED) {
        ht_mesh_sort_back_to_front(&hair, s.camera.eye);
        out->uploads_order = ht_renderer_set_mesh_order(r, &hair) == HT_OK;
    }
    ht_frame_desc frame = { .camera = s.camera, .lights = s.lights, .light_count = s.light_count, .aspect = 1.0f,
                            .opaque = head.index_count ? &head : NULL };
    gl->gl.ClearColor(s.background[0], s.background[1], s.background[2], 1.0f);
    gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (ht_renderer_draw(r, &frame) != HT_OK) goto done;
    out->tier = ht_renderer_tier(r);
    out->index_count = hair.index_count;
    out->trace = *ht_renderer_trace(r);
    const unsigned char *rgba = offscreen_read(gl);
    if (ht_image_alloc(&out->image, s.width, s.height, 4) != HT_OK) goto done;
    for (int y = 0; y < s.height; y++)
        memcpy(out->image.pixels + (size_t)y * s.width * 4, offscreen_row(rgba, s.width, s.height, y),
               (size_t)s.width * 4);
    ok = true;
done:
    ht_renderer_destroy(r);
    ht_mesh_free(&hair);
    ht_mesh_free(&head);
    return ok;
}

void ht_test_es_draw_free(ht_test_es_draw *d) { ht_image_free(&d->image); }

double ht_test_es_psnr(const ht_test_es_draw *a, const ht_test_es_draw *b) {
    ht_metrics whole;
    char err[256];
    ht_metrics_desc md = { .reference = a->image.pixels, .test = b->image.pixels, .width = a->image.width,
                           .height = a->image.height };
    if (ht_metrics_compare(&md, &whole, NULL, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return whole.psnr_db;
}

/* The tiers of a bundle that api runs, best first, then auto: on ES 1.x
   the fixed-function tiers (their programs), on ES 2.0+ the GLSL tiers
   with an ES text. */
static int tiers_to_draw(const char *bundle, offscreen_api api, ht_tier out[4]) {
    static const ht_tier glsl[] = { HT_TIER_MARSCHNER, HT_TIER_FULL, HT_TIER_VERTEX };
    static const ht_tier fixed[] = { HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
    const bool es1 = api == OFFSCREEN_API_GLES1;
    char path[192];
    int n = 0;
    for (size_t i = 0; i < 3; i++) {
        const ht_tier t = es1 ? fixed[i] : glsl[i];
        snprintf(path, sizeof path, es1 ? "%s/%s.json" : "%s/%s-es2.frag", bundle, ht_tier_name(t));
        FILE *f = fopen(path, "rb");
        if (f) {
            fclose(f);
            out[n++] = t;
        }
    }
    out[n++] = HT_TIER_AUTO;
    return n;
}

void ht_test_es_assert_same_passes(const ht_test_es_draw *desk, const ht_test_es_draw *es) {
    assert_true(es->trace.count >= 4);
    assert_int_equal(es->trace.count, desk->trace.count);
    for (int k = 0; k < es->trace.count; k++) {
        const ht_trace_entry *a = &desk->trace.entries[k], *b = &es->trace.entries[k];
        assert_int_equal(a->pass, b->pass);
        assert_int_equal(a->sub_pass, b->sub_pass);
        assert_int_equal(a->cull, b->cull);
        if (a->cull) assert_int_equal(a->cull_face, b->cull_face);
        assert_int_equal(a->depth_func, b->depth_func);
        assert_int_equal(a->depth_write, b->depth_write);
        assert_int_equal(a->color_write, b->color_write);
        assert_int_equal(a->blend, b->blend);
        assert_true(b->alpha_test);
        assert_int_equal(a->alpha_func, b->alpha_func);
        assert_true(a->alpha_ref == b->alpha_ref);
        assert_int_equal(a->index_count, b->index_count);
        assert_int_equal(b->gl_error, 0);
    }
}

void ht_test_es_scenes_match_desktop(offscreen_api api, const ht_device_profile *profile, int scenes) {
    for (int s = 0; s < scenes && s < HT_TEST_ES_SCENES; s++) {
        const char *bundle = ht_test_es_bundle(s);
        assert_non_null(bundle);
        ht_tier tiers[4];
        int n = tiers_to_draw(bundle, api, tiers);
        assert_true(n >= 3); /* two tiers at least, then auto */
        /* Auto on the first scene only: it picks by the device and the
           manifest, never the scene, and draws the text its forced tier
           drew (a second compile of it). */
        if (s > 0) n--;
        /* Auto on desktop GL draws the top tier (ES 1.x: the top fixed-function
           tier, when the device runs it): its forced draw stands for it. */
        ht_test_es_draw top = { 0 };
        for (int t = 0; t < n; t++) {
            ht_test_es_draw desk, es;
            if (!ht_test_es_draw_scene(bundle, ht_test_es_scene_names[s], api, tiers[t], profile, &es))
                fail_msg("%s %s on %s: %s", ht_test_es_scene_names[s], ht_tier_name(tiers[t]),
                         offscreen_api_name(api), es.log);
            if (tiers[t] == HT_TIER_AUTO) {
                desk = top;
            } else if (!ht_test_es_draw_scene(bundle, ht_test_es_scene_names[s], OFFSCREEN_API_GL, tiers[t], NULL,
                                              &desk)) {
                fail_msg("%s %s on desktop GL: %s", ht_test_es_scene_names[s], ht_tier_name(tiers[t]), desk.log);
            }
            double db = ht_test_es_psnr(&desk, &es);
            printf("%-8s %-9s %s: %s drew %s, %.2f dB against desktop GL's %s\n", ht_test_es_scene_names[s],
                   ht_tier_name(tiers[t]), offscreen_api_name(api), offscreen_api_name(api), ht_tier_name(es.tier),
                   db, ht_tier_name(desk.tier));
            assert_int_equal(es.tier, desk.tier);
            ht_test_es_assert_same_passes(&desk, &es);
            /* The ESSL 1.00 text on ES 2.0, 3.00 on ES 3.x (unless a profile lowers it). */
            if (!profile && api != OFFSCREEN_API_GLES1)
                assert_non_null(strstr(es.log, api == OFFSCREEN_API_GLES2 ? "-es2.frag (ESSL 1.00" : "-es3.frag (ESSL 3.00"));
            if (!(db >= HT_TEST_ES_MIN_PSNR_DB))
                fail_msg("%s %s: %.2f dB < %.0f dB", ht_test_es_scene_names[s], ht_tier_name(tiers[t]), db,
                         HT_TEST_ES_MIN_PSNR_DB);
            if (t == 0) top = desk;
            else ht_test_es_draw_free(&desk);
            ht_test_es_draw_free(&es);
        }
        if (tiers[n - 1] != HT_TIER_AUTO) ht_test_es_draw_free(&top); /* else freed as auto's desk */
    }
}

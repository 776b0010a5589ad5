/* support_render.c — see support_render.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <GL/gl.h>

#include <hairtier/hairgen.h>
#include "support_log.h"
#include "support_driver.h"
#include "support_render.h"
#include "support_scratch.h"

const float ht_test_background[3] = { 0.1f, 0.2f, 0.3f };

static const ht_light furball_lights[2] = {
    { HT_LIGHT_DIRECTIONAL, { 0.6f, 0.8f, 0.7f }, { 1, 0.97f, 0.92f } },
    { HT_LIGHT_POINT, { -2, 0.5f, 2 }, { 0.4f, 0.4f, 0.5f } },
};

ht_result ht_test_furball_mesh(ht_mesh *out) {
    const ht_furball_desc desc = { .hairs = ht_test_driver_hairs(400), .joints = 8, .length = 0.12f,
                                   .width = 0.03f, .seed = 3 };
    ht_result r = ht_mesh_build_furball(&desc, out);
    if (r == HT_OK) ht_mesh_sort_inside_out(out);
    return r;
}

bool ht_test_furball_setup(ht_test_furball *f, const char *name, int size) {
    memset(f, 0, sizeof *f);
    unsetenv("HAIRTIER_TIER");
    if (!ht_test_scratch_create(f->work, sizeof f->work, name)) return false;
    snprintf(f->bundle_dir, sizeof f->bundle_dir, "%s/bundle", f->work);
    char err[1024];
    if (ht_test_bundle("materials/dark-brown.json", "furball", "scenes/furball.json", f->bundle_dir,
                       sizeof f->bundle_dir, err, sizeof err) != HT_OK) {
        fprintf(stderr, "setup: %s\n", err);
        return false;
    }
    if (!ht_test_gl_create(&f->gl, size, size, NULL, err, sizeof err)) {
        fprintf(stderr, "setup: %s\n", err);
        return false;
    }
    return ht_test_furball_mesh(&f->mesh) == HT_OK;
}

int ht_test_furball_teardown(ht_test_furball *f) {
    ht_mesh_free(&f->mesh);
    ht_test_gl_destroy(&f->gl);
    return ht_test_scratch_remove(f->work);
}

bool ht_test_scratch_gl_setup(ht_test_scratch_gl *f, const char *name, int size) {
    memset(f, 0, sizeof *f);
    unsetenv("HAIRTIER_TIER");
    if (!ht_test_scratch_create(f->work, sizeof f->work, name)) return false;
    char err[512];
    if (!ht_test_gl_create(&f->gl, size, size, NULL, err, sizeof err)) {
        fprintf(stderr, "setup: %s\n", err);
        return false;
    }
    return true;
}

int ht_test_scratch_gl_teardown(ht_test_scratch_gl *f) {
    ht_test_gl_destroy(&f->gl);
    return ht_test_scratch_remove(f->work);
}

ht_frame_desc ht_test_furball_frame(float eye_z) {
    return (ht_frame_desc){ .camera = { .eye = { 0, 0.3f, eye_z }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 },
                                        .fov_y = 45 },
                            .lights = furball_lights, .light_count = 2 };
}

ht_frame_desc ht_test_furball_orbit_frame(float d, double deg) {
    ht_frame_desc f = ht_test_furball_frame(d);
    const double a = deg * M_PI / 180.0;
    f.camera.eye[0] = (float)(d * sin(a));
    f.camera.eye[2] = (float)(d * cos(a));
    return f;
}

void ht_test_furball_copy_bundle(const ht_test_furball *f, const char *name, char *out, size_t size) {
    snprintf(out, size, "%s/%s", f->work, name);
    ht_test_copy_dir(f->bundle_dir, out);
}

ht_renderer *ht_test_renderer_create(ht_renderer_desc desc, const char *bundle_dir, ht_result expect) {
    ht_test_log_clear();
    if (!desc.getproc) desc.getproc = ht_test_getproc;
    desc.log = ht_test_log_capture;
    desc.record_trace = true;
    if (!desc.bundle_dir) desc.bundle_dir = bundle_dir;
    ht_renderer *r = NULL;
    ht_result res = ht_renderer_create(&desc, &r);
    if (res != expect)
        fail_msg("ht_renderer_create: %s, expected %s; log:\n%s", ht_result_string(res), ht_result_string(expect),
                 ht_test_log_text);
    return r;
}

void ht_test_draw(const ht_test_gl *gl, ht_renderer *r, const ht_frame_desc *f, const float clear[3],
                  ht_image *img) {
    glViewport(0, 0, gl->width, gl->height);
    glClearColor(clear[0], clear[1], clear[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    assert_int_equal(ht_renderer_draw(r, f), HT_OK);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    assert_int_equal(ht_test_gl_read(gl, img), HT_OK);
}

ht_test_pixel_stats ht_test_pixel_stats_of(const ht_image *img, const float background[3]) {
    ht_test_pixel_stats s = { 0, 0 };
    int bg[3];
    for (int k = 0; k < 3; k++) bg[k] = (int)(background[k] * 255.0f + 0.5f);
    for (int i = 0; i < img->width * img->height; i++) {
        const uint8_t *p = img->pixels + 4 * i;
        if (abs(p[0] - bg[0]) > 2 || abs(p[1] - bg[1]) > 2 || abs(p[2] - bg[2]) > 2) s.changed++;
        if (p[0] > 200 && p[1] < 60 && p[2] > 200) s.magenta++;
    }
    return s;
}

void ht_test_run_child(const char *version, const char *bundle_dir, char *out, size_t size) {
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    assert_true(n > 0);
    exe[n] = '\0';
    char cmd[PATH_MAX + 512];
    snprintf(cmd, sizeof cmd, "MESA_GL_VERSION_OVERRIDE=%s '%s' --child '%s' 2>&1", version, exe, bundle_dir);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t used = fread(out, 1, size - 1, p);
    out[used] = '\0';
    assert_int_equal(pclose(p), 0);
}

bool ht_test_child_renderer(const char *bundle_dir, int size, ht_test_gl *gl, ht_renderer **r) {
    char err[256];
    *r = NULL;
    if (!ht_test_gl_create(gl, size, size, NULL, err, sizeof err)) {
        printf("child: %s\n", err);
        return false;
    }
    ht_test_log_clear();
    ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, .bundle_dir = bundle_dir,
                                                            .log = ht_test_log_capture }, r);
    fputs(ht_test_log_text, stdout);
    printf("result=%s tier=%s\n", ht_result_string(res), res == HT_OK ? ht_tier_name(ht_renderer_tier(*r)) : "-");
    if (res != HT_OK) *r = NULL;
    return true;
}

int ht_test_child_select_only(const char *bundle_dir) {
    ht_test_gl gl;
    ht_renderer *r;
    if (!ht_test_child_renderer(bundle_dir, 16, &gl, &r)) return 1;
    ht_renderer_destroy(r);
    ht_test_gl_destroy(&gl);
    return 0;
}

void ht_test_format_trace(const ht_trace *t, char *out, size_t size) {
    out[0] = '\0';
    for (int i = 0; i < t->count; i++) {
        const ht_trace_entry *e = &t->entries[i];
        size_t used = strlen(out);
        snprintf(out + used, size - used,
                 "trace pass %d.%d cull %d/0x%04x depth 0x%04x/%d color %d blend %d alpha %d/0x%04x/%.6f "
                 "range %u+%u error 0x%04x\n", (int)e->pass, e->sub_pass, e->cull, e->cull_face, e->depth_func,
                 e->depth_write, e->color_write, e->blend, e->alpha_test, e->alpha_func, (double)e->alpha_ref,
                 e->first_index, e->index_count, e->gl_error);
    }
}

ht_result ht_test_bundle(const char *material_path, const char *scene, const char *scene_path, char *dir,
                         size_t size, char *err, size_t err_size) {
    const char *slash = strrchr(material_path, '/'), *name = slash ? slash + 1 : material_path;
    const size_t name_length = strcspn(name, ".");
    char fixture[1024], manifest[1100];
    int n = snprintf(fixture, sizeof fixture, "%s/fixtures/%.*s/%s", ht_test_build_dir(), (int)name_length, name,
                     scene);
    snprintf(manifest, sizeof manifest, "%s/manifest.json", fixture);
    if (n > 0 && (size_t)n < size && access(manifest, R_OK) == 0) {
        memcpy(dir, fixture, (size_t)n + 1);
        return HT_OK;
    }
    return ht_generate_bundle(material_path, scene_path, dir, NULL, err, err_size);
}

/* test_render_gl11 — the `gl11` tier's backend (fallback/gl11.c) on
   OSMesa, on whichever Mesa driver runs it.

   - Forced (strict) on the fur ball: the full tier's pass list, state and
     draw ranges, hair drawn (neither blank nor magenta), no GL error, and
     no texture unit but 0, no shader (its colours' buffer object:
     test_render_buffer_arrays).
   - Mesa's own MESA_GL_VERSION_OVERRIDE=1.1 in a re-executed child: the
     runtime picks gl11 and logs why full, vertex, fixed4 and fixed were
     skipped; same trace as full; hair drawn (printed: whether the runtime
     found VBOs there, ARB_vertex_buffer_object; the no-VBO path is
     test_render_buffer_arrays's no_vbo profile).
   - The colour cache: the first frame shades every vertex on the CPU, an
     identical second frame shades none, a moved eye or a changed light
     colour shades every vertex again (ht_gl11_cpu_vertices).
   - After a frame the application's texture binding, texture enables,
     colour array and current colour are back.
   Prints the mean and max difference from the full tier's image (not a
   bound: what the tier's drops cost on this scene). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "gl11.h"
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"

#define SIZE 128

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "gl11", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static ht_frame_desc furball_frame(void) { return ht_test_furball_frame(2.0f); }

static ht_test_pixel_stats stats(const ht_image *img) { return ht_test_pixel_stats_of(img, ht_test_background); }

/* The full tier's trace and image of the fur-ball frame. */
static void full_tier(char *trace, size_t size, ht_image *img) {
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true },
                                             fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_frame_desc f = furball_frame();
    ht_test_draw(&fx.gl, r, &f, ht_test_background, img);
    ht_test_format_trace(ht_renderer_trace(r), trace, size);
    ht_renderer_destroy(r);
}

static void test_forced_gl11_draws_the_full_tiers_passes(void **state) {
    (void)state;
    static char full_trace[4096], trace[4096];
    ht_image full_img, img;
    full_tier(full_trace, sizeof full_trace, &full_img);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_GL11, .strict = true },
                                             fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_GL11);
    assert_true(ht_test_logged("hairtier: gl11: 1 unit"));
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_frame_desc f = furball_frame();
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    ht_test_format_trace(ht_renderer_trace(r), trace, sizeof trace);
    assert_string_equal(trace, full_trace);
    ht_test_pixel_stats s = stats(&img), sf = stats(&full_img);
    assert_int_equal(s.magenta, 0);
    assert_true(s.changed > SIZE * SIZE / 20);
    /* the same alpha and passes: the same hair shows, shaded differently */
    assert_true(s.changed >= sf.changed * 9 / 10);
    double sum = 0, sq = 0;
    int most = 0, n = 0;
    for (int i = 0; i < SIZE * SIZE; i++) {
        const uint8_t *a = img.pixels + 4 * i, *b = full_img.pixels + 4 * i;
        for (int c = 0; c < 3; c++) {
            int d = abs((int)a[c] - (int)b[c]);
            most = d > most ? d : most;
            sum += d;
            sq += (double)d * d;
            n++;
        }
    }
    double mse = sq / n;
    printf("gl11 vs full on the fur ball (%dx%d): mean %.2f/255, max %d/255, PSNR %.1f dB; covers %d pixels, full %d\n",
           SIZE, SIZE, sum / n, most, mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : 99.0, s.changed, sf.changed);
    ht_image_free(&img);
    ht_image_free(&full_img);
    ht_renderer_destroy(r);
}

static void test_a_static_frame_shades_no_vertex_on_the_cpu(void **state) {
    (void)state;
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_GL11, .strict = true },
                                             fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_frame_desc f = furball_frame();
    ht_image img;
    uint64_t before = ht_gl11_cpu_vertices();
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    ht_image_free(&img);
    assert_int_equal(ht_gl11_cpu_vertices() - before, fx.mesh.vertex_count);
    /* identical frame: nothing recomputed, the same pixels */
    ht_image first, second;
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &first);
    before = ht_gl11_cpu_vertices();
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &second);
    assert_int_equal(ht_gl11_cpu_vertices() - before, 0);
    assert_memory_equal(first.pixels, second.pixels, (size_t)SIZE * SIZE * 4);
    ht_image_free(&first);
    ht_image_free(&second);
    /* moved eye: every vertex again, once */
    ht_frame_desc moved = ht_test_furball_frame(2.2f);
    before = ht_gl11_cpu_vertices();
    ht_test_draw(&fx.gl, r, &moved, ht_test_background, &img);
    ht_image_free(&img);
    ht_test_draw(&fx.gl, r, &moved, ht_test_background, &img);
    ht_image_free(&img);
    assert_int_equal(ht_gl11_cpu_vertices() - before, fx.mesh.vertex_count);
    /* changed light colour: again */
    ht_light lights[2];
    memcpy(lights, moved.lights, sizeof lights);
    lights[1].color[0] = 1.5f;
    moved.lights = lights;
    before = ht_gl11_cpu_vertices();
    ht_test_draw(&fx.gl, r, &moved, ht_test_background, &img);
    ht_image_free(&img);
    assert_int_equal(ht_gl11_cpu_vertices() - before, fx.mesh.vertex_count);
    ht_renderer_destroy(r);
}

static void test_frame_restores_the_applications_state(void **state) {
    (void)state;
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_GL11, .strict = true },
                                             fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    GLuint app_texture = 0;
    glGenTextures(1, &app_texture);
    glBindTexture(GL_TEXTURE_2D, app_texture);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_DECAL);
    glColor4f(0.25f, 0.5f, 0.75f, 1.0f);
    ht_frame_desc f = furball_frame();
    ht_image img;
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    ht_image_free(&img);
    GLint bound = 0, mode = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
    glGetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &mode);
    assert_int_equal(bound, (GLint)app_texture);
    assert_int_equal(mode, GL_DECAL);
    assert_false(glIsEnabled(GL_TEXTURE_2D));
    assert_false(glIsEnabled(GL_COLOR_ARRAY));
    GLfloat color[4];
    glGetFloatv(GL_CURRENT_COLOR, color);
    assert_true(color[0] == 0.25f && color[1] == 0.5f && color[2] == 0.75f);
    glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDeleteTextures(1, &app_texture);
    glColor4f(1, 1, 1, 1);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    ht_renderer_destroy(r);
}

/* Child mode: argv = exe --child BUNDLE, with MESA_GL_VERSION_OVERRIDE=1.1. */
static int child_main(const char *bundle) {
    char err[256];
    if (!ht_test_gl_create(&fx.gl, SIZE, SIZE, NULL, err, sizeof err)) {
        printf("child: %s\n", err);
        return 1;
    }
    ht_mesh m;
    if (ht_test_furball_mesh(&m) != HT_OK) return 1;
    printf("version=%s\n", (const char *)glGetString(GL_VERSION));
    ht_test_log_clear();
    ht_renderer *r = NULL;
    ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, .bundle_dir = bundle,
                                                            .log = ht_test_log_capture, .record_trace = true }, &r);
    fputs(ht_test_log_text, stdout);
    printf("result=%s tier=%s\n", ht_result_string(res), res == HT_OK ? ht_tier_name(ht_renderer_tier(r)) : "-");
    if (res == HT_OK) printf("vbo=%d\n", ht_renderer_caps(r)->has_vbo);
    if (res == HT_OK && ht_renderer_set_mesh(r, &m) == HT_OK) {
        glViewport(0, 0, SIZE, SIZE);
        glClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        ht_frame_desc f = furball_frame();
        printf("draw=%s\n", ht_result_string(ht_renderer_draw(r, &f)));
        printf("gl_error=0x%04x\n", glGetError());
        ht_image img;
        if (ht_test_gl_read(&fx.gl, &img) == HT_OK) {
            ht_test_pixel_stats s = stats(&img);
            printf("changed=%d magenta=%d\n", s.changed, s.magenta);
            ht_image_free(&img);
        }
        static char trace[4096];
        ht_test_format_trace(ht_renderer_trace(r), trace, sizeof trace);
        fputs(trace, stdout);
    }
    ht_renderer_destroy(r);
    ht_mesh_free(&m);
    ht_test_gl_destroy(&fx.gl);
    return 0;
}

static void test_mesa_gl11_driver_selects_gl11_with_the_full_tiers_trace(void **state) {
    (void)state;
    static char out[16384], full_trace[4096];
    ht_image full_img;
    full_tier(full_trace, sizeof full_trace, &full_img);
    ht_image_free(&full_img);
    ht_test_run_child("1.1", fx.bundle_dir, out, sizeof out);
    if (!strstr(out, "version=1.1")) fail_msg("child did not get a GL 1.1 context:\n%s", out);
    if (!strstr(out, "result=ok tier=gl11")) fail_msg("child did not pick gl11:\n%s", out);
    const char *vbo = strstr(out, "vbo=");
    assert_non_null(vbo);
    printf("GL 1.1 child: %s\n", vbo[4] == '1' ? "VBOs (ARB_vertex_buffer_object)" : "no VBOs: client arrays");
    assert_non_null(strstr(out, "skipped full: needs GL 2.1, have 1.1"));
    assert_non_null(strstr(out, "skipped vertex: needs GL 2.0, have 1.1"));
    assert_non_null(strstr(out, "skipped fixed4: needs GL 1.2, have 1.1"));
    assert_non_null(strstr(out, "skipped fixed: needs GL 1.2, have 1.1"));
    assert_non_null(strstr(out, "draw=ok"));
    assert_non_null(strstr(out, "gl_error=0x0000"));
    const char *stats_line = strstr(out, "changed=");
    assert_non_null(stats_line);
    int changed = 0, magenta = -1;
    assert_int_equal(sscanf(stats_line, "changed=%d magenta=%d", &changed, &magenta), 2);
    assert_int_equal(magenta, 0);
    assert_true(changed > SIZE * SIZE / 20);
    const char *trace = strstr(out, "trace pass");
    assert_non_null(trace);
    assert_string_equal(trace, full_trace);
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "--child") == 0) return child_main(argv[2]);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forced_gl11_draws_the_full_tiers_passes),
        cmocka_unit_test(test_a_static_frame_shades_no_vertex_on_the_cpu),
        cmocka_unit_test(test_frame_restores_the_applications_state),
        cmocka_unit_test(test_mesa_gl11_driver_selects_gl11_with_the_full_tiers_trace),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

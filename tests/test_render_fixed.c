/* test_render_fixed — the `fixed` tier's backend (fallback/fixed.c) on
   OSMesa, on whichever Mesa driver runs it (make test: llvmpipe and
   softpipe).

   - Selection: a GL 1.3 device profile, and Mesa's own
     MESA_GL_VERSION_OVERRIDE=1.3 in a re-executed child, pick `fixed` and
     draw a fur ball that is neither blank nor magenta, with the full tier's
     pass list, state and draw ranges.
   - Shading probe (support_probe.h's grid of flat cells, shared with
     test_render_probe.c): every covered pixel against (a) ht_combiner_eval
     fed with the same per-vertex inputs interpolated to the pixel, within
     what GL's texture filtering precision allows, and (b) the oracle
     ht_model_shade_d with the tier's documented drops (shift texture 0.5,
     sparkle replaced by the sparkle texture's mean, key light only), the
     tier's error budget, printed per channel.
   - The texture-matrix rule (Kajiya-Kay under a directional key light):
     the probe against the emulator fed the same tangents and matrix and
     against the oracle with the rule's infinite viewer; GL reads the
     mesh's tangents through the frame's texture matrix (no CPU coordinate
     array), the matrix follows the light and camera, the colours the
     light's colour; the backend alone gives a point key light CPU
     coordinates with one log line.
   - Devices without enough units, without combine, without 3D textures or
     with too small a GL_MAX_3D_TEXTURE_SIZE are refused with the reason;
     a corrupt fixed.json or a missing LUT skips the tier with one line
     naming the file.
   - No shader call at all, the prime-Z pass binds no LUT, no GL error after
     any pass, and after a frame the texture environment and texture
     matrices are GL's initial ones: the next tier's frame is the same bytes as before.
   The fixture's bundle keeps full, vertex and fixed only (fixed4 and gl11,
   which also run at GL 1.3, have their own tests). `make test`'s softpipe
   run (support_driver.h) draws the selection's fur ball with blond only,
   probes the texture-matrix rule's two paths (matrix, CPU coordinates)
   and skips the models' extremes (the plain path with other constants). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "manifest.h"
#include "combiner.h"
#include "fixed.h"
#include "fixed_coords.h"
#include "gl_api.h"
#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include <hairtier/model.h>
#include "support_combiner_eval.h"
#include "support_driver.h"
#include "support_log.h"
#include "support_osmesa.h"
#include "support_probe.h"
#include "support_render.h"
#include "support_scratch.h"

#define SIZE HT_PROBE_SIZE   /* the probe's view; the fur ball is drawn at the same size */
#define GRID HT_PROBE_GRID
/* Fixed tier vs its CPU emulator, per channel in 1/255. llvmpipe filters
   with 8-bit fixed-point weights (the emulator in float), then rounds per
   stage: measured max 3, mean 0.2-0.4. softpipe filters in float: measured
   max 1 (one pixel), mean 0.00. */
#define EMULATOR_TOLERANCE 3
/* At LUT scale 4 (a light of colour 2 folded into the LUT, combiner.h) the
   last stage multiplies the LUT stage's rounding by 4 instead of 2:
   measured max 5 on llvmpipe. */
#define EMULATOR_TOLERANCE_SCALE_4 5
/* Fixed tier vs the oracle with the tier's documented drops, per channel in
   1/255, on cases within the LUT's resolution: an 8-bit LUT at scale 2
   (0.5/255 x 2 x base), linear interpolation between LUT texels, and dot
   products computed per vertex and interpolated across a cell. Measured
   with the 3D LUT's budget (32 x 32 x 16, emit_fixed.c): max 12 (shift
   100; 11 the plain probe under a light of colour 2), mean <= 0.91 over
   the cases (llvmpipe): the highlight's curvature between the budget's
   coarse texels (docs/accuracy.md). */
#define ORACLE_MAX 14
#define ORACLE_MEAN 1.0
/* The texture-matrix rule (Kajiya-Kay, directional key light) vs the oracle
   evaluated with the rule's infinite viewer, per channel in 1/255: the same
   sources as above without the CPU's per-vertex rounding of coordinates.
   Measured: max 2, mean <= 0.40 (llvmpipe and softpipe); against the true,
   local viewer (printed as "local V", not a bound) the probe's 30 degree
   field of view costs up to 45/255 at the generic light, 159 at L = -V. */
#define MATRIX_ORACLE_MAX 3
#define MATRIX_ORACLE_MEAN 0.6

static ht_test_furball fx;

/* ---- log lines ---- */

/* One line per message: a line break inside one would start a line
   without the renderer's prefix. */
static bool every_line_is_the_renderers(void) {
    for (const char *l = ht_test_log_text; *l; l = strchr(l, '\n') + 1) {
        if (strncmp(l, "hairtier: ", 10) != 0) return false;
        if (!strchr(l, '\n')) break;
    }
    return true;
}

/* The whole log line that contains `what` (without its newline). */
static bool logged_line(const char *what, char *line, size_t size) {
    const char *at = strstr(ht_test_log_text, what);
    if (!at) return false;
    const char *start = at;
    while (start > ht_test_log_text && start[-1] != '\n') start--;
    size_t n = strcspn(start, "\n");
    if (n >= size) n = size - 1;
    memcpy(line, start, n);
    line[n] = '\0';
    return true;
}

/* ---- GL calls the tests watch ---- */

typedef void (APIENTRYP draw_elements_fn)(GLenum, GLsizei, GLenum, const void *);
typedef void (APIENTRYP use_program_fn)(GLuint);
typedef GLuint (APIENTRYP create_fn)(void);
typedef GLuint (APIENTRYP create_shader_fn)(GLenum);

static draw_elements_fn real_draw_elements;
static use_program_fn real_use_program;
static create_fn real_create_program;
static create_shader_fn real_create_shader;
static PFNGLACTIVETEXTUREPROC active_texture;
static PFNGLCLIENTACTIVETEXTUREARBPROC client_active_texture;

static int shader_calls;

typedef struct draw_state {
    bool color_write;
    bool unit_2d[2], unit_3d[2];
    GLint env_mode[2];
    GLint program;
    /* unit 0 (the LUT's): where GL reads its texture coordinates, and the
       matrix it puts them through */
    bool coord_array;
    GLint coord_size, coord_stride;
    void *coord_pointer;
    GLfloat texture_matrix[16];
    void *color_pointer;
    GLint coord_buffer, color_buffer;   /* 0: client memory */
} draw_state;

#define MAX_DRAWS 16
static draw_state draws[MAX_DRAWS];
static int draw_count;

static void *as_data(void (*f)(void)) {
    void *p;
    memcpy(&p, &f, sizeof p);
    return p;
}

/* The arrays live in buffer objects where the device has them (the tier
   uploads its data once per change): then a pointer is an offset, and the
   test reads a copy of the whole buffer instead, the pointer moved into it. */
static void *array_copies[MAX_DRAWS][2];

static GLint read_back_array(GLenum binding, void **pointer, void **copy) {
    GLint buffer = 0;
    glGetIntegerv(binding, &buffer);
    if (!buffer) return 0;
    void (*get_sub_data)(GLenum, GLintptr, GLsizeiptr, void *);
    void *f = ht_test_getproc("glGetBufferSubData");
    memcpy(&get_sub_data, &f, sizeof f);
    GLint bound = 0, size = 0;
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &bound);
    void (*bind)(GLenum, GLuint);
    f = ht_test_getproc("glBindBuffer");
    memcpy(&bind, &f, sizeof f);
    void (*get_param)(GLenum, GLenum, GLint *);
    f = ht_test_getproc("glGetBufferParameteriv");
    memcpy(&get_param, &f, sizeof f);
    bind(GL_ARRAY_BUFFER, (GLuint)buffer);
    get_param(GL_ARRAY_BUFFER, GL_BUFFER_SIZE, &size);
    free(*copy);
    *copy = malloc(size > 0 ? (size_t)size : 1);
    if (*copy && size > 0) get_sub_data(GL_ARRAY_BUFFER, 0, size, *copy);
    bind(GL_ARRAY_BUFFER, (GLuint)bound);
    *pointer = (char *)*copy + (uintptr_t)*pointer;
    return buffer;
}

static void APIENTRY watch_draw_elements(GLenum mode, GLsizei count, GLenum type, const void *indices) {
    if (draw_count < MAX_DRAWS) {
        draw_state *d = &draws[draw_count++];
        GLboolean mask[4];
        glGetBooleanv(GL_COLOR_WRITEMASK, mask);
        d->color_write = mask[0] || mask[1] || mask[2] || mask[3];
        GLint active = GL_TEXTURE0;
        glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
        for (int u = 0; u < 2; u++) {
            active_texture(GL_TEXTURE0 + (GLenum)u);
            d->unit_2d[u] = glIsEnabled(GL_TEXTURE_2D);
            d->unit_3d[u] = glIsEnabled(GL_TEXTURE_3D);
            glGetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &d->env_mode[u]);
        }
        active_texture(GL_TEXTURE0);
        glGetFloatv(GL_TEXTURE_MATRIX, d->texture_matrix);
        active_texture((GLenum)active);
        GLint client = GL_TEXTURE0;
        glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &client);
        client_active_texture(GL_TEXTURE0);
        d->coord_array = glIsEnabled(GL_TEXTURE_COORD_ARRAY);
        glGetIntegerv(GL_TEXTURE_COORD_ARRAY_SIZE, &d->coord_size);
        glGetIntegerv(GL_TEXTURE_COORD_ARRAY_STRIDE, &d->coord_stride);
        glGetPointerv(GL_TEXTURE_COORD_ARRAY_POINTER, &d->coord_pointer);
        d->coord_buffer = read_back_array(GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING, &d->coord_pointer,
                                          &array_copies[draw_count - 1][0]);
        glGetPointerv(GL_COLOR_ARRAY_POINTER, &d->color_pointer);
        d->color_buffer = read_back_array(GL_COLOR_ARRAY_BUFFER_BINDING, &d->color_pointer,
                                          &array_copies[draw_count - 1][1]);
        client_active_texture((GLenum)client);
        glGetIntegerv(GL_CURRENT_PROGRAM, &d->program);
    }
    real_draw_elements(mode, count, type, indices);
}

/* Program 0 is no shader: the renderer unbinds the application's program
   around every frame, whatever the tier. */
static void APIENTRY watch_use_program(GLuint p) {
    if (p != 0) shader_calls++;
    real_use_program(p);
}

static GLuint APIENTRY watch_create_program(void) {
    shader_calls++;
    return real_create_program();
}

static GLuint APIENTRY watch_create_shader(GLenum type) {
    shader_calls++;
    return real_create_shader(type);
}

/* ht_test_getproc, with a few entry points wrapped so the tests see them. */
static void *watching_getproc(const char *name) {
    void *real = ht_test_getproc(name);
    if (!real) return NULL;
    if (strcmp(name, "glDrawElements") == 0) {
        memcpy(&real_draw_elements, &real, sizeof real);
        return as_data((void (*)(void))watch_draw_elements);
    }
    if (strcmp(name, "glUseProgram") == 0) {
        memcpy(&real_use_program, &real, sizeof real);
        return as_data((void (*)(void))watch_use_program);
    }
    if (strcmp(name, "glCreateProgram") == 0) {
        memcpy(&real_create_program, &real, sizeof real);
        return as_data((void (*)(void))watch_create_program);
    }
    if (strcmp(name, "glCreateShader") == 0) {
        memcpy(&real_create_shader, &real, sizeof real);
        return as_data((void (*)(void))watch_create_shader);
    }
    return real;
}

/* ---- fixtures ---- */

/* The fixture's bundle without the tiers after vertex other than fixed
   (fixed4, gl11: their own tests), so that GL 1.3 leaves fixed the only
   candidate, as the refusal tests below rely on. */
static bool keep_only_fixed_below_vertex(const char *dir) {
    cJSON *root = cJSON_Parse(ht_test_read_file(dir, "manifest.json"));
    if (!root) return false;
    cJSON *tiers = cJSON_GetObjectItem(root, "tiers");
    for (int i = cJSON_GetArraySize(tiers) - 1; i >= 0; i--) {
        const char *name = cJSON_GetObjectItem(cJSON_GetArrayItem(tiers, i), "name")->valuestring;
        if (strcmp(name, "full") != 0 && strcmp(name, "vertex") != 0 && strcmp(name, "fixed") != 0)
            cJSON_DeleteItemFromArray(tiers, i);
    }
    char *text = cJSON_Print(root);
    cJSON_Delete(root);
    if (!text) return false;
    ht_test_write_file(dir, "manifest.json", text);
    free(text);
    return true;
}

/* blond's fill light has a diffuse term above the sub-pass rule's 32/255
   (dark-brown's, the fixture's, stays under it): the fur ball with one. */
static char fill_dir[192];

static int setup(void **state) {
    (void)state;
    if (!ht_test_furball_setup(&fx, "fixed", SIZE)) return -1;
    /* the shared bundles are read only: these tests edit copies */
    char own[sizeof fx.bundle_dir];
    ht_test_furball_copy_bundle(&fx, "dark-brown", own, sizeof own);
    snprintf(fx.bundle_dir, sizeof fx.bundle_dir, "%s", own);
    if (!keep_only_fixed_below_vertex(fx.bundle_dir)) return -1;
    char err[1024], blond[192];
    snprintf(blond, sizeof blond, "%s/blond-shared", fx.work);
    if (ht_test_bundle("materials/blond.json", "furball", "scenes/furball.json", blond, sizeof blond, err,
                       sizeof err) != HT_OK) {
        fprintf(stderr, "setup: %s\n", err);
        return -1;
    }
    snprintf(fill_dir, sizeof fill_dir, "%s/blond", fx.work);
    ht_test_copy_dir(blond, fill_dir);
    if (!keep_only_fixed_below_vertex(fill_dir)) return -1;
    void *p = ht_test_getproc("glActiveTexture");
    memcpy(&active_texture, &p, sizeof p);
    p = ht_test_getproc("glClientActiveTexture");
    memcpy(&client_active_texture, &p, sizeof p);
    return active_texture && client_active_texture ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

static ht_frame_desc furball_frame(void) { return ht_test_furball_frame(2.0f); }

static ht_renderer *create(ht_renderer_desc desc, ht_result expect) {
    return ht_test_renderer_create(desc, fx.bundle_dir, expect);
}

static void render(ht_renderer *r, const ht_frame_desc *f, ht_image *img) {
    ht_test_draw(&fx.gl, r, f, ht_test_background, img);
}

static ht_test_pixel_stats stats(const ht_image *img) { return ht_test_pixel_stats_of(img, ht_test_background); }

/* One line per trace entry: what the tiers must agree on. */
/* The full tier's fur-ball frame: its trace into out, its image into img
   (NULL: not kept). */
static void full_tier_trace(const char *dir, char *out, size_t size, ht_image *img) {
    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir, .tier = HT_TIER_FULL, .strict = true }, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_image frame_img;
    ht_frame_desc f = furball_frame();
    render(r, &f, &frame_img);
    if (img) *img = frame_img;
    else ht_image_free(&frame_img);
    ht_test_format_trace(ht_renderer_trace(r), out, size);
    ht_renderer_destroy(r);
}

static ht_combiner_program bundle_program(const char *dir) {
    ht_combiner_program p;
    char err[512];
    if (ht_combiner_parse(ht_test_read_file(dir, "fixed.json"), "fixed.json", &p, err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    return p;
}

static int largest_lut_axis(const ht_combiner_program *p) {
    int n = p->lut_size[0];
    for (int i = 1; i < 3; i++) n = p->lut_size[i] > n ? p->lut_size[i] : n;
    return n;
}

/* The fixed tier's trace against the full tier's: sub-pass 0 of every pass
   is the full tier's line, and each additive sub-pass (combiner.h) follows
   it with the same pass, cull, alpha test and range, blending on, no
   depth write, depth EQUAL (LESS in the back pass, as its sub-pass 0). */
static void check_nested_trace(const char *fixed_trace, const char *full_trace, int sub_passes) {
    char main_lines[4096] = "", want[256], got[256];
    const char *line = fixed_trace;
    int subs_seen = 0;
    char last_main[256] = "";
    while (*line) {
        const char *end = strchr(line, '\n');
        size_t n = end ? (size_t)(end - line) + 1 : strlen(line);
        assert_true(n < sizeof got);
        memcpy(got, line, n);
        got[n] = '\0';
        int pass = -1, sub = -1;
        assert_int_equal(sscanf(got, "trace pass %d.%d", &pass, &sub), 2);
        if (sub == 0) {
            strncat(main_lines, got, sizeof main_lines - strlen(main_lines) - 1);
            snprintf(last_main, sizeof last_main, "%s", got);
        } else {
            /* the line the sub-pass must give: its pass's sub-pass 0 line, changed where it must */
            char depth[32], blend[16];
            unsigned func = 0;
            int write = 0;
            const char *d = strstr(last_main, "depth 0x"), *b = strstr(last_main, "blend ");
            assert_non_null(d);
            assert_non_null(b);
            assert_int_equal(sscanf(d, "depth 0x%x/%d", &func, &write), 2);
            snprintf(depth, sizeof depth, "depth 0x%04x/0", pass == HT_PASS_BACK ? func : (unsigned)GL_EQUAL);
            snprintf(blend, sizeof blend, "blend 1");
            const char *after_depth = strchr(d, ' ');
            after_depth = strchr(after_depth + 1, ' ');
            snprintf(want, sizeof want, "trace pass %d.%d%.*s%s%.*s%s%s", pass, sub,
                     (int)(d - strchr(last_main, ' ') - strlen(" pass 0.0")), strchr(last_main, ' ') + strlen(" pass 0.0"),
                     depth, (int)(b - after_depth), after_depth, blend, b + strlen("blend 0"));
            assert_string_equal(got, want);
            assert_true(pass != HT_PASS_PRIME_Z);
            subs_seen++;
        }
        line += n;
    }
    assert_string_equal(main_lines, full_trace);
    assert_int_equal(subs_seen, (HT_PASS_COUNT - 1) * (sub_passes - 1));
}

/* ---- selection and the fur ball ---- */

static void test_gl13_profile_selects_fixed_and_draws_the_full_tiers_passes(void **state) {
    (void)state;
    /* dark-brown (the fixture): the key light alone; blond: its fill light
       as one additive sub-pass per lit pass */
    const char *dirs[2] = { fx.bundle_dir, fill_dir };
    static char full_trace[2][4096], fixed_trace[4096];
    ht_image full_img[2];
    ht_frame_desc f = furball_frame();
    /* `make test`'s softpipe run (support_driver.h) draws blond only: its
       key light is dark-brown's whole frame, sub-pass 0 */
    const int first_bundle = ht_test_driver_cases_only() ? 1 : 0;
    for (int b = first_bundle; b < 2; b++) full_tier_trace(dirs[b], full_trace[b], sizeof full_trace[b], &full_img[b]);

    /* With the mesh in VBOs (the extension survives GL 1.3 on Mesa) and in
       client arrays. */
    for (int run = 2 * first_bundle; run < 4; run++) {
        const int no_vbo = run & 1, b = run / 2;
        const char *dir = dirs[b];
        ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir,
                                                    .profile = { .gl_major = 1, .gl_minor = 3, .texture_units = 2,
                                                                 .no_vbo = no_vbo } }, HT_OK);
        assert_int_equal(ht_renderer_tier(r), HT_TIER_FIXED);
        assert_true(ht_test_logged("skipped full: needs GL 2.1, have 1.3"));
        assert_true(ht_test_logged("skipped vertex: needs GL 2.0, have 1.3"));
        assert_true(ht_test_logged("hairtier: tier fixed (best supported"));
        if (no_vbo) assert_false(ht_renderer_caps(r)->has_vbo);
        assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
        ht_image img;
        render(r, &f, &img);
        ht_test_format_trace(ht_renderer_trace(r), fixed_trace, sizeof fixed_trace);
        const int adds = b;
        const int subs = ht_combiner_sub_passes(&(ht_combiner_program){ .add_light_count = adds });
        assert_int_equal(bundle_program(dir).add_light_count, adds);
        assert_int_equal(ht_renderer_trace(r)->count, HT_PASS_COUNT + (HT_PASS_COUNT - 1) * (subs - 1));
        for (int i = 0; i < ht_renderer_trace(r)->count; i++)
            assert_int_equal(ht_renderer_trace(r)->entries[i].gl_error, GL_NO_ERROR);
        check_nested_trace(fixed_trace, full_trace[b], subs);

        ht_test_pixel_stats s = stats(&img), sf = stats(&full_img[b]);
        printf("fur ball, %s (%s): fixed covers %d pixels, full %d\n", b ? "blond" : "dark-brown",
               ht_renderer_caps(r)->has_vbo ? "VBOs" : "client arrays", s.changed, sf.changed);
        assert_int_equal(s.magenta, 0);
        assert_true(s.changed > SIZE * SIZE / 20);
        /* Same alpha, same passes: the same hair shows, shaded differently. */
        assert_true(s.changed >= sf.changed * 9 / 10);
        ht_image_free(&img);
        ht_renderer_destroy(r);
    }
    for (int b = first_bundle; b < 2; b++) ht_image_free(&full_img[b]);
}

/* Child mode: argv = exe --child BUNDLE, with MESA_GL_VERSION_OVERRIDE=1.3. */
static int child_main(const char *bundle) {
    char err[256];
    if (!ht_test_gl_create(&fx.gl, SIZE, SIZE, NULL, err, sizeof err)) {
        printf("child: %s\n", err);
        return 1;
    }
    ht_mesh m;
    if (ht_test_furball_mesh(&m) != HT_OK) return 1;
    printf("version=%s\n", (const char *)glGetString(GL_VERSION));
    const GLubyte *sl = glGetString(GL_SHADING_LANGUAGE_VERSION);
    printf("glsl=%s\n", sl ? (const char *)sl : "none");
    while (glGetError() != GL_NO_ERROR) {}
    ht_test_log_clear();
    ht_renderer *r = NULL;
    ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, .bundle_dir = bundle,
                                                            .log = ht_test_log_capture, .record_trace = true }, &r);
    fputs(ht_test_log_text, stdout);
    printf("result=%s tier=%s\n", ht_result_string(res), res == HT_OK ? ht_tier_name(ht_renderer_tier(r)) : "-");
    if (res == HT_OK && ht_renderer_set_mesh(r, &m) == HT_OK) {
        glViewport(0, 0, SIZE, SIZE);
        glClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        ht_frame_desc f = furball_frame();
        printf("draw=%s\n", ht_result_string(ht_renderer_draw(r, &f)));
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

static void test_mesa_gl13_driver_runs_fixed_with_the_full_tiers_trace(void **state) {
    (void)state;
    static char out[16384], full_trace[4096];
    full_tier_trace(fx.bundle_dir, full_trace, sizeof full_trace, NULL);
    ht_test_run_child("1.3", fx.bundle_dir, out, sizeof out);
    if (!strstr(out, "version=1.3")) fail_msg("child did not get a GL 1.3 context:\n%s", out);
    if (!strstr(out, "result=ok tier=fixed")) fail_msg("child did not pick fixed:\n%s", out);
    assert_non_null(strstr(out, "skipped full: needs GL 2.1, have 1.3"));
    assert_non_null(strstr(out, "skipped vertex: needs GL 2.0, have 1.3"));
    assert_non_null(strstr(out, "draw=ok"));
    const char *stats_line = strstr(out, "changed=");
    assert_non_null(stats_line);
    int changed = 0, magenta = -1;
    assert_int_equal(sscanf(stats_line, "changed=%d magenta=%d", &changed, &magenta), 2);
    assert_int_equal(magenta, 0);
    assert_true(changed > SIZE * SIZE / 20);
    const char *trace = strstr(out, "trace pass");
    assert_non_null(trace);
    check_nested_trace(trace, full_trace, 1 + bundle_program(fx.bundle_dir).add_light_count);
}

/* ---- the additive sub-pass ---- */

/* A copy of the bundle from with another opaque cutoff. */
static void bundle_with_cutoff(const char *from, const char *name, double cutoff, char *dir, size_t size) {
    snprintf(dir, size, "%s/%s", fx.work, name);
    ht_test_copy_dir(from, dir);
    ht_test_set_json_number(dir, "manifest.json", "opaque_cutoff", cutoff);
}

typedef struct layering {
    double mean, psnr; /* of A against B + C over every channel of the frame */
    int max;
    long added;        /* sum of A - B: what the second light added */
    int fill_lit;      /* pixels the fill light alone lights */
} layering;

/* The fur ball with both lights (A), the key light alone (B) and the fill
   light alone drawn as the key (C: sub-pass 0, composited exactly), on
   black. Alpha compositing is linear in the colours, so an exact second
   light gives A = B + C; A - (B + C) is the additive sub-pass's error. */
static layering measure_layering(const char *dir) {
    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir, .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_frame_desc f = furball_frame();
    ht_light both[2] = { f.lights[0], f.lights[1] }, key[2] = { f.lights[0], f.lights[1] },
             fill[2] = { f.lights[1], f.lights[0] };
    for (int k = 0; k < 3; k++) key[1].color[k] = fill[1].color[k] = 0.0f;
    const ht_light *sets[3] = { both, key, fill };
    ht_image img[3];
    static const float black[3] = { 0, 0, 0 };
    for (int i = 0; i < 3; i++) {
        f.lights = sets[i];
        ht_test_draw(&fx.gl, r, &f, black, &img[i]);
    }
    layering m = { 0, 0, 0, 0, 0 };
    double se = 0.0, sum = 0.0;
    const size_t n = (size_t)SIZE * SIZE;
    for (size_t p = 0; p < n; p++) {
        bool lit = false;
        for (int c = 0; c < 3; c++) {
            int a = img[0].pixels[4 * p + c], b = img[1].pixels[4 * p + c], fc = img[2].pixels[4 * p + c];
            int e = a - (b + fc > 255 ? 255 : b + fc);
            se += (double)e * e;
            sum += abs(e);
            m.max = abs(e) > m.max ? abs(e) : m.max;
            m.added += a - b;
            lit = lit || fc > 2;
        }
        m.fill_lit += lit;
    }
    m.mean = sum / (3.0 * (double)n);
    m.psnr = se > 0 ? 10.0 * log10(255.0 * 255.0 * 3.0 * (double)n / se) : 99.0;
    for (int i = 0; i < 3; i++) ht_image_free(&img[i]);
    ht_renderer_destroy(r);
    return m;
}

/* The second light is drawn (the fill alone lights the hair; with the key
   it adds), exactly where the hair is opaque, and within a measured error
   where transparent layers overlap (combiner.h says which way). */
static void test_additive_sub_pass_adds_the_second_light_exactly_on_opaque_hair(void **state) {
    (void)state;
    char opaque[256];
    /* a tiny cutoff: every texel opaque, every fragment in the depth-EQUAL pass */
    bundle_with_cutoff(fill_dir, "all-opaque", 0.004, opaque, sizeof opaque);
    const char *dirs[2] = { opaque, fill_dir };
    layering m[2];
    for (int i = 0; i < 2; i++) {
        m[i] = measure_layering(dirs[i]);
        printf("additive sub-pass, %s: A - (B + C) mean %.3f/255, max %d/255, PSNR %.1f dB; the fill lights %d "
               "pixels, adds %ld in all\n", i == 0 ? "all opaque" : "shipped cutoff", m[i].mean, m[i].max, m[i].psnr,
               m[i].fill_lit, m[i].added);
        assert_true(m[i].fill_lit > SIZE * SIZE / 20);
        assert_true(m[i].added > 50L * SIZE * SIZE / 20);
    }
    /* opaque: exact but for 8-bit rounding per sub-pass and the few texels
       under even this cutoff (blond, measured mean 0.001/255 with one pixel
       at 16 on llvmpipe, where two strands meet at one depth and depth-EQUAL
       lets the other's fill through; mean 0.077, max 1 on softpipe, which
       rounds the other way more often) */
    assert_true(m[0].max <= 16);
    assert_true(m[0].mean < 0.1);
    /* overlapping transparent layers: measured mean 0.127/255, max 65, PSNR
       46.3 dB on llvmpipe, 0.190, 85, 45.3 dB on softpipe (deeper layers'
       fill mostly missing: the front pass) */
    assert_true(m[1].mean < 0.25);
    assert_true(m[1].psnr > 44.0);
}

/* ---- the shading probe ---- */

/* Barycentric weights of P in the cell's triangle that holds it (the plane
   faces the camera, so screen-space and world-space interpolation agree). */
static void cell_weights(const ht_mesh *m, int ci, const double P[3], int idx[3], double w[3]) {
    static const int tris[2][3] = { { 0, 1, 3 }, { 0, 3, 2 } };
    for (int t = 0; t < 2; t++) {
        const float *a = m->vertices[ci * 4 + tris[t][0]].position;
        const float *b = m->vertices[ci * 4 + tris[t][1]].position;
        const float *c = m->vertices[ci * 4 + tris[t][2]].position;
        double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
        double wb = ((P[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (P[1] - a[1])) / det;
        double wc = ((b[0] - a[0]) * (P[1] - a[1]) - (P[0] - a[0]) * (b[1] - a[1])) / det;
        double wa = 1.0 - wb - wc;
        if (t == 1 || (wa >= -1e-9 && wb >= -1e-9 && wc >= -1e-9)) {
            for (int k = 0; k < 3; k++) idx[k] = ci * 4 + tris[t][k];
            w[0] = wa;
            w[1] = wb;
            w[2] = wc;
            return;
        }
    }
}

typedef struct channel_error {
    int max[3];
    double sum[3];
    int pixels;
    int worst_cell;
} channel_error;

static void add_error(channel_error *e, int ci, const int expected[3], const uint8_t *got) {
    for (int k = 0; k < 3; k++) {
        int d = abs(expected[k] - got[k]);
        if (d > e->max[k]) {
            e->max[k] = d;
            e->worst_cell = ci;
        }
        e->sum[k] += d;
    }
}

static int max_of(const channel_error *e) {
    int m = e->max[0];
    for (int k = 1; k < 3; k++) m = e->max[k] > m ? e->max[k] : m;
    return m;
}

static double mean_of(const channel_error *e, int k) { return e->pixels ? e->sum[k] / e->pixels : 0.0; }

static void print_channel_error(const char *what, const channel_error *e) {
    printf("  %-8s max %2d %2d %2d  mean %.2f %.2f %.2f /255", what, e->max[0], e->max[1],
           e->max[2], mean_of(e, 0), mean_of(e, 1), mean_of(e, 2));
    if (e->worst_cell >= 0) printf(" (worst cell %d)", e->worst_cell);
    printf("\n");
}

typedef struct probe_case {
    ht_probe_material material;
    ht_light light;
    bool in_budget;      /* within the LUT's resolution: held to the oracle budget */
    bool matrix;         /* drawn by the texture-matrix rule (else CPU coordinates) */
} probe_case;

typedef struct probe_result {
    channel_error emulator, oracle;
    channel_error local;  /* texture matrix only: vs the oracle with the true, local V */
    bool matrix;         /* the texture-matrix rule drew it */
    int lut_scale;
} probe_result;

/* Renders the probe with the bundle's fixed tier and compares every covered
   pixel with the emulator and with the oracle. */
static probe_result probe(const probe_case *pc) {
    const ht_probe_material *p = &pc->material;
    const ht_light light = pc->light;
    char dir[256], err[2048], path[400];
    ht_material m;
    ht_probe_make_bundle(fx.work, p, &light, dir, sizeof dir, &m);
    ht_combiner_program prog = bundle_program(dir);

    ht_image lut = { 0 }, albedo = { 0 }, detail = { 0 };
    double sparkle_mean = 1.0; /* the tier's stand-in for the sparkle mask */
    snprintf(path, sizeof path, "%s/detail.png", dir);
    if (p->textured && ht_image_read_png(path, &detail, err, sizeof err) == HT_OK) {
        double sum = 0;
        for (int i = 0; i < detail.width * detail.height; i++) sum += detail.pixels[i * detail.channels + 1];
        sparkle_mean = sum / (255.0 * detail.width * detail.height);
        ht_image_free(&detail);
    }
    snprintf(path, sizeof path, "%s/fixed-lut.png", dir);
    assert_int_equal(ht_image_read_png(path, &lut, err, sizeof err), HT_OK);
    ht_combiner_texture textures[2] = { { "fixed-lut", &lut, prog.lut_size[2] }, { "albedo", &albedo, 1 } };
    int texture_count = 1;
    if (p->textured) {
        snprintf(path, sizeof path, "%s/albedo.png", dir);
        assert_int_equal(ht_image_read_png(path, &albedo, err, sizeof err), HT_OK);
        texture_count = 2;
    }

    ht_mesh mesh;
    ht_probe_build_mesh(&mesh);
    ht_frame_desc frame = ht_probe_frame(&light);
    const float *eye = frame.camera.eye;
    /* The program's rule: the texture matrix (a point light falls back to
       CPU coordinates read through GL's identity matrix, as the backend
       does), or CPU coordinates. */
    const bool matrix = ht_combiner_lut_coords(&prog) == HT_COORDS_TEXTURE_MATRIX && light.type != HT_LIGHT_POINT;
    float view_dir[3], texture_matrix[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    double len = 0.0;
    for (int k = 0; k < 3; k++) len += pow(eye[k] - frame.camera.target[k], 2);
    for (int k = 0; k < 3; k++) view_dir[k] = (float)((eye[k] - frame.camera.target[k]) / sqrt(len));
    float *coords = calloc((size_t)mesh.vertex_count * 3, sizeof *coords);
    float *colors = calloc((size_t)mesh.vertex_count * 4, sizeof *colors);
    assert_non_null(coords);
    assert_non_null(colors);
    if (matrix) {
        assert_int_equal(ht_fixed_coords_texture_matrix(&prog, &light, 1, view_dir, texture_matrix, err, sizeof err),
                         HT_OK);
        assert_int_equal(ht_fixed_coords_colors(&prog, mesh.vertices, mesh.vertex_count, &light, 1, colors, err,
                                                sizeof err), HT_OK);
        for (uint32_t i = 0; i < mesh.vertex_count; i++) memcpy(&coords[3 * i], mesh.vertices[i].tangent, 12);
    } else {
        assert_int_equal(ht_fixed_coords_compute(&prog, mesh.vertices, mesh.vertex_count, &light, 1, eye, coords,
                                                 colors, err, sizeof err), HT_OK);
    }

    ht_renderer *r = create((ht_renderer_desc){ .bundle_dir = dir, .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FIXED);
    assert_int_equal(ht_renderer_set_mesh(r, &mesh), HT_OK);
    ht_image img;
    ht_test_draw(&fx.gl, r, &frame, (const float[3]){ 0, 0, 0 }, &img);

    probe_result res;
    memset(&res, 0, sizeof res);
    res.emulator.worst_cell = res.oracle.worst_cell = res.local.worst_cell = -1;
    res.matrix = matrix;
    res.lut_scale = prog.lut_scale;
    for (int row = 0; row < SIZE; row++)
        for (int x = 0; x < SIZE; x++) {
            double P[3];
            int ci = ht_probe_cell_at(x, SIZE - 1 - row, P);
            if (ci < 0) continue;
            const ht_probe_cell *c = &ht_probe_cells[ci];
            const uint8_t *got = img.pixels + ((size_t)row * SIZE + x) * 4;

            /* (a) the emulator, fed what GL interpolates to this pixel */
            int idx[3] = { 0, 0, 0 };
            double w[3] = { 0, 0, 0 };
            cell_weights(&mesh, ci, P, idx, w);
            ht_combiner_fragment frag = { .uv = { (float)c->uv[0], (float)c->uv[1] } };
            for (int k = 0; k < 3; k++)
                frag.lut_coord[k] = (float)(w[0] * coords[3 * idx[0] + k] + w[1] * coords[3 * idx[1] + k] +
                                            w[2] * coords[3 * idx[2] + k]);
            /* texture-matrix stages: the interpolated tangent (or, on a
               point-light frame, the CPU coordinates) through the matrix */
            memcpy(frag.tangent, frag.lut_coord, sizeof frag.tangent);
            memcpy(frag.texture_matrix, texture_matrix, sizeof texture_matrix);
            for (int k = 0; k < 4; k++)
                frag.primary[k] = (float)(w[0] * colors[4 * idx[0] + k] + w[1] * colors[4 * idx[1] + k] +
                                          w[2] * colors[4 * idx[2] + k]);
            float rgba[4];
            assert_int_equal(ht_combiner_eval(&prog, textures, texture_count, &frag, rgba, err, sizeof err), HT_OK);
            int expected[3];
            for (int k = 0; k < 3; k++) expected[k] = ht_probe_to_byte(rgba[k]);
            add_error(&res.emulator, ci, expected, got);

            /* (b) the oracle, with the tier's documented drops */
            ht_surface s = ht_probe_surface(c, P);
            if (matrix) { /* the rule's infinite viewer; what it costs, for the record */
                ht_probe_oracle(&m.shading, &s, &light, P, expected);
                add_error(&res.local, ci, expected, got);
                for (int k = 0; k < 3; k++) s.V[k] = view_dir[k];
            }
            s.sparkle = sparkle_mean;
            if (p->textured) ht_probe_texel(&albedo, c->uv, 3, s.base);
            ht_probe_oracle(&m.shading, &s, &light, P, expected);
            add_error(&res.oracle, ci, expected, got);
            res.emulator.pixels++;
            res.oracle.pixels++;
        }
    printf("fixed probe %-14s %-11s light (%5.2f %5.2f %5.2f), LUT %dx%dx%d scale %d, %s: %d pixels\n", p->name,
           ht_probe_light_type(&light), (double)light.vector[0], (double)light.vector[1], (double)light.vector[2], prog.lut_size[0],
           prog.lut_size[1], prog.lut_size[2], prog.lut_scale, matrix ? "texture matrix" : "CPU coords",
           res.emulator.pixels);
    print_channel_error("emulator", &res.emulator);
    print_channel_error("oracle", &res.oracle);
    if (matrix) {
        res.local.pixels = res.oracle.pixels;
        print_channel_error("local V", &res.local);
    }
    assert_true(res.emulator.pixels > GRID * GRID * 20); /* the cells were drawn and found */

    free(coords);
    free(colors);
    ht_image_free(&img);
    ht_image_free(&lut);
    ht_image_free(&albedo);
    ht_renderer_destroy(r);
    ht_mesh_free(&mesh);
    return res;
}

static ht_light first_light(void) {
    return ht_probe_directional(ht_probe_first_light[0], ht_probe_first_light[1], ht_probe_first_light[2]);
}

static void run_probes(const probe_case *cases, int n) {
    channel_error all = { { 0, 0, 0 }, { 0, 0, 0 }, 0, -1 };
    for (int i = 0; i < n; i++) {
        probe_result res = probe(&cases[i]);
        if (res.matrix != cases[i].matrix)
            fail_msg("%s: drawn with %s, expected %s", cases[i].material.name,
                     res.matrix ? "the texture matrix" : "CPU coordinates",
                     cases[i].matrix ? "the texture matrix" : "CPU coordinates");
        const int tolerance = res.lut_scale == 4 ? EMULATOR_TOLERANCE_SCALE_4 : EMULATOR_TOLERANCE;
        if (max_of(&res.emulator) > tolerance)
            fail_msg("%s: fixed tier differs from its emulator by %d/255 (cell %d), tolerance %d",
                     cases[i].material.name, max_of(&res.emulator), res.emulator.worst_cell, tolerance);
        if (!cases[i].in_budget) continue;
        for (int k = 0; k < 3; k++) {
            all.max[k] = res.oracle.max[k] > all.max[k] ? res.oracle.max[k] : all.max[k];
            all.sum[k] += res.oracle.sum[k];
        }
        all.pixels += res.oracle.pixels;
        const int budget = res.matrix ? MATRIX_ORACLE_MAX : ORACLE_MAX;
        if (max_of(&res.oracle) > budget)
            fail_msg("%s: fixed tier differs from the oracle by %d/255 (cell %d), budget %d",
                     cases[i].material.name, max_of(&res.oracle), res.oracle.worst_cell, budget);
        /* a mean in output units grows with the light (the LUT's errors are
           multiplied by its colour): measured 0.65 at colour 2 */
        double brightest = 1.0;
        for (int k = 0; k < 3; k++) brightest = fmax(brightest, (double)cases[i].light.color[k]);
        for (int k = 0; res.matrix && k < 3; k++)
            if (mean_of(&res.oracle, k) > MATRIX_ORACLE_MEAN * brightest)
                fail_msg("%s: channel %d: mean error vs the infinite-viewer oracle %.2f/255, budget %.2f",
                         cases[i].material.name, k, mean_of(&res.oracle, k), MATRIX_ORACLE_MEAN * brightest);
    }
    if (all.pixels) {
        print_channel_error("budget", &all);
        for (int k = 0; k < 3; k++)
            if (mean_of(&all, k) > ORACLE_MEAN)
                fail_msg("channel %d: mean error vs the oracle %.2f/255, budget %.2f", k, mean_of(&all, k),
                         ORACLE_MEAN);
    }
}

/* backlit.json's key light: colour 2, which the primary colour alone would clamp to 1 */
static ht_light bright_light(void) {
    ht_light l = first_light();
    l.color[0] = 2.0f, l.color[1] = 1.9f, l.color[2] = 1.75f;
    return l;
}

/* `make test`'s softpipe run (support_driver.h) probes the first
   `distinct` cases of a list: one per code path of the backend; the rest
   are those paths with other constants. */
static void run_probes_on_driver(const probe_case *cases, int count, int distinct) {
    run_probes(cases, ht_test_driver_cases_only() ? distinct : count);
}

/* Every generic case on softpipe too: their mean against the oracle is
   one budget (ORACLE_MEAN), and the brightest cases alone come close to it. */
static void test_fixed_probe_tracks_emulator_and_oracle_on_generic_cells(void **state) {
    (void)state;
    const probe_case cases[] = {
        { ht_probe_plain, bright_light(), true, false },
        { { "textured", "scheuermann", 80, -0.1, 24, 0.15, true }, bright_light(), true, false },
        { { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false }, bright_light(), true, true },
        { ht_probe_plain, first_light(), true, false },
        { { "textured", "scheuermann", 80, -0.1, 24, 0.15, true },
          first_light(), true, false },
        { ht_probe_plain, (ht_light){ HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } }, true, false },
        { { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false },
          first_light(), true, true },
    };
    run_probes(cases, (int)(sizeof cases / sizeof cases[0]));
}

/* Kajiya-Kay under a directional key light: the texture-matrix rule, held
   to the emulator fed the same tangents and matrix, and to the oracle with
   the rule's infinite viewer (V = the camera's view direction for every
   pixel). L = -V, where H has no direction, is a constant row of the
   matrix and exact under the infinite viewer (the local viewer's version
   of that case is out of budget above); the zero-tangent cell is black
   through its primary colour. A point light keeps CPU coordinates and the
   local viewer. */
static void test_kajiya_kay_probe_through_the_texture_matrix_tracks_emulator_and_oracle(void **state) {
    (void)state;
    const ht_probe_material kk = { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false };
    const ht_probe_material narrow = { "kajiya-kay-300", "kajiya-kay", 300, 0, 0, 0, false };
    const probe_case cases[] = {
        /* the paths: the texture matrix, CPU coordinates */
        { kk, first_light(), true, true },
        { kk, (ht_light){ HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } }, true, false },
        { kk, ht_probe_directional(0, 0, -1), true, true },
        { kk, ht_probe_directional(0, 0, 1), true, true },
        { kk, ht_probe_directional(1, 0, 0), true, true },
        { narrow, ht_probe_directional(-0.4, 0.3, 0.9), true, true },
    };
    run_probes_on_driver(cases, (int)(sizeof cases / sizeof cases[0]), 2);
}

static void test_fixed_probe_tracks_emulator_at_the_models_extremes(void **state) {
    (void)state;
    HT_TEST_DRIVER_INDEPENDENT(); /* the generic cells' plain path with other constants */
    /* Light behind the strand: L = -V at the centre pixel, where H has no
       direction and turns by 180 degrees across the centre cell; per-vertex
       H (Heidrich-Seidel) cannot follow that (measured: up to 229/255 in
       that one cell), so only the emulator holds it. L = V, grazing;
       exponents 0 and 10000 (the LUT axis clamps at 256: the lobe widens, a
       documented drop, so only the emulator holds it); shifts of +-100. */
    const probe_case cases[] = {
        { ht_probe_plain, ht_probe_directional(0, 0, -1), false, false },
        { ht_probe_plain, ht_probe_directional(0, 0, 1), true, false },
        { ht_probe_plain, ht_probe_directional(1, 0, 0), true, false },
        { { "exponent-0", "scheuermann", 0, 0.0, 0, 0.0, false },
          first_light(), true, false },
        { { "exponent-10000", "scheuermann", 10000, 0.0, 10000, 0.0, false },
          first_light(), false, false },
        { { "shift-100", "scheuermann", 80, 100.0, 24, -100.0, false },
          first_light(), true, false },
    };
    run_probes(cases, (int)(sizeof cases / sizeof cases[0]));
}

/* ---- the texture-matrix rule on the device ---- */

static void check_env_defaults(int units);

static bool same_matrix(const GLfloat a[16], const float b[16], float tolerance) {
    for (int k = 0; k < 16; k++)
        if (fabsf(a[k] - b[k]) > tolerance) return false;
    return true;
}

/* What GL reads for the LUT: the mesh's own tangents through the frame's
   texture matrix, reloaded when the light or the camera moves; no
   CPU-computed coordinate array exists for such a frame. The primary
   colours follow the light's colour. After each frame the texture matrix is
   the identity again. The fur ball's Scheuermann program, for contrast,
   reads a packed CPU array. */
static void test_kajiya_kay_frames_read_tangents_through_the_texture_matrix_without_cpu_coordinates(void **state) {
    (void)state;
    const ht_probe_material kk = { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false };
    const ht_light sun = first_light();
    char dir[256], err[256];
    ht_material material;
    ht_probe_make_bundle(fx.work, &kk, &sun, dir, sizeof dir, &material);
    ht_combiner_program prog = bundle_program(dir);
    assert_int_equal(ht_combiner_lut_coords(&prog), HT_COORDS_TEXTURE_MATRIX);
    assert_int_equal(prog.stages[0].unit, 0);

    ht_renderer *r = create((ht_renderer_desc){ .getproc = watching_getproc, .bundle_dir = dir,
                                                .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    assert_true(ht_test_logged("coordinates by the texture matrix (infinite viewer)"));
    ht_mesh mesh;
    ht_probe_build_mesh(&mesh);
    assert_int_equal(ht_renderer_set_mesh(r, &mesh), HT_OK);

    ht_light dim = ht_probe_directional(-0.5, 0.2, 0.6);
    dim.color[0] = 0.3f, dim.color[1] = 0.6f, dim.color[2] = 0.2f;
    const ht_light *lights[3] = { &sun, &dim, &sun };
    const float eyes[3][3] = { { 0, 0, 4 }, { 1.5f, 0.5f, 3.5f }, { 0, 0, 4 } };
    float previous[16] = { 0 };
    for (int fi = 0; fi < 3; fi++) {
        ht_frame_desc f = ht_probe_frame(lights[fi]);
        memcpy(f.camera.eye, eyes[fi], sizeof f.camera.eye);
        float view_dir[3], want[16];
        double len = 0.0;
        for (int k = 0; k < 3; k++) len += pow(f.camera.eye[k] - f.camera.target[k], 2);
        for (int k = 0; k < 3; k++) view_dir[k] = (float)((f.camera.eye[k] - f.camera.target[k]) / sqrt(len));
        assert_int_equal(ht_fixed_coords_texture_matrix(&prog, lights[fi], 1, view_dir, want, err, sizeof err), HT_OK);
        /* a new light or camera is a new matrix */
        assert_int_equal(same_matrix(previous, want, 1e-3f), false);
        memcpy(previous, want, sizeof want);
        draw_count = 0;
        ht_image img;
        render(r, &f, &img);
        ht_image_free(&img);
        assert_int_equal(draw_count, HT_PASS_COUNT);
        for (int i = 0; i < draw_count; i++) {
            const draw_state *d = &draws[i];
            assert_true(d->coord_array);
            assert_int_equal(d->coord_size, 3);
            /* the device has VBOs: tangents and colours read from buffers */
            assert_true(d->coord_buffer != 0 && d->color_buffer != 0);
            /* every vertex's tangent, packed with its uv (tangent, uv) */
            assert_int_equal(d->coord_stride, (GLint)(5 * sizeof(float)));
            const char *base = d->coord_pointer;
            for (uint32_t v = 0; v < mesh.vertex_count; v++) {
                const float *t = (const float *)(base + (size_t)v * 5 * sizeof(float));
                for (int k = 0; k < 3; k++) assert_float_equal(t[k], mesh.vertices[v].tangent[k], 1e-6);
            }
            if (!same_matrix(d->texture_matrix, want, 1e-6f))
                fail_msg("frame %d draw %d: unit 0's texture matrix is not the frame's", fi, i);
            /* the primary colours: this frame's light colour x ao, black
               where the tangent has no direction */
            const float *c = d->color_pointer;
            for (uint32_t v = 0; v < mesh.vertex_count; v++) {
                const ht_probe_cell *cell = &ht_probe_cells[v / 4];
                bool zero_t = cell->T[0] == 0 && cell->T[1] == 0 && cell->T[2] == 0;
                for (int k = 0; k < 3; k++)
                    assert_float_equal(c[4 * v + k], zero_t ? 0.0f : fminf(1.0f, lights[fi]->color[k] *
                                                                           (float)cell->ao), 1e-6);
            }
        }
        check_env_defaults(2);
    }
    for (int i = 0; i < ht_renderer_trace(r)->count; i++)
        assert_int_equal(ht_renderer_trace(r)->entries[i].gl_error, GL_NO_ERROR);
    ht_renderer_destroy(r);
    ht_mesh_free(&mesh);

    ht_combiner_program fur = bundle_program(fx.bundle_dir);
    assert_int_equal(ht_combiner_lut_coords(&fur), HT_COORDS_CPU_DOTS);
    r = create((ht_renderer_desc){ .getproc = watching_getproc, .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    assert_true(ht_test_logged("coordinates on the CPU per vertex"));
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    draw_count = 0;
    ht_image img;
    ht_frame_desc f = furball_frame();
    render(r, &f, &img);
    ht_image_free(&img);
    assert_int_equal(draw_count, HT_PASS_COUNT + (HT_PASS_COUNT - 1) * fur.add_light_count);
    for (int i = 0; i < draw_count; i++) {
        assert_int_equal(draws[i].coord_stride, 0);
        static const float identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
        assert_true(same_matrix(draws[i].texture_matrix, identity, 0.0f));
    }
    ht_renderer_destroy(r);
}

static int occurrences(const char *text, const char *what) {
    int n = 0;
    for (const char *at = strstr(text, what); at; at = strstr(at + 1, what)) n++;
    return n;
}

/* One frame of the backend alone, up to the opaque pass's draw call; what
   unit 0 reads then: its coordinate stride and its texture matrix. */
static void backend_frame(void *backend, const ht_light *light, GLint *stride, GLfloat matrix[16]) {
    const ht_tier_backend *b = &ht_tier_fixed_backend;
    /* the probe camera: at (0, 0, 4) looking down -z */
    ht_tier_frame f = { .eye = { 0, 0, 4 }, .lights = light, .light_count = 1,
                        .view = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -4, 1 } };
    b->begin_frame(backend, &f);
    b->bind_pass(backend, HT_PASS_OPAQUE, 0);
    assert_true(b->set_arrays(backend, HT_PASS_OPAQUE, 0)); /* arrays pointed: the renderer draws */
    client_active_texture(GL_TEXTURE0);
    glGetIntegerv(GL_TEXTURE_COORD_ARRAY_STRIDE, stride);
    active_texture(GL_TEXTURE0);
    glGetFloatv(GL_TEXTURE_MATRIX, matrix);
    b->end_frame(backend);
    assert_int_equal(glGetError(), GL_NO_ERROR);
}

/* The renderer shades every light as the bundle plans it, so a
   texture-matrix program only ever sees a directional key light through
   it; the backend on its own still refuses to put a point light into the
   matrix: such a frame gets CPU coordinates (through the identity), with
   one log line however many frames. */
static void test_backend_gives_a_point_key_light_cpu_coordinates_logged_once(void **state) {
    (void)state;
    const ht_probe_material kk = { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false };
    const ht_light sun = first_light();
    const ht_light point = { HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } };
    char dir[256], err[512];
    ht_material material;
    ht_probe_make_bundle(fx.work, &kk, &sun, dir, sizeof dir, &material);
    const ht_combiner_program prog = bundle_program(dir);
    static ht_manifest bundle;
    assert_int_equal(ht_manifest_load(dir, &bundle, err, sizeof err), HT_OK);
    static ht_gl gl;
    assert_int_equal(ht_gl_load(&gl, ht_test_getproc, err, sizeof err), HT_OK);
    ht_caps caps;
    assert_int_equal(ht_caps_probe(ht_test_getproc, &caps), HT_OK);
    ht_test_log_clear();
    const ht_tier_context ctx = { &gl, &caps, &bundle, ht_manifest_find_tier(&bundle, HT_TIER_FIXED),
                                  ht_test_log_capture, NULL, false };
    assert_non_null(ctx.tier);
    void *backend = NULL;
    if (ht_tier_fixed_backend.create(&ctx, &backend, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_mesh mesh;
    ht_probe_build_mesh(&mesh);
    assert_int_equal(ht_tier_fixed_backend.set_mesh(backend, &mesh), HT_OK);

    static const float identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    const ht_light *frames[4] = { &sun, &point, &point, &sun };
    for (int fi = 0; fi < 4; fi++) {
        GLint stride = -1;
        GLfloat m[16];
        backend_frame(backend, frames[fi], &stride, m);
        if (frames[fi] == &point) {
            assert_int_equal(stride, 0);
            assert_true(same_matrix(m, identity, 0.0f));
        } else {
            float want[16];
            assert_int_equal(ht_fixed_coords_texture_matrix(&prog, frames[fi], 1, (const float[3]){ 0, 0, 1 }, want,
                                                            err, sizeof err), HT_OK);
            assert_int_equal(stride, (GLint)(5 * sizeof(float)));
            assert_true(same_matrix(m, want, 1e-6f));
        }
    }
    if (occurrences(ht_test_log_text, "light 0 is a point light") != 1 ||
        occurrences(ht_test_log_text, "CPU coordinates for such frames") != 1)
        fail_msg("want one line for the point light, log:\n%s", ht_test_log_text);
    ht_tier_fixed_backend.destroy(backend);
    ht_mesh_free(&mesh);
}

/* ---- devices that cannot run it ---- */

static void expect_refused(ht_device_profile profile, const char *dir, const char *reason) {
    char want[512], line[1024];
    snprintf(want, sizeof want, "hairtier: skipped fixed: %s", reason);
    /* GL 1.3 with at most 2 units leaves fixed the only candidate (fixed4
       needs 4): the renderer has no tier. */
    profile.gl_major = 1;
    profile.gl_minor = 3;
    if (profile.texture_units == 0) profile.texture_units = 2;
    ht_renderer *r = create((ht_renderer_desc){ .profile = profile, .bundle_dir = dir }, HT_ERR_NO_TIER);
    assert_null(r);
    if (!logged_line("skipped fixed: ", line, sizeof line)) fail_msg("no fixed line in:\n%s", ht_test_log_text);
    assert_string_equal(line, want);
    /* Forced and strict: the same reason is the error. */
    r = create((ht_renderer_desc){ .profile = profile, .bundle_dir = dir, .tier = HT_TIER_FIXED, .strict = true },
               HT_ERR_UNSUPPORTED);
    assert_null(r);
    snprintf(want, sizeof want, "fixed: %s (forced by desc.tier, strict)", reason);
    assert_true(ht_test_logged(want));
}

static void test_device_with_too_few_units_is_refused(void **state) {
    (void)state;
    expect_refused((ht_device_profile){ .texture_units = 1 }, fx.bundle_dir, "needs 2 texture units, have 1");
    /* A manifest that understates the units: the program itself is checked. */
    char dir[256], reason[512];
    ht_test_furball_copy_bundle(&fx, "one-unit-manifest", dir, sizeof dir);
    cJSON *root = cJSON_Parse(ht_test_read_file(dir, "manifest.json"));
    assert_non_null(root);
    cJSON *tiers = cJSON_GetObjectItem(root, "tiers");
    cJSON *t = NULL;
    cJSON_ArrayForEach(t, tiers) {
        if (strcmp(cJSON_GetObjectItem(t, "name")->valuestring, "fixed") == 0)
            cJSON_ReplaceItemInObject(cJSON_GetObjectItem(t, "requires"), "texture_units", cJSON_CreateNumber(1));
    }
    char *text = cJSON_Print(root);
    ht_test_write_file(dir, "manifest.json", text);
    free(text);
    cJSON_Delete(root);
    int stages = bundle_program(dir).stage_count;
    assert_true(stages > 1);
    snprintf(reason, sizeof reason, "%s/fixed.json: %d stages need %d texture units, have 1", dir, stages, stages);
    expect_refused((ht_device_profile){ .texture_units = 1 }, dir, reason);
}

static void test_device_without_combine_is_refused(void **state) {
    (void)state;
    expect_refused((ht_device_profile){ .hide_extensions = "GL_ARB_texture_env_combine GL_EXT_texture_env_combine" },
                   fx.bundle_dir, "needs GL_ARB_texture_env_combine");
}

static void test_device_with_small_3d_textures_is_refused(void **state) {
    (void)state;
    ht_combiner_program p = bundle_program(fx.bundle_dir);
    int largest = largest_lut_axis(&p);
    assert_true(p.lut_size[2] > 1); /* dark-brown's LUT is 3D */
    char reason[512];
    snprintf(reason, sizeof reason, "LUT %dx%dx%d needs GL_MAX_3D_TEXTURE_SIZE %d, have 16", p.lut_size[0],
             p.lut_size[1], p.lut_size[2], largest);
    expect_refused((ht_device_profile){ .max_3d_texture_size = 16 }, fx.bundle_dir, reason);
    snprintf(reason, sizeof reason, "LUT %dx%dx%d needs GL_MAX_3D_TEXTURE_SIZE %d, have %d", p.lut_size[0],
             p.lut_size[1], p.lut_size[2], largest, largest / 2);
    expect_refused((ht_device_profile){ .max_3d_texture_size = largest / 2 }, fx.bundle_dir, reason);
    /* Exactly the largest axis is enough. */
    ht_renderer *r = create((ht_renderer_desc){ .profile = { .gl_major = 1, .gl_minor = 3, .texture_units = 2,
                                                             .max_3d_texture_size = largest } }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FIXED);
    assert_int_equal(ht_renderer_caps(r)->max_3d_texture_size, largest);
    ht_renderer_destroy(r);
    /* No 3D textures at all: the LUT as two 2D textures (fixed_split.h),
       two more units; with four the tier draws. */
    snprintf(reason, sizeof reason, "%s/fixed.json: %d stages need %d texture units, have 2 (2 of them for the 3D "
             "LUT split in two 2D textures: no 3D textures)", fx.bundle_dir, p.stage_count + 2, p.stage_count + 2);
    expect_refused((ht_device_profile){ .hide_extensions = "GL_EXT_texture3D" }, fx.bundle_dir, reason);
    r = create((ht_renderer_desc){ .profile = { .gl_major = 1, .gl_minor = 3, .texture_units = 4,
                                                .hide_extensions = "GL_EXT_texture3D" },
                                   .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FIXED);
    assert_true(ht_test_logged("2D textures (no 3D textures: texel error up to 1/255)"));
    ht_renderer_destroy(r);
}

/* ---- broken bundles ---- */

static void expect_skipped(const char *dir, const char *reason_start) {
    ht_renderer *r = create((ht_renderer_desc){ .profile = { .gl_major = 1, .gl_minor = 3, .texture_units = 2 }, .bundle_dir = dir },
                            HT_ERR_NO_TIER);
    assert_null(r);
    char want[512], line[1024];
    snprintf(want, sizeof want, "hairtier: skipped fixed: %s", reason_start);
    if (!logged_line("skipped fixed: ", line, sizeof line)) fail_msg("no fixed line in:\n%s", ht_test_log_text);
    if (strncmp(line, want, strlen(want)) != 0) fail_msg("got  \"%s\"\nwant \"%s...\"", line, want);
    assert_true(every_line_is_the_renderers());
    /* A device that runs full is unaffected by a broken fixed tier. */
    r = create((ht_renderer_desc){ .bundle_dir = dir }, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL);
    ht_renderer_destroy(r);
}

static void test_corrupt_program_skips_fixed_naming_the_file(void **state) {
    (void)state;
    char dir[256], want[512];
    ht_test_furball_copy_bundle(&fx, "corrupt-program", dir, sizeof dir);
    ht_test_write_file(dir, "fixed.json", "{\"format\": \"hairtier-combiner/1\", \"model\": ");
    snprintf(want, sizeof want, "%s/fixed.json: line 1: malformed JSON", dir);
    expect_skipped(dir, want);

    /* A bad field is named by its path. */
    ht_test_furball_copy_bundle(&fx, "bad-scale", dir, sizeof dir);
    cJSON *root = cJSON_Parse(ht_test_read_file(dir, "fixed.json"));
    assert_non_null(root);
    cJSON *stage = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "stages"), 0);
    cJSON_ReplaceItemInObject(stage, "rgb_scale", cJSON_CreateNumber(3));
    char *out = cJSON_Print(root);
    ht_test_write_file(dir, "fixed.json", out);
    free(out);
    cJSON_Delete(root);
    snprintf(want, sizeof want, "%s/fixed.json: stages[0].rgb_scale", dir);
    expect_skipped(dir, want);

    char path[512];
    ht_test_furball_copy_bundle(&fx, "missing-program", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/fixed.json", dir);
    assert_int_equal(unlink(path), 0);
    snprintf(want, sizeof want, "%s/fixed.json: cannot read", dir);
    expect_skipped(dir, want);
}

static void test_missing_or_wrong_lut_skips_fixed_naming_the_file(void **state) {
    (void)state;
    char dir[256], want[512], path[512], err[256];
    ht_test_furball_copy_bundle(&fx, "missing-lut", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/fixed-lut.png", dir);
    assert_int_equal(unlink(path), 0);
    snprintf(want, sizeof want, "%s/fixed-lut.png: cannot read: No such file or directory", dir);
    expect_skipped(dir, want);

    /* A LUT image that is not the size the manifest lists. */
    ht_test_furball_copy_bundle(&fx, "small-lut", dir, sizeof dir);
    snprintf(path, sizeof path, "%s/fixed-lut.png", dir);
    ht_image small = { 0 };
    assert_int_equal(ht_image_alloc(&small, 4, 4, 3), HT_OK);
    assert_int_equal(ht_image_write_png(path, &small, err, sizeof err), HT_OK);
    ht_image_free(&small);
    snprintf(want, sizeof want, "%s/fixed-lut.png: 4x4, manifest says", dir);
    expect_skipped(dir, want);

    /* A truncated PNG. */
    ht_test_furball_copy_bundle(&fx, "truncated-lut", dir, sizeof dir);
    ht_test_write_file(dir, "fixed-lut.png", "\x89PNG\r\n\x1a\n");
    snprintf(want, sizeof want, "%s/fixed-lut.png: ", dir);
    expect_skipped(dir, want);
}

/* ---- GL state ---- */

static void check_env_defaults(int units) {
    static const struct { GLenum pname; GLint value; } defaults[] = {
        { GL_TEXTURE_ENV_MODE, GL_MODULATE },
        { GL_COMBINE_RGB, GL_MODULATE }, { GL_COMBINE_ALPHA, GL_MODULATE },
        { GL_SOURCE0_RGB, GL_TEXTURE }, { GL_SOURCE1_RGB, GL_PREVIOUS }, { GL_SOURCE2_RGB, GL_CONSTANT },
        { GL_SOURCE0_ALPHA, GL_TEXTURE }, { GL_SOURCE1_ALPHA, GL_PREVIOUS }, { GL_SOURCE2_ALPHA, GL_CONSTANT },
        { GL_OPERAND0_RGB, GL_SRC_COLOR }, { GL_OPERAND1_RGB, GL_SRC_COLOR }, { GL_OPERAND2_RGB, GL_SRC_ALPHA },
        { GL_OPERAND0_ALPHA, GL_SRC_ALPHA }, { GL_OPERAND1_ALPHA, GL_SRC_ALPHA },
        { GL_OPERAND2_ALPHA, GL_SRC_ALPHA },
    };
    for (int u = 0; u < units; u++) {
        active_texture(GL_TEXTURE0 + (GLenum)u);
        client_active_texture(GL_TEXTURE0 + (GLenum)u);
        for (size_t i = 0; i < sizeof defaults / sizeof defaults[0]; i++) {
            GLint v = 0;
            glGetTexEnviv(GL_TEXTURE_ENV, defaults[i].pname, &v);
            if (v != defaults[i].value)
                fail_msg("unit %d: texture env 0x%04x is 0x%04x, default 0x%04x", u, defaults[i].pname, v,
                         defaults[i].value);
        }
        GLfloat scale = 0, color[4] = { 1, 1, 1, 1 };
        glGetTexEnvfv(GL_TEXTURE_ENV, GL_RGB_SCALE, &scale);
        assert_float_equal(scale, 1.0f, 0.0f);
        glGetTexEnvfv(GL_TEXTURE_ENV, GL_ALPHA_SCALE, &scale);
        assert_float_equal(scale, 1.0f, 0.0f);
        glGetTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, color);
        for (int k = 0; k < 4; k++) assert_float_equal(color[k], 0.0f, 0.0f);
        assert_false(glIsEnabled(GL_TEXTURE_2D));
        assert_false(glIsEnabled(GL_TEXTURE_3D));
        assert_false(glIsEnabled(GL_TEXTURE_COORD_ARRAY));
        GLfloat m[16];
        glGetFloatv(GL_TEXTURE_MATRIX, m);
        for (int k = 0; k < 16; k++) assert_float_equal(m[k], (k % 5 == 0 ? 1.0f : 0.0f), 0.0f);
        GLint bound = -1;
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
        assert_int_equal(bound, 0);
        glGetIntegerv(GL_TEXTURE_BINDING_3D, &bound);
        assert_int_equal(bound, 0);
    }
    active_texture(GL_TEXTURE0);
    client_active_texture(GL_TEXTURE0);
    GLint v = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &v);
    assert_int_equal(v, GL_TEXTURE0);
    glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &v);
    assert_int_equal(v, GL_TEXTURE0);
    assert_false(glIsEnabled(GL_COLOR_ARRAY));
    GLint mode = 0;
    glGetIntegerv(GL_MATRIX_MODE, &mode);
    assert_int_equal(mode, GL_MODELVIEW);
    GLfloat current[4] = { 0, 0, 0, 0 };
    glGetFloatv(GL_CURRENT_COLOR, current);
    for (int k = 0; k < 4; k++) assert_float_equal(current[k], 1.0f, 0.0f);
    assert_int_equal(glGetError(), GL_NO_ERROR);
}

static void test_frame_calls_no_shaders_and_primes_z_without_the_lut(void **state) {
    (void)state;
    shader_calls = 0;
    draw_count = 0;
    ht_renderer *r = create((ht_renderer_desc){ .getproc = watching_getproc, .tier = HT_TIER_FIXED, .strict = true },
                            HT_OK);
    assert_true(ht_renderer_caps(r)->has_shaders); /* shaders were there to misuse */
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_image img;
    ht_frame_desc f = furball_frame();
    render(r, &f, &img);
    ht_image_free(&img);
    ht_renderer_destroy(r);
    assert_int_equal(shader_calls, 0);
    ht_combiner_program p = bundle_program(fx.bundle_dir);
    assert_int_equal(draw_count, HT_PASS_COUNT + (HT_PASS_COUNT - 1) * p.add_light_count);
    assert_int_equal(p.stage_count, 2);
    for (int i = 0; i < draw_count; i++) {
        const draw_state *d = &draws[i];
        assert_int_equal(d->program, 0);
        bool prime = i == 0; /* the prime-Z pass has no sub-passes: its draw is the first */
        assert_int_equal(d->color_write, !prime);
        /* unit 0: the LUT, off while priming Z; unit 1: albedo, whose alpha primes */
        assert_int_equal(d->unit_3d[0], !prime);
        assert_false(d->unit_2d[0]);
        assert_true(d->unit_2d[1]);
        assert_int_equal(d->env_mode[1], GL_COMBINE);
        if (!prime) assert_int_equal(d->env_mode[0], GL_COMBINE);
    }
}

/* Z from the prime pass must be the same texels as the full tier's. */
static void read_depth(float *out) {
    glReadPixels(0, 0, SIZE, SIZE, GL_DEPTH_COMPONENT, GL_FLOAT, out);
}

static void test_frame_restores_texture_env_and_leaves_other_tiers_unchanged(void **state) {
    (void)state;
    ht_frame_desc f = furball_frame();
    ht_renderer *full = create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true }, HT_OK);
    ht_renderer *flat = create((ht_renderer_desc){ .flat = true }, HT_OK);
    ht_renderer *fixed = create((ht_renderer_desc){ .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(full, &fx.mesh), HT_OK);
    assert_int_equal(ht_renderer_set_mesh(flat, &fx.mesh), HT_OK);
    assert_int_equal(ht_renderer_set_mesh(fixed, &fx.mesh), HT_OK);
    ht_image full_before, flat_before, fixed_img, full_after, flat_after;
    static float depth_full[SIZE * SIZE], depth_fixed[SIZE * SIZE];
    render(full, &f, &full_before);
    read_depth(depth_full);
    render(flat, &f, &flat_before);

    render(fixed, &f, &fixed_img);
    read_depth(depth_fixed);
    const ht_trace *t = ht_renderer_trace(fixed);
    assert_int_equal(t->count, HT_PASS_COUNT + (HT_PASS_COUNT - 1) * bundle_program(fx.bundle_dir).add_light_count);
    for (int i = 0; i < t->count; i++) assert_int_equal(t->entries[i].gl_error, GL_NO_ERROR);
    check_env_defaults(ht_renderer_caps(fixed)->texture_units < 4 ? ht_renderer_caps(fixed)->texture_units : 4);

    /* The tier after it draws the same bytes it drew before it. */
    render(full, &f, &full_after);
    render(flat, &f, &flat_after);
    assert_memory_equal(full_before.pixels, full_after.pixels, (size_t)SIZE * SIZE * 4);
    assert_memory_equal(flat_before.pixels, flat_after.pixels, (size_t)SIZE * SIZE * 4);

    /* Alpha comes from the same albedo texels in both tiers: the depth the
       prime and front passes leave agrees (a few texels at the cutoff may
       filter differently). */
    int differ = 0, hair = 0;
    for (int i = 0; i < SIZE * SIZE; i++) {
        hair += depth_full[i] < 1.0f;
        differ += depth_full[i] != depth_fixed[i];
    }
    printf("depth: %d of %d hair pixels differ between full and fixed\n", differ, hair);
    assert_true(hair > SIZE * SIZE / 20);
    assert_true(differ <= hair / 100);

    ht_image *imgs[5] = { &full_before, &flat_before, &fixed_img, &full_after, &flat_after };
    for (int i = 0; i < 5; i++) ht_image_free(imgs[i]);
    ht_renderer_destroy(full);
    ht_renderer_destroy(flat);
    ht_renderer_destroy(fixed);
}

static void test_mesh_changes_and_empty_frames_are_safe(void **state) {
    (void)state;
    ht_renderer *r = create((ht_renderer_desc){ .tier = HT_TIER_FIXED, .strict = true }, HT_OK);
    ht_frame_desc f = furball_frame();
    ht_image img;
    render(r, &f, &img); /* no mesh yet */
    ht_image_free(&img);
    ht_mesh empty = { 0 };
    assert_int_equal(ht_renderer_set_mesh(r, &empty), HT_OK);
    render(r, &f, &img);
    ht_image_free(&img);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    f.light_count = 0; /* unlit: black hair, still drawn */
    render(r, &f, &img);
    ht_test_pixel_stats s = stats(&img);
    assert_true(s.changed > SIZE * SIZE / 20);
    ht_image_free(&img);
    for (int i = 0; i < ht_renderer_trace(r)->count; i++)
        assert_int_equal(ht_renderer_trace(r)->entries[i].gl_error, GL_NO_ERROR);
    check_env_defaults(2);
    ht_renderer_destroy(r);
}

int main(int argc, char **argv) {
    if (argc == 3 && strcmp(argv[1], "--child") == 0) return child_main(argv[2]);
    ht_probe_make_cells();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gl13_profile_selects_fixed_and_draws_the_full_tiers_passes),
        cmocka_unit_test(test_mesa_gl13_driver_runs_fixed_with_the_full_tiers_trace),
        cmocka_unit_test(test_additive_sub_pass_adds_the_second_light_exactly_on_opaque_hair),
        cmocka_unit_test(test_fixed_probe_tracks_emulator_and_oracle_on_generic_cells),
        cmocka_unit_test(test_fixed_probe_tracks_emulator_at_the_models_extremes),
        cmocka_unit_test(test_kajiya_kay_probe_through_the_texture_matrix_tracks_emulator_and_oracle),
        cmocka_unit_test(test_kajiya_kay_frames_read_tangents_through_the_texture_matrix_without_cpu_coordinates),
        cmocka_unit_test(test_backend_gives_a_point_key_light_cpu_coordinates_logged_once),
        cmocka_unit_test(test_device_with_too_few_units_is_refused),
        cmocka_unit_test(test_device_without_combine_is_refused),
        cmocka_unit_test(test_device_with_small_3d_textures_is_refused),
        cmocka_unit_test(test_corrupt_program_skips_fixed_naming_the_file),
        cmocka_unit_test(test_missing_or_wrong_lut_skips_fixed_naming_the_file),
        cmocka_unit_test(test_frame_calls_no_shaders_and_primes_z_without_the_lut),
        cmocka_unit_test(test_frame_restores_texture_env_and_leaves_other_tiers_unchanged),
        cmocka_unit_test(test_mesh_changes_and_empty_frames_are_safe),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

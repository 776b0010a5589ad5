/* test_render_drivers — every shipped scene on a driver that really is old:
   Mesa restricted by its own MESA_GL_VERSION_OVERRIDE (1.1 .. 2.1) and
   MESA_EXTENSION_OVERRIDE (shaders, VBOs, combine, crossbar, dot3, 3D
   textures, NPOT, cube maps taken away), so an entry point or enum the
   driver lacks is really refused, not hidden inside the runtime. For every
   cell: no crash, the tier the selection rules promise for what the driver
   reports (the rules are restated here from docs/DESIGN.md, not taken from
   caps.c), and the same image (>= 40 dB) as that tier forced on the
   unrestricted driver. Mesa reads both variables at its first context, once
   per process, so each cell is a forked child that makes its first context;
   the parent loads libOSMesa and the scenes once, before any context, and
   the children inherit them.

   On softpipe (GALLIUM_DRIVER=softpipe, an interpreter) the test keeps the cell of the crash this test was built for, GL 1.3 without
   shaders (fixed4 on client arrays); llvmpipe runs every cell. `make
   test`'s softpipe run (support_driver.h) draws that cell's fur ball and
   patches at HT_TEST_DRIVER_SIDE², and the regression case below only as
   that cell. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "compare/tier_render.h"
#include <hairtier/hairgen.h>
#include "metrics.h"
#include "offscreen.h"
#include "offscreen_backend.h"
#include "support_driver.h"
#include "support_scene.h"
#include "support_render.h"
#include "support_scratch.h"

/* Rendered small, the fur balls and the ratboy's strands thinned: the
   cells prove which code runs and that it draws the same picture; the
   shipped size is test_render_scenes' job. */
#define SIZE 64
#define HAIRS 250
#define STRAND_EVERY 16
#define MIN_PSNR_DB 40.0

typedef struct scene_case {
    const char *name, *material, *scene;
} scene_case;

static const scene_case scenes[] = {
    { "furball", "materials/dark-brown.json", "scenes/furball.json" },
    { "patches", "materials/blond.json", "scenes/patches.json" },
    { "ratboy", "materials/kajiya-kay.json", "scenes/ratboy.json" },
    { "backlit", "materials/brown-marschner.json", "scenes/backlit.json" },
};
#define SCENE_COUNT (sizeof scenes / sizeof scenes[0])
/* The scenes a cell draws: `make test`'s softpipe run (support_driver.h)
   the first two, hair alone and hair with a head (the opaque mesh's
   arrays too); the others differ in material and geometry, made on the CPU. */
static size_t scene_count(void) { return ht_test_driver_cases_only() ? 2 : SCENE_COUNT; }
/* The side of the frames (support_driver.h: smaller on that run). */
static int side(void) { return ht_test_driver_side(SIZE); }

#define SHADER_EXTENSIONS                                                                               \
    "-GL_ARB_shader_objects -GL_ARB_vertex_shader -GL_ARB_fragment_shader -GL_ARB_vertex_program "      \
    "-GL_ARB_fragment_program -GL_ARB_shading_language_100"

typedef struct restriction {
    const char *name;
    const char *override;   /* MESA_EXTENSION_OVERRIDE; NULL: unset */
    bool no_shaders;        /* the GL 2.0 shader entry points refuse (Mesa: GL_INVALID_ENUM) */
} restriction;

static const restriction restrictions[] = {
    { "as-is", NULL, false },
    { "no-shaders", SHADER_EXTENSIONS, true },
    { "no-vbo", "-GL_ARB_vertex_buffer_object", false },
    { "no-combine", "-GL_ARB_texture_env_combine -GL_EXT_texture_env_combine", false },
    { "no-crossbar", "-GL_ARB_texture_env_crossbar", false },
    { "no-dot3", "-GL_ARB_texture_env_dot3 -GL_EXT_texture_env_dot3", false },
    { "no-3d", "-GL_EXT_texture3D", false },
    { "no-npot", "-GL_ARB_texture_non_power_of_two", false },
    { "no-cube", "-GL_ARB_texture_cube_map -GL_EXT_texture_cube_map", false },
};
#define RESTRICTION_COUNT (sizeof restrictions / sizeof restrictions[0])

static const char *const versions[] = { "1.1", "1.2", "1.3", "1.4", "1.5", "2.0", "2.1" };
#define VERSION_COUNT (sizeof versions / sizeof versions[0])

/* ---- the child: one context, every scene drawn, images to files ---- */

/* The cells' scenes, loaded by the parent before any context. */
static tier_scene loaded[SCENE_COUNT];
static char bundle_of[SCENE_COUNT][256];
static bool loaded_ok[SCENE_COUNT];
static char load_error[SCENE_COUNT][1024];

static void child_log(void *user, const char *line) {
    (void)user;
    printf("log %s\n", line);
}

static bool write_all(const char *path, const void *data, size_t size) {
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && ok;
}

/* In a child: the cell TAG drawing every scene as TIER. Prints "driver
   VERSION", "extensions LIST", then per scene "scene NAME tier TIER" (or "scene NAME failed RESULT");
   writes WORK/TAG-NAME.rgba. */
static int run_cell(const char *work, const char *tag, const char *tier_name) {
    char err[1024];
    ht_tier tier = ht_tier_from_name(tier_name);
    if (tier == HT_TIER_COUNT) return 2;
    offscreen *gl = offscreen_open(&(offscreen_desc){ .width = side(), .height = side(), .egl_device = -1 }, err, sizeof err);
    if (!gl) {
        printf("context failed: %s\n", err);
        return 3;
    }
    const char *version = (const char *)gl->gl.GetString(GL_VERSION);
    const char *extensions = (const char *)gl->gl.GetString(GL_EXTENSIONS);
    printf("driver %s\nextensions %s\n", version ? version : "", extensions ? extensions : "");
    fflush(stdout);
    for (size_t i = 0; i < scene_count(); i++) {
        if (!loaded_ok[i]) {
            printf("scene %s failed %s\n", scenes[i].name, load_error[i]);
            continue;
        }
        const tier_scene s = loaded[i];
        char out[320];
        ht_renderer *r = NULL;
        ht_result res = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle_of[i],
                                                                .tier = tier, .strict = tier != HT_TIER_AUTO,
                                                                .log = child_log },
                                           &r);
        if (res == HT_OK) res = ht_renderer_set_mesh(r, &s.hair);
        if (res == HT_OK) {
            ht_frame_desc frame = { .camera = s.scene.camera, .lights = s.scene.lights,
                                    .light_count = s.scene.light_count, .aspect = 1.0f,
                                    .opaque = s.head.index_count ? &s.head : NULL };
            gl->gl.ClearColor(s.scene.background[0], s.scene.background[1], s.scene.background[2], 1.0f);
            gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            res = ht_renderer_draw(r, &frame);
        }
        if (res == HT_OK) {
            snprintf(out, sizeof out, "%s/%s-%s.rgba", work, tag, scenes[i].name);
            if (!write_all(out, offscreen_read(gl), (size_t)side() * side() * 4)) res = HT_ERR_IO;
        }
        if (res == HT_OK) printf("scene %s tier %s\n", scenes[i].name, ht_tier_name(ht_renderer_tier(r)));
        else printf("scene %s failed %s\n", scenes[i].name, ht_result_string(res));
        fflush(stdout);
        ht_renderer_destroy(r);
    }
    offscreen_close(gl);
    return 0;
}

/* ---- the parent ---- */

static char work[64];

static int setup(void **state) {
    (void)state;
    char err_of_setup[1024];
    if (!ht_test_scratch_create(work, sizeof work, "drivers")) return -1;
    for (size_t i = 0; i < scene_count(); i++) {
        char err[1024], path[256], name[64];
        snprintf(name, sizeof name, "%s.json", scenes[i].name);
        ht_test_scene_copy(scenes[i].scene, work, name, side(), ht_test_driver_hairs(HAIRS), false, path, sizeof path);
        ht_test_scene_thin_strands(work, name, STRAND_EVERY);
        snprintf(bundle_of[i], sizeof bundle_of[i], "%s/%s-bundle", work, scenes[i].name);
        if (ht_test_bundle(scenes[i].material, scenes[i].name, path, bundle_of[i], sizeof bundle_of[i], err,
                           sizeof err) != HT_OK) {
            fprintf(stderr, "setup: %s\n", err);
            return -1;
        }
        loaded_ok[i] = tier_scene_load(path, &loaded[i], load_error[i], sizeof load_error[i]) == HT_OK;
    }
    /* libOSMesa (and LLVM under it) relocated once, not per cell; no context yet */
    const char *context = getenv("HAIRTIER_CONTEXT");
    if ((!context || strcmp(context, "osmesa") == 0) && !offscreen_osmesa_available(NULL, err_of_setup, sizeof err_of_setup))
        fprintf(stderr, "setup: %s (the cells will say so)\n", err_of_setup);
    return 0;
}

static int teardown(void **state) {
    (void)state;
    for (size_t i = 0; i < SCENE_COUNT; i++)
        if (loaded_ok[i]) tier_scene_free(&loaded[i]);
    return ht_test_scratch_remove(work);
}

/* Forks a cell with the two variables (NULL: unset), its stdout and stderr
   into WORK/TAG.log. */
static pid_t start_child(const char *version, const char *override, const char *tag, const char *tier) {
    char log[256];
    snprintf(log, sizeof log, "%s/%s.log", work, tag);
    fflush(stdout); /* else the child writes the parent's pending output again */
    fflush(stderr);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        FILE *f = freopen(log, "w", stdout);
        if (!f || dup2(1, 2) < 0) _exit(126);
        if (version) setenv("MESA_GL_VERSION_OVERRIDE", version, 1);
        else unsetenv("MESA_GL_VERSION_OVERRIDE");
        if (override) setenv("MESA_EXTENSION_OVERRIDE", override, 1);
        else unsetenv("MESA_EXTENSION_OVERRIDE");
        int code = run_cell(work, tag, tier);
        fflush(stdout);
        _exit(code);
    }
    return pid;
}

/* Waits for the child; its log (malloc'd) and exit status. */
static char *finish_child(pid_t pid, const char *tag, int *status) {
    assert_int_equal(waitpid(pid, status, 0), pid);
    char log[256];
    snprintf(log, sizeof log, "%s/%s.log", work, tag);
    char *text = ht_test_read_all(log, NULL);
    assert_non_null(text);
    return text;
}

static char *run_child(const char *version, const char *override, const char *tag, const char *tier, int *status) {
    return finish_child(start_child(version, override, tag, tier), tag, status);
}

/* The word after "KEY " on the line that starts with it, copied into out. */
static bool line_value(const char *text, const char *key, char *out, size_t size) {
    size_t k = strlen(key);
    for (const char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        if (strncmp(p, key, k) == 0 && p[k] == ' ') {
            const char *v = p + k + 1;
            size_t n = strcspn(v, "\n");
            if (n >= size) n = size - 1;
            memcpy(out, v, n);
            out[n] = '\0';
            return true;
        }
    }
    return false;
}

static bool lists(const char *extensions, const char *name) {
    size_t n = strlen(name);
    for (const char *p = extensions; (p = strstr(p, name)); p += n)
        if ((p == extensions || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

/* What docs/DESIGN.md promises for a driver of this version listing these
   extensions: the combiner tiers need GL 1.2 (edge clamping) and
   multitexture and combine, which GL 1.3 made core;
   GLSL needs 2.0 (full 2.1) and shader entry points that work; a tier
   whose shaders the driver refuses falls to the next. The bundle's tiers
   from best to cheapest: marschner (Marschner materials), full, vertex,
   fixed4, fixed, gl11. */
static const char *promised_tier(const char *scene, double version, const char *extensions, bool shaders_work) {
    bool multitexture = version >= 1.3 || lists(extensions, "GL_ARB_multitexture");
    bool combine = version >= 1.3 || lists(extensions, "GL_ARB_texture_env_combine") ||
                   lists(extensions, "GL_EXT_texture_env_combine");
    bool glsl = version >= 2.0 && shaders_work;
    /* llvmpipe has 8 units, so every unit count a tier asks for is there */
    if (strcmp(scene, "backlit") == 0 && glsl && version >= 2.1) return "marschner";
    if (glsl && version >= 2.1) return "full";
    if (glsl && combine && multitexture) return "vertex";
    if (version >= 1.2 && multitexture && combine) return "fixed4";
    return "gl11";
}

static uint8_t *read_image(const char *tag, const char *scene) {
    char path[256];
    snprintf(path, sizeof path, "%s/%s-%s.rgba", work, tag, scene);
    size_t size = 0;
    uint8_t *data = (uint8_t *)ht_test_read_all(path, &size);
    if (data && size != (size_t)side() * side() * 4) {
        free(data);
        return NULL;
    }
    return data;
}

/* The reference of each tier: forced, strict, on the unrestricted driver;
   made on first use. */
static bool reference_made[HT_TIER_COUNT];

static void make_reference(const char *tier) {
    ht_tier t = ht_tier_from_name(tier);
    if (reference_made[t]) return;
    char tag[96];
    snprintf(tag, sizeof tag, "ref-%s", tier);
    int status = 0;
    char *out = run_child(NULL, NULL, tag, tier, &status);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail_msg("reference %s: child failed:\n%s", tier, out);
    free(out);
    reference_made[t] = true;
}

static int cells_checked;

static void cell_tag(const char *version, const restriction *rx, char *tag, size_t size) {
    snprintf(tag, size, "gl%s-%s", version, rx->name);
}

static pid_t start_cell(const char *version, const restriction *rx) {
    char tag[64];
    cell_tag(version, rx, tag, sizeof tag);
    return start_child(version, rx->override, tag, "auto");
}

static void check_cell(pid_t pid, const char *version, const restriction *rx) {
    char tag[64];
    cell_tag(version, rx, tag, sizeof tag);
    int status = 0;
    char *out = finish_child(pid, tag, &status);
    if (WIFSIGNALED(status))
        fail_msg("%s: the child died of signal %d (%s)\n%s", tag, WTERMSIG(status), strsignal(WTERMSIG(status)), out);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail_msg("%s: the child exited %d\n%s", tag, WEXITSTATUS(status), out);
    char driver[64] = "", extensions[16384] = "";
    assert_true(line_value(out, "driver", driver, sizeof driver));
    line_value(out, "extensions", extensions, sizeof extensions);
    if (strncmp(driver, version, strlen(version)) != 0) fail_msg("%s: the driver says GL %s", tag, driver);
    for (size_t i = 0; i < scene_count(); i++) {
        char key[64], got[64];
        snprintf(key, sizeof key, "scene %s tier", scenes[i].name);
        if (!line_value(out, key, got, sizeof got)) fail_msg("%s: %s drew nothing:\n%s", tag, scenes[i].name, out);
        const char *want = promised_tier(scenes[i].name, atof(version), extensions, !rx->no_shaders);
        if (strcmp(got, want) != 0) fail_msg("%s: %s: tier %s, the rules promise %s\n%s", tag, scenes[i].name, got, want, out);
        make_reference(got);
        char ref_tag[96];
        snprintf(ref_tag, sizeof ref_tag, "ref-%s", got);
        uint8_t *ref = read_image(ref_tag, scenes[i].name), *img = read_image(tag, scenes[i].name);
        assert_non_null(ref);
        assert_non_null(img);
        ht_metrics whole;
        char err[256];
        assert_int_equal(ht_metrics_compare(&(ht_metrics_desc){ .reference = ref, .test = img, .width = side(), .height = side() },
                                            &whole, NULL, err, sizeof err),
                         HT_OK);
        if (!(whole.psnr_db >= MIN_PSNR_DB))
            fail_msg("%s: %s (%s): %.2f dB against %s forced on the unrestricted driver, want >= %.0f", tag,
                     scenes[i].name, got, whole.psnr_db, got, MIN_PSNR_DB);
        printf("%-22s %-8s %-9s %s dB\n", tag, scenes[i].name, got,
               isinf(whole.psnr_db) ? "identical" : (snprintf(err, sizeof err, "%.1f", whole.psnr_db), err));
        free(ref);
        free(img);
    }
    cells_checked++;
    free(out);
}

static bool subset(void) {
    const char *e = getenv("GALLIUM_DRIVER");
    return e && strcmp(e, "softpipe") == 0;
}

static void test_restricted_drivers_draw_the_promised_tier_without_crashing(void **state) {
    (void)state;
    /* two cells at a time (the children are single-threaded GL work) */
    pid_t running[2] = { 0, 0 };
    size_t cell[2] = { 0, 0 };
    int slot = 0;
    for (size_t c = 0; c <= VERSION_COUNT * RESTRICTION_COUNT + 1; c++) {
        if (running[slot]) {
            check_cell(running[slot], versions[cell[slot] / RESTRICTION_COUNT], &restrictions[cell[slot] % RESTRICTION_COUNT]);
            running[slot] = 0;
        }
        if (c < VERSION_COUNT * RESTRICTION_COUNT) {
            size_t v = c / RESTRICTION_COUNT, r = c % RESTRICTION_COUNT;
            if (subset() && !(v == 2 && r == 1)) continue;
            running[slot] = start_cell(versions[v], &restrictions[r]);
            cell[slot] = c;
        }
        slot ^= 1;
    }
    printf("%d cells, %zu scenes each\n", cells_checked, scene_count());
}

/* The regression the matrix was built for: GL 1.3 without shaders drew
   fixed4 through a NULL glBindBuffer (no VBOs before 1.5). */
static void test_gl13_without_shaders_draws_fixed4_with_client_arrays(void **state) {
    (void)state;
    /* the softpipe run's one cell of the matrix is this one, checked there
       for its tier and picture; the log line is the GL version's, not the driver's */
    HT_TEST_DRIVER_INDEPENDENT();
    int status = 0;
    char *out = run_child("1.3", SHADER_EXTENSIONS, "gl13-regression", "auto", &status);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) fail_msg("the child failed:\n%s", out);
    assert_non_null(strstr(out, "no VBOs"));
    assert_non_null(strstr(out, "scene furball tier fixed4"));
    free(out);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gl13_without_shaders_draws_fixed4_with_client_arrays),
        cmocka_unit_test(test_restricted_drivers_draw_the_promised_tier_without_crashing),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

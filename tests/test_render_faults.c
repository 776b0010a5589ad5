/* test_render_faults — faults at run time (docs/robustness.md "Faults at
   run time"): support_gl_fault.h sits between the runtime and OSMesa and
   fails, one at a time, the n-th shader compile, program link, texture
   upload, buffer upload, or reports GL_OUT_OF_MEMORY after the n-th call
   of any entry point. For each class, n runs over every call of that class
   that ht_renderer_create + ht_renderer_set_mesh + one ht_renderer_draw
   make without faults, once in auto mode and once for each tier forced
   (strict). Every run must end in one of:
     - HT_OK at the same tier (the fault hit a call whose error GL lets the
       runtime ignore, or it was reported by the draw with one line);
     - HT_OK at a lower tier (auto), the dropped tier and the reason named
       in one log line;
     - a clean error code from create, set_mesh or draw, the reason in one
       log line;
   and, after ht_renderer_destroy, every texture, buffer, shader and
   program the runtime made is deleted (no double delete either), the
   matrices GL is left with are finite, and nothing crashed. Memory: `make
   asan` runs this binary under LeakSanitizer.

   HT_FAULT_VERBOSE=1 prints every run's outcome and log. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <GL/gl.h>

#include "file_open.h"
#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include "support_gl_fault.h"
#include "support_log.h"
#include "support_render.h"

#define SIZE 48

static ht_test_furball fx;
static bool verbose;

static char bundle_dir[192];

/* The fixture's material with 16x16 textures: every run decodes them. */
static bool make_small_bundle(void) {
    char *text = ht_file_read_text("materials/dark-brown.json", 1 << 20, NULL, 0);
    if (!text) return false;
    char material[160];
    snprintf(material, sizeof material, "%s/small.json", fx.work);
    FILE *f = fopen(material, "w");
    if (!f) {
        free(text);
        return false;
    }
    for (const char *p = text; *p;) {
        const char *at = strstr(p, "\"size\": 256");
        size_t n = at ? (size_t)(at - p) : strlen(p);
        fwrite(p, 1, n, f);
        if (!at) break;
        fputs("\"size\": 16", f);
        p = at + strlen("\"size\": 256");
    }
    free(text);
    if (fclose(f) != 0) return false;
    snprintf(bundle_dir, sizeof bundle_dir, "%s/small", fx.work);
    char err[1024];
    if (ht_generate_bundle(material, "scenes/furball.json", bundle_dir, NULL, err, sizeof err) != HT_OK) {
        fprintf(stderr, "setup: %s\n", err);
        return false;
    }
    return true;
}

/* The fixture's fur ball with 40 hairs, not 400: each of the ~2 900 runs
   builds every tier's arrays from the mesh and draws it, and which calls a
   run makes does not depend on the hair count (the same fault points and
   the same outcomes per class as with 400; one batch of each either way). */
static bool make_small_mesh(void) {
    static const ht_furball_desc desc = { .hairs = 40, .joints = 8, .length = 0.12f, .width = 0.03f, .seed = 3 };
    ht_mesh small;
    if (ht_mesh_build_furball(&desc, &small) != HT_OK) return false;
    ht_mesh_sort_inside_out(&small);
    ht_mesh_free(&fx.mesh);
    fx.mesh = small;
    return true;
}

static int setup(void **state) {
    (void)state;
    verbose = getenv("HT_FAULT_VERBOSE") != NULL;
    return ht_test_furball_setup(&fx, "faults", SIZE) && make_small_bundle() && make_small_mesh() ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

/* What one run of create + set_mesh + draw came to. */
typedef struct outcome {
    ht_result create, mesh, draw;   /* HT_OK for a step not reached */
    ht_tier tier;                   /* HT_TIER_COUNT when create failed */
    bool fired;
    const char *failed_step;        /* NULL when every step returned HT_OK */
    ht_result failed_result;
    long calls_after_create, calls_after_mesh;   /* calls of any entry point */
    size_t log_mesh, log_draw;      /* where set_mesh's and draw's lines start in the log */
} outcome;

static int count_lines_with(const char *text, const char *a, const char *b) {
    int n = 0;
    for (const char *line = text; *line;) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        char buf[2048];
        snprintf(buf, sizeof buf, "%.*s", (int)len, line);
        if (strstr(buf, a) && (!b || strstr(buf, b))) n++;
        line += len + (end ? 1 : 0);
    }
    return n;
}

static void check_finite_gl_state(const ht_renderer *r) {
    GLfloat m[16];
    const GLenum which[2] = { GL_MODELVIEW_MATRIX, GL_PROJECTION_MATRIX };
    for (int k = 0; k < 2; k++) {
        glGetFloatv(which[k], m);
        for (int i = 0; i < 16; i++) assert_true(isfinite(m[i]));
    }
    const ht_trace *t = ht_renderer_trace(r);
    for (int i = 0; i < t->count; i++) assert_true(isfinite(t->entries[i].alpha_ref));
}

static outcome run(ht_tier tier, ht_fault_class cls, long n) {
    outcome o = { .tier = HT_TIER_COUNT, .log_mesh = sizeof ht_test_log_text, .log_draw = sizeof ht_test_log_text };
    ht_fault_arm(cls, n);
    ht_test_log_clear();
    ht_renderer *r = NULL;
    o.create = ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_fault_getproc,
                                                       .bundle_dir = bundle_dir, .tier = tier,
                                                       .strict = tier != HT_TIER_AUTO, .record_trace = true,
                                                       .log = ht_test_log_capture }, &r);
    if (o.create != HT_OK) {
        assert_null(r);
        o.failed_step = "create";
        o.failed_result = o.create;
    } else {
        o.tier = ht_renderer_tier(r);
        o.calls_after_create = ht_fault_state_get()->calls[HT_FAULT_ANY_CALL];
        o.log_mesh = strlen(ht_test_log_text);
        o.mesh = ht_renderer_set_mesh(r, &fx.mesh);
        o.calls_after_mesh = ht_fault_state_get()->calls[HT_FAULT_ANY_CALL];
        o.log_draw = strlen(ht_test_log_text);
        if (o.mesh != HT_OK) {
            o.failed_step = "set_mesh";
            o.failed_result = o.mesh;
        } else {
            glViewport(0, 0, SIZE, SIZE);
            glClearColor(0.1f, 0.2f, 0.3f, 1);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            ht_frame_desc f = ht_test_furball_frame(2.4f);
            o.draw = ht_renderer_draw(r, &f);
            if (o.draw != HT_OK) {
                o.failed_step = "draw";
                o.failed_result = o.draw;
            }
            check_finite_gl_state(r);
        }
        ht_renderer_destroy(r);
    }
    while (glGetError() != GL_NO_ERROR) {}
    const ht_fault_state *s = ht_fault_state_get();
    o.fired = s->fired;
    if (verbose)
        printf("-- tier %s, %s #%ld: fired %d, create %s, tier %s, mesh %s, draw %s\n%s", ht_tier_name(tier),
               ht_fault_class_name(cls), n, o.fired, ht_result_string(o.create),
               o.tier == HT_TIER_COUNT ? "-" : ht_tier_name(o.tier), ht_result_string(o.mesh),
               ht_result_string(o.draw), ht_test_log_text);
    for (int k = 0; k < HT_FAULT_OBJECT_COUNT; k++)
        if (s->live[k])
            fail_msg("tier %s, %s #%ld: %d %s left undeleted (%d made, %d deleted); log:\n%s", ht_tier_name(tier),
                     ht_fault_class_name(cls), n, s->live[k], ht_fault_object_name(k), s->created[k], s->deleted[k],
                     ht_test_log_text);
    if (s->stray_deletes)
        fail_msg("tier %s, %s #%ld: %d deletes of names not live (double deletes); log:\n%s", ht_tier_name(tier),
                 ht_fault_class_name(cls), n, s->stray_deletes, ht_test_log_text);
    return o;
}

static const ht_tier modes[] = { HT_TIER_AUTO, HT_TIER_FULL, HT_TIER_VERTEX, HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
#define MODE_COUNT (int)(sizeof modes / sizeof modes[0])

/* What the log says an injected fault was. */
static const char *marker(ht_fault_class cls) {
    return cls == HT_FAULT_COMPILE ? "injected compile failure" : cls == HT_FAULT_LINK ? "injected link failure"
                                                                                       : "GL_OUT_OF_MEMORY";
}

static const char *last_line(char *buf, size_t size) {
    size_t n = strlen(ht_test_log_text);
    while (n && ht_test_log_text[n - 1] == '\n') n--;
    size_t start = n;
    while (start && ht_test_log_text[start - 1] != '\n') start--;
    snprintf(buf, size, "%.*s", (int)(n - start), ht_test_log_text + start);
    return buf;
}

/* A line that echoes the driver's info log ("hairtier: FILE: LOG"), which
   the GLSL backend prints in full besides its one-line reason. */
static bool is_info_log_echo(const char *line) {
    return !strstr(line, "failed: ") && (strstr(line, HT_FAULT_COMPILE_LOG) || strstr(line, HT_FAULT_LINK_LOG));
}

/* Lines of text (from offset from) that contain what, neither a skipped
   line nor an info log echo. */
static int reason_lines(size_t from, const char *what) {
    int n = 0;
    const char *text = ht_test_log_text + (from < sizeof ht_test_log_text ? from : strlen(ht_test_log_text));
    for (const char *line = text; *line;) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        char buf[2048];
        snprintf(buf, sizeof buf, "%.*s", (int)len, line);
        if (strstr(buf, what) && !strstr(buf, "hairtier: skipped ") && !is_info_log_echo(buf) &&
            !strstr(buf, "hairtier: tier ")) n++;
        line += len + (end ? 1 : 0);
    }
    return n;
}

enum { DROPPED, CREATE_FAILED, MESH_FAILED, DRAW_FAILED, NOT_DRAWN, UNAFFECTED, NOT_FIRED, OUTCOME_COUNT };
static const char *const outcome_names[OUTCOME_COUNT] = {
    "HT_OK, lower tier", "create refused", "set_mesh refused", "draw HT_ERR_GL",
    "draw HT_OK, hair not drawn, one line", "HT_OK, same tier, nothing logged", "did not fire" };

static int judge(ht_tier mode, ht_tier clean_tier, ht_fault_class cls, long n, const outcome *o) {
    char last[2048];
    const char *m = marker(cls);
    if (!o->fired) {
        /* a fault on a path the fault-free run does not take (after a drop) */
        assert_int_equal(o->create, HT_OK);
        assert_int_equal(o->mesh, HT_OK);
        assert_int_equal(o->draw, HT_OK);
        return NOT_FIRED;
    }
    if (o->failed_step) {
        assert_true(o->failed_result > HT_OK && o->failed_result <= HT_ERR_OUT_OF_MEMORY);
        size_t from = strcmp(o->failed_step, "create") == 0 ? 0
                      : strcmp(o->failed_step, "set_mesh") == 0 ? o->log_mesh : o->log_draw;
        const char *want = strcmp(o->failed_step, "set_mesh") == 0 && cls != HT_FAULT_COMPILE &&
                           cls != HT_FAULT_LINK && !strstr(ht_test_log_text + from, m) ? "out of memory" : m;
        if (reason_lines(from, want) != 1)
            fail_msg("tier %s, %s #%ld: %s %s: want one line naming \"%s\"; log:\n%s", ht_tier_name(mode),
                     ht_fault_class_name(cls), n, o->failed_step, ht_result_string(o->failed_result), want,
                     ht_test_log_text);
        if (strcmp(o->failed_step, "create") == 0 && !strstr(last_line(last, sizeof last), want))
            fail_msg("tier %s, %s #%ld: the last line does not name the reason; log:\n%s", ht_tier_name(mode),
                     ht_fault_class_name(cls), n, ht_test_log_text);
        return strcmp(o->failed_step, "create") == 0 ? CREATE_FAILED
               : strcmp(o->failed_step, "set_mesh") == 0 ? MESH_FAILED : DRAW_FAILED;
    }
    if (o->tier != clean_tier) {
        /* only auto falls: a forced tier is strict */
        assert_int_equal(mode, HT_TIER_AUTO);
        assert_true(o->tier > clean_tier);
        char skipped[64];
        snprintf(skipped, sizeof skipped, "hairtier: skipped %s: ", ht_tier_name(clean_tier));
        if (count_lines_with(ht_test_log_text, skipped, NULL) != 1 ||
            count_lines_with(ht_test_log_text, skipped, m) != 1)
            fail_msg("tier %s, %s #%ld: want one line \"%s...%s...\"; log:\n%s", ht_tier_name(mode),
                     ht_fault_class_name(cls), n, skipped, m, ht_test_log_text);
        return DROPPED;
    }
    /* Same tier, every step HT_OK: a failed compile or link never gets here;
       a failed upload in the draw is one line (the backend draws nothing). */
    if (cls == HT_FAULT_COMPILE || cls == HT_FAULT_LINK)
        fail_msg("tier %s, %s #%ld: HT_OK at tier %s after the failure; log:\n%s", ht_tier_name(mode),
                 ht_fault_class_name(cls), n, ht_tier_name(o->tier), ht_test_log_text);
    int lines = reason_lines(o->log_draw, m);
    if (lines > 1 || (lines == 0 && cls != HT_FAULT_ANY_CALL))
        fail_msg("tier %s, %s #%ld: HT_OK at tier %s with %d lines naming it; log:\n%s", ht_tier_name(mode),
                 ht_fault_class_name(cls), n, ht_tier_name(o->tier), lines, ht_test_log_text);
    return lines ? NOT_DRAWN : UNAFFECTED;
}

/* Every call of cls that the fault-free run of each mode makes, failed in
   turn. */
static void sweep(ht_fault_class cls, bool skip_forced_full) {
    int tally[OUTCOME_COUNT] = { 0 };
    for (int mi = 0; mi < MODE_COUNT; mi++) {
        if (skip_forced_full && modes[mi] == HT_TIER_FULL) continue;
        outcome clean = run(modes[mi], HT_FAULT_NONE, 0);
        assert_int_equal(clean.create, HT_OK);
        assert_int_equal(clean.draw, HT_OK);
        long calls = ht_fault_state_get()->calls[cls];
        for (long n = 1; n <= calls; n++) {
            outcome o = run(modes[mi], cls, n);
            tally[judge(modes[mi], clean.tier, cls, n, &o)]++;
        }
    }
    printf("%s:", ht_fault_class_name(cls));
    for (int k = 0; k < OUTCOME_COUNT; k++)
        if (tally[k]) printf(" %s %d;", outcome_names[k], tally[k]);
    printf("\n");
}

static void test_compile_faults(void **state) { (void)state; sweep(HT_FAULT_COMPILE, false); }
static void test_link_faults(void **state) { (void)state; sweep(HT_FAULT_LINK, false); }
static void test_texture_upload_faults(void **state) { (void)state; sweep(HT_FAULT_TEX_IMAGE, false); }
static void test_buffer_upload_faults(void **state) { (void)state; sweep(HT_FAULT_BUFFER_DATA, false); }
static void test_out_of_memory_at_any_call(void **state) { (void)state; sweep(HT_FAULT_ANY_CALL, true); }

int main(void) {
    /* GL 2.1 (GLSL 1.20, every tier): one GL_EXTENSIONS string instead of
       glGetStringi per extension keeps the any-call sweep short. */
    setenv("MESA_GL_VERSION_OVERRIDE", "2.1", 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_compile_faults),
        cmocka_unit_test(test_link_faults),
        cmocka_unit_test(test_texture_upload_faults),
        cmocka_unit_test(test_buffer_upload_faults),
        cmocka_unit_test(test_out_of_memory_at_any_call),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

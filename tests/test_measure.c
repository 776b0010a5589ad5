/* test_measure — `hairgen --measure` (shadergen/measure.h): every tier of
   the bundle gets a valid `measured` object the runtime reads, the rest of
   the bundle is byte for byte what hairgen writes without the flag, the
   image numbers repeat across runs, a failed measurement leaves nothing,
   and the error:DB policy picks from what was measured (through the API
   and through hairview). No assertion on a time: only that the cost ratios
   are there, finite and consistent with the policy's choice. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <cJSON.h>
#include <GL/gl.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <hairtier/hairgen.h>
#include "manifest.h"
#include "measure.h"
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"
#include "support_scratch.h"

/* Small, so that five tiers times seven frames take little time; two
   lights so that the lower tiers drop something and score below full. */
static const char small_scene[] =
    "{\"format\": \"hairtier-scene/1\", \"resolution\": [96, 96],\n"
    " \"camera\": {\"eye\": [0.82, 1.63, 2.75], \"target\": [0, -0.1, 0], \"up\": [0, 1, 0], \"fov_y\": 40},\n"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [0.6, 0.8, 0.7], \"color\": [1, 0.97, 0.92]},\n"
    "            {\"type\": \"directional\", \"direction\": [-0.7, 0.2, -0.6], \"color\": [0.35, 0.4, 0.5]}],\n"
    " \"background\": [0.08, 0.08, 0.1],\n"
    " \"geometry\": {\"type\": \"furball\", \"hairs\": 100, \"joints\": 8, \"length\": 0.12, \"width\": 0.03, \"seed\": 7}}\n";

static char work[64], scene[128], measured[128], plain[128];

/* Runs `env build/hairgen args`; its stdout and stderr go to work/out.txt
   and work/err.txt. The exit status. */
static int run_hairgen(const char *env, const char *args) {
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[1500];
    snprintf(cmd, sizeof cmd, "%s %s/hairgen %s >%s/out.txt 2>%s/err.txt", env ? env : "", build ? build : "build",
             args, work, work);
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static char *work_file(const char *name) {
    char path[256];
    snprintf(path, sizeof path, "%s/%s", work, name);
    char *text = ht_test_read_all(path, NULL);
    assert_non_null(text);
    return text;
}

static int setup(void **state) {
    (void)state;
    unsetenv("HAIRTIER_POLICY");
    unsetenv("HAIRTIER_TIER");
    if (!ht_test_scratch_create(work, sizeof work, "measure")) return -1;
    snprintf(scene, sizeof scene, "%s/small.json", work);
    snprintf(measured, sizeof measured, "%s/measured", work);
    snprintf(plain, sizeof plain, "%s/plain", work);
    FILE *f = fopen(scene, "w");
    if (!f) return -1;
    fputs(small_scene, f);
    fclose(f);
    char args[600];
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --measure -o %s", scene, measured);
    if (run_hairgen(NULL, args) != 0) return -1;
    /* test_hairgen_prints_the_measured_table reads what this run printed. */
    char from[128], to[128];
    snprintf(from, sizeof from, "%s/out.txt", work);
    snprintf(to, sizeof to, "%s/measured-out.txt", work);
    if (rename(from, to) != 0) return -1;
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s -o %s", scene, plain);
    return run_hairgen(NULL, args) == 0 ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

static ht_manifest *load(const char *dir) {
    static ht_manifest m;
    char err[512];
    if (ht_manifest_load(dir, &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return &m;
}

static cJSON *manifest_json(const char *dir) { return ht_test_read_json(dir, "manifest.json"); }

static void test_every_tier_carries_a_measured_object_the_runtime_reads(void **state) {
    (void)state;
    const ht_manifest *m = load(measured);
    assert_int_equal(m->tier_count, 5);
    const ht_manifest_measured *full = &m->tiers[0].measured;
    assert_int_equal(m->tiers[0].tier, HT_TIER_FULL);
    assert_true(full->present);
    assert_true(isinf(full->psnr_db)); /* null: full against itself */
    assert_true(full->ssim == 1.0 && full->delta_e00_mean == 0.0 && full->delta_e00_p95 == 0.0);
    assert_true(full->flip_mean == 0.0 && full->flip_p95 == 0.0);
    assert_true(full->cost_ratio == 1.0);

    /* The driver is the one this process gets from OSMesa. */
    ht_test_gl gl;
    char err[256];
    if (!ht_test_gl_create(&gl, 16, 16, NULL, err, sizeof err)) fail_msg("%s", err);
    char renderer[128];
    snprintf(renderer, sizeof renderer, "%s", (const char *)glGetString(GL_RENDERER));
    ht_test_gl_destroy(&gl);

    for (int i = 0; i < m->tier_count; i++) {
        const ht_manifest_measured *t = &m->tiers[i].measured;
        if (!t->present) fail_msg("%s: no measured object", m->tiers[i].name);
        assert_string_equal(t->scene, "small.json");
        assert_string_equal(t->driver, renderer);
        assert_true(isfinite(t->cost_ratio) && t->cost_ratio > 0);
        assert_true(isfinite(t->ssim) && t->ssim <= 1 && t->ssim > 0);
        assert_true(isfinite(t->delta_e00_mean) && t->delta_e00_mean >= 0);
        assert_true(isfinite(t->delta_e00_p95) && t->delta_e00_p95 >= 0);
        if (i == 0) continue;
        /* Every lower tier drops something on this two-light scene. */
        if (!(isfinite(t->psnr_db) && t->psnr_db > 10 && t->psnr_db < 100))
            fail_msg("%s: psnr_db %g", m->tiers[i].name, t->psnr_db);
        assert_true(t->ssim < 1 && t->delta_e00_mean > 0);
        if (!(t->flip_mean > 0 && t->flip_mean <= 1 && t->flip_p95 >= 0 && t->flip_p95 <= 1))
            fail_msg("%s: flip_mean %g, flip_p95 %g", m->tiers[i].name, t->flip_mean, t->flip_p95);
    }

    /* In the text: full's PSNR is JSON null, the others numbers. */
    cJSON *root = manifest_json(measured);
    cJSON *tier;
    int index = 0;
    cJSON_ArrayForEach(tier, cJSON_GetObjectItemCaseSensitive(root, "tiers")) {
        cJSON *psnr = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(tier, "measured"), "psnr_db");
        assert_true(index == 0 ? cJSON_IsNull(psnr) : cJSON_IsNumber(psnr));
        index++;
    }
    cJSON_Delete(root);
}

/* What setup's `hairgen --measure` printed. */
static void test_hairgen_prints_the_measured_table(void **state) {
    (void)state;
    char *out = work_file("measured-out.txt");
    assert_non_null(strstr(out, "measured: scene small.json (96x96), driver "));
    assert_non_null(strstr(out, "; whole frame against full; "));
    /* a software rasterizer has no clock to raise: the two rounds only */
    assert_non_null(strstr(out, "frame ms: median of 5 after 2 warm-up, tiers round-robin"));
    const char *table = strstr(out, "\ntier     frame_ms");
    assert_non_null(table);
    const char *names[] = { "\nfull ", "\nvertex ", "\nfixed4 ", "\nfixed ", "\ngl11 " };
    for (int i = 0; i < 5; i++)
        if (!strstr(table, names[i])) fail_msg("no row%s in:\n%s", names[i], out);
    free(out);
}

/* The table hairgen prints for a result (ht_measure_print); free() it. */
static char *printed_table(const ht_measure_result *result) {
    char *text = NULL;
    size_t size = 0;
    FILE *f = open_memstream(&text, &size);
    assert_non_null(f);
    ht_measure_print(f, result);
    assert_int_equal(fclose(f), 0);
    return text;
}

/* On a GPU the warm-up rounds go on for ht_timing_warmup_ms, and the
   table says how many there were and why. */
static void test_measured_table_names_a_gpus_warmup(void **state) {
    (void)state;
    ht_measure_result r = { .scene = "s.json", .driver = "NVIDIA H200", .width = 8, .height = 8,
                            .warmup_rounds = 7, .warmup_ms = HT_TIMING_WARMUP_MS };
    assert_true(ht_timing_warmup_ms(r.driver) > 0);
    char *text = printed_table(&r);
    if (!strstr(text, "median of 5 after 7 warm-up (250 ms of them: a GPU's clock), tiers round-robin"))
        fail_msg("the table:\n%s", text);
    free(text);
}

/* A Marschner bundle is measured against its marschner tier, and the
   printed table says so (not "against full"). The bundle is the shared
   fixture (brown-marschner x furball: its bake and fit cost 2 s, the
   measuring 1 s), measured as hairgen measures it (ht_measure_step, the
   table of ht_measure_print that hairgen prints) on its own scene at 96²,
   100 hairs of 4 joints: what is checked is the table's naming. */
static void test_hairgen_names_marschner_as_the_reference_of_a_marschner_bundle(void **state) {
    (void)state;
    char fixture[256], dir[256], err[2048] = "";
    snprintf(fixture, sizeof fixture, "%s/marschner-generated", work);
    if (ht_test_bundle("materials/brown-marschner.json", "furball", "scenes/furball.json", fixture, sizeof fixture,
                       err, sizeof err) != HT_OK)
        fail_msg("%s", err);
    snprintf(dir, sizeof dir, "%s/marschner", work);
    ht_test_copy_dir(fixture, dir);
    ht_scene furball;
    if (ht_scene_load("scenes/furball.json", &furball, err, sizeof err) != HT_OK) fail_msg("%s", err);
    furball.width = furball.height = 96;
    furball.furball.hairs = 100;
    furball.furball.joints = 4;
    ht_measure_job job = { .scene_path = "scenes/furball.json", .out_dir = dir };
    if (ht_measure_step(&job, dir, &furball, err, sizeof err) != HT_OK) fail_msg("%s", err);
    const ht_manifest *m = load(dir);
    assert_int_equal(m->tiers[0].tier, HT_TIER_MARSCHNER);
    assert_true(isinf(m->tiers[0].measured.psnr_db)); /* the reference against itself */
    char *out = printed_table(&job.result);
    if (!strstr(out, "; whole frame against marschner; ") || !strstr(out, "cost = ms / marschner's ms") ||
        strstr(out, "against full") || !strstr(out, "\nmarschner "))
        fail_msg("the table does not name marschner as its reference:\n%s", out);
    free(out);
}

/* Every file but the manifest byte for byte, and the manifest without its
   measured objects byte for byte: --measure adds those and nothing else,
   and without it hairgen writes what it always did. */
static void test_measure_adds_only_the_measured_objects(void **state) {
    (void)state;
    DIR *d = opendir(plain);
    assert_non_null(d);
    struct dirent *e;
    int files = 0;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.' || strcmp(e->d_name, "manifest.json") == 0) continue;
        char pa[512], pb[512];
        snprintf(pa, sizeof pa, "%s/%s", plain, e->d_name);
        snprintf(pb, sizeof pb, "%s/%s", measured, e->d_name);
        size_t na = 0, nb = 0;
        char *a = ht_test_read_all(pa, &na), *b = ht_test_read_all(pb, &nb);
        if (!b) fail_msg("%s: missing with --measure", e->d_name);
        assert_int_equal(na, nb);
        assert_memory_equal(a, b, na);
        free(a);
        free(b);
        files++;
    }
    closedir(d);
    assert_true(files >= 10);
    /* No file the plain bundle lacks (a leftover temporary manifest). */
    int measured_files = 0;
    d = opendir(measured);
    while ((e = readdir(d)) != NULL) measured_files += e->d_name[0] != '.';
    closedir(d);
    assert_int_equal(measured_files, files + 1);

    cJSON *root = manifest_json(measured);
    cJSON *tier;
    cJSON_ArrayForEach(tier, cJSON_GetObjectItemCaseSensitive(root, "tiers")) {
        assert_non_null(cJSON_GetObjectItemCaseSensitive(tier, "measured"));
        cJSON_DeleteItemFromObjectCaseSensitive(tier, "measured");
        /* a device-only variant (hairtier.h ht_variant) is measured where
           the tier has one here: fixed4 with the local viewer, fixed
           (Scheuermann) with CPU coordinates; no other tier */
        const char *name = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(tier, "name"));
        const cJSON *device = cJSON_GetObjectItemCaseSensitive(tier, "measured_device");
        const char *program = strcmp(name, "fixed4") == 0 ? "fixed4.json" : strcmp(name, "fixed") == 0 ? "fixed.json" : NULL;
        const char *cpu = strcmp(name, "fixed4") == 0 ? "\"viewer\":\t\"local\"" : "\"coords\":\t\"cpu-dots\"";
        bool expect = program && strstr(ht_test_read_file(measured, program), cpu) != NULL;
        assert_int_equal(device != NULL, expect);
        if (device) assert_true(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(device, "psnr_db")));
        cJSON_DeleteItemFromObjectCaseSensitive(tier, "measured_device");
    }
    char *stripped = cJSON_Print(root);
    cJSON_Delete(root);
    char path[300];
    snprintf(path, sizeof path, "%s/manifest.json", plain);
    char *original = ht_test_read_all(path, NULL);
    assert_string_equal(stripped, original);
    free(original);
    cJSON_free(stripped);
}

/* The tier error:DB must pick: the least cost_ratio among the tiers whose
   PSNR reaches DB (the first of equals, the bundle's order). */
static int expected_pick(const ht_manifest *m, double db) {
    int pick = -1;
    for (int i = 0; i < m->tier_count; i++) {
        const ht_manifest_measured *t = &m->tiers[i].measured;
        if (t->psnr_db >= db && (pick < 0 || t->cost_ratio < m->tiers[pick].measured.cost_ratio)) pick = i;
    }
    assert_true(pick >= 0);
    return pick;
}

/* "tier NAME (error:DB: 34.4 dB >= DB dB, cost 0.7x full": the line names
   the tier and carries its numbers. */
static void expected_line(const ht_manifest *m, int pick, double db, char *out, size_t size) {
    const ht_manifest_measured *t = &m->tiers[pick].measured;
    char psnr[32];
    if (isinf(t->psnr_db)) snprintf(psnr, sizeof psnr, "identical to full");
    else snprintf(psnr, sizeof psnr, "%.1f dB", t->psnr_db);
    snprintf(out, size, "error:%g: %s >= %g dB, cost %.2gx full", db, psnr, db, t->cost_ratio);
}

static void test_error_policy_picks_the_cheapest_measured_tier_that_reaches_it(void **state) {
    (void)state;
    const ht_manifest *m = load(measured);
    double best_lower = 0;
    for (int i = 1; i < m->tier_count; i++)
        if (m->tiers[i].measured.psnr_db > best_lower) best_lower = m->tiers[i].measured.psnr_db;
    /* 30 dB (the example), 0 (every tier: the cheapest of all),
       and above every lower tier (only full reaches it). */
    const double thresholds[] = { 30, 0, best_lower + 0.5 };
    ht_test_gl gl;
    char err[256];
    if (!ht_test_gl_create(&gl, 96, 96, NULL, err, sizeof err)) fail_msg("%s", err);
    for (size_t k = 0; k < sizeof thresholds / sizeof *thresholds; k++) {
        char policy[32], want[200], line[260];
        snprintf(policy, sizeof policy, "error:%g", thresholds[k]);
        int pick = expected_pick(m, thresholds[k]);
        if (k == 2) assert_int_equal(m->tiers[pick].tier, HT_TIER_FULL);
        ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .policy = policy }, measured, HT_OK);
        if (ht_renderer_tier(r) != m->tiers[pick].tier)
            fail_msg("%s chose %s, expected %s; log:\n%s", policy, ht_tier_name(ht_renderer_tier(r)),
                     m->tiers[pick].name, ht_test_log_text);
        expected_line(m, pick, thresholds[k], want, sizeof want);
        snprintf(line, sizeof line, "tier %s (%s", m->tiers[pick].name, want);
        if (!ht_test_logged(line)) fail_msg("no \"%s\" in the log:\n%s", line, ht_test_log_text);
        ht_renderer_destroy(r);
    }
    ht_test_gl_destroy(&gl);
}

static void test_hairview_error_30_says_which_tier_and_why(void **state) {
    (void)state;
    const ht_manifest *m = load(measured);
    int pick = expected_pick(m, 30);
    const char *build = getenv("HAIRTIER_BUILD");
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "%s/hairview --bundle %s --scene %s --policy error:30 --frames 1 -o %s/view.png 2>/dev/null",
             build ? build : "build", measured, scene, work);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    char out[2048];
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = '\0';
    assert_int_equal(pclose(p), 0);
    char want[200], line[300];
    expected_line(m, pick, 30, want, sizeof want);
    snprintf(line, sizeof line, "tier=%s reason=%s, the cheapest that runs and reaches it", m->tiers[pick].name, want);
    if (!strstr(out, line)) fail_msg("no \"%s\" in:\n%s", line, out);
}

static int count_temporaries(void) {
    DIR *d = opendir(work);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) n += strstr(e->d_name, ".tmp-") != NULL;
    closedir(d);
    return n;
}

/* A driver that cannot run full (GL 1.3), or a frame too small for SSIM:
   one line naming the tier and why, exit 1, no bundle and no temporary; an
   existing bundle stays as it was. */
static void test_a_failed_measurement_writes_nothing(void **state) {
    (void)state;
    /* GL 1.3, over an existing bundle (of another material, so that a
       bundle published anyway would show): it stays as it was. */
    char dir[256], args[700], kept[256], path[300];
    snprintf(kept, sizeof kept, "%s/kept", work);
    ht_test_copy_dir(plain, kept);
    snprintf(path, sizeof path, "%s/manifest.json", kept);
    char *before = ht_test_read_all(path, NULL);
    snprintf(args, sizeof args, "materials/blond.json --scene %s --measure -o %s", scene, kept);
    assert_int_equal(run_hairgen("MESA_GL_VERSION_OVERRIDE=1.3", args), 1);
    char *err = work_file("err.txt");
    assert_string_equal(err, "hairgen: measure: a tier cannot run here: full: needs GL 2.1, have 1.3 "
                             "(forced by desc.tier, strict)\n");
    free(err);
    char *after = ht_test_read_all(path, NULL);
    assert_non_null(after);
    assert_string_equal(before, after);
    free(before);
    free(after);
    assert_int_equal(count_temporaries(), 0);

    /* No NaN ever reaches a manifest; a new bundle's directory is not made. */
    snprintf(dir, sizeof dir, "%s/failed", work);
    char tiny[256];
    snprintf(tiny, sizeof tiny, "%s/tiny.json", work);
    char *text = ht_test_read_all(scene, NULL);
    char *size = strstr(text, "[96, 96]");
    assert_non_null(size);
    memcpy(size, "[ 8,  8]", 8);
    FILE *f = fopen(tiny, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    free(text);
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --measure -o %s", tiny, dir);
    assert_int_equal(run_hairgen(NULL, args), 1);
    err = work_file("err.txt");
    assert_string_equal(err, "hairgen: measure: vertex: ssim: nan is outside [-1, 1] "
                             "(a frame under 11x11 pixels has no SSIM window)\n");
    free(err);
    assert_false(ht_test_path_exists(dir));
    assert_int_equal(count_temporaries(), 0);
}

/* Issue 19 row 9: with no hair in view every tier scored "identical", so
   error: and fastest picked gl11 on a blank comparison. Refused now, one
   line, nothing written. */
static void test_measure_refuses_a_scene_with_no_hair_in_view(void **state) {
    (void)state;
    char away[256], dir[256], args[700];
    snprintf(away, sizeof away, "%s/away.json", work);
    char *text = ht_test_read_all(scene, NULL);
    char *target = strstr(text, "\"target\": [0, -0.1, 0]");
    assert_non_null(target);
    memcpy(target, "\"target\": [9,  9.0, 9]", strlen("\"target\": [0, -0.1, 0]")); /* looking away */
    FILE *f = fopen(away, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    free(text);
    snprintf(dir, sizeof dir, "%s/blank", work);
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --measure -o %s", away, dir);
    assert_int_equal(run_hairgen(NULL, args), 1);
    char *err = work_file("err.txt");
    assert_string_equal(err, "hairgen: measure: away.json: the reference tier (full) draws no hair pixel over the "
                             "background: no hair in view to measure the tiers on\n");
    free(err);
    assert_false(ht_test_path_exists(dir));
    assert_int_equal(count_temporaries(), 0);
}

/* No libOSMesa (HAIRGEN_OSMESA naming a file that is not there, or a
   library without OSMesa's functions): --measure draws through EGL
   (Mesa's surfaceless platform here) and measures what OSMesa measures,
   exactly: llvmpipe draws the same frame the same way behind either
   context, so this second run is also the check that the image numbers
   repeat across runs (the times need not). */
static void test_measure_without_libosmesa_draws_through_egl(void **state) {
    (void)state;
    char dir[256], args[700];
    snprintf(dir, sizeof dir, "%s/egl-measured", work);
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --measure -o %s", scene, dir);
    if (run_hairgen("env -u HAIRTIER_CONTEXT EGL_PLATFORM=surfaceless HAIRGEN_OSMESA=/nonexistent/libOSMesa.so.8",
                    args) != 0) {
        char *err = work_file("err.txt");
        fail_msg("hairgen %s through EGL: %s", args, err);
    }
    ht_manifest *egl = malloc(sizeof *egl);
    assert_non_null(egl);
    *egl = *load(dir);
    const ht_manifest *osmesa = load(measured);
    assert_int_equal(egl->tier_count, osmesa->tier_count);
    for (int i = 0; i < egl->tier_count; i++) {
        const ht_manifest_measured *e = &egl->tiers[i].measured, *o = &osmesa->tiers[i].measured;
        if (!e->present) fail_msg("%s: no measured object", egl->tiers[i].name);
        if (!(e->psnr_db == o->psnr_db && e->ssim == o->ssim && e->delta_e00_mean == o->delta_e00_mean &&
              e->delta_e00_p95 == o->delta_e00_p95 && e->flip_mean == o->flip_mean && e->flip_p95 == o->flip_p95))
            fail_msg("%s: %g dB, %g, %g, %g, flip %g, %g through EGL; %g dB, %g, %g, %g, flip %g, %g through OSMesa",
                     egl->tiers[i].name, e->psnr_db, e->ssim, e->delta_e00_mean, e->delta_e00_p95, e->flip_mean,
                     e->flip_p95, o->psnr_db, o->ssim, o->delta_e00_mean, o->delta_e00_p95, o->flip_mean, o->flip_p95);
    }
    free(egl);
    assert_int_equal(count_temporaries(), 0);
}

/* Neither library loads (HAIRGEN_OSMESA: missing or not OSMesa;
   HAIRGEN_EGL: missing): one line naming both, exit 1, no bundle and no
   temporary. */
static void test_measure_without_osmesa_or_egl_writes_nothing(void **state) {
    (void)state;
    static const char *const libraries[] = { "/nonexistent/libOSMesa.so.8", "libm.so.6" };
    static const char *const why[] = { "cannot open shared object file", "no symbol OSMesaCreateContextAttribs" };
    for (int i = 0; i < 2; i++) {
        char dir[256], args[700], env[256], want[300];
        snprintf(dir, sizeof dir, "%s/no-context", work);
        snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --measure -o %s", scene, dir);
        snprintf(env, sizeof env, "env -u HAIRTIER_CONTEXT HAIRGEN_OSMESA=%s HAIRGEN_EGL=/nonexistent/libEGL.so.1",
                 libraries[i]);
        assert_int_equal(run_hairgen(env, args), 1);
        char *err = work_file("err.txt");
        snprintf(want, sizeof want, "hairgen: measure: no offscreen context: osmesa: %s", libraries[i]);
        if (strncmp(err, want, strlen(want)) != 0 || !strstr(err, why[i]) ||
            !strstr(err, "; egl: /nonexistent/libEGL.so.1: cannot open shared object file") ||
            strchr(err, '\n') != err + strlen(err) - 1)
            fail_msg("got: %s", err);
        free(err);
        assert_false(ht_test_path_exists(dir));
        assert_int_equal(count_temporaries(), 0);
    }
}

/* An -o the generator accepts (at most 1023 bytes) whose temporary sibling
   the runtime could not read: refused with one line, nothing left. */
static void test_an_output_path_too_long_to_measure_is_refused(void **state) {
    (void)state;
    char dir[1100];
    snprintf(dir, sizeof dir, "%s", work);
    while (strlen(dir) < 900) {
        size_t n = strlen(dir);
        dir[n] = '/';
        memset(dir + n + 1, 'd', 100);
        dir[n + 101] = '\0';
        assert_true(mkdir(dir, 0700) == 0);
    }
    size_t n = strlen(dir);
    dir[n] = '/';
    memset(dir + n + 1, 'b', 1020 - n - 1);
    dir[1020] = '\0';
    char args[1400];
    snprintf(args, sizeof args, "materials/dark-brown.json --scene %s --measure -o %s", scene, dir);
    assert_int_equal(run_hairgen(NULL, args), 1);
    char *err = work_file("err.txt");
    if (!strstr(err, "the bundle's temporary directory path is 1031 bytes, more than the 1023 the runtime reads"))
        fail_msg("%s", err);
    assert_ptr_equal(strchr(err, '\n'), err + strlen(err) - 1);
    free(err);
    assert_false(ht_test_path_exists(dir));
    dir[n] = '\0';
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) assert_true(e->d_name[0] == '.');
    closedir(d);
}

/* The step hairgen --measure runs (ht_measure_step), given the scene the
   bundle was planned for: without a scene file that must be the built-in
   one (512², ht_scene_default); it is measured here at 96², 100 of its
   2000 hairs, 4 of their 16 joints (the same camera and lights: 2000
   hairs of 16 joints through every tier's seven frames cost 11 s). */
static bool planned_for_built_in;

static ht_result measure_built_in_smaller(void *job, const char *dir, const ht_scene *scene, char *err,
                                          size_t err_size) {
    ht_scene built_in;
    ht_scene_default(&built_in);
    planned_for_built_in = scene->width == 512 && scene->height == 512 && scene->width == built_in.width &&
                           scene->height == built_in.height && scene->light_count == built_in.light_count &&
                           scene->geometry == built_in.geometry &&
                           memcmp(&scene->camera, &built_in.camera, sizeof built_in.camera) == 0 &&
                           memcmp(&scene->furball, &built_in.furball, sizeof built_in.furball) == 0;
    ht_scene smaller = *scene;
    smaller.width = smaller.height = 96;
    smaller.furball.hairs = 100;
    smaller.furball.joints = 4;
    return ht_measure_step(job, dir, &smaller, err, err_size);
}

/* hairgen --measure without --scene: ht_bundle_make with no scene path and
   ht_measure_step with a job whose scene_path is NULL (shadergen/hairgen.c,
   run_measure_or_header); the same calls here, the scene made smaller on
   its way to the step. */
static void test_without_a_scene_the_built_in_one_is_measured(void **state) {
    (void)state;
    char dir[256], err[2048] = "";
    snprintf(dir, sizeof dir, "%s/built-in", work);
    ht_measure_job job = { .scene_path = NULL, .out_dir = dir };
    planned_for_built_in = false;
    if (ht_generate_bundle_then("materials/dark-brown.json", NULL, dir, NULL, measure_built_in_smaller, &job, err,
                                sizeof err) != HT_OK)
        fail_msg("%s", err);
    assert_true(planned_for_built_in);
    const ht_manifest *m = load(dir);
    assert_true(m->tier_count >= 2);
    for (int i = 0; i < m->tier_count; i++) {
        assert_true(m->tiers[i].measured.present);
        assert_string_equal(m->tiers[i].measured.scene, HT_MEASURE_BUILT_IN_SCENE);
    }
    char *text = printed_table(&job.result);
    if (!strstr(text, "measured: scene built-in (96x96)")) fail_msg("the table:\n%s", text);
    free(text);
}

/* A result the reader would refuse is refused before the manifest is
   touched, naming the tier and field. */
static void test_write_manifest_refuses_numbers_out_of_range(void **state) {
    (void)state;
    char dir[256], path[300], err[512];
    snprintf(dir, sizeof dir, "%s/bad-numbers", work);
    ht_test_copy_dir(plain, dir);
    snprintf(path, sizeof path, "%s/manifest.json", dir);
    char *before = ht_test_read_all(path, NULL);
    ht_measure_result res = { .tier_count = 5, .scene = "small.json", .driver = "test" };
    const char *names[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int i = 0; i < 5; i++) {
        snprintf(res.tiers[i].name, sizeof res.tiers[i].name, "%s", names[i]);
        res.tiers[i].cost_ratio = 1;
        res.tiers[i].whole = (ht_metrics){ .psnr_db = i ? 30 : INFINITY, .ssim = 1 };
    }
    ht_measure_result bad = res;
    bad.tiers[3].whole.ssim = NAN;
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "measure: fixed: ssim: nan is outside [-1, 1]"));
    bad = res;
    bad.tiers[1].cost_ratio = 0;
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "measure: vertex: cost_ratio: 0 is outside (0, 1e6]"));
    bad = res;
    bad.tiers[2].whole.psnr_db = -INFINITY;
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "measure: fixed4: psnr_db: -inf"));
    bad = res;
    bad.tiers[4].whole.delta_e00_p95 = 1e9;
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "measure: gl11: delta_e00_p95: "));
    bad = res;
    bad.tiers[1].flip.mean = 1.5;
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "measure: vertex: flip_mean: 1.5 is outside [0, 1]"));
    bad = res;
    bad.tiers[2].flip.p95 = NAN;
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_UNSUPPORTED);
    assert_non_null(strstr(err, "measure: fixed4: flip_p95: nan is outside [0, 1]"));
    bad = res;
    bad.tier_count = 4; /* gl11 not measured */
    assert_int_equal(ht_measure_write_manifest(dir, &bad, err, sizeof err), HT_ERR_PARSE);
    assert_non_null(strstr(err, "tiers[4]: \"gl11\" was not measured"));
    char *after = ht_test_read_all(path, NULL);
    assert_string_equal(before, after);
    free(after);

    /* And the good one is written, rounded, read back. */
    res.tiers[1].whole.psnr_db = 31.23456;
    res.tiers[1].cost_ratio = 0.123456;
    res.tiers[1].flip = (ht_flip_result){ .mean = 0.0123456, .p95 = 0.0987654 };
    assert_int_equal(ht_measure_write_manifest(dir, &res, err, sizeof err), HT_OK);
    const ht_manifest *m = load(dir);
    assert_true(isinf(m->tiers[0].measured.psnr_db));
    assert_true(m->tiers[1].measured.psnr_db == 31.23);
    assert_true(m->tiers[1].measured.cost_ratio == 0.1235);
    assert_true(m->tiers[1].measured.flip_mean == 0.01235 && m->tiers[1].measured.flip_p95 == 0.09877);
    assert_true(m->tiers[0].measured.flip_mean == 0.0);
    assert_string_equal(m->tiers[1].measured.driver, "test");
    free(before);
}

static void test_scene_label_is_the_base_name_cut_whole_characters(void **state) {
    (void)state;
    char label[64];
    ht_measure_scene_label(NULL, label);
    assert_string_equal(label, "built-in");
    ht_measure_scene_label("scenes/furball.json", label);
    assert_string_equal(label, "furball.json");
    ht_measure_scene_label("patches.json", label);
    assert_string_equal(label, "patches.json");
    /* 62 ASCII bytes then a two-byte character: the character is left out whole. */
    char long_name[128];
    memset(long_name, 'a', 62);
    snprintf(long_name + 62, sizeof long_name - 62, "\xc3\xa9tude.json");
    ht_measure_scene_label(long_name, label);
    assert_int_equal(strlen(label), 62);
    memset(long_name, 'b', 70);
    long_name[70] = '\0';
    ht_measure_scene_label(long_name, label);
    assert_int_equal(strlen(label), 63);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_scene_label_is_the_base_name_cut_whole_characters),
        cmocka_unit_test(test_every_tier_carries_a_measured_object_the_runtime_reads),
        cmocka_unit_test(test_measure_adds_only_the_measured_objects),
        cmocka_unit_test(test_hairgen_prints_the_measured_table),
        cmocka_unit_test(test_measured_table_names_a_gpus_warmup),
        cmocka_unit_test(test_hairgen_names_marschner_as_the_reference_of_a_marschner_bundle),
        cmocka_unit_test(test_measure_without_libosmesa_draws_through_egl),
        cmocka_unit_test(test_measure_without_osmesa_or_egl_writes_nothing),
        cmocka_unit_test(test_error_policy_picks_the_cheapest_measured_tier_that_reaches_it),
        cmocka_unit_test(test_hairview_error_30_says_which_tier_and_why),
        cmocka_unit_test(test_a_failed_measurement_writes_nothing),
        cmocka_unit_test(test_measure_refuses_a_scene_with_no_hair_in_view),
        cmocka_unit_test(test_write_manifest_refuses_numbers_out_of_range),
        cmocka_unit_test(test_an_output_path_too_long_to_measure_is_refused),
        cmocka_unit_test(test_without_a_scene_the_built_in_one_is_measured),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

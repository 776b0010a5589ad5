/* test_policy — the speed-for-accuracy dial: policies chosen by selection
   (pure: synthetic caps, manifest measured numbers, injected timings), the
   manifest's per-tier "measured" object, and the renderer honouring
   desc.policy, HAIRTIER_POLICY and desc.time_tier on OSMesa (no wall-clock
   assertion anywhere: every timing is injected). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cJSON.h>
#include <cmocka.h>

#include "manifest.h"
#include "select.h"
#include "support_caps.h"
#include "support_log.h"
#include "support_render.h"
#include "support_scratch.h"

/* Five tiers as hairgen lists them, each with measured numbers unless the
   test strips them. cost_ratio = frame time / full's. */
#define TIER(name, req, files, measured) \
    "{\"name\": \"" name "\", \"requires\": " req ", \"files\": " files measured "}"
#define MEASURED(psnr, cost) \
    ", \"measured\": {\"psnr_db\": " psnr ", \"ssim\": 0.9, \"delta_e00_mean\": 1.5, \"delta_e00_p95\": 4," \
    " \"cost_ratio\": " cost ", \"scene\": \"furball\", \"driver\": \"llvmpipe\"}"
#define MANIFEST(m_full, m_vertex, m_fixed4, m_fixed, m_gl11) \
    "{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"material\": \"t\", \"model\": \"scheuermann\"," \
    " \"lights\": [\"directional\"], \"opaque_cutoff\": 0.9, \"tiers\": [" \
    TIER("full", "{\"api\": \"gl\", \"gl\": \"2.1\", \"glsl\": \"1.20\"}", "{\"vertex\": \"f.vert\", \"fragment\": \"f.frag\"}", m_full) "," \
    TIER("vertex", "{\"api\": \"gl\", \"gl\": \"2.0\", \"glsl\": \"1.10\", \"texture_units\": 4}", "{\"vertex\": \"v.vert\"}", m_vertex) "," \
    TIER("fixed4", "{\"api\": \"gl\", \"gl\": \"1.3\", \"glsl\": null, \"texture_units\": 4}", "{\"program\": \"fixed4.json\"}", m_fixed4) "," \
    TIER("fixed", "{\"api\": \"gl\", \"gl\": \"1.3\", \"glsl\": null, \"texture_units\": 2}", "{\"program\": \"fixed.json\"}", m_fixed) "," \
    TIER("gl11", "{\"api\": \"gl\", \"gl\": \"1.1\", \"glsl\": null}", "{\"program\": \"gl11.json\"}", m_gl11) "]}"

static const char measured_manifest[] =
    MANIFEST(MEASURED("null", "1"), MEASURED("32.1", "0.6"), MEASURED("31.2", "0.4"), MEASURED("27", "0.5"),
             MEASURED("29", "0.45"));
static const char plain_manifest[] = MANIFEST("", "", "", "", "");
/* The same with FLIP means: fixed4 is the cheapest but the only one over
   0.05. */
#define MEASURED_FLIP(psnr, flip, p95, cost) \
    ", \"measured\": {\"psnr_db\": " psnr ", \"ssim\": 0.9, \"delta_e00_mean\": 1.5, \"delta_e00_p95\": 4," \
    " \"flip_mean\": " flip ", \"flip_p95\": " p95 ", \"cost_ratio\": " cost "}"
static const char flip_manifest[] =
    MANIFEST(MEASURED_FLIP("null", "0", "0", "1"), MEASURED_FLIP("32.1", "0.02", "0.1", "0.6"),
             MEASURED_FLIP("31.2", "0.06", "0.3", "0.4"), MEASURED_FLIP("27", "0.04", "0.2", "0.5"),
             MEASURED_FLIP("29", "0.045", "0.25", "0.45"));
/* Only full has FLIP numbers (the others were measured before FLIP). */
static const char flip_partial_manifest[] =
    MANIFEST(MEASURED_FLIP("null", "0", "0", "1"), MEASURED("32.1", "0.6"), MEASURED("31.2", "0.4"),
             MEASURED("27", "0.5"), MEASURED("29", "0.45"));
/* Only two tiers measured: fastest falls back to the bundle's order. */
static const char partial_manifest[] = MANIFEST(MEASURED("null", "1"), "", MEASURED("31.2", "0.4"), "", "");

static ht_manifest parse(const char *text) {
    ht_manifest m;
    char err[512];
    if (ht_manifest_parse(text, "/bundle", "/bundle/manifest.json", &m, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return m;
}

static ht_policy policy(const char *text) {
    ht_policy p;
    char err[256];
    if (ht_policy_parse(text, &p, err, sizeof err) != HT_OK) fail_msg("%s", err);
    return p;
}

static ht_tier pick(const ht_manifest *m, const ht_caps *c, const char *policy_text, ht_selection *s) {
    char err[512];
    ht_select_desc d = { .caps = c, .bundle = m, .policy = policy(policy_text) };
    if (ht_select_tier(&d, s, err, sizeof err) != HT_OK) fail_msg("%s: %s", policy_text, err);
    return s->tier;
}

static void test_policy_parse_accepts_the_four_and_names_what_is_wrong(void **state) {
    (void)state;
    ht_policy p;
    char err[256];
    assert_int_equal(ht_policy_parse(NULL, &p, err, sizeof err), HT_OK);
    assert_int_equal(p.kind, HT_POLICY_BEST);
    assert_int_equal(policy("fastest").kind, HT_POLICY_FASTEST);
    p = policy("error:30.5");
    assert_true(p.kind == HT_POLICY_ERROR && p.value == 30.5);
    p = policy("frame:16.7");
    assert_true(p.kind == HT_POLICY_FRAME && fabs(p.value - 16.7) < 1e-12);
    const char *bad[] = { "quick", "error:", "error:abc", "error:-1", "frame:0", "frame:12ms", "frame:inf", "Best" };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        err[0] = '\0';
        assert_int_equal(ht_policy_parse(bad[i], &p, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        if (!strstr(err, bad[i])) fail_msg("\"%s\": message \"%s\" does not quote it", bad[i], err);
    }
}

/* Issue 19 row 8: strtod took a space, a sign and hex, so "error: 30",
   "error:0x1e" and "error:-0" were policies; a newline split the message. */
static void test_policy_numbers_are_plain_decimals_and_messages_one_line(void **state) {
    (void)state;
    ht_policy p;
    char err[256];
    const char *bad[] = { "error: 30", "error:0x1e", "error:-0", "error:+5", "error:30 ", "error:1e3",
                          "error:.5", "error:5.", "frame:\t16", "frame:0x10", "error:nan", "error:30\n" };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        err[0] = '\0';
        if (ht_policy_parse(bad[i], &p, err, sizeof err) != HT_ERR_INVALID_ARGUMENT) fail_msg("accepted: %s", bad[i]);
        if (strchr(err, '\n') || strchr(err, '\t')) fail_msg("not one line: %s", err);
    }
    assert_int_equal(policy("error:0").kind, HT_POLICY_ERROR);
    assert_true(policy("error:30").value == 30.0);
    assert_true(policy("frame:0.5").value == 0.5);
    /* a newline in a policy's name is escaped, not printed */
    assert_int_equal(ht_policy_parse("best\nhairtier: tier full", &p, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    if (strchr(err, '\n') || !strstr(err, "best\\nhairtier")) fail_msg("%s", err);
}

static void test_manifest_reads_the_measured_object_and_null_psnr_as_identical(void **state) {
    (void)state;
    ht_manifest m = parse(measured_manifest);
    const ht_manifest_measured *full = &m.tiers[0].measured, *fixed4 = &m.tiers[2].measured;
    assert_true(full->present && isinf(full->psnr_db) && full->cost_ratio == 1.0);
    assert_true(fixed4->present && fixed4->psnr_db == 31.2 && fixed4->cost_ratio == 0.4);
    assert_true(fixed4->ssim == 0.9 && fixed4->delta_e00_mean == 1.5 && fixed4->delta_e00_p95 == 4.0);
    assert_string_equal(fixed4->scene, "furball");
    assert_string_equal(fixed4->driver, "llvmpipe");
    assert_false(parse(plain_manifest).tiers[0].measured.present);
}

static void test_manifest_refuses_a_bad_measured_object_naming_the_field(void **state) {
    (void)state;
    struct { const char *measured, *field; } cases[] = {
        { ", \"measured\": {\"psnr_db\": 30, \"ssim\": 0.9, \"delta_e00_mean\": 1, \"delta_e00_p95\": 2, \"cost_ratio\": 0}",
          "tiers[0].measured.cost_ratio" },
        { ", \"measured\": {\"psnr_db\": -1, \"ssim\": 0.9, \"delta_e00_mean\": 1, \"delta_e00_p95\": 2, \"cost_ratio\": 1}",
          "tiers[0].measured.psnr_db" },
        { ", \"measured\": {\"psnr_db\": 30, \"delta_e00_mean\": 1, \"delta_e00_p95\": 2, \"cost_ratio\": 1}",
          "tiers[0].measured.ssim" },
        { ", \"measured\": {\"psnr\": 30, \"psnr_db\": 30, \"ssim\": 0.9, \"delta_e00_mean\": 1, \"delta_e00_p95\": 2, \"cost_ratio\": 1}",
          "tiers[0].measured.psnr" },
        { ", \"measured\": 3", "tiers[0].measured" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char text[4096], err[512];
        snprintf(text, sizeof text,
                 "{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"lights\": [\"directional\"], \"opaque_cutoff\": 0.9, \"tiers\": ["
                 TIER("gl11", "{\"api\": \"gl\", \"gl\": \"1.1\", \"glsl\": null}", "{\"program\": \"gl11.json\"}", "%s") "]}",
                 cases[i].measured);
        ht_manifest m;
        assert_int_equal(ht_manifest_parse(text, "/b", "/b/manifest.json", &m, err, sizeof err), HT_ERR_PARSE);
        if (!strstr(err, cases[i].field)) fail_msg("case %zu: \"%s\" does not name %s", i, err, cases[i].field);
    }
}

static void test_best_is_the_default_and_picks_as_before(void **state) {
    (void)state;
    ht_manifest m = parse(measured_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_selection s;
    assert_int_equal(pick(&m, &c, "best", &s), HT_TIER_FULL);
    assert_string_equal(s.reason, "best supported");
}

static void test_fastest_takes_the_least_measured_cost_of_the_tiers_that_run(void **state) {
    (void)state;
    ht_manifest m = parse(measured_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_selection s;
    assert_int_equal(pick(&m, &c, "fastest", &s), HT_TIER_FIXED4); /* 0.4, below gl11's 0.45 */
    assert_non_null(strstr(s.reason, "cost 0.4x full"));
    /* A GL 1.3 device with 2 units runs fixed and gl11 only. */
    c = ht_test_caps(1, 3, 0, 0, 2);
    assert_int_equal(pick(&m, &c, "fastest", &s), HT_TIER_GL11);
    assert_non_null(strstr(s.reason, "cost 0.45x full"));
}

static void test_fastest_without_measured_costs_takes_the_last_that_runs(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_selection s;
    ht_manifest m = parse(plain_manifest);
    assert_int_equal(pick(&m, &c, "fastest", &s), HT_TIER_GL11);
    assert_non_null(strstr(s.reason, "bundle's order"));
    m = parse(partial_manifest);
    assert_int_equal(pick(&m, &c, "fastest", &s), HT_TIER_GL11);
}

static void test_error_budget_takes_the_cheapest_tier_that_reaches_it(void **state) {
    (void)state;
    ht_manifest m = parse(measured_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_selection s;
    /* >= 30 dB: full (inf, 1), vertex (32.1, 0.6), fixed4 (31.2, 0.4) → fixed4 */
    assert_int_equal(pick(&m, &c, "error:30", &s), HT_TIER_FIXED4);
    assert_non_null(strstr(s.reason, "31.2 dB >= 30 dB, cost 0.4x full"));
    /* >= 32: vertex; >= 28: fixed4 (0.4 beats gl11's 0.45 at 29 dB); >= 40: full */
    assert_int_equal(pick(&m, &c, "error:32", &s), HT_TIER_VERTEX);
    assert_int_equal(pick(&m, &c, "error:28", &s), HT_TIER_FIXED4);
    assert_int_equal(pick(&m, &c, "error:40", &s), HT_TIER_FULL);
    assert_non_null(strstr(s.reason, "identical to full"));
    /* >= 0 on a GL 1.3, 2-unit device: fixed (0.5) or gl11 (0.45) → gl11 */
    c = ht_test_caps(1, 3, 0, 0, 2);
    assert_int_equal(pick(&m, &c, "error:0", &s), HT_TIER_GL11);
    /* >= 30 there: neither reaches it; the most accurate, gl11 at 29 dB */
    assert_int_equal(pick(&m, &c, "error:30", &s), HT_TIER_GL11);
    assert_non_null(strstr(s.reason, "no tier that runs reaches 30 dB; the most accurate: 29.0 dB"));
}

static void test_error_budget_needs_measured_numbers(void **state) {
    (void)state;
    ht_manifest m = parse(plain_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = { .caps = &c, .bundle = &m, .policy = policy("error:30") };
    ht_selection s;
    char err[512];
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "no tier has measured numbers"));
    assert_int_equal(s.index, -1);
    /* Partly measured: the unmeasured tiers are skipped with a line. */
    m = parse(partial_manifest);
    assert_int_equal(pick(&m, &c, "error:30", &s), HT_TIER_FIXED4);
    assert_non_null(strstr(s.reason, "vertex: no measured numbers"));
}

static void test_flip_policy_parses_a_mean_in_0_1_and_names_what_is_wrong(void **state) {
    (void)state;
    ht_policy p = policy("error:flip:0.05");
    assert_true(p.kind == HT_POLICY_ERROR_FLIP && p.value == 0.05);
    assert_true(policy("error:flip:0").value == 0.0 && policy("error:flip:1").value == 1.0);
    const char *bad[] = { "error:flip:", "error:flip:1.5", "error:flip:-0.1", "error:flip:abc", "error:flip:nan",
                          "error:flip:0.05x", "error:FLIP:0.05" };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char err[256] = "";
        assert_int_equal(ht_policy_parse(bad[i], &p, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        if (!strstr(err, bad[i]) || strchr(err, '\n')) fail_msg("\"%s\": message \"%s\"", bad[i], err);
    }
}

static void test_manifest_reads_flip_numbers_and_takes_their_absence_as_unmeasured(void **state) {
    (void)state;
    ht_manifest m = parse(flip_manifest);
    assert_true(m.tiers[1].measured.flip_mean == 0.02 && m.tiers[1].measured.flip_p95 == 0.1);
    assert_true(m.tiers[0].measured.flip_mean == 0.0);
    m = parse(measured_manifest);
    assert_true(m.tiers[1].measured.present && isnan(m.tiers[1].measured.flip_mean) &&
                isnan(m.tiers[1].measured.flip_p95));
}

static void test_manifest_refuses_bad_flip_numbers_naming_the_field(void **state) {
    (void)state;
    struct { const char *flip, *field; } cases[] = {
        { "\"flip_mean\": 1.5, \"flip_p95\": 0.2", "tiers[0].measured.flip_mean" },
        { "\"flip_mean\": 0.1, \"flip_p95\": -0.01", "tiers[0].measured.flip_p95" },
        { "\"flip_p95\": 0.2", "tiers[0].measured.flip_mean" },
        { "\"flip_mean\": 0.1", "tiers[0].measured.flip_p95" },
        { "\"flip_mean\": \"low\", \"flip_p95\": 0.2", "tiers[0].measured.flip_mean" },
        { "\"flip_mean\": null, \"flip_p95\": 0.2", "tiers[0].measured.flip_mean" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        char text[4096], err[512];
        snprintf(text, sizeof text,
                 "{\"format\": \"hairtier-bundle/1\", \"generator\": \"" HT_MANIFEST_GENERATOR "\", \"lights\": [\"directional\"], \"opaque_cutoff\": 0.9, \"tiers\": ["
                 TIER("gl11", "{\"api\": \"gl\", \"gl\": \"1.1\", \"glsl\": null}", "{\"program\": \"gl11.json\"}",
                      ", \"measured\": {\"psnr_db\": 30, \"ssim\": 0.9, \"delta_e00_mean\": 1, \"delta_e00_p95\": 2,"
                      " \"cost_ratio\": 1, %s}") "]}",
                 cases[i].flip);
        ht_manifest m;
        err[0] = '\0';
        assert_int_equal(ht_manifest_parse(text, "/b", "/b/manifest.json", &m, err, sizeof err), HT_ERR_PARSE);
        if (!strstr(err, cases[i].field) || strchr(err, '\n'))
            fail_msg("case %zu: \"%s\" does not name %s in one line", i, err, cases[i].field);
    }
}

static void test_flip_budget_takes_the_cheapest_tier_within_it(void **state) {
    (void)state;
    ht_manifest m = parse(flip_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_selection s;
    /* <= 0.05: full (0, 1), vertex (0.02, 0.6), fixed (0.04, 0.5), gl11
       (0.045, 0.45); fixed4 (0.06, 0.4) is cheaper but over → gl11 */
    assert_int_equal(pick(&m, &c, "error:flip:0.05", &s), HT_TIER_GL11);
    assert_non_null(strstr(s.reason, "error:flip:0.05: FLIP 0.045 <= 0.05, cost 0.45x full"));
    /* error:30 would take fixed4: PSNR and FLIP disagree here on purpose */
    assert_int_equal(pick(&m, &c, "error:30", &s), HT_TIER_FIXED4);
    assert_int_equal(pick(&m, &c, "error:flip:0.03", &s), HT_TIER_VERTEX);
    assert_int_equal(pick(&m, &c, "error:flip:0", &s), HT_TIER_FULL);
    assert_int_equal(pick(&m, &c, "error:flip:1", &s), HT_TIER_FIXED4);
    /* A GL 1.3, 2-unit device runs fixed (0.04) and gl11 (0.045): none is
       within 0.01, so the least FLIP, fixed. */
    c = ht_test_caps(1, 3, 0, 0, 2);
    assert_int_equal(pick(&m, &c, "error:flip:0.01", &s), HT_TIER_FIXED);
    assert_non_null(strstr(s.reason, "no tier that runs is within 0.01; the most accurate: FLIP 0.04"));
}

static void test_flip_budget_needs_flip_numbers(void **state) {
    (void)state;
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_selection s;
    char err[512];
    /* Measured before FLIP: refused with one line, like error:DB unmeasured. */
    ht_manifest m = parse(measured_manifest);
    ht_select_desc d = { .caps = &c, .bundle = &m, .policy = policy("error:flip:0.05") };
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "policy error:flip:0.05: no tier has measured FLIP numbers"));
    /* Only full has them: the others are skipped with a line. */
    m = parse(flip_partial_manifest);
    assert_int_equal(pick(&m, &c, "error:flip:0.05", &s), HT_TIER_FULL);
    assert_non_null(strstr(s.reason, "vertex: no measured FLIP (policy error:flip:0.05)"));
    /* A device that runs none of the tiers with FLIP numbers. */
    c = ht_test_caps(1, 3, 0, 0, 2);
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    m = parse(flip_partial_manifest);
    d.bundle = &m;
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, "no tier that runs here has measured FLIP numbers"));
}

static void test_frame_budget_keeps_the_best_tier_within_it(void **state) {
    (void)state;
    ht_manifest m = parse(plain_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    /* injected timings per bundle tier: full, vertex, fixed4, fixed, gl11 */
    ht_select_desc d = { .caps = &c, .bundle = &m, .policy = policy("frame:10"),
                         .frame_ms = { 30.0, 12.0, 8.0, 9.0, 6.0 } };
    ht_selection s;
    char err[512];
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FIXED4);
    assert_non_null(strstr(s.reason, "8.00 ms <= 10 ms"));
    d.policy = policy("frame:50");
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FULL);
    d.policy = policy("frame:2");
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_GL11);
    assert_non_null(strstr(s.reason, "no tier within 2 ms; the fastest timed: 6.00 ms"));
    /* Not timed yet: best. */
    memset(d.frame_ms, 0, sizeof d.frame_ms);
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_FULL);
    assert_non_null(strstr(s.reason, "not timed yet"));
}

static void test_a_forced_tier_wins_over_the_policy(void **state) {
    (void)state;
    ht_manifest m = parse(measured_manifest);
    ht_caps c = ht_test_caps(4, 5, 4, 50, 8);
    ht_select_desc d = { .caps = &c, .bundle = &m, .policy = policy("fastest"), .requested = HT_TIER_VERTEX };
    ht_selection s;
    char err[512];
    assert_int_equal(ht_select_tier(&d, &s, err, sizeof err), HT_OK);
    assert_int_equal(s.tier, HT_TIER_VERTEX);
    assert_string_equal(s.reason, "forced by desc.tier");
}

/* ---- the renderer, on OSMesa with the fur-ball bundle ---- */

static ht_test_furball fx;

static int render_setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "policy", 64) ? 0 : -1;
}

static int render_teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

/* A copy of the fixture's bundle whose every tier carries measured numbers
   (the shape hairgen --measure writes, with numbers chosen for the test),
   edited with cJSON. */
static void write_measured_copy(char *dir, size_t size) {
    static const struct { const char *tier; double psnr, cost; } numbers[] = {
        { "vertex", 32.1, 0.6 }, { "fixed4", 31.2, 0.4 }, { "fixed", 27.0, 0.5 }, { "gl11", 29.0, 0.45 } };
    ht_test_furball_copy_bundle(&fx, "measured", dir, size);
    char *text = ht_test_read_file(dir, "manifest.json");
    cJSON *root = cJSON_Parse(text); /* text: the helper's own buffer */
    assert_non_null(root);
    cJSON *tier;
    cJSON_ArrayForEach(tier, cJSON_GetObjectItemCaseSensitive(root, "tiers")) {
        const char *name = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(tier, "name"));
        cJSON *m = cJSON_AddObjectToObject(tier, HT_MANIFEST_KEY_MEASURED);
        double psnr = -1, cost = 1;
        for (size_t i = 0; i < sizeof numbers / sizeof *numbers; i++)
            if (strcmp(numbers[i].tier, name) == 0) psnr = numbers[i].psnr, cost = numbers[i].cost;
        if (psnr < 0) cJSON_AddNullToObject(m, HT_MANIFEST_KEY_PSNR_DB);
        else cJSON_AddNumberToObject(m, HT_MANIFEST_KEY_PSNR_DB, psnr);
        cJSON_AddNumberToObject(m, HT_MANIFEST_KEY_SSIM, 0.95);
        cJSON_AddNumberToObject(m, HT_MANIFEST_KEY_DELTA_E00_MEAN, 1.0);
        cJSON_AddNumberToObject(m, HT_MANIFEST_KEY_DELTA_E00_P95, 3.0);
        cJSON_AddNumberToObject(m, HT_MANIFEST_KEY_COST_RATIO, cost);
        cJSON_AddStringToObject(m, HT_MANIFEST_KEY_SCENE, "furball");
        cJSON_AddStringToObject(m, HT_MANIFEST_KEY_DRIVER, "synthetic");
    }
    char *out = cJSON_Print(root);
    ht_test_write_file(dir, "manifest.json", out);
    free(out);
    cJSON_Delete(root);
}

static void test_renderer_error_policy_logs_the_choice_with_its_numbers(void **state) {
    (void)state;
    char dir[256];
    write_measured_copy(dir, sizeof dir);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .policy = "error:30" }, dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FIXED4);
    assert_true(ht_test_logged("tier fixed4 (error:30: 31.2 dB >= 30 dB, cost 0.4x full"));
    ht_image img;
    ht_frame_desc f = ht_test_furball_frame(2.5f);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    assert_true(ht_test_pixel_stats_of(&img, ht_test_background).changed > 0);
    ht_image_free(&img);
    ht_renderer_destroy(r);
    /* Without measured numbers: a clear error at create. */
    ht_test_renderer_create((ht_renderer_desc){ .policy = "error:30" }, fx.bundle_dir, HT_ERR_INVALID_ARGUMENT);
    assert_true(ht_test_logged("no tier has measured numbers (hairgen --measure writes them)"));
}

static void test_renderer_reads_hairtier_policy_and_the_desc_wins(void **state) {
    (void)state;
    setenv("HAIRTIER_POLICY", "fastest", 1);
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ 0 }, fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_GL11);
    ht_renderer_destroy(r);
    r = ht_test_renderer_create((ht_renderer_desc){ .policy = "best" }, fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL);
    ht_renderer_destroy(r);
    setenv("HAIRTIER_POLICY", "sometimes", 1);
    ht_test_renderer_create((ht_renderer_desc){ 0 }, fx.bundle_dir, HT_ERR_INVALID_ARGUMENT);
    assert_true(ht_test_logged("HAIRTIER_POLICY: policy: \"sometimes\" is not best, fastest, error:DB, error:flip:E or frame:MS"));
    unsetenv("HAIRTIER_POLICY");
}

/* Injected frame times (ms) per tier; -1: not timed. */
static double fake_ms[HT_TIER_COUNT];
static int timed_calls;

static double fake_timer(void *user, ht_tier tier) {
    (void)user;
    timed_calls++;
    return fake_ms[tier];
}

static void test_renderer_frame_policy_times_every_tier_and_logs_each(void **state) {
    (void)state;
    fake_ms[HT_TIER_FULL] = 40.0;
    fake_ms[HT_TIER_VERTEX] = 20.0;
    fake_ms[HT_TIER_FIXED4] = 9.0;
    fake_ms[HT_TIER_FIXED] = 12.0;
    fake_ms[HT_TIER_GL11] = -1.0;
    timed_calls = 0;
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .policy = "frame:10", .time_tier = fake_timer },
                                             fx.bundle_dir, HT_OK);
    assert_int_equal(timed_calls, 5);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FIXED4);
    assert_true(ht_test_logged("timed full: 40.000 ms a frame (desc.time_tier)"));
    assert_true(ht_test_logged("timed gl11: no time (desc.time_tier)"));
    assert_true(ht_test_logged("tier fixed4 (frame:10: 9.00 ms <= 10 ms, the best that runs within budget"));
    /* Asked again with other numbers and a budget of its own: re-chosen, the mesh set again. */
    fake_ms[HT_TIER_VERTEX] = 25.0;
    ht_frame_desc f = ht_test_furball_frame(2.5f);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    assert_int_equal(ht_renderer_choose_by_frame_time(r, &fx.mesh, &f, 30.0), HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_VERTEX);
    ht_image img;
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    assert_true(ht_test_pixel_stats_of(&img, ht_test_background).changed > 0);
    ht_image_free(&img);
    ht_renderer_destroy(r);
}

/* The real timer draws every tier; only what it chose is asserted, never a time. */
static void test_renderer_frame_policy_times_by_drawing_after_set_mesh(void **state) {
    (void)state;
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .policy = "frame:100000" }, fx.bundle_dir, HT_OK);
    assert_true(ht_test_logged("not timed yet, best supported"));
    ht_frame_desc f = ht_test_furball_frame(2.5f);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    assert_int_equal(ht_renderer_choose_by_frame_time(r, &fx.mesh, &f, 0), HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL); /* every tier is within 100 s */
    const char *names[] = { "full", "vertex", "fixed4", "fixed", "gl11" };
    for (int i = 0; i < 5; i++) {
        char line[64];
        snprintf(line, sizeof line, "timed %s: ", names[i]);
        if (!ht_test_logged(line)) fail_msg("no line \"%s\"", line);
    }
    assert_true(ht_test_logged("after 0 ms of warm-up frames, at least one)")); /* llvmpipe: no clock */
    ht_image img;
    ht_test_draw(&fx.gl, r, &f, ht_test_background, &img);
    assert_true(ht_test_pixel_stats_of(&img, ht_test_background).changed > 0);
    ht_image_free(&img);
    /* A budget is needed: best policy and 0 ms is refused. */
    ht_renderer *b = ht_test_renderer_create((ht_renderer_desc){ 0 }, fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_choose_by_frame_time(b, &fx.mesh, &f, 0), HT_ERR_INVALID_ARGUMENT);
    assert_true(ht_test_logged("budget_ms"));
    ht_renderer_destroy(b);
    ht_renderer_destroy(r);
}

/* A GPU warms up HT_TIMING_WARMUP_MS before timing; a software
   rasterizer, or no renderer string, one frame. */
static void test_timing_warms_up_a_gpu_only(void **state) {
    (void)state;
    static const char *const software[] = { "llvmpipe (LLVM 15.0.6, 256 bits)", "softpipe",
                                            "Mesa OffScreen", "Software Rasterizer",
                                            "Google SwiftShader", NULL };
    for (size_t i = 0; i < sizeof software / sizeof software[0]; i++)
        assert_true(ht_timing_warmup_ms(software[i]) == 0.0);
    static const char *const gpus[] = { "NVIDIA H200/PCIe/SSE2", "Mali-400 MP", "V3D 4.2", "Adreno (TM) 306", "" };
    for (size_t i = 0; i < sizeof gpus / sizeof gpus[0]; i++)
        assert_true(ht_timing_warmup_ms(gpus[i]) == HT_TIMING_WARMUP_MS);
}

int main(void) {
    unsetenv("HAIRTIER_POLICY");
    unsetenv("HAIRTIER_TIER");
    const struct CMUnitTest pure[] = {
        cmocka_unit_test(test_policy_parse_accepts_the_four_and_names_what_is_wrong),
        cmocka_unit_test(test_policy_numbers_are_plain_decimals_and_messages_one_line),
        cmocka_unit_test(test_manifest_reads_the_measured_object_and_null_psnr_as_identical),
        cmocka_unit_test(test_manifest_refuses_a_bad_measured_object_naming_the_field),
        cmocka_unit_test(test_best_is_the_default_and_picks_as_before),
        cmocka_unit_test(test_fastest_takes_the_least_measured_cost_of_the_tiers_that_run),
        cmocka_unit_test(test_fastest_without_measured_costs_takes_the_last_that_runs),
        cmocka_unit_test(test_error_budget_takes_the_cheapest_tier_that_reaches_it),
        cmocka_unit_test(test_error_budget_needs_measured_numbers),
        cmocka_unit_test(test_flip_policy_parses_a_mean_in_0_1_and_names_what_is_wrong),
        cmocka_unit_test(test_manifest_reads_flip_numbers_and_takes_their_absence_as_unmeasured),
        cmocka_unit_test(test_manifest_refuses_bad_flip_numbers_naming_the_field),
        cmocka_unit_test(test_flip_budget_takes_the_cheapest_tier_within_it),
        cmocka_unit_test(test_flip_budget_needs_flip_numbers),
        cmocka_unit_test(test_frame_budget_keeps_the_best_tier_within_it),
        cmocka_unit_test(test_a_forced_tier_wins_over_the_policy),
    };
    const struct CMUnitTest render[] = {
        cmocka_unit_test(test_renderer_error_policy_logs_the_choice_with_its_numbers),
        cmocka_unit_test(test_renderer_reads_hairtier_policy_and_the_desc_wins),
        cmocka_unit_test(test_renderer_frame_policy_times_every_tier_and_logs_each),
        cmocka_unit_test(test_timing_warms_up_a_gpu_only),
        cmocka_unit_test(test_renderer_frame_policy_times_by_drawing_after_set_mesh),
    };
    int failed = cmocka_run_group_tests_name("policy selection", pure, NULL, NULL);
    failed += cmocka_run_group_tests_name("policy renderer", render, render_setup, render_teardown);
    return failed;
}

/* test_render_lod_async — ht_lod_chain with async on (lod.h): the frame
   that switches to a level needing a sort or a widened copy uploads
   nothing and draws the level before (the select returns it, pending
   says so); after ht_lod_chain_wait the next select uploads the job's
   result and the frame is byte for byte what the synchronous chain draws
   for the same camera. Superseded jobs (another level, the eye past the
   order's reach), async turned off and the chain freed while a job runs,
   soft and per-draw widened levels, and an upload that fails when the
   result arrives (the chain still says what the renderer draws). Nothing
   here reads a clock. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "support_gl_fault.h"
#include "support_render.h"

/* The context's size; the levels are chosen for a viewport view_h high:
   SORT_VIEW puts the 400-hair ball's sorted levels (strands under 1.5 px)
   a few units away, WIDE_VIEW its widened ones (under a pixel). */
#define SIZE 64
#define SORT_VIEW 256
#define WIDE_VIEW 64
static int view_h = SORT_VIEW;

static ht_test_furball fx;

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "render_lod_async", SIZE) ? 0 : -1;
}
static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

/* A full-tier renderer on the GL fault layer (its uploads counted), the
   width rule per vertex on or off. */
static ht_renderer *renderer(bool per_vertex) {
    ht_renderer *r = ht_test_renderer_create((ht_renderer_desc){ .tier = HT_TIER_FULL, .strict = true,
                                                                 .getproc = ht_test_fault_getproc },
                                             fx.bundle_dir, HT_OK);
    ht_renderer_set_width_rule(r, per_vertex);
    return r;
}

/* Since ht_fault_arm: glBufferData and glBufferSubData, and the latter
   alone (an index upload, ht_renderer_set_mesh_order). */
static long uploads(void) { return ht_fault_state_get()->calls[HT_FAULT_BUFFER_DATA]; }
static long index_uploads(void) { return ht_fault_state_get()->buffer_sub_data; }

static void chain_make(ht_lod_chain *c, bool width_rule, bool async) {
    assert_int_equal(ht_lod_chain_build(&fx.mesh, c), HT_OK);
    c->width_rule = width_rule;
    c->async = async;
}

static int select_at(ht_lod_chain *c, ht_renderer *r, const ht_frame_desc *f) {
    ht_result res;
    const int level = ht_lod_chain_select(c, r, &f->camera, view_h, &res);
    assert_int_equal(res, HT_OK);
    return level;
}

static bool sorted(const ht_lod_chain *c, const ht_renderer *r) { (void)r; return c->ordered_level >= 0; }
static bool widened(const ht_lod_chain *c, const ht_renderer *r) { return c->wide_renderer == r; }

/* The first distance past 3 (steps of 15 %) at which a synchronous chain
   with the width rule, at 3 then there, draws a level past `past` the way
   `drawn` says (r says per vertex or per draw). */
static float find_distance(ht_renderer *r, bool (*drawn)(const ht_lod_chain *, const ht_renderer *), int past) {
    const ht_frame_desc near = ht_test_furball_orbit_frame(3, 0);
    for (float d = 3.45f; d < 300; d *= 1.15f) {
        ht_lod_chain c;
        chain_make(&c, true, false);
        select_at(&c, r, &near);
        const ht_frame_desc far = ht_test_furball_orbit_frame(d, 0);
        const bool found = select_at(&c, r, &far) > past && drawn(&c, r);
        ht_lod_chain_free(&c);
        if (found) return d;
    }
    fail_msg("no distance draws such a level");
    return 0;
}

/* One frame of a and of b: the same bytes, with hair in them. */
static void assert_same_image(ht_renderer *a, ht_renderer *b, const ht_frame_desc *f) {
    ht_image x, y;
    ht_test_draw(&fx.gl, a, f, ht_test_background, &x);
    ht_test_draw(&fx.gl, b, f, ht_test_background, &y);
    assert_true(ht_test_pixel_stats_of(&x, ht_test_background).changed > 20);
    assert_memory_equal(x.pixels, y.pixels, (size_t)x.width * x.height * x.channels);
    ht_image_free(&x);
    ht_image_free(&y);
}

/* r's next frame: every pass draws [first, first + count) of what it holds. */
static void assert_draws(ht_renderer *r, const ht_frame_desc *f, uint32_t first, uint32_t count) {
    ht_image img;
    ht_test_draw(&fx.gl, r, f, ht_test_background, &img);
    ht_image_free(&img);
    const ht_trace *t = ht_renderer_trace(r);
    assert_int_equal(t->count, HT_PASS_COUNT);
    for (int i = 0; i < t->count; i++) {
        assert_int_equal(t->entries[i].first_index, first);
        assert_int_equal(t->entries[i].index_count, count);
    }
}

/* The width rule per vertex: at 3 level 0 as built; the frame asking for
   a sorted level past 0 uploads nothing and still draws level 0 (pending);
   after the wait one index upload, and the synchronous chain's frame. */
static void switch_sorts_off_the_frame(void **state) {
    (void)state;
    view_h = SORT_VIEW;
    ht_renderer *rs = renderer(true), *ra = renderer(true);
    const float d = find_distance(rs, sorted, 0);
    ht_lod_chain sync, as;
    chain_make(&sync, true, false);
    chain_make(&as, true, true);
    const ht_frame_desc near = ht_test_furball_orbit_frame(3, 0), far = ht_test_furball_orbit_frame(d, 0);
    assert_int_equal(select_at(&sync, rs, &near), 0);
    assert_int_equal(select_at(&as, ra, &near), 0);
    assert_false(ht_lod_chain_pending(&as)); /* level 0 as built: nothing to sort */
    assert_null(as.job);
    const int want = select_at(&sync, rs, &far);
    assert_true(want > 0 && sync.ordered_level == want);

    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &far), 0); /* the level drawn: the one before */
    assert_true(ht_lod_chain_pending(&as));
    assert_int_equal(uploads(), 0);
    assert_int_equal(as.ordered_level, -1);
    assert_int_equal(as.current, 0);
    assert_draws(ra, &far, as.first[0], as.index_count[0]);
    ht_lod_chain_wait(&as);
    assert_true(ht_lod_chain_pending(&as)); /* done, not yet uploaded */

    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &far), want);
    assert_false(ht_lod_chain_pending(&as));
    assert_null(as.job);
    assert_int_equal(as.ordered_level, want);
    assert_int_equal(uploads(), 1);
    assert_int_equal(index_uploads(), 1);
    assert_memory_equal(as.ordered_eye, far.camera.eye, sizeof as.ordered_eye);
    assert_same_image(rs, ra, &far);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &far), want); /* the same camera: nothing */
    assert_int_equal(uploads(), 0);
    assert_false(ht_lod_chain_pending(&as));
    ht_lod_chain_free(&as);
    ht_lod_chain_free(&sync);
    ht_renderer_destroy(rs);
    ht_renderer_destroy(ra);
}

/* Jobs asked for no more: one for a level superseded by another level
   before it is uploaded (dropped, level 0 drawn until the second is
   done); the eye turned past HT_LOD_RESORT_DEG (the old order drawn
   meanwhile); a result whose eye is already past the reach of the
   frame's (uploaded, and a new sort started); async turned off while a
   job runs (the select sorts, the job dropped); a plain level asked for
   while a job runs (drawn at once); the chain freed while a job runs.
   make asan: nothing leaks. */
static void superseded_jobs(void **state) {
    (void)state;
    view_h = SORT_VIEW;
    ht_renderer *rs = renderer(true), *ra = renderer(true);
    const float d1 = find_distance(rs, sorted, 0);
    ht_lod_chain probe;
    chain_make(&probe, true, false);
    const ht_frame_desc near = ht_test_furball_orbit_frame(3, 0), far1 = ht_test_furball_orbit_frame(d1, 0);
    select_at(&probe, rs, &near);
    const int first = select_at(&probe, rs, &far1);
    ht_lod_chain_free(&probe);
    const float d2 = find_distance(rs, sorted, first);
    ht_lod_chain sync, as;
    chain_make(&sync, true, false);
    chain_make(&as, true, true);
    const ht_frame_desc far2 = ht_test_furball_orbit_frame(d2, 0);
    select_at(&sync, rs, &near);
    const int want = select_at(&sync, rs, &far2);
    assert_true(want > first && sync.ordered_level == want);

    select_at(&as, ra, &near);
    assert_int_equal(select_at(&as, ra, &far1), 0);
    ht_lod_chain_wait(&as); /* done, and another level asked for: dropped, the next one started */
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &far2), 0);
    assert_true(ht_lod_chain_pending(&as));
    assert_int_equal(uploads(), 0);
    assert_int_equal(as.ordered_level, -1);
    ht_lod_chain_wait(&as);
    assert_int_equal(select_at(&as, ra, &far2), want);
    assert_false(ht_lod_chain_pending(&as));
    assert_same_image(rs, ra, &far2);

    /* past the order's reach: sorted on the job, the old order drawn meanwhile */
    const ht_frame_desc turned = ht_test_furball_orbit_frame(d2, 8);
    assert_int_equal(select_at(&sync, rs, &turned), want);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &turned), want);
    assert_true(ht_lod_chain_pending(&as));
    assert_int_equal(uploads(), 0);
    assert_memory_equal(as.ordered_eye, far2.camera.eye, sizeof as.ordered_eye);
    assert_draws(ra, &turned, as.first[want], as.index_count[want]);
    ht_lod_chain_wait(&as);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &turned), want);
    assert_int_equal(index_uploads(), 1);
    assert_int_equal(uploads(), 1);
    assert_memory_equal(as.ordered_eye, turned.camera.eye, sizeof as.ordered_eye);
    assert_same_image(rs, ra, &turned);

    /* a result already past the frame's reach: uploaded (nearer than what
       is drawn), and the next sort started at once */
    const ht_frame_desc t16 = ht_test_furball_orbit_frame(d2, 16), t24 = ht_test_furball_orbit_frame(d2, 24);
    select_at(&as, ra, &t16);
    ht_lod_chain_wait(&as);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_at(&as, ra, &t24), want);
    assert_int_equal(index_uploads(), 1);
    assert_memory_equal(as.ordered_eye, t16.camera.eye, sizeof as.ordered_eye);
    assert_true(ht_lod_chain_pending(&as));
    ht_lod_chain_wait(&as);
    select_at(&as, ra, &t24);
    assert_memory_equal(as.ordered_eye, t24.camera.eye, sizeof as.ordered_eye);
    assert_false(ht_lod_chain_pending(&as));

    /* async turned off with a job in flight: this select sorts, the job is dropped */
    const ht_frame_desc t32 = ht_test_furball_orbit_frame(d2, 32);
    select_at(&as, ra, &t32);
    assert_true(ht_lod_chain_pending(&as));
    as.async = false;
    assert_int_equal(select_at(&as, ra, &t32), want);
    assert_null(as.job);
    assert_false(ht_lod_chain_pending(&as));
    assert_memory_equal(as.ordered_eye, t32.camera.eye, sizeof as.ordered_eye);
    as.async = true;

    /* a plain level while a job runs: drawn at once, the job's result dropped */
    const ht_frame_desc t40 = ht_test_furball_orbit_frame(d2, 40);
    select_at(&as, ra, &t40);
    assert_true(ht_lod_chain_pending(&as));
    assert_int_equal(select_at(&as, ra, &near), 0);
    assert_false(ht_lod_chain_pending(&as));
    assert_int_equal(as.ordered_level, -1);
    assert_draws(ra, &near, as.first[0], as.index_count[0]);
    ht_lod_chain_wait(&as);
    assert_int_equal(select_at(&as, ra, &near), 0);
    assert_null(as.job);

    /* freed with a job in flight: joined, nothing left */
    select_at(&as, ra, &far2);
    assert_true(ht_lod_chain_pending(&as));
    ht_lod_chain_free(&as);
    assert_null(as.job);
    ht_lod_chain_free(&sync);
    ht_renderer_destroy(rs);
    ht_renderer_destroy(ra);
}

/* Soft cells beside plain ones (test_render_lod's): error:30 takes
   (2 soft) at 1/2, (0) at 1. */
static const ht_lod_cell soft_cells[] = {
    { 0, HT_TIER_FULL, 1, INFINITY, 1, 0 },    { 1, HT_TIER_FULL, 1, 29, 0.5, 0 },
    { 2, HT_TIER_FULL, 1, 28, 0.4, 3 },
    { 0, HT_TIER_FULL, 0.5, INFINITY, 1, 0 },  { 1, HT_TIER_FULL, 0.5, 30.9, 0.30, 0 },
    { 2, HT_TIER_FULL, 0.5, 27.8, 0.14, 0 },   { 2, HT_TIER_FULL, 0.5, 30.4, 0.24, 3 },
    { 1, HT_TIER_FULL, 0.5, 31.6, 0.45, 3 },
};

static int select_pair_at(ht_lod_chain *c, ht_renderer *r, const ht_frame_desc *f) {
    const ht_lod_rule rule = { .kind = HT_POLICY_ERROR, .value = 30, .cells = soft_cells,
                               .cell_count = (int)(sizeof soft_cells / sizeof soft_cells[0]),
                               .size1_px = ht_projected_width_px(c->width, 3.0, f->camera.fov_y, 512) };
    ht_result res;
    const int level = ht_lod_chain_select_pair(c, r, &f->camera, 512, &rule, &res);
    assert_int_equal(res, HT_OK);
    return level;
}

/* A soft level: the first frame (nothing held yet) draws the plain level
   as built while the widened copy is made; then the soft level, 3x wide
   at opacity 1/3, the synchronous chain's frame; turned past the reach,
   the old order until the re-sort's indices go up alone; plain level 0
   close up at once. The width rule per draw: the frame whose level is
   widened draws level 0 until the copy is made, then the synchronous
   chain's frame. */
static void widened_levels(void **state) {
    (void)state;
    ht_renderer *rs = renderer(false), *ra = renderer(false);
    ht_lod_chain sync, as;
    chain_make(&sync, false, false);
    chain_make(&as, false, true);
    const ht_frame_desc f0 = ht_test_furball_orbit_frame(6, 0), turned = ht_test_furball_orbit_frame(6, 8), close = ht_test_furball_orbit_frame(3, 8);
    assert_int_equal(select_pair_at(&sync, rs, &f0), 2);
    assert_true(sync.soften == 3.0f && sync.wide_renderer == rs);
    assert_int_equal(select_pair_at(&as, ra, &f0), 2);
    assert_true(ht_lod_chain_pending(&as));
    assert_true(as.soften == 0.0f && as.wide_renderer == NULL && as.uploaded == ra);
    assert_draws(ra, &f0, as.first[2], as.index_count[2]);
    ht_lod_chain_wait(&as);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_pair_at(&as, ra, &f0), 2);
    assert_false(ht_lod_chain_pending(&as));
    assert_true(as.soften == 3.0f && as.wide_renderer == ra && as.uploaded == NULL && as.wide_level == 2);
    assert_int_equal(uploads(), 2); /* the widened level's vertices and indices */
    assert_same_image(rs, ra, &f0);

    assert_int_equal(select_pair_at(&sync, rs, &turned), 2);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_pair_at(&as, ra, &turned), 2);
    assert_true(ht_lod_chain_pending(&as));
    assert_int_equal(uploads(), 0);
    assert_memory_equal(as.wide_eye, f0.camera.eye, sizeof as.wide_eye);
    ht_lod_chain_wait(&as);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(select_pair_at(&as, ra, &turned), 2);
    assert_int_equal(uploads(), 1);
    assert_int_equal(index_uploads(), 1);
    assert_memory_equal(as.wide_eye, turned.camera.eye, sizeof as.wide_eye);
    assert_same_image(rs, ra, &turned);

    assert_int_equal(select_pair_at(&sync, rs, &close), 0);
    assert_int_equal(select_pair_at(&as, ra, &close), 0);
    assert_false(ht_lod_chain_pending(&as));
    assert_true(as.soften == 0.0f && as.wide_renderer == NULL && as.uploaded == ra);
    assert_same_image(rs, ra, &close);
    ht_lod_chain_free(&as);
    ht_lod_chain_free(&sync);

    /* the width rule per draw */
    view_h = WIDE_VIEW;
    const float d = find_distance(rs, widened, 0);
    chain_make(&sync, true, false);
    chain_make(&as, true, true);
    const ht_frame_desc near = ht_test_furball_orbit_frame(3, 0), far = ht_test_furball_orbit_frame(d, 0);
    const int before = select_at(&sync, rs, &near);
    assert_null(sync.wide_renderer);
    const int want = select_at(&sync, rs, &far);
    assert_true(sync.wide_renderer == rs && sync.wide_factor > 1);
    assert_int_equal(select_at(&as, ra, &near), before);
    assert_int_equal(select_at(&as, ra, &far), before);
    assert_true(ht_lod_chain_pending(&as));
    assert_null(as.wide_renderer);
    ht_lod_chain_wait(&as);
    assert_int_equal(select_at(&as, ra, &far), want);
    assert_true(as.wide_renderer == ra && as.wide_factor == sync.wide_factor);
    assert_same_image(rs, ra, &far);
    ht_lod_chain_free(&as);
    ht_lod_chain_free(&sync);
    ht_renderer_destroy(rs);
    ht_renderer_destroy(ra);
}

/* The index upload of a finished sort fails (the GL fault layer: a GL
   error, after which the renderer holds no mesh): the select returns -1
   with the error and the chain says r holds nothing of it and draws no
   level; the next select uploads `all` and draws the level as built
   while it is sorted again, then the synchronous chain's frame. */
static void failed_upload_forgets_the_mesh(void **state) {
    (void)state;
    view_h = SORT_VIEW;
    ht_renderer *rs = renderer(true), *ra = renderer(true);
    const float d = find_distance(rs, sorted, 0);
    ht_lod_chain sync, as;
    chain_make(&sync, true, false);
    chain_make(&as, true, true);
    const ht_frame_desc near = ht_test_furball_orbit_frame(3, 0), far = ht_test_furball_orbit_frame(d, 0);
    select_at(&sync, rs, &near);
    const int want = select_at(&sync, rs, &far);
    select_at(&as, ra, &near);
    assert_int_equal(select_at(&as, ra, &far), 0);
    ht_lod_chain_wait(&as);
    ht_fault_arm(HT_FAULT_BUFFER_DATA, 1);
    ht_result res = HT_OK;
    assert_int_equal(ht_lod_chain_select(&as, ra, &far.camera, view_h, &res), -1);
    assert_true(ht_fault_state_get()->fired);
    assert_int_not_equal(res, HT_OK);
    ht_fault_arm(HT_FAULT_NONE, 0);
    assert_int_equal(as.current, -1);
    assert_int_equal(as.ordered_level, -1);
    assert_null(as.uploaded);
    assert_null(as.job);
    assert_false(ht_lod_chain_pending(&as));
    assert_int_equal(select_at(&as, ra, &far), want);
    assert_true(ht_lod_chain_pending(&as));
    assert_ptr_equal(as.uploaded, ra);
    assert_int_equal(as.ordered_level, -1);
    assert_draws(ra, &far, as.first[want], as.index_count[want]);
    ht_lod_chain_wait(&as);
    assert_int_equal(select_at(&as, ra, &far), want);
    assert_int_equal(as.ordered_level, want);
    assert_same_image(rs, ra, &far);
    ht_lod_chain_free(&as);
    ht_lod_chain_free(&sync);
    ht_renderer_destroy(rs);
    ht_renderer_destroy(ra);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(switch_sorts_off_the_frame),
        cmocka_unit_test(superseded_jobs),
        cmocka_unit_test(widened_levels),
        cmocka_unit_test(failed_upload_forgets_the_mesh),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

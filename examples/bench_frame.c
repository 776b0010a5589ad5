/* bench_frame — the frame cost of each tier against the geometry floor,
   measured side by side in one run on the same context, and each tier's
   error against the full tier's image of that run:
   a scene (--scene, default the fur ball; its camera, lights, background
   and, for patches, the head), dark-brown, at 512 x 512 (--size), median of
   9 frames (--frames) after one warm-up; a fur ball gets 10 000 hairs x 16
   joints (--hairs). The floor is the same mesh drawn in the same four passes
   with a flat colour and no textures or shaders (ht_renderer_desc.flat).
   Prints the median frame time of each, the ratios tier / floor and
   tier / full, PSNR against full (shadergen/metrics.h, whole frame; on GL
   ES 1.1, which has no full tier, against the best tier that runs, and
   the CSV's columns against full are not numbers) and the
   per-vertex CPU work per frame (ht_renderer_get_stats), with the camera
   still and again with the eye orbiting the target by ORBIT_STEP every
   frame, as in a game (--no-orbit skips that); frames are taken
   round-robin. fixed4 and fixed run twice: exact, and as their device-only
   variant ("fixed4-device", "fixed-device"; hairtier.h ht_variant). --csv FILE also writes the rows (support_results.h) with
   series NAME (--series, default "matrix"), atomically.
   Run: make bench (build/bench_suite runs it per scene and driver).
   --context osmesa|egl and --egl-device N pick the GL context as hairview's
   do (platform/offscreen.h); --hairs goes to 1 000 000 (32 M vertices at
   16 joints: a real GPU's size, not llvmpipe's). --api gles2|gles3 times
   the GLSL tiers on a GL ES context ("full-gles2", "vertex-gles2", ...;
   the fixed tiers run on desktop GL and ES 1.1 only) beside the full tier on a desktop
   GL context of the same driver ("full", a second EGL context), frames
   round-robin across both: the ratios and errors are then against
   desktop full, the floor is ES's. --lods times (LOD,
   tier) pairs instead of the tiers (docs/lod.md): full detail in the full
   tier, then levels 1 and 2 of the mesh (lod.h's ladder) in full, fixed4
   and gl11, each against full detail's image, and names the pair
   error:30 would pick among them (the cheapest at >= 30 dB); --soft draws
   those levels soft (lod.h), --width-rule with the width rule where their
   strands are under a pixel (full detail stays the plain reference);
   --truth measures every contender against the 16x truth instead
   (measure_lod.h's, drawn once in this run) and adds full detail drawn
   with the width rule ("full-rule", the full detail thin strands ship as),
   the error pick naming its cost against both full details;
   --samples N draws every contender multisampled. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "file_atomic.h"
#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "flip.h"
#include "measure_lod.h"
#include "metrics.h"
#include "offscreen.h"
#include <hairtier/scene.h>
#include "bench/support_results.h"
#include "tempdir.h"
#include "timing.h"
#include "view_args.h"

#define MAX_FRAMES 64
#define MAX_CONTENDERS 12
#define ORBIT_STEP 0.0175f /* radians a frame: one degree */

static int WIDTH = 512, HEIGHT = 512, FRAMES = 9, HAIRS = 10000;
#define MAX_HAIRS 1000000

static bool HAIRS_GIVEN = false, ORBIT = true, LODS = false, WIDTH_RULE = false, TRUTH = false;
static int SAMPLES = 0;
static float SOFT = 0.0f; /* --soft's factor, 0: plain levels */
static offscreen_kind CONTEXT = OFFSCREEN_AUTO;
static int EGL_DEVICE = -1;
static offscreen_api API = OFFSCREEN_API_GL;
static offscreen *gl;   /* the context every contender draws in, but ... */
static offscreen *desk; /* ... desktop full's in a GL ES run (NULL otherwise) */
static const char *SCENE = "scenes/furball.json", *CSV = NULL, *SERIES = "matrix";

static void quiet(void *user, const char *line) { (void)user, (void)line; }

typedef struct contender {
    const char *name;        /* as printed */
    const char *tier;        /* as recorded: "floor", "full", ... */
    ht_renderer *renderer;   /* NULL: the tier does not run here */
    offscreen *context;      /* where it draws: gl or desk */
    double samples[MAX_FRAMES], orbit_samples[MAX_FRAMES];
    uint64_t cpu_still, cpu_orbit;   /* per-vertex CPU work over the timed frames */
    unsigned char *image;    /* the last timed frame, GL rows; what the metrics compare */
    ht_metrics whole, hair;  /* against full's image */
    ht_flip_result flip;     /* the same, LDR-FLIP */
} contender;

/* What every frame of the run draws: the scene's view, lights and head. */
typedef struct stage {
    const ht_scene *scene;
    const ht_mesh *head;     /* NULL: none */
} stage;

static ht_frame_desc frame_of(const stage *st) {
    const ht_scene *s = st->scene;
    return (ht_frame_desc){ .camera = s->camera, .lights = s->lights, .light_count = s->light_count,
                            .aspect = (float)WIDTH / (float)HEIGHT, .opaque = st->head };
}

static void clear(offscreen *o, const ht_scene *s) {
    o->gl.ClearColor(s->background[0], s->background[1], s->background[2], 1.0f);
    o->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

/* NULL when the tier does not run here (or, for HT_VARIANT_DEVICE, has no
   device-only variant for this bundle). */
static ht_renderer *create(const char *bundle, ht_tier tier, bool flat, ht_variant variant, const ht_mesh *mesh) {
    if (!mesh) return NULL; /* a LOD this mesh does not have */
    ht_renderer *r = NULL;
    if (ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = bundle, .tier = tier,
                                                .strict = true, .flat = flat, .log = quiet,
                                                .variant = variant ? variant : HT_VARIANT_EXACT }, &r) != HT_OK)
        return NULL;
    if (variant == HT_VARIANT_DEVICE && ht_renderer_variant(r) != HT_VARIANT_DEVICE) {
        ht_renderer_destroy(r);
        return NULL;
    }
    if (ht_renderer_set_mesh(r, mesh) != HT_OK) {
        ht_renderer_destroy(r);
        return NULL;
    }
    return r;
}

/* Frame i of a run: the scene's view, or with orbit the eye turned round
   the target's vertical by ORBIT_STEP more each frame (the warm-up, i = -1,
   too: every timed frame has an eye its tier has not seen). */
static ht_frame_desc run_frame(const stage *st, int i, bool orbit) {
    ht_frame_desc frame = frame_of(st);
    if (!orbit) return frame;
    const float *t = frame.camera.target, a = ORBIT_STEP * (float)(i + 2);
    const float x = frame.camera.eye[0] - t[0], z = frame.camera.eye[2] - t[2];
    frame.camera.eye[0] = t[0] + x * cosf(a) - z * sinf(a);
    frame.camera.eye[2] = t[2] + x * sinf(a) + z * cosf(a);
    return frame;
}

/* Frames are taken round-robin (floor, full, vertex, fixed, floor, ...), so
   a change in machine load during the run falls on every contender alike.
   Still frames keep the last one's image (what the metrics compare). */
static bool time_round_robin(contender *c, int count, const stage *st, bool orbit) {
    uint64_t before[MAX_CONTENDERS] = { 0 };
    for (int i = -1; i < FRAMES; i++) { /* frame -1 warms up */
        ht_frame_desc frame = run_frame(st, i, orbit);
        for (int k = 0; k < count; k++) {
            if (!c[k].renderer) continue;
            if (i == 0) before[k] = ht_renderer_get_stats(c[k].renderer).cpu_vertices;
            offscreen *o = c[k].context;
            if (desk && !offscreen_make_current(o)) return false;
            clear(o, st->scene);
            double t0 = now_ms();
            if (ht_renderer_draw(c[k].renderer, &frame) != HT_OK) return false;
            o->gl.Finish();
            if (i >= 0) (orbit ? c[k].orbit_samples : c[k].samples)[i] = now_ms() - t0;
            if (i == FRAMES - 1 && !orbit) memcpy(c[k].image, offscreen_read(o), (size_t)WIDTH * HEIGHT * 4);
        }
    }
    for (int k = 0; k < count; k++) {
        if (!c[k].renderer) continue;
        uint64_t n = ht_renderer_get_stats(c[k].renderer).cpu_vertices - before[k];
        if (orbit) c[k].cpu_orbit = n;
        else c[k].cpu_still = n;
    }
    return true;
}

/* The contender the others are measured against: full, or where it does
   not run (GL ES 1.1: no shaders) the best tier that does. */
static int REF = 1;
/* The image every error is against: REF's, or with --truth the 16x truth. */
static unsigned char *truth_image;
static const unsigned char *reference_image(const contender *c) { return truth_image ? truth_image : c[REF].image; }

/* Each tier's error against the reference's image of this run. */
static bool measure_errors(contender *c, int count) {
    char err[256];
    for (int k = 0; k < count; k++) {
        if (!c[k].renderer) continue;
        if (ht_metrics_compare(&(ht_metrics_desc){ .reference = reference_image(c), .test = c[k].image, .width = WIDTH,
                                                   .height = HEIGHT },
                               &c[k].whole, &c[k].hair, err, sizeof err) != HT_OK ||
            ht_flip_compare(&(ht_flip_desc){ .reference = reference_image(c), .test = c[k].image, .width = WIDTH,
                                             .height = HEIGHT },
                            NULL, &c[k].flip, err, sizeof err) != HT_OK) {
            fprintf(stderr, "bench_frame: %s: %s\n", c[k].name, err);
            return false;
        }
    }
    return true;
}

/* "scenes/furball.json" -> "furball". */
static void scene_name(const char *path, char *out, size_t size) {
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t n = strcspn(base, ".");
    snprintf(out, size, "%.*s", (int)n, base);
}

/* The median of c's timed frames (its samples stay in frame order). */
static double median_ms(const contender *c) {
    double samples[MAX_FRAMES];
    memcpy(samples, c->samples, sizeof samples);
    return median(samples, FRAMES);
}

static double median_orbit_ms(const contender *c) {
    double samples[MAX_FRAMES];
    memcpy(samples, c->orbit_samples, sizeof samples);
    return median(samples, FRAMES);
}

static bool write_rows(FILE *f, void *rows, char *why, size_t why_size) {
    (void)why, (void)why_size;
    return bench_rows_write_csv(f, rows);
}

/* The run's rows, in the benchmark's CSV (support_results.h). */
static bool write_csv(const contender *c, int count, const ht_scene *scene, uint32_t triangles) {
    bench_rows rows = { 0 };
    const double floor_ms = median_ms(&c[0]), full_ms = median_ms(&c[1]);
    /* Columns against full: not a number where full did not run. */
    const bool full = REF == 1;
    bool ok = true;
    for (int k = 0; k < count && ok; k++) {
        bench_row *r = bench_rows_add(&rows);
        if (!r) {
            ok = false;
            break;
        }
        snprintf(r->series, sizeof r->series, "%s", SERIES);
        scene_name(SCENE, r->scene, sizeof r->scene);
        const char *renderer = (const char *)gl->gl.GetString(GL_RENDERER);
        snprintf(r->renderer, sizeof r->renderer, "%s", renderer ? renderer : "unknown");
        snprintf(r->driver, sizeof r->driver, "%.*s", (int)strcspn(r->renderer, " "), r->renderer);
        r->hairs = scene->geometry == HT_GEOMETRY_FURBALL ? HAIRS : -1;
        r->triangles = triangles, r->width = WIDTH, r->height = HEIGHT, r->frames = FRAMES;
        snprintf(r->tier, sizeof r->tier, "%s", c[k].tier);
        r->ran = c[k].renderer != NULL;
        if (!r->ran) continue;
        r->median_ms = median_ms(&c[k]);
        r->per_floor = r->median_ms / floor_ms;
        r->per_full = full ? r->median_ms / full_ms : NAN;
        r->whole = c[k].whole, r->hair = c[k].hair;
        r->flip_mean = c[k].flip.mean, r->flip_p95 = c[k].flip.p95;
        if (!full) {
            r->whole.psnr_db = r->whole.ssim = r->whole.delta_e00_mean = r->whole.delta_e00_p95 = NAN;
            r->hair.psnr_db = r->hair.ssim = r->hair.delta_e00_mean = r->hair.delta_e00_p95 = NAN;
            r->flip_mean = r->flip_p95 = NAN;
        }
        r->cpu_still = (double)c[k].cpu_still / FRAMES;
        r->cpu_orbit = ORBIT ? (double)c[k].cpu_orbit / FRAMES : NAN;
        r->orbit_ms = ORBIT ? median_orbit_ms(&c[k]) : NAN;
        r->orbit_per_full = ORBIT && full ? r->orbit_ms / median_orbit_ms(&c[1]) : NAN;
    }
    char err[512] = "out of memory";
    if (ok) ok = ht_file_write_atomic(CSV, write_rows, &rows, err, sizeof err) == HT_OK;
    if (!ok) fprintf(stderr, "bench_frame: %s\n", err);
    bench_rows_free(&rows);
    return ok;
}

static void print_table(const contender *c, int count) {
    const double floor_ms = median_ms(&c[0]), full_ms = median_ms(&c[REF]);
    const double full_orbit = ORBIT ? median_orbit_ms(&c[REF]) : NAN;
    char per_ref[16], vs_ref[16];
    snprintf(per_ref, sizeof per_ref, "/ %.6s", c[REF].name);
    snprintf(vs_ref, sizeof vs_ref, "vs %.6s", truth_image ? "truth" : c[REF].name);
    printf("  %-14s %31s %21s %22s %9s %9s\n", "", "camera still", "eye orbiting", "CPU vertices per frame",
           "PSNR dB", "FLIP");
    printf("  %-14s %9s %10s %10s %10s %10s %11s %10s %9s %9s\n", "", "median", "/ floor", per_ref, "median", per_ref,
           "still", "orbiting", vs_ref, "mean");
    for (int k = 0; k < count; k++) {
        if (!c[k].renderer) {
            printf("  %-14s       n/a (does not run here)\n", c[k].name);
            continue;
        }
        double ms = median_ms(&c[k]);
        char orbit[32] = "-", orbit_ms[32] = "-", orbit_ratio[32] = "-";
        if (ORBIT) {
            double oms = median_orbit_ms(&c[k]);
            snprintf(orbit, sizeof orbit, "%.0f", (double)c[k].cpu_orbit / FRAMES);
            snprintf(orbit_ms, sizeof orbit_ms, "%.2f ms", oms);
            snprintf(orbit_ratio, sizeof orbit_ratio, "%.2fx", oms / full_orbit);
        }
        printf("  %-14s %8.2f ms %9.2fx %9.2fx %10s %10s %11.0f %10s %9.1f %9.4f\n", c[k].name, ms, ms / floor_ms,
               ms / full_ms, orbit_ms, orbit_ratio, (double)c[k].cpu_still / FRAMES, orbit, c[k].whole.psnr_db,
               c[k].flip.mean);
    }
}

/* --lods: the pair error:DB would pick among this run's contenders (the
   cheapest whose PSNR against the reference, full detail in full or the
   truth, is at least db), as the runtime's rule does over measured cells;
   with the truth, its cost against full-rule (the last contender) too. */
static void print_error_pick(const contender *c, int count, double db) {
    const double ref_ms = median_ms(&c[REF]);
    int pick = -1;
    for (int k = 1; k < count; k++)
        if (c[k].renderer && c[k].whole.psnr_db >= db && (pick < 0 || median_ms(&c[k]) < median_ms(&c[pick])))
            pick = k;
    if (pick < 0) {
        printf("error:%g picks none of these pairs\n", db);
        return;
    }
    printf("error:%g picks %s: %.2fx %s's cost", db, c[pick].name, median_ms(&c[pick]) / ref_ms, c[REF].name);
    if (truth_image && c[count - 1].renderer)
        printf(", %.2fx %s's", median_ms(&c[pick]) / median_ms(&c[count - 1]), c[count - 1].name);
    printf(", %.1f dB%s\n", c[pick].whole.psnr_db, truth_image ? " against the truth" : "");
}

/* --lods: the pop of each switch, PSNR between a level and the level
   before in its tier (level 1's: full detail, full-rule with the truth). */
static void print_pops(const contender *c, int count) {
    const int zero = truth_image && c[count - 1].renderer ? count - 1 : REF;
    printf("pop dB (a level against the one before, level 1 against %s):", c[zero].name);
    for (int k = 1; k < count; k++) {
        int level;
        char tier[16], before[32];
        if (!c[k].renderer || sscanf(c[k].name, "lod%d-%15s", &level, tier) != 2) continue;
        snprintf(before, sizeof before, "lod%d-%s", level - 1, tier);
        int b = level == 1 ? zero : -1;
        for (int j = 1; j < count && b < 0; j++)
            if (c[j].renderer && strcmp(c[j].name, before) == 0) b = j;
        ht_metrics pop;
        char err[256];
        if (b < 0 || ht_metrics_compare(&(ht_metrics_desc){ .reference = c[b].image, .test = c[k].image,
                                                            .width = WIDTH, .height = HEIGHT },
                                        &pop, NULL, err, sizeof err) != HT_OK)
            continue;
        printf(" %s %d>%d %.1f", tier, level, level - 1, pop.psnr_db);
    }
    printf("\n");
}

/* A mesh drawn as ht_lod_chain draws a level with width_rule set where its
   strands are under a pixel: the factor, and above 1 *wide its widened
   copy and *opacity the rule's; 1 (*wide zeroed) where nothing changes. */
static double width_rule(const ht_mesh *m, const ht_scene *scene, ht_mesh *wide, float *opacity) {
    double f = 1.0;
    *wide = (ht_mesh){ 0 };
    if (!m->vertices ||
        ht_mesh_width_rule(m, ht_mesh_projected_width_px(m, &scene->camera, HEIGHT), SAMPLES, scene->camera.eye, wide,
                           &f) != HT_OK ||
        !(f > 1.0)) {
        ht_mesh_free(wide);
        return 1.0;
    }
    *opacity = (float)(1.0 / f);
    return f;
}

/* --truth: the 16x truth of the run's full detail into truth_image, in a
   context of its own, the run's made current again. */
static char truth_error[1024];
static bool draw_truth(const char *dir, const ht_scene *scene, const stage *st, const ht_mesh *mesh) {
    const ht_frame_desc frame = frame_of(st);
    truth_image = malloc((size_t)WIDTH * HEIGHT * 4);
    bool ok = truth_image &&
              ht_measure_truth(&(ht_measure_truth_desc){ .bundle_dir = dir, .tier = HT_TIER_FULL, .width = WIDTH,
                                                         .height = HEIGHT, .context = CONTEXT, .egl_device = EGL_DEVICE,
                                                         .background = { scene->background[0], scene->background[1],
                                                                         scene->background[2] },
                                                         .frame = &frame, .mesh = mesh },
                               truth_image, truth_error, sizeof truth_error) == HT_OK;
    if (!truth_image) snprintf(truth_error, sizeof truth_error, "out of memory");
    if (!offscreen_make_current(gl)) ok = false;
    if (!ok) {
        free(truth_image);
        truth_image = NULL;
    }
    return ok;
}

/* Everything but the scratch directory, which main removes whatever this
   returns. */
static int run(const char *work) {
    char err[2048];
    char dir[128];
    snprintf(dir, sizeof dir, "%s/bundle", work);
    ht_scene scene;
    if (ht_scene_load(SCENE, &scene, err, sizeof err) != HT_OK ||
        ht_generate_bundle("materials/dark-brown.json", SCENE, dir, NULL, err, sizeof err) != HT_OK) {
        fprintf(stderr, "bench_frame: %s\n", err);
        return 1;
    }
    if (HAIRS_GIVEN && scene.geometry != HT_GEOMETRY_FURBALL) {
        fprintf(stderr, "bench_frame: --hairs: %s is not a fur-ball scene\n", SCENE);
        return 2;
    }

    gl = offscreen_open(&(offscreen_desc){ .kind = CONTEXT, .width = WIDTH, .height = HEIGHT,
                                           .egl_device = EGL_DEVICE, .api = API, .samples = SAMPLES },
                        err, sizeof err);
    if (!gl) {
        fprintf(stderr, "bench_frame: %s\n", err);
        return 1;
    }

    int status = 1;
    ht_mesh mesh = { 0 }, head = { 0 };
    if (scene.geometry == HT_GEOMETRY_FURBALL) {
        scene.furball.hairs = HAIRS;
        scene.furball.joints = 16;
    }
    if (ht_scene_build_meshes(&scene, SCENE, &mesh, &head, err, sizeof err) != HT_OK) {
        fprintf(stderr, "bench_frame: %s\n", err);
        goto close_context;
    }

    if (scene.geometry == HT_GEOMETRY_FURBALL)
        printf("fur ball %d hairs x %d joints (%u triangles)", scene.furball.hairs, scene.furball.joints,
               mesh.index_count / 3);
    else if (scene.geometry == HT_GEOMETRY_PATCHES)
        printf("%s: patches %d layers x %d strips x %d segments (%u triangles) on a head", SCENE,
               scene.patches.layers, scene.patches.strips, scene.patches.segments, mesh.index_count / 3);
    else
        printf("%s: strands (%u triangles)%s", SCENE, mesh.index_count / 3, head.index_count ? " on a head" : "");
    printf(", %dx%d, %s (%s), median of %d frames\n", WIDTH, HEIGHT, (const char *)gl->gl.GetString(GL_RENDERER),
           gl->display, FRAMES);
    /* Best first, as the bundle lists them; a tier this build lacks is skipped. */
    typedef struct run_desc { const char *name, *tier; ht_variant variant; int lod; } run_desc; /* lod 3: full, ruled */
    static const run_desc tier_runs[] = {
        { "full", "full", HT_VARIANT_EXACT, 0 },     { "vertex", "vertex", HT_VARIANT_EXACT, 0 },
        { "fixed4", "fixed4", HT_VARIANT_EXACT, 0 }, { "fixed4-device", "fixed4", HT_VARIANT_DEVICE, 0 },
        { "fixed", "fixed", HT_VARIANT_EXACT, 0 },   { "fixed-device", "fixed", HT_VARIANT_DEVICE, 0 },
        { "gl11", "gl11", HT_VARIANT_EXACT, 0 },
    };
    /* --lods: (LOD, tier) pairs beside full detail (the same contender slots). */
    static const run_desc lod_runs[] = {
        { "full", "full", HT_VARIANT_EXACT, 0 },        { "lod1-full", "full", HT_VARIANT_EXACT, 1 },
        { "lod2-full", "full", HT_VARIANT_EXACT, 2 },   { "lod1-fixed4", "fixed4", HT_VARIANT_EXACT, 1 },
        { "lod2-fixed4", "fixed4", HT_VARIANT_EXACT, 2 }, { "lod1-gl11", "gl11", HT_VARIANT_EXACT, 1 },
        { "lod2-gl11", "gl11", HT_VARIANT_EXACT, 2 },     { "full-rule", "full", HT_VARIANT_EXACT, 3 },
    };
    enum { TIER_RUNS = sizeof tier_runs / sizeof tier_runs[0], LOD_RUNS = sizeof lod_runs / sizeof lod_runs[0] };
    _Static_assert(TIER_RUNS + 1 <= MAX_CONTENDERS && LOD_RUNS + 1 <= MAX_CONTENDERS, "MAX_CONTENDERS");
    const run_desc *runs = LODS ? lod_runs : tier_runs;
    const int TIERS = !LODS ? TIER_RUNS : TRUTH ? LOD_RUNS : LOD_RUNS - 1; /* full-rule with --truth only */
    ht_mesh lods[4] = { { 0 } }; /* [1], [2]: the levels --lods draws; [3]: full detail with the rule */
    float opacity[4] = { 1.0f, 1.0f, 1.0f, 1.0f }; /* theirs: ht_lod_opacity, or the width rule's */
    for (int l = 1; LODS && l < 3 && l <= ht_lod_max_level(&mesh); l++) {
        ht_lod_desc d;
        ht_lod_level(l, &d);
        d.soften = SOFT;
        if (ht_mesh_build_lod(&mesh, &d, &lods[l]) != HT_OK) fprintf(stderr, "bench_frame: LOD %d: not built\n", l);
        else if (d.soften > 1) ht_mesh_sort_back_to_front(&lods[l], scene.camera.eye); /* lod.h's soft levels */
        opacity[l] = ht_lod_opacity(&d);
        ht_mesh wide;
        const double f = WIDTH_RULE ? width_rule(&lods[l], &scene, &wide, &opacity[l]) : 1.0;
        if (f > 1.0) {
            ht_mesh_free(&lods[l]);
            lods[l] = wide;
            printf("level %d: width rule %.3f, opacity %.3f\n", l, f, 1.0 / f);
        }
    }
    if (TRUTH) {
        const double f = width_rule(&mesh, &scene, &lods[3], &opacity[3]);
        /* strands a pixel wide or more: full detail as it is (a copy) */
        if (f > 1.0 || ht_mesh_widen(&mesh, 1.0, &lods[3]) == HT_OK)
            printf("full-rule: width rule %.3f, opacity %.3f\n", f, 1.0 / f);
    }
    contender c[MAX_CONTENDERS] = { { .name = "geometry floor", .tier = "floor", .context = gl,
                                 .renderer = create(dir, HT_TIER_AUTO, true, HT_VARIANT_EXACT, &mesh) } };
    int count = TIERS + 1;
    if (API == OFFSCREEN_API_GL || API == OFFSCREEN_API_GLES1) {
        for (int k = 0; k < TIERS; k++) {
            ht_tier t = ht_tier_from_name(runs[k].tier);
            const ht_mesh *m = runs[k].lod == 0 ? &mesh : lods[runs[k].lod].vertices ? &lods[runs[k].lod] : NULL;
            c[k + 1] = (contender){ .name = runs[k].name, .tier = runs[k].name, .context = gl,
                                    .renderer = t == HT_TIER_COUNT ? NULL : create(dir, t, false, runs[k].variant, m) };
            if (c[k + 1].renderer && runs[k].lod > 0 && ht_renderer_set_opacity_scale(c[k + 1].renderer, opacity[runs[k].lod]) != HT_OK) {
                ht_renderer_destroy(c[k + 1].renderer);
                c[k + 1].renderer = NULL;
            }
        }
    } else {
        /* floor, desktop full, then the GLSL tiers on ES ("full-gles2", ...) */
        static char names[2][32];
        for (int k = 0; k < 2; k++) {
            snprintf(names[k], sizeof names[k], "%s-%s", tier_runs[k].tier, offscreen_api_name(API));
            c[k + 2] = (contender){ .name = names[k], .tier = names[k], .context = gl,
                                    .renderer = create(dir, ht_tier_from_name(tier_runs[k].tier), false, HT_VARIANT_EXACT,
                                                       &mesh) };
        }
        count = 4;
        desk = offscreen_open(&(offscreen_desc){ .kind = OFFSCREEN_EGL, .width = WIDTH, .height = HEIGHT,
                                                 .egl_device = EGL_DEVICE, .api = OFFSCREEN_API_GL }, err, sizeof err);
        if (!desk) fprintf(stderr, "bench_frame: desktop GL beside GL ES: %s\n", err);
        c[1] = (contender){ .name = "full-gl", .tier = "full", .context = desk,
                            .renderer = desk ? create(dir, HT_TIER_FULL, false, HT_VARIANT_EXACT, &mesh) : NULL };
        if (!offscreen_make_current(gl)) c[1].renderer = NULL;
    }
    bool images = true;
    for (int k = 0; k < count; k++)
        if (c[k].renderer && !(c[k].image = malloc((size_t)WIDTH * HEIGHT * 4))) images = false;
    stage st = { &scene, head.index_count ? &head : NULL };
    for (REF = 1; REF < count - 1 && !c[REF].renderer; REF++) {}
    if (!images) {
        fprintf(stderr, "bench_frame: out of memory for the tiers' images\n");
    } else if (!c[0].renderer || !c[REF].renderer || !time_round_robin(c, count, &st, false) ||
               (ORBIT && !time_round_robin(c, count, &st, true))) {
        fprintf(stderr, "bench_frame: the geometry floor or every tier failed to render\n");
    } else if (TRUTH && !draw_truth(dir, &scene, &st, &mesh)) {
        fprintf(stderr, "bench_frame: the truth: %s\n", truth_error);
    } else if (measure_errors(c, count)) {
        print_table(c, count);
        if (LODS) print_pops(c, count);
        if (LODS) print_error_pick(c, count, 30.0);
        status = CSV && !write_csv(c, count, &scene, mesh.index_count / 3) ? 1 : 0;
    }
    for (int k = 0; k < count; k++) {
        if (c[k].renderer) {
            if (desk) offscreen_make_current(c[k].context);
            ht_renderer_destroy(c[k].renderer);
        }
        free(c[k].image);
    }
    if (desk) {
        offscreen_close(desk);
        desk = NULL;
        offscreen_make_current(gl);
    }
    for (int l = 0; l < 4; l++) ht_mesh_free(&lods[l]);
    free(truth_image);
    truth_image = NULL;
close_context:
    ht_mesh_free(&mesh);
    ht_mesh_free(&head);
    offscreen_close(gl);
    gl = NULL;
    return status;
}

enum { KEY_HAIRS = CLI_LONG_ONLY, KEY_FRAMES, KEY_SCENE, KEY_CSV, KEY_SERIES, KEY_EGL_DEVICE, KEY_CONTEXT, KEY_API,
       KEY_NO_ORBIT, KEY_SIZE, KEY_LODS, KEY_SAMPLES, KEY_SOFT, KEY_WIDTH_RULE, KEY_TRUTH };
static const struct option long_options[] = {
    { "hairs", required_argument, NULL, KEY_HAIRS },
    { "frames", required_argument, NULL, KEY_FRAMES },
    { "scene", required_argument, NULL, KEY_SCENE },
    { "csv", required_argument, NULL, KEY_CSV },
    { "series", required_argument, NULL, KEY_SERIES },
    { "egl-device", required_argument, NULL, KEY_EGL_DEVICE },
    { "context", required_argument, NULL, KEY_CONTEXT },
    { "api", required_argument, NULL, KEY_API },
    { "no-orbit", no_argument, NULL, KEY_NO_ORBIT },
    { "size", required_argument, NULL, KEY_SIZE },
    { "lods", no_argument, NULL, KEY_LODS },
    { "soft", optional_argument, NULL, KEY_SOFT },
    { "width-rule", no_argument, NULL, KEY_WIDTH_RULE },
    { "truth", no_argument, NULL, KEY_TRUTH },
    { "samples", required_argument, NULL, KEY_SAMPLES },
    { 0 },
};

static const cli_program program = {
    .name = "bench_frame",
    .synopsis = "usage: bench_frame [--scene SCENE.json] [--hairs N] [--size S] [--frames F] [--no-orbit]\n"
                "                   [--csv FILE [--series NAME]] [--context osmesa|egl] [--egl-device N]\n"
                "                   [--api gl|gles1|gles2|gles3] [--lods [--soft[=F]] [--width-rule] [--truth]] [--samples N]\n",
    .help = "Times every tier of dark-brown against the geometry floor on one context, frames round-robin:\n"
            "median frame ms, the ratios to the floor and to full, PSNR against full and the per-vertex CPU\n"
            "work, with the camera still and orbiting (--no-orbit skips that).\n"
            "  --scene FILE   default scenes/furball.json\n"
            "  --hairs N      a fur ball's hairs, 1.." CLI_STR(MAX_HAIRS) " (default 10000)\n"
            "  --size S       16..4096 pixels a side (default 512)\n"
            "  --frames F     timed frames, 1.." CLI_STR(MAX_FRAMES) " (default 9)\n"
            "  --csv FILE     also write the rows, series NAME (--series, default matrix)\n"
            "  --context K    osmesa or egl; --egl-device N: EGL device N\n"
            "  --api A        gl (default), gles1, gles2 or gles3: a GL ES context (EGL); on gles2 and\n"
            "                 gles3 the GLSL tiers beside full on desktop GL (a second EGL context)\n"
            "  --lods         (LOD, tier) pairs instead of the tiers: full detail, levels 1 and 2 in full,\n"
            "                 fixed4 and gl11 (docs/lod.md), and the pair error:30 picks among them\n"
            "  --soft[=F]     with --lods, levels 1 and 2 soft (lod.h: F, default 3, times wider at 1/F\n"
            "                 the opacity, sorted back to front for the scene's eye)\n"
            "  --width-rule   with --lods, a level whose strands are under a pixel drawn as the runtime's\n"
            "                 width rule draws it (lod.h: about a pixel wide, opacity scaled); full\n"
            "                 detail, the reference, as it is\n"
            "  --truth        with --lods, every PSNR against the 16x truth (full detail drawn at 4 x 4 the\n"
            "                 pixels, box-filtered), and full detail with the width rule beside (full-rule)\n"
            "  --samples N    a multisampled framebuffer, 2..32 samples (GL 3.0)\n",
    .long_options = long_options,
};

/* value as an integer in lo..hi into *out: NULL, or why not. */
static const char *number(const char *name, const char *value, int lo, int hi, int *out) {
    static char message[96];
    char *end;
    long n = strtol(value, &end, 10);
    if (end != value && !*end && n >= lo && n <= hi) {
        *out = (int)n;
        return NULL;
    }
    snprintf(message, sizeof message, "%s: expected a number in [%d, %d]", name, lo, hi);
    return message;
}

/* A text value: NULL, or why not (empty). */
static const char *text(const char *name, const char *value, const char **out) {
    static char message[64];
    *out = value;
    if (value[0]) return NULL;
    snprintf(message, sizeof message, "%s: empty value", name);
    return message;
}

static const char *take(void *user, int key, const char *value) {
    (void)user;
    int size = 0;
    const char *why;
    switch (key) {
    case KEY_HAIRS: HAIRS_GIVEN = true; return number("--hairs", value, 1, MAX_HAIRS, &HAIRS);
    case KEY_FRAMES: return number("--frames", value, 1, MAX_FRAMES, &FRAMES);
    case KEY_SCENE: return text("--scene", value, &SCENE);
    case KEY_CSV: return text("--csv", value, &CSV);
    case KEY_SERIES: return text("--series", value, &SERIES);
    case KEY_EGL_DEVICE: return offscreen_device_value(value, &EGL_DEVICE);
    case KEY_CONTEXT: return offscreen_context_value(value, &CONTEXT);
    case KEY_API: return offscreen_api_value(value, &API);
    case KEY_NO_ORBIT: ORBIT = false; return NULL;
    case KEY_LODS: LODS = true; return NULL;
    case KEY_SOFT: return view_args_soften(value, &SOFT);
    case KEY_WIDTH_RULE: WIDTH_RULE = true; return NULL;
    case KEY_TRUTH: TRUTH = true; return NULL;
    case KEY_SAMPLES: return number("--samples", value, 2, 32, &SAMPLES);
    case KEY_SIZE:
        if ((why = number("--size", value, 16, 4096, &size))) return why;
        WIDTH = HEIGHT = size;
        return NULL;
    default: return cli_unexpected(value);
    }
}

int main(int argc, char **argv) {
    int rc = cli_parse(&program, argc, argv, take, NULL);
    if (rc != CLI_RUN) return rc;
    const char *why = NULL;
    if (!offscreen_options_check(&CONTEXT, EGL_DEVICE, &why) || !offscreen_api_check(&CONTEXT, API, &why))
        return cli_usage_error(&program, why);
    if (TRUTH && (!LODS || API != OFFSCREEN_API_GL))
        return cli_usage_error(&program, "--truth: with --lods on desktop GL only");
    char work[] = "/tmp/hairtier-bench-frame-XXXXXX";
    if (!mkdtemp(work)) {
        perror("mkdtemp");
        return 1;
    }
    int status = run(work);
    if (tempdir_remove(work) != 0) {
        fprintf(stderr, "bench_frame: cannot remove %s\n", work);
        status = 1;
    }
    return status;
}

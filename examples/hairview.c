/* hairview — renders a scene with a hairgen bundle offscreen (OSMesa or
   EGL) and writes a PNG.

   build/hairview --bundle DIR --scene SCENE.json [--tier auto|marschner|full|vertex|fixed4|fixed|gl11]
                  [--policy best|fastest|error:DB|error:flip:E|frame:MS] [--strict] [--flat] [--frames N]
                  [--lod auto|N | --cards] [--size F] [--distance D] [--samples N] [--supersample K]
                  [--width-rule[=vertex|draw|off]] [--soft[=F]] [--lod-async] [--context osmesa|egl] [--egl-device N]
                  [--api gl|gles1|gles2|gles3] [--device-profile NAME] -o OUT.png

   --api gles1|gles2|gles3 draws on a GL ES context (EGL); --device-profile NAME
   caps what the runtime may use to a named device's (hairtier.h, e.g.
   mali400), on that device's API unless --api says otherwise.
   --lod picks the geometry level (lod.h; auto: full detail while a strand
   is at least a pixel wide) and prints `lod=N strands=K strand_px=W`
   first; --size and --distance shrink the hair on screen (--distance A:B
   dollies the eye over the frames through one ht_lod_chain, re-picking
   the (level, tier) pair every frame and printing `lod_pair: frame=F ...`
   at each switch); --samples
   multisamples (platform/offscreen_msaa.c); --supersample K draws K x K
   times the pixels and box-filters them down (a reference; docs/lod.md);
   --width-rule draws a strand under a pixel (at the pixels drawn) about a
   pixel wide with its opacity scaled by the ratio, blended far to near (lod.h):
   per vertex where the tier can, else (and with =draw) per draw. Without
   it, a pair picked from cells measured with the rule (hairgen
   --lod-reference supersample) is drawn with it per draw, as measured
   (prints width_rule=from-cells; =off: never). --lod-async turns the
   dolly's chain asynchronous (lod.h, chain.async): a level's sort or
   widened copy on a thread, the level before drawn until it is done.
   --context picks how the GL context is made (platform/offscreen.h; default
   HAIRTIER_CONTEXT, else osmesa where libOSMesa loads, else egl);
   --egl-device N draws on EGL device N (EGL_EXT_platform_device) and implies
   --context egl. A context that cannot be made is one line and exit 1.

   Prints `tier=NAME reason=...` then `frame_ms=...` (the mean of N timed
   frames after a warm-up, one frame or on a GPU 250 ms of them, each ended
   by glFinish) on stdout; every skipped
   tier's reason goes to stderr. On any failure: one line naming the file or
   field on stderr, exit status 1, and no PNG. HAIRTIER_TIER is honoured
   unless --tier is given, HAIRTIER_POLICY unless --policy is. With
   frame:MS the scene's mesh and frame are timed on every tier the device
   runs (ht_renderer_choose_by_frame_time) before the timed frames. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hairtier/scene.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include <hairtier/lod.h>
#include <math.h>
#include "offscreen.h"
#include "cli.h"
#include "view_args.h"
#include "compare/grid_levels.h"
#include "timing.h"

typedef struct options {
    view_args view;       /* --bundle, --scene, -o, --frames, the context */
    ht_tier tier;
    const char *policy;   /* NULL → HAIRTIER_POLICY */
    bool strict, flat;
    ht_device_profile profile; /* --device-profile; zero → HAIRTIER_DEVICE_PROFILE */
    int lod;              /* -1: auto (lod.h's best rule); else the level */
    double size;          /* the image's size / the scene's, (0, 4] */
    double distance;      /* 0: the scene's camera; else the eye this far from the target */
    double distance_to;   /* --distance A:B: the eye dollied from A to B over the frames; 0: none */
    int samples;          /* 0: no multisampling; else the framebuffer's samples */
    int supersample;      /* 1; K: drawn K x K times larger, box-filtered down to the PNG */
    int width_rule;       /* lod.h's width rule on the mesh drawn: WIDTH_RULE_*, AUTO unless given */
    float soft;           /* 0; else --lod N draws the level soft by this factor (lod.h: widened, back to front) */
    bool cards;           /* the bundle's stored cards (hairgen --cards) instead of the strands */
    bool lod_async;       /* --lod-async: the dolly's chain.async */
} options;

/* The library's log: every line goes to stderr, one line late, so that
   when a call fails its last line (the error) is printed once, as
   hairview's error line, instead of twice. */
static char held[1024];

static void print_held(void) {
    if (held[0]) fprintf(stderr, "%s\n", held);
    held[0] = '\0';
}

static void log_line(void *user, const char *line) {
    (void)user;
    print_held();
    snprintf(held, sizeof held, "%s", line);
}

/* The failed call's error line: the library's last line without its
   prefix, else r's name. */
static int fail(ht_result r) {
    const char *prefix = "hairtier: ";
    const char *line = strncmp(held, prefix, strlen(prefix)) == 0 ? held + strlen(prefix) : held;
    fprintf(stderr, "hairview: %s\n", held[0] ? line : ht_result_string(r));
    held[0] = '\0';
    return 1;
}

enum { KEY_TIER = VIEW_KEY_END, KEY_POLICY, KEY_STRICT, KEY_FLAT, KEY_PROFILE, KEY_LOD, KEY_SIZE, KEY_DISTANCE, KEY_SAMPLES,
       KEY_SUPERSAMPLE, KEY_WIDTH_RULE, KEY_CARDS, KEY_SOFT, KEY_LOD_ASYNC };
/* --width-rule: per vertex where the tier's programs can, else per draw;
   --width-rule=draw: per draw in every tier. */
enum { WIDTH_RULE_OFF, WIDTH_RULE_VERTEX, WIDTH_RULE_DRAW, WIDTH_RULE_AUTO };

static const struct option long_options[] = {
    VIEW_ARGS_LONG_OPTIONS,
    { "tier", required_argument, NULL, KEY_TIER },
    { "policy", required_argument, NULL, KEY_POLICY },
    { "strict", no_argument, NULL, KEY_STRICT },
    { "flat", no_argument, NULL, KEY_FLAT },
    { "device-profile", required_argument, NULL, KEY_PROFILE },
    { "lod", required_argument, NULL, KEY_LOD },
    { "cards", no_argument, NULL, KEY_CARDS },
    { "size", required_argument, NULL, KEY_SIZE },
    { "distance", required_argument, NULL, KEY_DISTANCE },
    { "samples", required_argument, NULL, KEY_SAMPLES },
    { "supersample", required_argument, NULL, KEY_SUPERSAMPLE },
    { "width-rule", optional_argument, NULL, KEY_WIDTH_RULE },
    { "soft", optional_argument, NULL, KEY_SOFT },
    { "lod-async", no_argument, NULL, KEY_LOD_ASYNC },
    { 0 },
};

static const cli_program program = {
    .name = "hairview",
    .synopsis = "usage: hairview --bundle DIR --scene SCENE.json [--tier auto|marschner|full|vertex|fixed4|fixed|gl11]\n"
                "                [--policy best|fastest|error:DB|error:flip:E|frame:MS] [--strict] [--flat] [--frames N]\n"
                "                [--lod auto|N | --cards] [--size F] [--distance D] [--samples N] [--supersample K]\n"
                "                [--width-rule[=vertex|draw|off]] [--soft[=F]] [--lod-async]\n"
                "                [--context osmesa|egl] [--egl-device N] [--api gl|gles1|gles2|gles3]\n"
                "                [--device-profile NAME] -o OUT.png\n",
    .help = "Renders SCENE with the bundle's tier that the device runs best (or --tier, --policy) and writes\n"
            "OUT.png. Prints tier=NAME reason=... and frame_ms=... (the mean of N timed frames, default 10,\n"
            "after a warm-up (one frame; on a GPU 250 ms of them), each ended by glFinish) on stdout;\n"
            "the library's log on stderr.\n"
            "  --tier NAME     force a tier (default HAIRTIER_TIER, else auto)\n"
            "  --policy P      best, fastest, error:DB, error:flip:E, frame:MS (default HAIRTIER_POLICY, else best)\n"
            "  --strict        fail instead of falling to a lower tier\n"
            "  --flat          the geometry floor: a flat colour, no bundle needed\n"
            "  --frames N      timed frames, 1..100000\n"
            "  --lod L         auto (full detail while a strand is >= 1 px wide, docs/lod.md) or a level 0..7\n"
            "                  (default 0); prints lod=N strands=K strand_px=W\n"
            "  --cards         the cards the bundle stores (hairgen --cards: clumps of strands as\n"
            "                  textured ribbons, docs/lod.md); with such a bundle --lod N draws its\n"
            "                  stored level N\n"
            "  --size F        draw F times the scene's image size, (0, 4] (default 1)\n"
            "  --distance D    the eye D scene units from the target, along the scene's view (default: the scene's);\n"
            "                  A:B dollies it from A to B over the frames, --lod auto re-picking the pair each frame\n"
            "                  (prints lod_pair: frame=F lod=N tier=T at each switch)\n"
            "  --samples N     draw multisampled, N samples (2..32; a framebuffer object, GL 3.0), resolved before the PNG\n"
            "  --supersample K draw K x K times the pixels and box-filter them down (1..8; a reference)\n"
            "  --width-rule[=vertex|draw|off]  strands under a pixel drawn a pixel wide, opacity scaled by the ratio\n"
            "                  (docs/lod.md): per vertex where the tier can (full, marschner, gl11, vertex on\n"
            "                  GL ES; prints width_rule=vertex), else or with =draw one factor for the mesh's mean\n"
            "                  width (prints width_rule=F opacity=S); in the --distance dolly too (prints\n"
            "                  width_rule: frame=F vertex|draw). Unset, a pair picked from cells measured\n"
            "                  with it (--lod-reference supersample) is drawn with it per draw (prints\n"
            "                  width_rule=from-cells); =off never\n"
            "  --soft[=F]      a level past 0 drawn soft: its ribbons F (default 3) times wider at 1/F the\n"
            "                  opacity, sorted back to front (docs/lod.md); prints soften=S opacity=A\n"
            "  --lod-async     the --distance dolly's level sorts and widened copies on a thread, the level\n"
            "                  before drawn until done (prints lod_pending: frame=F at each wait; the PNG after\n"
            "                  the last one is done)\n"
            "  --context K     osmesa or egl (default HAIRTIER_CONTEXT, else osmesa where it loads, else egl)\n"
            "  --egl-device N  draw on EGL device N (implies --context egl)\n"
            "  --api A         gl (default), gles1, gles2 or gles3 (GL ES through EGL; ES 1.1 runs the\n                  fixed-function tiers only)\n"
            "  --device-profile NAME  what a named device allows: gl11, gl13, gl20, videocore4, mali400,\n"
            "                  videocore6 (an ES device's API unless --api is given)\n"
            "On failure: one line naming the file or field on stderr, exit 1, no PNG; usage errors exit 2.\n",
    .short_options = VIEW_ARGS_SHORT_OPTIONS,
    .long_options = long_options,
};

static const char *take(void *user, int key, const char *value) {
    options *o = user;
    static char message[300];
    bool taken;
    const char *why = view_args_take(&o->view, key, value, 100000, &taken);
    if (taken) return why;
    switch (key) {
    case KEY_TIER:
        o->tier = ht_tier_from_name(value);
        return o->tier == HT_TIER_COUNT ? "--tier: expected auto, marschner, full, vertex, fixed4, fixed or gl11" : NULL;
    case KEY_POLICY: {
        o->policy = value;
        ht_policy p;
        char err[200];
        if (ht_policy_parse(value, &p, err, sizeof err) == HT_OK) return NULL;
        snprintf(message, sizeof message, "--%s", err);
        return message;
    }
    case KEY_STRICT: o->strict = true; return NULL;
    case KEY_FLAT: o->flat = true; return NULL;
    case KEY_WIDTH_RULE:
        o->width_rule = !value || !strcmp(value, "vertex") ? WIDTH_RULE_VERTEX
                        : !strcmp(value, "draw")          ? WIDTH_RULE_DRAW
                        : !strcmp(value, "off")           ? WIDTH_RULE_OFF
                                                          : WIDTH_RULE_AUTO;
        return o->width_rule == WIDTH_RULE_AUTO ? "--width-rule: expected vertex, draw or off" : NULL;
    case KEY_SOFT: return view_args_soften(value, &o->soft);
    case KEY_PROFILE: {
        char err[200];
        if (ht_device_profile_parse(value, &o->profile, err, sizeof err) == HT_OK) return NULL;
        snprintf(message, sizeof message, "--device-profile: %s", err);
        return message;
    }
    case KEY_CARDS: o->cards = true; return NULL;
    case KEY_LOD_ASYNC: o->lod_async = true; return NULL;
    case KEY_LOD: {
        char *end;
        if (strcmp(value, "auto") == 0) { o->lod = -1; return NULL; }
        const long n = strtol(value, &end, 10);
        if (*value && !*end && n >= 0 && n < HT_LOD_FILE_MAX_LEVELS) { o->lod = (int)n; return NULL; }
        return "--lod: expected auto or a level 0..7";
    }
    case KEY_SAMPLES:
    case KEY_SUPERSAMPLE: {
        char *end;
        const long n = strtol(value, &end, 10);
        const bool ms = key == KEY_SAMPLES;
        if (!*value || *end || n < (ms ? 2 : 1) || n > (ms ? 32 : 8))
            return ms ? "--samples: expected an integer 2..32" : "--supersample: expected an integer 1..8";
        *(ms ? &o->samples : &o->supersample) = (int)n;
        return NULL;
    }
    case KEY_SIZE:
    case KEY_DISTANCE: {
        char *end;
        const double x = strtod(value, &end);
        const bool size = key == KEY_SIZE;
        bool to_ok = true;
        if (!size && *value && *end == ':') { /* A:B, a dolly */
            o->distance_to = strtod(end + 1, &end);
            to_ok = o->distance_to > 0 && o->distance_to <= 1e4;
        }
        if (!to_ok || !*value || *end || !(x > 0) || !(x <= (size ? 4.0 : 1e4)))
            return size ? "--size: expected a number in (0, 4]"
                        : "--distance: expected a number in (0, 10000], or A:B (a dolly over the frames)";
        *(size ? &o->size : &o->distance) = x;
        return NULL;
    }
    default: return cli_unexpected(value);
    }
}

static int parse_args(int argc, char **argv, options *o) {
    *o = (options){ .view = view_args_defaults(10), .tier = HT_TIER_AUTO, .size = 1.0, .supersample = 1,
                     .width_rule = WIDTH_RULE_AUTO };
    int rc = cli_parse(&program, argc, argv, take, o);
    if (rc != CLI_RUN) return rc;
    /* An ES device's profile draws on its API unless --api says otherwise. */
    if (o->view.api == OFFSCREEN_API_GL && o->profile.es_major > 0)
        o->view.api = o->profile.es_major >= 3 ? OFFSCREEN_API_GLES3 : OFFSCREEN_API_GLES2;
    const char *why = view_args_check(&o->view, false);
    if (why) return cli_usage_error(&program, why);
    if (!o->view.bundle && !o->flat) return cli_usage_error(&program, "--bundle: required (unless --flat)");
    if (o->lod_async && !(o->distance_to > 0))
        return cli_usage_error(&program, "--lod-async: the --distance A:B dolly's chain only");
    return CLI_RUN;
}

typedef struct view {
    offscreen *gl;
    ht_mesh hair, head;
    ht_renderer *renderer;
} view;

static void view_free(view *v) {
    ht_renderer_destroy(v->renderer);
    ht_mesh_free(&v->hair);
    ht_mesh_free(&v->head);
    offscreen_close(v->gl);
}

static void draw_frame(const ht_scene *s, const view *v, const ht_frame_desc *frame, ht_result *r) {
    v->gl->gl.ClearColor(s->background[0], s->background[1], s->background[2], 1.0f);
    v->gl->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_result fr = ht_renderer_draw(v->renderer, frame);
    if (fr != HT_OK && *r == HT_OK) *r = fr;
    v->gl->gl.Finish();
}

/* Frames drawn before timing: one (shader variants, texture uploads), and
   more until offscreen_warmup_ms have passed (a GPU's clock). */
static void warm_up(const ht_scene *s, const view *v, const ht_frame_desc *frame, ht_result *r) {
    for (const double until = now_ms() + offscreen_warmup_ms(v->gl); *r == HT_OK;) {
        draw_frame(s, v, frame, r);
        if (now_ms() >= until) break;
    }
}

/* --size and --distance: a smaller image or a farther eye, so the hair's
   projected size changes and --lod auto has something to switch on. */
static const char *apply_view(const options *o, ht_scene *s) {
    s->width = (int)lround(s->width * o->size) * o->supersample;
    s->height = (int)lround(s->height * o->size) * o->supersample;
    if (s->width < 1 || s->height < 1 || s->width > 8192 || s->height > 8192)
        return "--size, --supersample: the drawn image must stay 1 to 8192 pixels a side";
    if (o->distance > 0) {
        double d[3], len = 0;
        for (int k = 0; k < 3; k++) { d[k] = (double)s->camera.eye[k] - s->camera.target[k]; len += d[k] * d[k]; }
        len = sqrt(len);
        for (int k = 0; k < 3; k++) s->camera.eye[k] = (float)(s->camera.target[k] + d[k] / len * o->distance);
    }
    return NULL;
}

/* The eye's distance from the camera's target. */
static double eye_distance(const ht_scene *s) {
    double d = 0;
    for (int k = 0; k < 3; k++) d += ((double)s->camera.eye[k] - s->camera.target[k]) * (s->camera.eye[k] - s->camera.target[k]);
    return sqrt(d);
}

/* The renderer switched to `tier` (the pair's), made at its first use. */
static int retier(view *v, ht_tier tier) {
    ht_result r = ht_renderer_set_tier(v->renderer, tier, NULL);
    return r == HT_OK ? 0 : fail(r);
}

/* frame:MS's reference: the (LOD 0, reference tier) frame at this size on
   this device, the mean of 3 after warm_up. 0 when it cannot draw. */
static double reference_ms(const options *o, const view *v, const ht_scene *s, const ht_frame_desc *f, ht_tier tier) {
    ht_renderer *r = NULL;
    if (ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = o->view.bundle,
                                                .tier = tier, .strict = true, .profile = o->profile },
                           &r) != HT_OK)
        return 0;
    double ms = 0;
    if (ht_renderer_set_mesh(r, &v->hair) == HT_OK) {
        view timed = *v;
        timed.renderer = r;
        ht_result fr = HT_OK;
        warm_up(s, &timed, f, &fr);
        const double t0 = now_ms();
        for (int i = 0; i < 3; i++) draw_frame(s, &timed, f, &fr);
        ms = fr == HT_OK ? (now_ms() - t0) / 3 : 0;
    }
    ht_renderer_destroy(r);
    return ms;
}

/* A bundle's measured (level, tier) cells (hairgen --measure-lods) when the
   policy picks pairs (error:DB, frame:MS) and the hair is shaded; *ref the
   reference pair's (level 0, its PSNR infinite; against the supersampled
   truth none is: the first level-0 cell, the first tier's). 0: none, or no
   reference. */
static int pair_cells(const options *o, const view *v, const ht_policy *policy, ht_lod_cell *cells, int *ref) {
    const bool pair = policy->kind == HT_POLICY_ERROR || policy->kind == HT_POLICY_FRAME;
    const int n = pair && !o->flat ? ht_renderer_lod_cells(v->renderer, cells, HT_LOD_MAX_CELLS) : 0;
    *ref = -1;
    for (int i = 0; i < n; i++)
        if (cells[i].lod == 0 && (isinf(cells[i].psnr) || *ref < 0)) *ref = i;
    return *ref >= 0 ? n : 0;
}

/* " soft F" for a soft pair's factor, "" for a plain one (buf: 32 bytes). */
static const char *soft_text(float soften, char *buf) {
    buf[0] = '\0';
    if (soften > 1) snprintf(buf, 32, " soft %g", (double)soften);
    return buf;
}

/* --lod auto with error:DB or frame:MS and a bundle measured with
   --measure-lods: the (LOD, tier) pair the rule picks at this projected
   size (the scene's times --size, over --distance's change), the renderer
   made to draw its tier, *soften its soft cell's (0: plain); else (-1)
   the best rule decides the level. */
static int auto_pair(const options *o, view *v, const ht_scene *s, const ht_frame_desc *f, const ht_policy *policy,
                     double size, int max_level, int *level, float *soften) {
    static ht_lod_cell cells[HT_LOD_MAX_CELLS];
    int ref;
    *level = -1;
    const int n = pair_cells(o, v, policy, cells, &ref);
    if (n == 0) return 0;
    double ms = 0;
    if (policy->kind == HT_POLICY_FRAME && !(ms = reference_ms(o, v, s, f, cells[ref].tier))) return 0;
    const int pick = policy->kind == HT_POLICY_ERROR ? ht_lod_pick_error(cells, n, size, policy->value, -1)
                                                     : ht_lod_pick_frame(cells, n, size, policy->value, ms, -1);
    if (pick < 0 || cells[pick].lod > max_level) return 0;
    printf("lod_pair: lod=%d tier=%s at size %.3f: %.2f dB, cost %.3fx (lod 0, %s)", cells[pick].lod,
           ht_tier_name(cells[pick].tier), size, cells[pick].psnr, cells[pick].cost, ht_tier_name(cells[ref].tier));
    if (policy->kind == HT_POLICY_FRAME) printf(" = %.3f ms of %.3f", cells[pick].cost * ms, policy->value);
    char soft[32];
    printf("%s\n", soft_text(cells[pick].soften, soft));
    *level = cells[pick].lod;
    *soften = cells[pick].soften > 1 ? cells[pick].soften : 0.0f;
    return retier(v, cells[pick].tier);
}

/* Replaces the full mesh by the level --lod asks for (auto: the pair rule
   above, else lod.h's best rule at the camera's distance to the target)
   and prints what it drew; *paired: the pair rule chose the tier too.
   ladder (NULL: none): the bundle's stored levels (lods.bin) for this
   scene, every level drawn is the file's (--cards: its cards level). */
static int choose_lod(const options *o, const ht_scene *s, double scene_distance, view *v, const ht_frame_desc *f,
                      const ht_policy *policy, const ht_lod_file *ladder, bool *paired, float *opacity) {
    ht_mesh *hair = &v->hair;
    const double d = eye_distance(s);
    const double px = ht_mesh_projected_width_px(hair, &s->camera, s->height / o->supersample);
    const int max_level = ladder ? ladder->level_count - 1 : ht_lod_max_level(hair);
    int level = o->lod;
    float soften = o->soft;
    *paired = false;
    *opacity = 1.0f;
    if (o->cards) {
        for (level = 0; level <= max_level && ladder->levels[level].kind != HT_LOD_KIND_CARDS; level++) {}
        if (level > max_level) {
            fprintf(stderr, "hairview: --cards: %s/%s stores no cards (make the bundle with hairgen --cards)\n",
                    o->view.bundle, HT_LOD_FILE_NAME);
            return 1;
        }
    } else if (o->lod < 0) {
        if (auto_pair(o, v, s, f, policy, o->size * scene_distance / d, max_level, &level, &soften)) return 1;
        *paired = level >= 0;
        if (level < 0) level = ht_lod_pick_best(px, -1, max_level);
    }
    if (level > max_level) {
        fprintf(stderr, "hairview: --lod: %d is past this scene's last level %d (%u strands%s)\n", level, max_level,
                hair->component_count, ladder ? ", the levels lods.bin stores" : "");
        return 1;
    }
    /* counted before a soft level's sort makes every segment a component */
    uint32_t strands = hair->component_count;
    /* a plain bundle's level 0 is not stored: the scene's mesh is it */
    const bool stored = ladder && ladder->levels[level].kind != HT_LOD_KIND_SCENE;
    if (soften > 1 && ladder && ladder->levels[level].kind == HT_LOD_KIND_CARDS) {
        fprintf(stderr, "hairview: --soft: %s/%s: level %d is cards, which are never soft\n", o->view.bundle,
                HT_LOD_FILE_NAME, level);
        return 1;
    }
    if (stored || (!ladder && level > 0)) {
        ht_lod_desc desc;
        ht_mesh lod;
        ht_lod_level(level, &desc);
        ht_result r = stored ? ht_lod_file_level_mesh(ladder, level, &lod) : ht_mesh_build_lod(hair, &desc, &lod);
        if (r != HT_OK) {
            fprintf(stderr, "hairview: %s: geometry: cannot %s LOD %d: %s\n", o->view.scene, stored ? "read" : "build",
                    level, ht_result_string(r));
            return 1;
        }
        ht_mesh_free(hair);
        *hair = lod;
        strands = hair->component_count;
    }
    if (soften > 1 && level > 0) {
        /* lod.h: the plain level widened, its translucent ribbons far to near */
        ht_mesh soft;
        ht_result r = ht_mesh_widen_back_to_front(hair, soften, s->camera.eye, &soft);
        if (r != HT_OK) {
            fprintf(stderr, "hairview: %s: geometry: LOD %d soft: %s\n", o->view.scene, level, ht_result_string(r));
            return 1;
        }
        ht_mesh_free(hair);
        *hair = soft;
        *opacity = 1.0f / soften;
        if ((r = ht_renderer_set_opacity_scale(v->renderer, *opacity)) != HT_OK) return fail(r);
        printf("soften=%.3f opacity=%.3f\n", soften, 1.0 / soften);
    }
    printf("lod=%d strands=%u strand_px=%.3f", level, strands, px);
    if (ladder)
        printf(" stored kind=%s param=%u components=%u",
               ladder->levels[level].kind == HT_LOD_KIND_CARDS ? "cards"
               : stored                                        ? "strands"
                                                               : "scene",
               ladder->levels[level].param, strands);
    printf("\n");
    return 0;
}

/* The mean strand's width in pixels drawn (a supersampled frame's too). */
static double mean_strand_px(const ht_scene *s, const ht_mesh *hair) {
    return ht_mesh_projected_width_px(hair, &s->camera, s->height);
}

/* The width rule drawn: --width-rule's, else per draw when the pair was
   picked from cells measured with it (lod.h), else none. */
static int width_rule_for(const options *o, const view *v, bool paired) {
    if (o->width_rule != WIDTH_RULE_AUTO) return o->width_rule;
    if (!paired || !ht_renderer_lod_cells_width_rule(v->renderer)) return WIDTH_RULE_OFF;
    printf("width_rule=from-cells\n");
    return WIDTH_RULE_DRAW;
}

/* --width-rule=draw on the mesh choose_lod left (drawn at `opacity`): its
   mean strand widened to about a pixel, the opacity scaled by the inverse. */
static int apply_width_rule(const options *o, const ht_scene *s, ht_renderer *r, ht_mesh *hair, float opacity) {
    double f = 1.0;
    ht_mesh wide;
    ht_result res = ht_mesh_width_rule(hair, mean_strand_px(s, hair), ht_renderer_samples(r), s->camera.eye, &wide, &f);
    if (res != HT_OK) {
        fprintf(stderr, "hairview: %s: geometry: --width-rule: %s\n", o->view.scene, ht_result_string(res));
        return 1;
    }
    if (f > 1.0) {
        ht_mesh_free(hair);
        *hair = wide;
        if ((res = ht_renderer_set_opacity_scale(r, (float)(opacity / f))) != HT_OK) return fail(res);
    }
    printf("width_rule=%.3f opacity=%.3f\n", f, opacity / f);
    return 0;
}

/* The bundle's stored levels (lods.bin), when it has them and they are
   this scene's (their level 0 is the scene's mesh): *has set. A stored
   ladder of another scene is left for the levels built at run time, but
   one holding cards is refused (the bundle's textures are their atlas,
   which the scene's own mesh would sample wrongly). */
static int read_stored_levels(const options *o, const ht_mesh *hair, ht_lod_file *ladder, bool *has) {
    char path[4200], err[512];
    stored_ladder kind;
    *has = false;
    if (stored_ladder_read(o->view.bundle, o->view.scene, hair, ladder, &kind, path, sizeof path, err, sizeof err) !=
        HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    *has = kind == STORED_THIS_SCENE;
    if (kind == STORED_NONE && o->cards) {
        fprintf(stderr, "hairview: --cards: %s: absent (make the bundle with hairgen --cards)\n", path);
        return 1;
    }
    if (kind == STORED_OTHER_SCENE && o->cards) {
        fprintf(stderr, "hairview: %s: its level 0 is not %s's mesh: these cards are another scene's\n", path,
                o->view.scene);
        return 1;
    }
    if (kind == STORED_OTHER_SCENE) printf("stored_levels: %s is another scene's; levels built from %s\n", path, o->view.scene);
    return 0;
}

/* --lod auto --distance A:B: the eye dollied from A to B over the frames,
   the (level, tier) pair re-picked every frame by the policy (error:DB,
   frame:MS with a bundle's measured cells; else best) through one
   ht_lod_chain in one renderer; prints each switch, the mean frame and
   the longest (a switch's stall). --lod-async: each wait for a job, and
   the last one waited for after the timed frames, so the PNG is the
   level asked for. */
static int dolly(const options *o, view *v, ht_scene *s, double scene_distance, const ht_lod_file *ladder,
                 const ht_policy *policy, ht_frame_desc *frame, double *frame_ms) {
    ht_lod_chain chain;
    ht_result r = ladder ? ht_lod_chain_from_scene_file(ladder, &v->hair, &chain) : ht_lod_chain_build(&v->hair, &chain);
    if (r != HT_OK) {
        fprintf(stderr, "hairview: %s: levels: %s\n", ladder ? o->view.bundle : o->view.scene, ht_result_string(r));
        return 1;
    }
    static ht_lod_cell cells[HT_LOD_MAX_CELLS];
    const int viewport_h = s->height / o->supersample;
    ht_lod_rule rule = { .kind = HT_POLICY_BEST, .value = policy->value, .cells = cells,
                         .size1_px = ht_projected_width_px(chain.width, scene_distance, s->camera.fov_y,
                                                           (int)lround(viewport_h / o->size)) };
    int ref;
    rule.cell_count = pair_cells(o, v, policy, cells, &ref);
    if (rule.cell_count > 0) rule.kind = policy->kind;
    /* on the level drawn (lod.h): per vertex where the tier can, else per draw */
    const int width_rule = width_rule_for(o, v, rule.cell_count > 0);
    chain.width_rule = width_rule != WIDTH_RULE_OFF;
    chain.async = o->lod_async;
    ht_renderer_set_width_rule(v->renderer, width_rule == WIDTH_RULE_VERTEX);
    if (rule.kind == HT_POLICY_FRAME && !(rule.reference_ms = reference_ms(o, v, s, frame, cells[ref].tier))) {
        ht_lod_chain_free(&chain);
        fprintf(stderr, "hairview: frame:MS: the reference pair (lod 0, %s) does not draw\n", ht_tier_name(cells[ref].tier));
        return 1;
    }
    double dir[3], len = 0;
    for (int k = 0; k < 3; k++) dir[k] = (double)s->camera.eye[k] - s->camera.target[k], len += dir[k] * dir[k];
    len = sqrt(len);
    /* frame:MS: the reference pair timed again with the eye where the hair
       is at each measured size (chain size = --size x scene distance /
       distance), as each size's cells are ratios of their own reference */
    static ht_lod_reference_frame frames[8];
    const ht_camera start = s->camera;
    for (int i = 0; rule.kind == HT_POLICY_FRAME && i < rule.cell_count && rule.reference_frame_count < 8; i++) {
        bool known = false;
        for (int j = 0; j < rule.reference_frame_count; j++) known |= frames[j].size == cells[i].size;
        if (known || !(cells[i].size > 0)) continue;
        const double d = o->size * scene_distance / cells[i].size;
        for (int k = 0; k < 3; k++) s->camera.eye[k] = (float)(s->camera.target[k] + dir[k] / len * d);
        frame->camera = s->camera;
        frames[rule.reference_frame_count] = (ht_lod_reference_frame){ cells[i].size,
                                                                        reference_ms(o, v, s, frame, cells[ref].tier) };
        printf("frame_reference: size=%.3f distance=%.3f ms=%.3f\n", cells[i].size, d,
               frames[rule.reference_frame_count].ms);
        rule.reference_frame_count++;
    }
    rule.reference_frames = frames;
    s->camera = start;
    frame->camera = start;
    ht_result fr = HT_OK;
    int last_level = -1;
    ht_tier last_tier = HT_TIER_COUNT;
    float last_soften = -1.0f;
    char soft[32];
    double ms = 0, last_widen = 1.0, max_ms = 0, max_select = 0;
    int max_frame = 0, pending_frames = 0;
    bool per_vertex = false, was_pending = false;
    for (int f = 0; f < o->view.frames && fr == HT_OK; f++) {
        const double t = o->view.frames > 1 ? (double)f / (o->view.frames - 1) : 0;
        const double d = o->distance + (o->distance_to - o->distance) * t;
        for (int k = 0; k < 3; k++) s->camera.eye[k] = (float)(s->camera.target[k] + dir[k] / len * d);
        frame->camera = s->camera;
        const double t0 = now_ms();
        const int level = ht_lod_chain_select_pair(&chain, v->renderer, &s->camera, viewport_h, &rule, &fr);
        const double select_ms = now_ms() - t0;
        if (level < 0) break;
        draw_frame(s, v, frame, &fr);
        const double frame_ms = now_ms() - t0;
        ms += frame_ms;
        /* past the first frame, which uploads everything and makes the tier's programs */
        if (f > 0 && frame_ms > max_ms) max_ms = frame_ms, max_frame = f;
        if (f > 0 && select_ms > max_select) max_select = select_ms;
        const bool pending = ht_lod_chain_pending(&chain);
        if (pending && !was_pending) printf("lod_pending: frame=%d distance=%.3f select_ms=%.3f\n", f, d, select_ms);
        pending_frames += pending;
        was_pending = pending;
        if (level != last_level || ht_renderer_tier(v->renderer) != last_tier || chain.soften != last_soften)
            printf("lod_pair: frame=%d lod=%d tier=%s distance=%.3f size=%.3f select_ms=%.3f%s\n", f, level,
                   ht_tier_name(ht_renderer_tier(v->renderer)), d, chain.size, select_ms, soft_text(chain.soften, soft));
        if (width_rule == WIDTH_RULE_VERTEX && ht_renderer_width_rule_per_vertex(v->renderer) != per_vertex) {
            per_vertex = !per_vertex;
            printf("width_rule: frame=%d %s\n", f, per_vertex ? "vertex" : "draw");
        }
        /* the width rule's own factor: what is drawn over the soft level's */
        const double widen = chain.wide_renderer ? chain.wide_factor / chain.wide_soften : 1.0;
        if (widen != last_widen)
            printf("width_rule: frame=%d widen=%.3f opacity=%.3f\n", f, widen, 1.0 / chain.wide_factor);
        last_widen = widen;
        last_soften = chain.soften;
        last_level = level;
        last_tier = ht_renderer_tier(v->renderer);
    }
    /* the PNG: what the last frame asked for (untimed) */
    for (int k = 0; k < 4 && fr == HT_OK && ht_lod_chain_pending(&chain); k++) {
        ht_lod_chain_wait(&chain);
        const int level = ht_lod_chain_select_pair(&chain, v->renderer, &s->camera, viewport_h, &rule, &fr);
        if (level >= 0) draw_frame(s, v, frame, &fr);
        printf("lod_waited: lod=%d%s\n", level, soft_text(chain.soften, soft));
    }
    ht_lod_chain_free(&chain);
    if (fr != HT_OK) return fail(fr);
    printf("dolly: %d frames, %.3f to %.3f, rule %s, cpu_vertices=%llu%s\n", o->view.frames, o->distance,
           o->distance_to, rule.kind == HT_POLICY_ERROR ? "error" : rule.kind == HT_POLICY_FRAME ? "frame" : "best",
           (unsigned long long)ht_renderer_get_stats(v->renderer).cpu_vertices, o->lod_async ? " async" : "");
    printf("dolly: after the first frame, max_frame_ms=%.3f (frame %d) max_select_ms=%.3f\n", max_ms, max_frame,
           max_select);
    if (o->lod_async) printf("dolly: %d frames drawn while a job ran\n", pending_frames);
    *frame_ms = ms / o->view.frames;
    return 0;
}

/* One still camera: the level --lod asks for (or the stored level), the
   width rule, the frames timed into *ms. */
static int draw_still(const options *o, view *v, ht_scene *scene, double scene_distance, const ht_lod_file *ladder,
                      const ht_policy *policy, ht_frame_desc *frame, double *ms) {
    bool paired = false;
    float opacity = 1.0f;
    if (choose_lod(o, scene, scene_distance, v, frame, policy, ladder, &paired, &opacity)) return 1;
    print_held();
    ht_result r;
    const int width_rule = width_rule_for(o, v, paired);
    if (width_rule == WIDTH_RULE_VERTEX) ht_renderer_set_width_rule(v->renderer, true);
    else if (width_rule && apply_width_rule(o, scene, v->renderer, &v->hair, opacity)) return 1;
    if ((r = ht_renderer_set_mesh(v->renderer, &v->hair)) != HT_OK) return fail(r);
    print_held();

    if (!o->flat && !paired && policy->kind == HT_POLICY_FRAME) {
        if ((r = ht_renderer_choose_by_frame_time(v->renderer, &v->hair, frame, 0)) != HT_OK) return fail(r);
        print_held();
    }
    /* per vertex where the tier drawing now can, else per draw */
    if (width_rule == WIDTH_RULE_VERTEX && ht_renderer_width_rule_per_vertex(v->renderer)) {
        /* drawn back to front where it applies, as it is where not (lod.h) */
        const int samples = ht_renderer_samples(v->renderer);
        const bool applies = ht_width_rule_applies(mean_strand_px(scene, &v->hair), samples);
        if (!applies) {
            printf("width_rule=vertex not applied: %d samples resolve the strands\n", samples);
        } else {
            printf("width_rule=vertex\n");
            ht_mesh_sort_back_to_front(&v->hair, scene->camera.eye);
            ht_renderer_set_back_to_front(v->renderer, true);
            if ((r = ht_renderer_set_mesh(v->renderer, &v->hair)) != HT_OK) return fail(r);
        }
    } else if (width_rule == WIDTH_RULE_VERTEX) {
        ht_renderer_set_width_rule(v->renderer, false);
        if (apply_width_rule(o, scene, v->renderer, &v->hair, opacity)) return 1;
        if ((r = ht_renderer_set_mesh(v->renderer, &v->hair)) != HT_OK) return fail(r);
    }
    ht_result fr = HT_OK;
    warm_up(scene, v, frame, &fr);
    double t0 = now_ms();
    for (int i = 0; i < o->view.frames; i++) draw_frame(scene, v, frame, &fr);
    *ms = (now_ms() - t0) / o->view.frames;
    if (fr != HT_OK) return fail(fr);
    print_held();

    return 0;
}

static int run(const options *o, view *v) {
    char err[1024];
    ht_scene scene;
    if (ht_scene_load(o->view.scene, &scene, err, sizeof err) != HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    const double scene_distance = eye_distance(&scene);
    const char *why = apply_view(o, &scene);
    if (why) {
        fprintf(stderr, "hairview: %s\n", why);
        return 1;
    }
    v->gl = offscreen_open(&(offscreen_desc){ .kind = o->view.context, .width = scene.width, .height = scene.height,
                                              .egl_device = o->view.egl_device, .api = o->view.api,
                                              .samples = o->samples },
                           err, sizeof err);
    if (!v->gl) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    fprintf(stderr, "hairview: context %s\n", v->gl->display);

    ht_result r = ht_scene_build_meshes(&scene, o->view.scene, &v->hair, &v->head, err, sizeof err);
    if (r != HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    r = ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, .bundle_dir = o->view.bundle, .tier = o->tier,
                                                .strict = o->strict, .log = log_line, .flat = o->flat,
                                                .policy = o->policy, .profile = o->profile },
                           &v->renderer);
    if (r != HT_OK) return fail(r);
    print_held();
    const char *policy_text = o->policy ? o->policy : getenv("HAIRTIER_POLICY");
    ht_policy policy = { HT_POLICY_BEST, 0 };
    if (ht_policy_parse(policy_text && policy_text[0] ? policy_text : NULL, &policy, err, sizeof err) != HT_OK)
        policy.kind = HT_POLICY_BEST; /* the renderer has refused it already */
    ht_lod_file ladder;
    bool has_stored = false;
    if (read_stored_levels(o, &v->hair, &ladder, &has_stored)) return 1;
    ht_frame_desc frame = { .camera = scene.camera, .lights = scene.lights, .light_count = scene.light_count,
                            .aspect = (float)scene.width / (float)scene.height,
                            .opaque = v->head.index_count ? &v->head : NULL };
    double ms = 0;
    if (o->distance_to > 0 && (o->lod >= 0 || o->cards || o->soft > 0)) {
        fprintf(stderr, "hairview: --distance A:B: a dolly picks the level per frame (--lod auto), without --cards "
                        "or --soft\n");
        if (has_stored) ht_lod_file_free(&ladder);
        return 1;
    }
    const int drawn = o->distance_to > 0
                          ? dolly(o, v, &scene, scene_distance, has_stored ? &ladder : NULL, &policy, &frame, &ms)
                          : draw_still(o, v, &scene, scene_distance, has_stored ? &ladder : NULL, &policy, &frame, &ms);
    if (has_stored) ht_lod_file_free(&ladder);
    if (drawn) return 1;

    ht_image img;
    const int k = o->supersample, w = scene.width / k, h = scene.height / k;
    if (ht_image_alloc(&img, w, h, 3) != HT_OK) {
        fprintf(stderr, "hairview: %s: out of memory\n", o->view.out);
        return 1;
    }
    offscreen_read_box(v->gl, k, 3, true, img.pixels); /* k = 1: a copy */
    r = ht_image_write_png(o->view.out, &img, err, sizeof err);
    ht_image_free(&img);
    if (r != HT_OK) {
        fprintf(stderr, "hairview: %s\n", err);
        return 1;
    }
    const char *tier = o->flat ? "flat" : ht_tier_name(ht_renderer_tier(v->renderer));
    printf("tier=%s reason=%s\n", tier, ht_renderer_reason(v->renderer));
    printf("frame_ms=%.3f\n", ms);
    return 0;
}

int main(int argc, char **argv) {
    options o;
    int rc = parse_args(argc, argv, &o);
    if (rc != CLI_RUN) return rc;
    view v = { 0 };
    rc = run(&o, &v);
    view_free(&v);
    print_held();
    return rc;
}

/* haircompare — the speed-for-accuracy report a person opens: one scene
   rendered with every tier of a bundle the device runs, written as a
   directory with index.html (plain HTML and SVG, no script, relative
   links) and the PNGs beside it.

   build/haircompare --bundle DIR --scene SCENE.json [--frames N] -o REPORT_DIR

   For each tier of the manifest, best first: the tier forced and strict on
   its own offscreen context (examples/compare/tier_render.h, as tier_sheet),
   its image at full size, its per-pixel CIEDE2000 against the reference
   (marschner when it runs, else full) as a heatmap
   (examples/compare/heatmap.h), both cut and enlarged where the
   reference's highlight is brightest (examples/compare/crop.h), and a
   table row: frame ms, cost ratio to the reference, PSNR, SSIM, ΔE00 mean
   and p95 (shadergen/metrics.h) beside the bundle's measured numbers, and
   the features the manifest says the tier drops; then an SVG plot of
   error against cost. A bundle storing this scene's levels (lods.bin:
   hairgen --scene, --cards) or measured with hairgen --measure-lods gets
   a grid too: every geometry LOD (the stored ones, cards too, else those
   built from the scene: compare/grid_levels.h) by every tier at a quarter
   size, each against (LOD 0, the reference), beside the manifest's
   numbers for the cell where it has them. A cards bundle's tier images
   draw its stored level 0. Why not grow tier_sheet: its one PNG is the quick
   look on a terminal and in docs; a report is a directory written whole
   (temporary sibling, renamed at the end) with a table and plot that a PNG
   cannot carry. Both share the rendering (tier_render.c).

   Exit status 0 when the report is written (some tiers may not have run),
   1 when no tier ran or on any other failure (one line on stderr, no
   report, REPORT_DIR as it was), 2 on usage. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare/crop.h"
#include "compare/grid_levels.h"
#include "compare/heatmap.h"
#include "compare/report.h"
#include "compare/report_dir.h"
#include "compare/tier_render.h"
#include <hairtier/image.h>
#include <hairtier/lod.h>
#include "cli.h"
#include "offscreen.h"
#include "view_args.h"

#define MAX_FRAMES 1000

typedef struct options {
    view_args view;  /* --bundle, --scene, -o, --frames, the context */
    char out[4096];  /* -o without trailing slashes: its temporary sibling sits beside it */
} options;

static const struct option long_options[] = { VIEW_ARGS_LONG_OPTIONS, { 0 } };

static const cli_program program = {
    .name = "haircompare",
    .synopsis = "usage: haircompare --bundle DIR --scene SCENE.json [--frames N] [--context osmesa|egl] [--egl-device N]\n"
                "                   [--api gl|gles1|gles2|gles3]\n"
                "                   -o REPORT_DIR\n",
    .help = "Renders SCENE with every tier of the bundle the device runs (forced, strict) and writes\n"
            "REPORT_DIR/index.html: the tier images side by side, each tier's per-pixel CIEDE2000\n"
            "against the reference (marschner when it runs, else full) as a heatmap (0 black to\n"
            CLI_STR(REPORT_HEAT_MAX) " white, cubehelix), " CLI_STR(REPORT_CROP_SCALE) "x enlarged crops of the reference's brightest\n"
            "highlight, a table (frame ms, cost ratio to the reference, PSNR, SSIM, dE00 mean and p95, FLIP mean and p95,\n"
            "beside the bundle's measured numbers; needs, features dropped) and a plot of error\n"
            "against cost; for a bundle storing levels (lods.bin, cards too) or measured with --measure-lods, every\n"
            "level by every tier at a quarter size beside the manifest's numbers for the cell.\n"
            "Frame ms: median of N frames (default 5, at most " CLI_STR(MAX_FRAMES) ") after a warm-up, each ended by\n"
            "glFinish. The report is written whole or not at all; an existing REPORT_DIR is replaced\n"
            "only when it is empty or an earlier report. --context, --egl-device: the GL context,\n"
            "as hairview's (default HAIRTIER_CONTEXT, else osmesa where it loads, else egl).\n",
    .short_options = VIEW_ARGS_SHORT_OPTIONS,
    .long_options = long_options,
};

static int parse_args(int argc, char **argv, options *o) {
    *o = (options){ .view = view_args_defaults(5) };
    int rc = view_args_parse(&program, argc, argv, &o->view, MAX_FRAMES, true);
    if (rc != CLI_RUN) return rc;
    const char *out = o->view.out;
    size_t len = strlen(out);
    while (len > 1 && out[len - 1] == '/') len--;
    if (len == 0 || len >= sizeof o->out || (len == 1 && out[0] == '/'))
        return cli_usage_error(&program, "-o: not a usable directory");
    memcpy(o->out, out, len);
    o->out[len] = '\0';
    return CLI_RUN;
}

/* A GL (bottom-up RGBA) frame as a top-down RGB image, written as PNG
   and kept in img for the crops. */
static ht_result write_frame(const char *path, const unsigned char *rgba, int w, int h, ht_image *img, char *err,
                             size_t err_size) {
    ht_result r = ht_image_alloc(img, w, h, 3);
    if (r != HT_OK) {
        snprintf(err, err_size, "%s: out of memory", path);
        return r;
    }
    for (int y = 0; y < h; y++) {
        const unsigned char *src = offscreen_row(rgba, w, h, y);
        unsigned char *dst = img->pixels + (size_t)y * (size_t)w * 3;
        for (int x = 0; x < w; x++) memcpy(dst + 3 * x, src + 4 * x, 3);
    }
    return ht_image_write_png(path, img, err, err_size);
}

/* Metrics, cost and heatmap (kept in heat) of tier t against the reference frame. */
static ht_result compare_tier(const options *o, const char *tmp, const tier_scene *ts, const uint8_t bg[3],
                              const tier_frame *ref, const tier_frame *frame, bool is_reference, report_tier *p,
                              ht_image *heat, char *err, size_t err_size) {
    const ht_scene *s = &ts->scene;
    const ht_metrics_desc d = { .reference = ref->rgba, .test = frame->rgba, .width = s->width, .height = s->height,
                                .background = bg };
    ht_result r = ht_metrics_compare(&d, &p->whole, &p->hair, err, err_size);
    if (r == HT_OK)
        r = ht_flip_compare(&(ht_flip_desc){ .reference = ref->rgba, .test = frame->rgba, .width = s->width,
                                             .height = s->height },
                            NULL, &p->flip, err, err_size);
    if (r != HT_OK) return r;
    p->cost_ratio = frame->frame_ms / ref->frame_ms;
    p->compared = true;
    if (is_reference) return HT_OK;
    double *map = malloc(sizeof *map * (size_t)s->width * (size_t)s->height);
    if (!map) r = HT_ERR_OUT_OF_MEMORY;
    if (r == HT_OK) r = ht_metrics_delta_e00_map(&d, map, err, err_size);
    if (r == HT_OK) r = heatmap_image(map, s->width, s->height, true, REPORT_HEAT_MAX, heat);
    if (r == HT_OK) {
        char path[4300];
        /* a copy: GCC's -O1 -Wrestrict takes two fields of one struct for
           overlapping */
        char name[sizeof p->name];
        memcpy(name, p->name, sizeof name);
        snprintf(p->heatmap, sizeof p->heatmap, "%s-error.png", name);
        snprintf(path, sizeof path, "%s/%s", tmp, p->heatmap);
        r = ht_image_write_png(path, heat, err, err_size);
    } else if (r == HT_ERR_OUT_OF_MEMORY) {
        snprintf(err, err_size, "%s: out of memory for the %s heatmap", o->out, p->name);
    }
    free(map);
    return r;
}

/* region of src, enlarged, as tmp/file. */
static ht_result write_crop(const char *out, const char *tmp, const char *file, const ht_image *src,
                            const crop_region *region, char *err, size_t err_size) {
    ht_image zoomed = { 0 };
    char path[4300];
    snprintf(path, sizeof path, "%s/%s", tmp, file);
    ht_result r = crop_zoom(src, region, REPORT_CROP_SCALE, &zoomed);
    if (r == HT_OK) r = ht_image_write_png(path, &zoomed, err, err_size);
    else snprintf(err, err_size, "%s/%s: cannot make the crop: %s", out, file, ht_result_string(r));
    ht_image_free(&zoomed);
    return r;
}

/* The reference's brightest highlight, cut from every tier's image and heatmap. */
static ht_result write_crops(const options *o, const char *tmp, report *rep, const uint8_t bg[3],
                             const ht_image *images, const ht_image *heats, char *err, size_t err_size) {
    ht_result r = crop_find_brightest(&images[rep->reference], bg, REPORT_CROP_SIZE, &rep->crop);
    if (r != HT_OK) {
        snprintf(err, err_size, "%s: cannot find the crop: %s", o->out, ht_result_string(r));
        return r;
    }
    for (int t = 0; t < rep->tier_count && r == HT_OK; t++) {
        report_tier *p = &rep->tiers[t];
        char name[sizeof p->name]; /* a copy, as in compare_tier (-Wrestrict) */
        memcpy(name, p->name, sizeof name);
        if (!p->ran) continue;
        snprintf(p->crop, sizeof p->crop, "%s-crop.png", name);
        r = write_crop(o->out, tmp, p->crop, &images[t], &rep->crop, err, err_size);
        if (r == HT_OK && heats[t].pixels) {
            snprintf(p->heatmap_crop, sizeof p->heatmap_crop, "%s-error-crop.png", name);
            r = write_crop(o->out, tmp, p->heatmap_crop, &heats[t], &rep->crop, err, err_size);
        }
    }
    return r;
}

static void print_table(const report *r) {
    printf("against %s:\n", report_reference_name(r));
    printf("%-7s %9s %6s %7s %7s %7s %7s %9s %8s\n", "tier", "frame_ms", "cost", "psnr_db", "ssim", "de_mean", "de_p95",
           "flip_mean", "flip_p95");
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        if (!p->ran) printf("%-7s not run: %s\n", p->name, p->reason);
        else if (!p->compared) printf("%-7s %9.2f\n", p->name, p->frame_ms);
        else
            printf("%-7s %9.2f %6.2f %7.2f %7.4f %7.3f %7.3f %9.4f %8.4f\n", p->name, p->frame_ms, p->cost_ratio,
                   p->whole.psnr_db, p->whole.ssim, p->whole.delta_e00_mean, p->whole.delta_e00_p95, p->flip.mean,
                   p->flip.p95);
    }
    metric_order o = report_metric_order(r);
    if (o.discordant == 0) printf("psnr_flip_order=agree pairs=%d\n", o.pairs);
    else
        printf("psnr_flip_order=differ pairs=%d discordant=%d first=%s>%s\n", o.pairs, o.discordant, r->tiers[o.a].name,
               r->tiers[o.b].name);
}

/* One grid row: level l (kind k + 1: widened by the grid's soften[k], back
   to front, at its inverse opacity) drawn by every tier that ran, each
   image written into tmp and kept in frames for the measuring. */
static ht_result render_lod_row(const options *o, const char *tmp, const grid_levels *lv, tier_scene *small,
                                report *rep, int l, int kind, tier_frame *frames, char *err, size_t err_size) {
    report_lod_grid *g = &rep->lods;
    ht_result r = HT_OK;
    char soft[32] = "";
    if (kind) snprintf(soft, sizeof soft, "soft%g", (double)g->soften[kind - 1]);
    for (int t = 0; t < rep->tier_count && r == HT_OK; t++) {
        report_lod_cell *c = report_lod_row_cell(g, l, kind, t);
        if (!rep->tiers[t].ran) continue;
        fprintf(stderr, "haircompare: rendering %s %d%s%s with %s at %gx\n", lv->cards[l] ? "cards, level" : "level", l,
                kind ? " " : "", soft, rep->tiers[t].name, g->size);
        tier_render(o->view.bundle, small, rep->tiers[t].tier, o->view.frames, &frames[t]);
        if (!(c->ran = frames[t].ran)) continue;
        c->frame_ms = frames[t].frame_ms;
        char name[sizeof rep->tiers[t].name], path[4300];
        memcpy(name, rep->tiers[t].name, sizeof name); /* a copy, as in compare_tier (-Wrestrict) */
        snprintf(c->image, sizeof c->image, "lod%d%s-%s.png", l, soft, name);
        snprintf(path, sizeof path, "%s/%s", tmp, c->image);
        ht_image img = { 0 };
        r = write_frame(path, frames[t].rgba, g->width, g->height, &img, err, err_size);
        ht_image_free(&img);
    }
    return r;
}

/* A row's cells against (level 0, the reference tier). */
static ht_result measure_lod_row(report *rep, report_lod_cell *cells, const tier_frame *frames, const tier_frame *ref,
                                 bool reference_row, char *err, size_t err_size) {
    const report_lod_grid *g = &rep->lods;
    ht_result r = HT_OK;
    for (int t = 0; t < rep->tier_count && r == HT_OK; t++) {
        report_lod_cell *c = &cells[t];
        if (!c->ran || !ref->ran) continue;
        r = ht_metrics_compare(&(ht_metrics_desc){ .reference = ref->rgba, .test = frames[t].rgba,
                                                   .width = g->width, .height = g->height },
                               &c->whole, NULL, err, err_size);
        if (reference_row && t == rep->reference) c->whole.psnr_db = INFINITY;
        c->cost_ratio = c->frame_ms / ref->frame_ms;
    }
    return r;
}

/* The factors of the bundle's soft cells (lod.h), in the order its cells
   first name them, into g: the grid shows each strand level past 0 soft by
   each too. */
static void measured_softens(const report *rep, report_lod_grid *g) {
    g->soften_count = 0;
    for (int i = 0; i < rep->measured_lods.cell_count; i++) {
        const float s = rep->measured_lods.cells[i].soften;
        int k = 0;
        while (k < g->soften_count && g->soften[k] != s) k++;
        if (s > 1 && k == g->soften_count && k < HT_LOD_MAX_SOFTENS) g->soften[g->soften_count++] = s;
    }
}

/* The LOD x tier grid (report.h): every level lv holds (the bundle's
   stored ones, cards too, else those built from the scene), and each
   strand level past 0 soft when the bundle measured soft cells, drawn by
   every tier that ran, at the measured size nearest REPORT_LOD_SIZE,
   against (level 0, the reference tier). For a bundle that stores this
   scene's levels or was measured with --measure-lods. */
static ht_result build_lod_grid(const options *o, const char *tmp, const tier_scene *ts, const grid_levels *lv,
                                report *rep, char *err, size_t err_size) {
    report_lod_grid *g = &rep->lods;
    if ((rep->measured_lods.cell_count == 0 && !lv->stored) || rep->reference < 0) return HT_OK;
    g->size = report_lod_size(&rep->measured_lods);
    g->source = lv->stored ? REPORT_LOD_STORED : lv->other_scene ? REPORT_LOD_BUILT_OTHER_SCENE : REPORT_LOD_BUILT;
    tier_scene small = *ts;
    small.scene.width = (int)fmax(16, lround(ts->scene.width * g->size));
    small.scene.height = (int)fmax(16, lround(ts->scene.height * g->size));
    g->width = small.scene.width;
    g->height = small.scene.height;
    g->levels = lv->count < REPORT_LOD_MAX_LEVELS ? lv->count : REPORT_LOD_MAX_LEVELS;
    measured_softens(rep, g);
    static tier_frame frames[REPORT_LOD_MAX_LEVELS][REPORT_MAX_TIERS],
        soft_frames[HT_LOD_MAX_SOFTENS][REPORT_LOD_MAX_LEVELS][REPORT_MAX_TIERS];
    memset(frames, 0, sizeof frames);
    memset(soft_frames, 0, sizeof soft_frames);
    ht_result r = HT_OK;
    for (int l = 0; l < g->levels && r == HT_OK; l++) {
        bool borrowed = false;
        ht_mesh level;
        if ((r = grid_levels_mesh(lv, &ts->hair, l, &level, &borrowed)) != HT_OK) {
            snprintf(err, err_size, "%s: geometry: cannot %s LOD %d: %s", lv->stored ? rep->bundle : rep->scene,
                     lv->stored ? "read" : "build", l, ht_result_string(r));
            break;
        }
        g->strands[l] = level.component_count;
        g->cards[l] = lv->cards[l];
        g->strands_per_card[l] = lv->cards[l] ? lv->param[l] : 0;
        small.hair = level;
        small.opacity = 0.0f;
        r = render_lod_row(o, tmp, lv, &small, rep, l, 0, frames[l], err, err_size);
        for (int k = 0; k < g->soften_count && r == HT_OK && l > 0 && !lv->cards[l]; k++) {
            g->soft[k][l] = true;
            if ((r = ht_mesh_widen_back_to_front(&level, g->soften[k], ts->scene.camera.eye, &small.hair)) == HT_OK) {
                small.opacity = 1.0f / g->soften[k];
                r = render_lod_row(o, tmp, lv, &small, rep, l, k + 1, soft_frames[k][l], err, err_size);
                ht_mesh_free(&small.hair);
            } else {
                snprintf(err, err_size, "%s: geometry: LOD %d soft %g: %s", rep->scene, l, (double)g->soften[k],
                         ht_result_string(r));
            }
        }
        if (!borrowed) ht_mesh_free(&level);
    }
    const tier_frame *ref = &frames[0][rep->reference];
    for (int l = 0; l < g->levels && r == HT_OK; l++) {
        r = measure_lod_row(rep, g->cells[l], frames[l], ref, l == 0, err, err_size);
        for (int k = 0; k < g->soften_count && r == HT_OK; k++)
            if (g->soft[k][l]) r = measure_lod_row(rep, g->soft_cells[k][l], soft_frames[k][l], ref, false, err, err_size);
    }
    report_lod_attach_measured(rep);
    for (int l = 0; l < REPORT_LOD_MAX_LEVELS; l++)
        for (int t = 0; t < REPORT_MAX_TIERS; t++) {
            tier_frame_free(&frames[l][t]);
            for (int k = 0; k < HT_LOD_MAX_SOFTENS; k++) tier_frame_free(&soft_frames[k][l][t]);
        }
    return r;
}

/* A bundle storing its own level 0 (hairgen --cards: the scene's strands
   with their uv moved into the atlas) draws it in every tier's image: the
   scene's own mesh would sample the atlas as the material's texture. */
static ht_result use_stored_level0(const char *bundle, const grid_levels *lv, tier_scene *ts, char *err,
                                   size_t err_size) {
    if (!lv->stored || lv->file.levels[0].kind == HT_LOD_KIND_SCENE) return HT_OK;
    ht_mesh level0;
    bool borrowed;
    ht_result r = grid_levels_mesh(lv, &ts->hair, 0, &level0, &borrowed);
    if (r != HT_OK) {
        snprintf(err, err_size, "%s/%s: level 0: %s", bundle, HT_LOD_FILE_NAME, ht_result_string(r));
        return r;
    }
    ht_mesh_free(&ts->hair);
    ts->hair = level0;
    return HT_OK;
}

/* The grid on stdout: each (level, tier) cell's PSNR and cost, and the
   bundle's beside them when it has them. */
static void print_lod_grid(const report *r) {
    const report_lod_grid *g = &r->lods;
    if (!g->levels) return;
    printf("lods: %s at %g of the scene's size, against (level 0, %s)\n",
           g->source == REPORT_LOD_STORED ? "the bundle's stored levels" : "levels built from the scene", g->size,
           report_reference_name(r));
    printf("%-5s %-7s %8s %-7s %7s %6s %10s %11s\n", "level", "kind", "strands", "tier", "psnr_db", "cost",
           "bundle_db", "bundle_cost");
    for (int l = 0; l < g->levels; l++)
        for (int kind = 0; kind <= g->soften_count; kind++)
            for (int t = 0; t < r->tier_count && report_lod_has_row(g, l, kind); t++) {
                const report_lod_cell *c = report_lod_row_cell(g, l, kind, t);
                if (!c->ran) continue;
                char soft[32];
                snprintf(soft, sizeof soft, "soft%g", kind ? (double)g->soften[kind - 1] : 0.0);
                printf("%-5d %-7s %8u %-7s %7.2f %6.3f", l, g->cards[l] ? "cards" : kind ? soft : "strands",
                       g->strands[l], r->tiers[t].name, c->whole.psnr_db, c->cost_ratio);
                if (c->measured) printf(" %10.2f %11.3f", c->measured_psnr_db, c->measured_cost_ratio);
                printf("\n");
            }
}

/* Renders, measures and writes every file into tmp; 0 or 1. */
static int build(const options *o, const char *tmp, const tier_scene *ts, const grid_levels *lv, report *rep, char *err,
                 size_t err_size) {
    tier_frame frames[REPORT_MAX_TIERS] = { 0 };
    ht_image images[REPORT_MAX_TIERS] = { 0 }, heats[REPORT_MAX_TIERS] = { 0 };
    int rc = 1;
    bool any = false;
    uint8_t bg[3];
    for (int c = 0; c < 3; c++) bg[c] = (uint8_t)(ts->scene.background[c] * 255.0f + 0.5f);
    tier_render_use_context(o->view.context, o->view.egl_device, o->view.api);
    for (int t = 0; t < rep->tier_count; t++) {
        report_tier *p = &rep->tiers[t];
        if (!p->known) {
            snprintf(p->reason, sizeof p->reason, "a tier this runtime does not know");
            continue;
        }
        fprintf(stderr, "haircompare: rendering %s\n", p->name);
        tier_render(o->view.bundle, ts, p->tier, o->view.frames, &frames[t]);
        p->ran = frames[t].ran;
        p->frame_ms = frames[t].frame_ms;
        snprintf(p->reason, sizeof p->reason, "%s", frames[t].reason);
        if (!rep->driver[0]) snprintf(rep->driver, sizeof rep->driver, "%s", frames[t].driver);
        if (!p->ran) continue;
        any = true;
        char path[4300];
        char name[sizeof p->name]; /* a copy, as in compare_tier (-Wrestrict) */
        memcpy(name, p->name, sizeof name);
        snprintf(p->image, sizeof p->image, "%s.png", name);
        snprintf(path, sizeof path, "%s/%s", tmp, p->image);
        if (write_frame(path, frames[t].rgba, ts->scene.width, ts->scene.height, &images[t], err, err_size) != HT_OK)
            goto done;
    }
    if (!any) {
        snprintf(err, err_size, "no tier ran: %s", rep->tier_count ? rep->tiers[0].reason : "the bundle lists none");
        goto done;
    }
    int ref = rep->reference = report_pick_reference(rep);
    for (int t = 0; ref >= 0 && t < rep->tier_count; t++)
        if (rep->tiers[t].ran && compare_tier(o, tmp, ts, bg, &frames[ref], &frames[t], t == ref, &rep->tiers[t],
                                              &heats[t], err, err_size) != HT_OK)
            goto done;
    if (ref >= 0 && write_crops(o, tmp, rep, bg, images, heats, err, err_size) != HT_OK) goto done;
    if (build_lod_grid(o, tmp, ts, lv, rep, err, err_size) != HT_OK) goto done;

    char path[4300];
    snprintf(path, sizeof path, "%s/index.html", tmp);
    FILE *f = fopen(path, "wb");
    if (!f) {
        snprintf(err, err_size, "%s/index.html: cannot write: %s", o->out, strerror(errno));
        goto done;
    }
    int written = report_write_page(f, rep);
    if (fclose(f) != 0 || written != 0) {
        snprintf(err, err_size, "%s/index.html: write failed", o->out);
        goto done;
    }
    rc = 0;
done:
    for (int t = 0; t < rep->tier_count; t++) {
        tier_frame_free(&frames[t]);
        ht_image_free(&images[t]);
        ht_image_free(&heats[t]);
    }
    return rc;
}

int main(int argc, char **argv) {
    options o;
    int rc = parse_args(argc, argv, &o);
    if (rc != CLI_RUN) return rc;

    char err[8192], tmp[4200];
    report rep;
    report_init(&rep);
    rep.bundle = o.view.bundle;
    rep.scene = o.view.scene;
    rep.frames = o.view.frames;
    tier_scene ts = { 0 };
    grid_levels lv = { 0 };
    if (report_read_bundle(&rep, o.view.bundle, err, sizeof err) != HT_OK ||
        tier_scene_load(o.view.scene, &ts, err, sizeof err) != HT_OK ||
        grid_levels_open(o.view.bundle, o.view.scene, &ts.hair, &lv, err, sizeof err) != HT_OK ||
        use_stored_level0(o.view.bundle, &lv, &ts, err, sizeof err) != HT_OK) {
        fprintf(stderr, "haircompare: %s\n", err);
        grid_levels_close(&lv);
        tier_scene_free(&ts);
        report_free(&rep);
        return 1;
    }
    rep.width = ts.scene.width;
    rep.height = ts.scene.height;
    if (report_dir_begin(o.out, tmp, sizeof tmp, err, sizeof err) != HT_OK) {
        fprintf(stderr, "haircompare: %s\n", err);
        rc = 1;
    } else {
        rc = build(&o, tmp, &ts, &lv, &rep, err, sizeof err);
        if (rc == 0 && report_dir_publish(tmp, o.out, err, sizeof err) != HT_OK) rc = 1;
        if (rc != 0) {
            report_dir_remove(tmp);
            /* Name the report's own path, not the temporary one that is gone. */
            size_t tl = strlen(tmp);
            if (strncmp(err, tmp, tl) == 0) {
                char why[4000];
                snprintf(why, sizeof why, "%s", err + tl);
                snprintf(err, sizeof err, "%s%s", o.out, why);
            }
            fprintf(stderr, "haircompare: %s (nothing written)\n", err);
        } else {
            print_table(&rep);
            print_lod_grid(&rep);
            printf("haircompare: wrote %s/index.html\n", o.out);
        }
    }
    grid_levels_close(&lv);
    tier_scene_free(&ts);
    report_free(&rep);
    return rc;
}

/* tier_sheet — the technical artist's contact sheet: one scene rendered with
   every tier of a bundle side by side, each with its error against `full`.

   build/tier_sheet --bundle DIR --scene SCENE.json [--frames N] [--context osmesa|egl]
                    [--egl-device N] -o SHEET.png

   Panels, left to right: marschner (only when it runs: a Marschner
   material's bundle), full, vertex, fixed4, fixed, gl11; errors are against
   the first panel. Top row: the tier's image
   (forced tier, strict: no silent downgrade; a tier the device cannot run
   is a grey panel with the reason). Bottom row: per-pixel max channel
   difference from full's image through a ramp (black 0, red, yellow, white
   at 64/255 and above); full's own heatmap is black. Labels use a built-in
   3x5 bitmap font, drawn after the errors are measured.

   Prints a table on stdout: tier, frame ms (median of N frames after one
   warm-up, each ended by glFinish), mean and max error vs full in /255. The
   mean is over the pixels hair or head covers in either image (pixels that
   differ from the background), so an empty border does not dilute it.
   --context and --egl-device pick the GL context as hairview's do
   (platform/offscreen.h); each tier gets a fresh one.
   Exit status 0 when the sheet is written (some tiers may not have run),
   1 when no tier ran or on any other failure (one line on stderr, no
   sheet), 2 on usage. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "offscreen.h"
#include "view_args.h"
#include "compare/tier_render.h"

#define TIERS 6          /* marschner, full, vertex, fixed4, fixed, gl11: the sheet's columns */
#define GAP 4            /* pixels between panels */
#define HEAT_FULL 64     /* difference (/255) the ramp reaches white at */
#define FONT_SCALE 2
#define MAX_FRAMES 1000

static const ht_tier columns[TIERS] = { HT_TIER_MARSCHNER, HT_TIER_FULL, HT_TIER_VERTEX,
                                        HT_TIER_FIXED4,    HT_TIER_FIXED, HT_TIER_GL11 };

typedef view_args options;

typedef struct panel {
    tier_frame frame;      /* the image (NULL when the tier did not run), reason, frame ms */
    double mean_err;
    int max_err;
    bool compared;
} panel;

/* ---- a 3x5 bitmap font: rows top to bottom, '#' lit ---- */

typedef struct glyph {
    char c;
    const char *rows; /* 15 characters, 3 per row */
} glyph;

static const glyph font[] = {
    { 'A', ".#.#.#####.##.#" }, { 'B', "##.#.###.#.###." }, { 'C', ".###..#..#...##" },
    { 'D', "##.#.##.##.###." }, { 'E', "####..##.#..###" }, { 'F', "####..##.#..#.." },
    { 'G', ".###..#.##.#.##" }, { 'H', "#.##.#####.##.#" }, { 'I', "###.#..#..#.###" },
    { 'J', "..#..#..##.#.#." }, { 'K', "#.##.###.#.##.#" }, { 'L', "#..#..#..#..###" },
    { 'M', "#.########.##.#" }, { 'N', "##.#.##.##.##.#" }, { 'O', ".#.#.##.##.#.#." },
    { 'P', "##.#.###.#..#.." }, { 'Q', ".#.#.##.###..##" }, { 'R', "##.#.###.#.##.#" },
    { 'S', ".###...#...###." }, { 'T', "###.#..#..#..#." }, { 'U', "#.##.##.##.####" },
    { 'V', "#.##.##.##.#.#." }, { 'W', "#.##.########.#" }, { 'X', "#.##.#.#.#.##.#" },
    { 'Y', "#.##.#.#..#..#." }, { 'Z', "###..#.#.#..###" }, { '0', "####.##.##.####" },
    { '1', ".#.##..#..#.###" }, { '2', "##...#.#.#..###" }, { '3', "##...#.#...###." },
    { '4', "#.##.####..#..#" }, { '5', "####..##...###." }, { '6', ".###..####.####" },
    { '7', "###..#.#..#..#." }, { '8', "####.#####.####" }, { '9', "####.####..###." },
    { '.', ".............#." }, { ',', "..........#.#.." }, { ':', "....#.....#...." },
    { '-', "......###......" }, { '/', "..#..#.#.#..#.." }, { '(', "..#.#..#..#...#" },
    { ')', "#...#..#..#.#.." }, { '=', "...###...###..." }, { '_', "............###" },
    { '+', "....#.###.#...." }, { '%', "#.#..#.#.#..#.#" }, { '\'', ".#..#.........." },
    { '"', "#.##.#........." }, { '>', "#...#...#.#.#.." }, { '<', "..#.#.#...#...#" },
    { '?', "##...#.#.....#." },
};

static const char *glyph_rows(char c) {
    c = (char)toupper((unsigned char)c);
    for (size_t i = 0; i < sizeof font / sizeof font[0]; i++)
        if (font[i].c == c) return font[i].rows;
    return c == ' ' ? NULL : glyph_rows('?');
}

#define GLYPH_W (3 * FONT_SCALE)
#define GLYPH_H (5 * FONT_SCALE)
#define ADVANCE (GLYPH_W + FONT_SCALE)
#define LINE (GLYPH_H + 2 * FONT_SCALE)

static void fill_rect(ht_image *img, int x0, int y0, int w, int h, const unsigned char rgb[3]) {
    for (int y = y0 < 0 ? 0 : y0; y < y0 + h && y < img->height; y++)
        for (int x = x0 < 0 ? 0 : x0; x < x0 + w && x < img->width; x++)
            memcpy(img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * 3, rgb, 3);
}

/* One line of text on a dark box, clipped to max_chars. */
static void draw_text(ht_image *img, int x, int y, const char *text, int max_chars) {
    static const unsigned char box[3] = { 0, 0, 0 }, ink[3] = { 235, 235, 235 };
    int n = (int)strlen(text);
    if (n > max_chars) n = max_chars;
    if (n == 0) return;
    fill_rect(img, x - FONT_SCALE, y - FONT_SCALE, n * ADVANCE + FONT_SCALE, LINE, box);
    for (int i = 0; i < n; i++) {
        const char *rows = glyph_rows(text[i]);
        if (!rows) continue;
        for (int k = 0; k < 15; k++)
            if (rows[k] == '#')
                fill_rect(img, x + i * ADVANCE + (k % 3) * FONT_SCALE, y + (k / 3) * FONT_SCALE, FONT_SCALE,
                          FONT_SCALE, ink);
    }
}

/* Word-wrapped text from (x, y), at most max_chars a line. */
static void draw_wrapped(ht_image *img, int x, int y, const char *text, int max_chars, int max_lines) {
    char line[256];
    if (max_chars > (int)sizeof line - 1) max_chars = (int)sizeof line - 1;
    for (int l = 0; l < max_lines && *text; l++) {
        int n = (int)strlen(text);
        if (n > max_chars) {
            n = max_chars;
            while (n > max_chars / 2 && text[n] != ' ') n--;
        }
        memcpy(line, text, (size_t)n);
        line[n] = '\0';
        draw_text(img, x, y + l * LINE, line, max_chars);
        text += n;
        while (*text == ' ') text++;
    }
}

/* ---- comparing and composing ---- */

static int max_channel_diff(const unsigned char *a, const unsigned char *b) {
    int m = 0;
    for (int c = 0; c < 3; c++) {
        int d = abs((int)a[c] - (int)b[c]);
        if (d > m) m = d;
    }
    return m;
}

/* Covered: anything but the cleared background (one step of rounding allowed). */
static bool covered(const unsigned char *px, const unsigned char bg[3]) {
    return max_channel_diff(px, bg) > 1;
}

static void compare(const ht_scene *s, const panel *full, panel *p) {
    unsigned char bg[3];
    for (int c = 0; c < 3; c++) bg[c] = (unsigned char)(s->background[c] * 255.0f + 0.5f);
    size_t n = (size_t)s->width * (size_t)s->height, count = 0;
    double sum = 0;
    int max = 0;
    for (size_t i = 0; i < n; i++) {
        const unsigned char *a = full->frame.rgba + 4 * i, *b = p->frame.rgba + 4 * i;
        int d = max_channel_diff(a, b);
        if (d > max) max = d;
        if (covered(a, bg) || covered(b, bg)) {
            sum += d;
            count++;
        }
    }
    p->mean_err = count ? sum / (double)count : 0.0;
    p->max_err = max;
    p->compared = true;
}

static void heat(int d, unsigned char out[3]) {
    int t = d >= HEAT_FULL ? 3 * 255 : d * 3 * 255 / HEAT_FULL; /* 0..765: red, then green, then blue rise */
    for (int c = 0; c < 3; c++) {
        int v = t - c * 255;
        out[c] = (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
    }
}

/* Copies a GL (bottom-up RGBA) image, or its heatmap against `ref`, into the sheet. */
static void blit(ht_image *sheet, int x0, int y0, const ht_scene *s, const unsigned char *rgba,
                 const unsigned char *ref) {
    for (int y = 0; y < s->height; y++) {
        const unsigned char *src = offscreen_row(rgba, s->width, s->height, y);
        const unsigned char *rsrc = ref ? offscreen_row(ref, s->width, s->height, y) : NULL;
        unsigned char *dst = sheet->pixels + ((size_t)(y0 + y) * (size_t)sheet->width + (size_t)x0) * 3;
        for (int x = 0; x < s->width; x++) {
            if (rsrc) heat(max_channel_diff(src + 4 * x, rsrc + 4 * x), dst + 3 * x);
            else memcpy(dst + 3 * x, src + 4 * x, 3);
        }
    }
}

/* Columns first..TIERS-1 are shown: the marschner column only when that
   tier ran (a Scheuermann bundle has none); errors are against column first. */
static void compose(ht_image *sheet, const ht_scene *s, const panel *panels, int first) {
    static const unsigned char grey[3] = { 90, 90, 90 }, gap[3] = { 40, 40, 40 };
    fill_rect(sheet, 0, 0, sheet->width, sheet->height, gap);
    const int chars = (s->width - 4 * FONT_SCALE) / ADVANCE;
    const int lines = (s->height - 4 * FONT_SCALE) / LINE - 1;
    const panel *full = &panels[first];
    const char *ref = ht_tier_name(columns[first]);
    for (int t = first; t < TIERS; t++) {
        const panel *p = &panels[t];
        const int x = (t - first) * (s->width + GAP), y = s->height + GAP, pad = 2 * FONT_SCALE;
        char text[700];
        if (p->frame.ran) {
            blit(sheet, x, 0, s, p->frame.rgba, NULL);
            snprintf(text, sizeof text, "%s  %.1f ms", ht_tier_name(columns[t]), p->frame.frame_ms);
            draw_text(sheet, x + pad, pad, text, chars);
        } else {
            fill_rect(sheet, x, 0, s->width, s->height, grey);
            snprintf(text, sizeof text, "%s: not run", ht_tier_name(columns[t]));
            draw_text(sheet, x + pad, pad, text, chars);
            draw_wrapped(sheet, x + pad, pad + LINE, p->frame.reason, chars, lines);
        }
        if (p->compared) {
            blit(sheet, x, y, s, p->frame.rgba, full->frame.rgba);
            snprintf(text, sizeof text, "vs %s: mean %.2f  max %d /255", ref, p->mean_err, p->max_err);
        } else {
            fill_rect(sheet, x, y, s->width, s->height, grey);
            if (p->frame.ran) snprintf(text, sizeof text, "no %s image to compare with", ref);
            else snprintf(text, sizeof text, "no image");
        }
        draw_text(sheet, x + pad, y + pad, text, chars);
    }
}

static void print_table(const panel *panels, int first) {
    printf("panels left to right:");
    for (int t = first; t < TIERS; t++) printf("%s %s", t == first ? "" : ",", ht_tier_name(columns[t]));
    printf("; top: image, bottom: error vs %s (black 0, white >= %d/255)\n", ht_tier_name(columns[first]),
           HEAT_FULL);
    printf("%-9s %9s %9s %7s\n", "tier", "frame_ms", "mean_err", "max_err");
    for (int t = first; t < TIERS; t++) {
        const panel *p = &panels[t];
        const char *name = ht_tier_name(columns[t]);
        if (!p->frame.ran) printf("%-9s %9s %9s %7s  not run: %s\n", name, "-", "-", "-", p->frame.reason);
        else if (!p->compared) printf("%-9s %9.3f %9s %7s\n", name, p->frame.frame_ms, "-", "-");
        else printf("%-9s %9.3f %9.2f %7d\n", name, p->frame.frame_ms, p->mean_err, p->max_err);
    }
}

/* ---- command line ---- */

static const struct option long_options[] = { VIEW_ARGS_LONG_OPTIONS, { 0 } };

static const cli_program program = {
    .name = "tier_sheet",
    .synopsis = "usage: tier_sheet --bundle DIR --scene SCENE.json [--frames N] [--context osmesa|egl] [--egl-device N]\n"
                "                  [--api gl|gles1|gles2|gles3]\n"
                "                  -o SHEET.png\n",
    .help = "Renders SCENE with every tier of the bundle (forced, strict) side by side.\n"
            "Panels left to right: marschner (when it runs), full, vertex, fixed4, fixed, gl11; errors are\n"
            "against the first. Top row: the tier's image, or a grey\n"
            "panel with the reason it cannot run here. Bottom row: per-pixel max channel\n"
            "difference from it (black 0, then red, yellow, white at " CLI_STR(HEAT_FULL) "/255 and above).\n"
            "Prints tier, frame ms (median of N frames, default 5, each ended by glFinish),\n"
            "mean error (over pixels covered in either image) and max error, in /255.\n"
            "--context: how the GL context is made (default HAIRTIER_CONTEXT, else osmesa where\n"
            "libOSMesa loads, else egl); --egl-device N: EGL device N (EGL_EXT_platform_device);\n"
            "--api gles1|gles2|gles3: a GL ES context (EGL; ES 1.1: fixed4, fixed, gl11).\n",
    .short_options = VIEW_ARGS_SHORT_OPTIONS,
    .long_options = long_options,
};

int main(int argc, char **argv) {
    options o = view_args_defaults(5);
    int rc = view_args_parse(&program, argc, argv, &o, MAX_FRAMES, true);
    if (rc != CLI_RUN) return rc;

    char err[1024];
    tier_scene ts;
    if (tier_scene_load(o.scene, &ts, err, sizeof err) != HT_OK) {
        fprintf(stderr, "tier_sheet: %s\n", err);
        return 1;
    }
    const ht_scene scene = ts.scene;

    panel panels[TIERS] = { 0 };
    tier_render_use_context(o.context, o.egl_device, o.api);
    for (int t = 0; t < TIERS; t++) tier_render(o.bundle, &ts, columns[t], o.frames, &panels[t].frame);
    bool any = false;
    for (int t = 0; t < TIERS; t++) any = any || panels[t].frame.ran;
    if (!any) {
        /* A bad bundle fails every tier the same way: one line, no sheet. */
        fprintf(stderr, "tier_sheet: no tier ran: %s\n", panels[1].frame.reason); /* full's */
        for (int t = 0; t < TIERS; t++) tier_frame_free(&panels[t].frame);
        tier_scene_free(&ts);
        return 1;
    }
    const int first = panels[0].frame.ran ? 0 : 1, shown = TIERS - first;
    if (panels[first].frame.ran)
        for (int t = first; t < TIERS; t++)
            if (panels[t].frame.ran) compare(&scene, &panels[first], &panels[t]);

    ht_image sheet = { 0 };
    rc = 0;
    if (ht_image_alloc(&sheet, shown * scene.width + (shown - 1) * GAP, 2 * scene.height + GAP, 3) != HT_OK) {
        fprintf(stderr, "tier_sheet: %s: out of memory\n", o.out);
        rc = 1;
    } else {
        compose(&sheet, &scene, panels, first);
        if (ht_image_write_png(o.out, &sheet, err, sizeof err) != HT_OK) {
            fprintf(stderr, "tier_sheet: %s\n", err);
            rc = 1;
        } else {
            print_table(panels, first);
        }
    }
    ht_image_free(&sheet);
    for (int t = 0; t < TIERS; t++) tier_frame_free(&panels[t].frame);
    tier_scene_free(&ts);
    return rc;
}

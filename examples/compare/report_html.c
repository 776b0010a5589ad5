/* report_html.c — index.html: header, the tiers' image and heatmap cards,
   legend, highlight crops, then the tables (report_table.c) and the plot
   (report_plot.c); report.h. Numbers are written with printf in the C
   locale (the programs never call setlocale). */
#include <stdlib.h>
#include <string.h>

#include "heatmap.h"
#include "report.h"

void report_init(report *r) {
    memset(r, 0, sizeof *r);
    r->reference = -1;
}

void report_free(report *r) {
    for (int i = 0; i < r->note_count; i++) free(r->notes[i]);
    for (int t = 0; t < r->tier_count; t++)
        for (int i = 0; i < r->tiers[t].dropped_count; i++) free(r->tiers[t].dropped[i]);
    report_init(r);
}

void report_escape(FILE *f, const char *s) {
    if (!s) return;
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&#39;", f); break;
        default: fputc(*s, f);
        }
    }
}

int report_pick_reference(const report *r) {
    int ref = -1;
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        if (p->ran && (p->tier == HT_TIER_MARSCHNER || (p->tier == HT_TIER_FULL && ref < 0))) ref = t;
    }
    return ref;
}

const char *report_reference_name(const report *r) {
    return r->reference >= 0 && r->reference < r->tier_count ? r->tiers[r->reference].name : "the reference";
}

void report_write_legend(FILE *f, const report *r) {
    enum { BAR_W = 512, BAR_H = 18, LEFT = 16, W = BAR_W + 2 * LEFT, H = 64, STOPS = 33, TICKS = 5 };
    fprintf(f, "<svg class=\"legend\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
               "xmlns=\"http://www.w3.org/2000/svg\" font-size=\"13\" role=\"img\" "
               "aria-label=\"colour scale: per-pixel CIEDE2000 from 0 to %g\">\n",
            W, H, W, H, REPORT_HEAT_MAX);
    fputs("<defs><linearGradient id=\"heat\" x1=\"0\" x2=\"1\" y1=\"0\" y2=\"0\">\n", f);
    for (int i = 0; i < STOPS; i++) {
        uint8_t c[3];
        double t = (double)i / (STOPS - 1);
        heatmap_colour(t, c);
        fprintf(f, "<stop offset=\"%.4f\" stop-color=\"#%02x%02x%02x\"/>\n", t, c[0], c[1], c[2]);
    }
    fputs("</linearGradient></defs>\n", f);
    fprintf(f, "<rect x=\"%d\" y=\"2\" width=\"%d\" height=\"%d\" fill=\"url(#heat)\" stroke=\"#777\"/>\n", LEFT,
            BAR_W, BAR_H);
    for (int i = 0; i < TICKS; i++) {
        double v = REPORT_HEAT_MAX * i / (TICKS - 1);
        double x = LEFT + BAR_W * (double)i / (TICKS - 1);
        fprintf(f, "<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"#bbb\"/>\n", x, 2 + BAR_H, x,
                2 + BAR_H + 5);
        fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"%s\" fill=\"#ddd\">%s%g</text>\n", x, 2 + BAR_H + 19,
                i == 0 ? "start" : i == TICKS - 1 ? "end" : "middle", i == TICKS - 1 ? "&#8805; " : "", v);
    }
    fprintf(f, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\" fill=\"#aaa\">"
               "per-pixel CIEDE2000 (&#916;E00) against ", LEFT + BAR_W / 2, H - 4);
    report_escape(f, report_reference_name(r));
    fputs("</text>\n", f);
    fputs("</svg>\n", f);
}


/* Cards wrap and images scale down where the window is narrower than one
   (max-width), so nothing needs a sideways scroll; where they fit they
   keep their pixel size, as the screenshot check needs. */
static void write_style(FILE *f, const report *r) {
    fprintf(f,
            "<style>\n"
            "html{background:#15161a}\n"
            "body{margin:0;padding:%dpx;color:#e4e4e4;background:#15161a;"
            "font:14px/1.45 'DejaVu Sans',Verdana,sans-serif}\n"
            "h1{margin:0 0 6px;font-size:24px;font-weight:600}\n"
            "header p{margin:2px 0;color:#b8b8b8}\n"
            "header p.ref{color:#e4e4e4}\n"
            "code{font-family:'DejaVu Sans Mono',monospace;font-size:13px;color:#f0d9a8;overflow-wrap:anywhere}\n"
            ".tiers{display:flex;flex-wrap:wrap;gap:%dpx;margin-top:16px}\n"
            ".tier{width:%dpx;max-width:100%%;margin:0}\n"
            ".crops .tier{width:%dpx}\n"
            ".cap{height:32px;line-height:32px;margin:0;overflow:hidden;white-space:nowrap;text-overflow:ellipsis}\n"
            ".cap b{font-size:17px;margin-right:8px}\n"
            ".cap span{color:#b0b0b0}\n"
            ".tier img,.box{display:block;width:100%%;height:auto;aspect-ratio:%d/%d}\n"
            ".crops img,.crops .box{aspect-ratio:%d/%d;image-rendering:pixelated;margin-bottom:6px}\n"
            "img{outline:1px solid #303139}\n"
            ".box{box-sizing:border-box;padding:4%%;background:#1d1e23;color:#a8a8a8;border:1px dashed #4a4b52;"
            "overflow:hidden;display:flex;flex-direction:column;justify-content:center;text-align:center;"
            "font-size:13px}\n"
            "h2{font-size:18px;margin:28px 0 10px;font-weight:600}\n"
            "table{border-collapse:collapse}\n"
            ".wide{overflow-x:auto}\n"
            "th,td{border:1px solid #3a3b42;padding:6px 9px;vertical-align:top;text-align:left}\n"
            "thead th{background:#23242a;font-weight:600}\n"
            "thead th.group{text-align:center}\n"
            "th.measured,td.measured{background:#1b2126}\n"
            "thead th.measured{background:#222b31}\n"
            "td.none{color:#8a8a8a;text-align:center}\n"
            "tbody th span{color:#9a9a9a;font-size:12px;font-weight:400}\n"
            ".lodrow{display:flex;flex-wrap:wrap;gap:8px 12px;margin-bottom:14px}\n"
            ".lodhead{width:140px;font-size:15px;font-weight:600}\n"
            ".lodhead span{color:#9a9a9a;font-size:12px;font-weight:400}\n"
            "figure.lod{margin:0;max-width:100%%;font-size:12px}\n"
            "figure.lod .cap{height:20px;line-height:20px}\n"
            "figure.lod .cap b{font-size:13px}\n"
            "figure.lod img{display:block;max-width:100%%;height:auto}\n"
            "figure.lod p{margin:4px 0 0}\n"
            "span.measured{color:#9fc3d8}\n"
            "tbody th{font-size:15px}\n"
            "td.num{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums}\n"
            "td.needs{max-width:360px}\n"
            "td.notrun{color:#e0a070}\n"
            "td.dropped{max-width:760px;font-size:13px;color:#c8c8c8}\n"
            "td.dropped ul{margin:0;padding-left:18px}\n"
            "p.note,ul.notes{color:#b8b8b8;max-width:1100px}\n"
            ".plot{display:block;max-width:100%%;height:auto;background:#1c1d22;border:1px solid #3a3b42}\n"
            ".legend{display:block;max-width:100%%;height:auto}\n"
            "</style>\n",
            REPORT_MARGIN, REPORT_GAP, r->width, r->crop.w * REPORT_CROP_SCALE, r->width, r->height,
            r->crop.w > 0 ? r->crop.w : 1, r->crop.h > 0 ? r->crop.h : 1);
}

static void write_header(FILE *f, const report *r) {
    const char *ref = report_reference_name(r);
    fputs("<header>\n<h1>hairtier tiers: ", f);
    report_escape(f, r->material);
    fputs("</h1>\n<p>bundle <code>", f);
    report_escape(f, r->bundle);
    fputs("</code>, scene <code>", f);
    report_escape(f, r->scene);
    fprintf(f, "</code>, %d&times;%d</p>\n<p>every tier forced (strict) on <code>", r->width, r->height);
    report_escape(f, r->driver[0] ? r->driver : "no context");
    fprintf(f, "</code>; frame ms: median of %d frame%s after one warm-up, each ended by glFinish</p>\n", r->frames,
            r->frames == 1 ? "" : "s");
    if (r->reference >= 0) {
        fputs("<p class=\"ref\">reference: <b>", f);
        report_escape(f, ref);
        fputs("</b> (the marschner tier when it runs, else full): every heatmap, error and cost on this page is "
              "measured against it</p>\n<p>each tier: its image, below it its per-pixel CIEDE2000 against <b>", f);
        report_escape(f, ref);
        fputs("</b> (scale under the images)</p>\n", f);
    } else {
        fputs("<p class=\"ref\">no reference: neither marschner nor full ran here, so nothing is compared</p>\n", f);
    }
    fputs("</header>\n", f);
}

static void write_missing(FILE *f, const char *what, const char *what_name, const char *why) {
    fprintf(f, "<div class=\"box\">%s", what);
    report_escape(f, what_name);
    if (why) {
        fputs("<br>", f);
        report_escape(f, why);
    }
    fputs("</div>\n", f);
}

static void write_img(FILE *f, const char *file, int w, int h, const char *name, const char *what) {
    fputs("<img src=\"", f);
    report_escape(f, file);
    fprintf(f, "\" width=\"%d\" height=\"%d\" alt=\"", w, h);
    report_escape(f, name);
    fputs(what, f);
    fputs("\">\n", f);
}

static void write_images(FILE *f, const report *r) {
    const char *ref = report_reference_name(r);
    fputs("<div class=\"tiers\">\n", f);
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        fputs("<figure class=\"tier\">\n<p class=\"cap\"><b>", f);
        report_escape(f, p->name);
        fputs("</b><span>", f);
        if (p->ran) fprintf(f, "%.1f ms", p->frame_ms);
        if (p->compared && t != r->reference) {
            fprintf(f, ", %.2f&times; ", p->cost_ratio);
            report_escape(f, ref);
            fputs("&#8217;s cost", f);
        }
        if (!p->ran) fputs("not run", f);
        fputs("</span></p>\n", f);
        if (p->image[0]) write_img(f, p->image, r->width, r->height, p->name, " tier");
        else write_missing(f, "this device cannot run this tier:", NULL, p->reason);
        fputs("<p class=\"cap\"><span>", f);
        if (p->heatmap[0]) {
            fputs("vs ", f);
            report_escape(f, ref);
            fprintf(f, ": &#916;E00 mean %.2f, p95 %.2f; PSNR %.1f dB", p->whole.delta_e00_mean,
                    p->whole.delta_e00_p95, p->whole.psnr_db);
        } else if (p->compared) {
            fputs("the reference every heatmap is measured against", f);
        }
        fputs("</span></p>\n", f);
        if (p->heatmap[0]) write_img(f, p->heatmap, r->width, r->height, p->name, " error");
        else if (p->compared) write_missing(f, "the reference: ", p->name, "no error to show");
        else write_missing(f, p->ran ? "no heatmap: no reference tier (marschner or full) ran here" : "no image",
                           NULL, NULL);
        fputs("</figure>\n", f);
    }
    fputs("</div>\n", f);
}

/* Each tier's crop over its heatmap's, one line of cards. */
static void write_crops(FILE *f, const report *r) {
    if (r->crop.w == 0) return;
    /* the region shrinks to a frame smaller than REPORT_CROP_SIZE */
    const int w = r->crop.w * REPORT_CROP_SCALE, h = r->crop.h * REPORT_CROP_SCALE;
    const char *ref = report_reference_name(r);
    fprintf(f, "<h2>Brightest highlight, %d&times;</h2>\n<p class=\"note\">The %d&times;%d pixels at (%d, %d) "
               "(top-left corner, image pixels from the top-left) where <b>", REPORT_CROP_SCALE, r->crop.w,
            r->crop.h, r->crop.x, r->crop.y);
    report_escape(f, ref);
    fprintf(f, "</b>&#8217;s hair is brightest (the most luminance summed over hair pixels), cut from every tier&#8217;s "
               "image (top) and heatmap (below it) and enlarged %d&times; with nearest-neighbour pixels.</p>\n"
               "<div class=\"tiers crops\">\n", REPORT_CROP_SCALE);
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        if (!p->crop[0]) continue;
        fputs("<figure class=\"tier\">\n<p class=\"cap\"><b>", f);
        report_escape(f, p->name);
        fputs("</b></p>\n", f);
        write_img(f, p->crop, w, h, p->name, " highlight");
        if (p->heatmap_crop[0]) write_img(f, p->heatmap_crop, w, h, p->name, " highlight error");
        else write_missing(f, t == r->reference ? "the reference" : "no heatmap", NULL, NULL);
        fputs("</figure>\n", f);
    }
    fputs("</div>\n", f);
}

static void write_definitions(FILE *f, const report *r) {
    const char *ref = report_reference_name(r);
    fputs("<p class=\"note\">PSNR, SSIM and &#916;E00 over the whole frame; the hair-pixel column counts the "
          "pixels where either image differs from the background. Definitions: <code>shadergen/metrics.h</code> "
          "(SSIM: Wang et al. 2004 on luminance; &#916;E00: CIEDE2000 after sRGB &#8594; CIELAB D65, mean and "
          "nearest-rank 95th percentile). Cost: the tier&#8217;s median frame time over ", f);
    report_escape(f, ref);
    fputs("&#8217;s, on ", f);
    report_escape(f, r->driver[0] ? r->driver : "no context");
    fputs(" (a ratio measured in this run, side by side; not a prediction for other devices). "
          "Heatmap colours: cubehelix (Green 2011), luminance rising with the error.</p>\n", f);
}

static void write_notes(FILE *f, const report *r) {
    if (!r->note_count) return;
    fputs("<p class=\"note\">The bundle&#8217;s notes (what the plan did not model):</p>\n<ul class=\"notes\">\n", f);
    for (int i = 0; i < r->note_count; i++) {
        fputs("<li>", f);
        report_escape(f, r->notes[i]);
        fputs("</li>\n", f);
    }
    fputs("</ul>\n", f);
}

int report_write_page(FILE *f, const report *r) {
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
          "<meta name=\"generator\" content=\"haircompare\">\n<title>hairtier tiers: ", f);
    report_escape(f, r->material);
    fputs("</title>\n", f);
    write_style(f, r);
    fputs("</head>\n<body>\n", f);
    write_header(f, r);
    write_images(f, r);
    fputs("<h2>Colour scale</h2>\n", f);
    report_write_legend(f, r);
    write_crops(f, r);
    report_write_lod_grid(f, r);
    fputs("<h2>Measurements against ", f);
    report_escape(f, report_reference_name(r));
    fputs("</h2>\n", f);
    /* a window narrower than a table scrolls the table, not the page */
    fputs("<div class=\"wide\">\n", f);
    report_write_table(f, r);
    fputs("</div>\n", f);
    write_definitions(f, r);
    fputs("<h2>Error against cost</h2>\n", f);
    report_write_plot(f, r);
    fputs("<h2>What each tier needs and drops</h2>\n", f);
    fputs("<div class=\"wide\">\n", f);
    report_write_needs(f, r);
    fputs("</div>\n", f);
    write_notes(f, r);
    fputs("</body>\n</html>\n", f);
    return ferror(f) ? -1 : 0;
}

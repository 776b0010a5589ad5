/* report_html.c — index.html: header, image and heatmap rows, legend,
   table, plot (report.h). Numbers are written with printf in the C locale
   (the programs never call setlocale). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "heatmap.h"
#include "report.h"

void report_init(report *r) { memset(r, 0, sizeof *r); }

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

report_rect report_image_rect(const report *r, int column, int row) {
    return (report_rect){ .x = REPORT_MARGIN + column * (r->width + REPORT_GAP),
                          .y = REPORT_MARGIN + REPORT_HEADER_H + REPORT_CAPTION_H + row * (r->height + REPORT_CAPTION_H),
                          .w = r->width,
                          .h = r->height };
}

int report_page_width(const report *r) {
    int n = r->tier_count > 0 ? r->tier_count : 1;
    return 2 * REPORT_MARGIN + n * r->width + (n - 1) * REPORT_GAP;
}

/* A number, or an en dash when there is none; infinite PSNR is "∞". */
static void number(FILE *f, bool have, double v, const char *fmt) {
    if (!have) fputs("&ndash;", f);
    else if (isinf(v)) fputs("&infin;", f);
    else if (isnan(v)) fputs("n/a", f);
    else fprintf(f, fmt, v);
}

void report_write_legend(FILE *f) {
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
               "per-pixel CIEDE2000 (&#916;E00) against full</text>\n",
            LEFT + BAR_W / 2, H - 4);
    fputs("</svg>\n", f);
}

void report_write_table(FILE *f, const report *r) {
    fputs("<table class=\"metrics\">\n<thead><tr><th>tier</th><th>needs</th><th>frame ms</th><th>cost vs full</th>"
          "<th>PSNR dB</th><th>SSIM</th><th>&#916;E00 mean</th><th>&#916;E00 p95</th>"
          "<th>hair pixels: &#916;E00 mean / p95</th><th>features dropped</th></tr></thead>\n<tbody>\n", f);
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        fputs("<tr><th scope=\"row\">", f);
        report_escape(f, p->name);
        fputs("</th><td class=\"needs\">", f);
        report_escape(f, p->needs);
        fputs("</td>", f);
        if (!p->ran) {
            fputs("<td colspan=\"7\" class=\"notrun\">not run: ", f);
            report_escape(f, p->reason);
            fputs("</td>", f);
        } else {
            fputs("<td class=\"num\">", f);
            number(f, true, p->frame_ms, "%.1f");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->cost_ratio, "%.2f&times;");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->whole.psnr_db, "%.1f");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->whole.ssim, "%.4f");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->whole.delta_e00_mean, "%.2f");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->whole.delta_e00_p95, "%.2f");
            fputs("</td><td class=\"num\">", f);
            number(f, p->compared, p->hair.delta_e00_mean, "%.2f");
            fputs(" / ", f);
            number(f, p->compared, p->hair.delta_e00_p95, "%.2f");
            fputs("</td>", f);
        }
        fputs("<td class=\"dropped\">", f);
        if (p->dropped_count == 0) fputs("nothing", f);
        else {
            fputs("<ul>", f);
            for (int i = 0; i < p->dropped_count; i++) {
                fputs("<li>", f);
                report_escape(f, p->dropped[i]);
                fputs("</li>", f);
            }
            fputs("</ul>", f);
        }
        fputs("</td></tr>\n", f);
    }
    fputs("</tbody>\n</table>\n", f);
}

static void write_style(FILE *f, const report *r) {
    fprintf(f,
            "<style>\n"
            "html{background:#15161a}\n"
            "body{margin:0;padding:%dpx;width:%dpx;color:#e4e4e4;background:#15161a;"
            "font:14px/1.45 'DejaVu Sans',Verdana,sans-serif}\n"
            "header{height:%dpx;overflow:hidden}\n"
            "h1{margin:0 0 6px;font-size:24px;font-weight:600}\n"
            "header p{margin:2px 0;color:#b8b8b8}\n"
            "code{font-family:'DejaVu Sans Mono',monospace;font-size:13px;color:#f0d9a8}\n"
            ".row{display:flex;gap:%dpx}\n"
            ".col{width:%dpx;flex:none}\n"
            ".cap{height:%dpx;line-height:%dpx;margin:0;overflow:hidden;white-space:nowrap;text-overflow:ellipsis}\n"
            ".cap b{font-size:17px;margin-right:8px}\n"
            ".cap span{color:#b0b0b0}\n"
            "img,.box{display:block;width:%dpx;height:%dpx}\n"
            "img{outline:1px solid #303139}\n"
            ".box{box-sizing:border-box;padding:32px;background:#1d1e23;color:#a8a8a8;border:1px dashed #4a4b52;"
            "overflow:hidden;display:flex;flex-direction:column;justify-content:center;text-align:center}\n"
            "h2{font-size:18px;margin:28px 0 10px;font-weight:600}\n"
            "table{border-collapse:collapse;max-width:1800px}\n"
            "th,td{border:1px solid #3a3b42;padding:6px 9px;vertical-align:top;text-align:left}\n"
            "thead th{background:#23242a;font-weight:600}\n"
            "tbody th{font-size:15px}\n"
            "td.num{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums}\n"
            "td.needs{max-width:220px}\n"
            "td.notrun{color:#e0a070}\n"
            "td.dropped{max-width:640px;font-size:13px;color:#c8c8c8}\n"
            "td.dropped ul{margin:0;padding-left:18px}\n"
            "p.note,ul.notes{color:#b8b8b8;max-width:1100px}\n"
            ".plot{background:#1c1d22;border:1px solid #3a3b42}\n"
            ".side{display:flex;gap:40px;align-items:flex-start}\n"
            "</style>\n",
            REPORT_MARGIN, report_page_width(r) - 2 * REPORT_MARGIN, REPORT_HEADER_H, REPORT_GAP, r->width,
            REPORT_CAPTION_H, REPORT_CAPTION_H, r->width, r->height);
}

static void write_header(FILE *f, const report *r) {
    fputs("<header>\n<h1>hairtier tiers: ", f);
    report_escape(f, r->material);
    fputs("</h1>\n<p>bundle <code>", f);
    report_escape(f, r->bundle);
    fputs("</code>, scene <code>", f);
    report_escape(f, r->scene);
    fprintf(f, "</code>, %d&times;%d</p>\n<p>every tier forced (strict) on <code>", r->width, r->height);
    report_escape(f, r->driver[0] ? r->driver : "no context");
    fprintf(f, "</code>; frame ms: median of %d frames after one warm-up, each ended by glFinish</p>\n", r->frames);
    fputs("<p>top: each tier's image; below it: its per-pixel CIEDE2000 against <b>full</b> "
          "(scale under the images)</p>\n</header>\n", f);
}

static void write_missing(FILE *f, const char *what, const char *why) {
    fprintf(f, "<div class=\"box\">%s", what);
    if (why) {
        fputs("<br>", f);
        report_escape(f, why);
    }
    fputs("</div>\n", f);
}

static void write_images(FILE *f, const report *r) {
    fputs("<div class=\"row\">\n", f);
    for (int t = 0; t < r->tier_count; t++) {
        const report_tier *p = &r->tiers[t];
        fputs("<div class=\"col\">\n<p class=\"cap\"><b>", f);
        report_escape(f, p->name);
        fputs("</b><span>", f);
        if (p->ran) fprintf(f, "%.1f ms", p->frame_ms);
        if (p->compared && t > 0) fprintf(f, ", %.2f&times; full&#8217;s cost", p->cost_ratio);
        if (!p->ran) fputs("not run", f);
        fputs("</span></p>\n", f);
        if (p->image[0]) {
            fputs("<img src=\"", f);
            report_escape(f, p->image);
            fputs("\" alt=\"", f);
            report_escape(f, p->name);
            fputs(" tier\">\n", f);
        } else {
            write_missing(f, "this device cannot run this tier:", p->reason);
        }
        fputs("<p class=\"cap\"><span>", f);
        if (p->heatmap[0]) fprintf(f, "vs full: &#916;E00 mean %.2f, p95 %.2f; PSNR %.1f dB", p->whole.delta_e00_mean,
                                   p->whole.delta_e00_p95, p->whole.psnr_db);
        else if (p->compared) fputs("the reference every heatmap is measured against", f);
        fputs("</span></p>\n", f);
        if (p->heatmap[0]) {
            fputs("<img src=\"", f);
            report_escape(f, p->heatmap);
            fputs("\" alt=\"", f);
            report_escape(f, p->name);
            fputs(" error against full\">\n", f);
        } else if (p->compared) {
            write_missing(f, "reference (full): no error to show", NULL);
        } else {
            write_missing(f, p->ran ? "no heatmap: full did not run here, nothing to compare with" : "no image",
                          NULL);
        }
        fputs("</div>\n", f);
    }
    fputs("</div>\n", f);
}

static void write_definitions(FILE *f, const report *r) {
    fputs("<p class=\"note\">PSNR, SSIM and &#916;E00 over the whole frame; the hair-pixel column counts the "
          "pixels where either image differs from the background. Definitions: <code>shadergen/metrics.h</code> "
          "(SSIM: Wang et al. 2004 on luminance; &#916;E00: CIEDE2000 after sRGB &#8594; CIELAB D65, mean and "
          "nearest-rank 95th percentile). Cost: the tier&#8217;s median frame time over full&#8217;s, on ", f);
    report_escape(f, r->driver[0] ? r->driver : "no context");
    fputs(" (a ratio measured in this run, side by side; not a prediction for other devices). "
          "Heatmap colours: cubehelix (Green 2011), luminance rising with the error.</p>\n", f);
    if (r->note_count) {
        fputs("<p class=\"note\">The bundle&#8217;s notes (what the plan did not model):</p>\n<ul class=\"notes\">\n", f);
        for (int i = 0; i < r->note_count; i++) {
            fputs("<li>", f);
            report_escape(f, r->notes[i]);
            fputs("</li>\n", f);
        }
        fputs("</ul>\n", f);
    }
}

int report_write_page(FILE *f, const report *r) {
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
          "<meta name=\"generator\" content=\"haircompare\">\n<title>hairtier tiers: ", f);
    report_escape(f, r->material);
    fputs("</title>\n", f);
    write_style(f, r);
    fputs("</head>\n<body>\n", f);
    write_header(f, r);
    write_images(f, r);
    fputs("<h2>Colour scale</h2>\n", f);
    report_write_legend(f);
    fputs("<div class=\"side\">\n<section>\n<h2>Measurements against full</h2>\n", f);
    report_write_table(f, r);
    write_definitions(f, r);
    fputs("</section>\n<section>\n<h2>Error against cost</h2>\n", f);
    report_write_plot(f, r);
    fputs("</section>\n</div>\n", f);
    fputs("</body>\n</html>\n", f);
    return ferror(f) ? -1 : 0;
}

/* report_lod.c — the report's LOD x tier grid (report.h): which measured
   size it shows, the manifest's numbers per cell, and the HTML table. */
#include <math.h>
#include <string.h>

#include "report.h"

double report_lod_size(const ht_manifest_lods *m) {
    double best = 0;
    for (int i = 0; i < m->cell_count; i++) {
        const double s = m->cells[i].size;
        if (best == 0 || fabs(log2(s / REPORT_LOD_SIZE)) < fabs(log2(best / REPORT_LOD_SIZE))) best = s;
    }
    return best;
}

void report_lod_attach_measured(report *r) {
    const ht_manifest_lods *m = &r->measured_lods;
    for (int i = 0; i < m->cell_count; i++) {
        const ht_manifest_lod_cell *c = &m->cells[i];
        /* the grid draws the plain levels; a soft cell is another pair */
        if (c->size != r->lods.size || c->level >= r->lods.levels || c->soften > 1) continue;
        for (int t = 0; t < r->tier_count; t++) {
            if (strcmp(r->tiers[t].name, c->tier) != 0) continue;
            report_lod_cell *g = &r->lods.cells[c->level][t];
            g->measured = true;
            g->measured_psnr_db = c->psnr_db;
            g->measured_cost_ratio = c->cost_ratio;
        }
    }
}

/* A PSNR as the page writes it: infinite is the reference itself. */
static void write_db(FILE *f, double db) {
    if (isinf(db)) fputs("&#8734;", f);
    else fprintf(f, "%.1f", db);
}

void report_write_lod_grid(FILE *f, const report *r) {
    const report_lod_grid *g = &r->lods;
    if (g->levels == 0) return;
    const char *ref = report_reference_name(r);
    fprintf(f, "<h2>Geometry levels &#215; tiers at %g of the scene&#8217;s size</h2>\n"
               "<p class=\"note\">Every level of detail (rows: fewer strands, widened to keep the drawn area; "
               "<code>docs/lod.md</code>) drawn by every tier that ran (columns) at %d&#215;%d, each against "
               "(level 0, <b>", g->size, g->width, g->height);
    report_escape(f, ref);
    fputs("</b>) at this size: PSNR in dB and cost (frame time over that pair&#8217;s, this run); in brackets "
          "the bundle&#8217;s own numbers for the cell (<code>hairgen --measure-lods</code>), which "
          "<code>--policy error:DB</code> and <code>frame:MS</code> choose a pair from.</p>\n", f);
    fputs("<div class=\"wide\">\n<table class=\"lods\">\n<thead><tr><th>level</th>", f);
    for (int t = 0; t < r->tier_count; t++) {
        if (!g->cells[0][t].ran) continue;
        fputs("<th>", f);
        report_escape(f, r->tiers[t].name);
        fputs("</th>", f);
    }
    fputs("</tr></thead>\n<tbody>\n", f);
    for (int l = 0; l < g->levels; l++) {
        fprintf(f, "<tr><th scope=\"row\">%d<br><span>%u strands</span></th>", l, g->strands[l]);
        for (int t = 0; t < r->tier_count; t++) {
            const report_lod_cell *c = &g->cells[l][t];
            if (!g->cells[0][t].ran) continue;
            if (!c->ran) {
                fputs("<td class=\"none\">not drawn</td>", f);
                continue;
            }
            fputs("<td class=\"lod\"><img src=\"", f);
            report_escape(f, c->image);
            fprintf(f, "\" width=\"%d\" height=\"%d\" alt=\"level %d, ", g->width, g->height, l);
            report_escape(f, r->tiers[t].name);
            fputs("\"><br>", f);
            write_db(f, c->whole.psnr_db);
            fprintf(f, " dB, %.2f&#215;", c->cost_ratio);
            if (c->measured) {
                fputs("<br><span>[", f);
                write_db(f, c->measured_psnr_db);
                fprintf(f, " dB, %.2f&#215;]</span>", c->measured_cost_ratio);
            }
            fputs("</td>", f);
        }
        fputs("</tr>\n", f);
    }
    fputs("</tbody>\n</table>\n</div>\n", f);
}

/* report_lod.c — the report's LOD x tier grid (report.h): which measured
   size it shows, the manifest's numbers per cell, and the HTML. */
#include <math.h>
#include <string.h>

#include "report.h"

report_lod_cell *report_lod_row_cell(const report_lod_grid *g, int level, int row_kind, int tier) {
    return (report_lod_cell *)(row_kind ? &g->soft_cells[row_kind - 1][level][tier] : &g->cells[level][tier]);
}

bool report_lod_has_row(const report_lod_grid *g, int level, int row_kind) {
    return row_kind == 0 || (row_kind <= g->soften_count && g->soft[row_kind - 1][level]);
}

double report_lod_size(const ht_manifest_lods *m) {
    double best = 0;
    for (int i = 0; i < m->cell_count; i++) {
        const double s = m->cells[i].size;
        if (best == 0 || fabs(log2(s / REPORT_LOD_SIZE)) < fabs(log2(best / REPORT_LOD_SIZE))) best = s;
    }
    return best > 0 ? best : REPORT_LOD_SIZE;
}

void report_lod_attach_measured(report *r) {
    const ht_manifest_lods *m = &r->measured_lods;
    report_lod_grid *g = &r->lods;
    g->measured_cells = g->other_cells = 0;
    for (int i = 0; i < m->cell_count; i++) {
        const ht_manifest_lod_cell *c = &m->cells[i];
        if (c->size != g->size) continue;
        int t = 0;
        while (t < r->tier_count && strcmp(r->tiers[t].name, c->tier) != 0) t++;
        const int l = c->level;
        int kind = 0; /* a soft cell's row: the one drawn soft by the factor it was measured with */
        while (c->soften > 1 && kind < g->soften_count && g->soften[kind] != c->soften) kind++;
        if (c->soften > 1) kind++;
        /* the same geometry: the row's kind and its strand (card) count */
        if (t == r->tier_count || l >= g->levels || (c->cards != 0) != g->cards[l] || c->strands != g->strands[l] ||
            !report_lod_has_row(g, l, kind)) {
            g->other_cells++;
            continue;
        }
        report_lod_cell *cell = report_lod_row_cell(g, l, kind, t);
        cell->measured = true;
        cell->measured_psnr_db = c->psnr_db;
        cell->measured_cost_ratio = c->cost_ratio;
        g->measured_cells++;
    }
}

/* A PSNR as the page writes it: infinite is the reference itself. */
static void write_db(FILE *f, double db) {
    if (isinf(db)) fputs("&#8734;", f);
    else fprintf(f, "%.1f", db);
}

static void write_intro(FILE *f, const report *r) {
    const report_lod_grid *g = &r->lods;
    int strand_levels = 0, cards = 0;
    for (int l = 0; l < g->levels; l++) g->cards[l] ? cards++ : strand_levels++;
    fprintf(f, "<h2>Geometry levels &#215; tiers at %g of the scene&#8217;s size</h2>\n<p class=\"note\">Levels: ", g->size);
    if (g->source == REPORT_LOD_STORED) {
        fprintf(f, "<b>the bundle&#8217;s stored levels</b> (<code>" HT_LOD_FILE_NAME "</code>, made from this "
                   "scene&#8217;s mesh): %d strand level%s", strand_levels, strand_levels == 1 ? "" : "s");
        if (cards) fprintf(f, " and %d of cards (textured ribbons, one a clump of strands, drawn with the "
                              "bundle&#8217;s atlas)", cards);
    } else {
        fprintf(f, "<b>built from the scene</b> (levels 0 to %d of <code>lod.h</code>&#8217;s ladder): %s",
                g->levels - 1,
                g->source == REPORT_LOD_BUILT_OTHER_SCENE
                    ? "the bundle&#8217;s <code>" HT_LOD_FILE_NAME "</code> was made from another scene&#8217;s mesh"
                    : "the bundle stores none");
    }
    int soft = 0;
    for (int l = 0; l < g->levels; l++) soft += g->soften_count && g->soft[0][l];
    if (soft) {
        fprintf(f, "; %d of them also soft by ", soft);
        for (int k = 0; k < g->soften_count; k++)
            fprintf(f, "%s%g", k == 0 ? "" : k + 1 == g->soften_count ? " and " : ", ", (double)g->soften[k]);
        fputs(" (ribbons that many times wider at the inverse opacity, far to near, a row each: the bundle "
              "measured soft cells, which <code>error:DB</code> may pick)", f);
    }
    fprintf(f, ". Each drawn by every tier that ran at %d&#215;%d against (level 0, <b>", g->width, g->height);
    report_escape(f, report_reference_name(r));
    fputs("</b>) at this size: PSNR in dB and cost (frame time over that pair&#8217;s, this run; "
          "<code>docs/lod.md</code>). ", f);
    if (g->measured_cells)
        fputs("Below them, <span class=\"measured\">bundle</span>: the manifest&#8217;s numbers for the cell "
              "(<code>hairgen --measure-lods</code>), which <code>--policy error:DB</code> and <code>frame:MS</code> "
              "choose a pair from.", f);
    else
        fputs("The bundle has no measured numbers for these cells (<code>hairgen --measure-lods</code> writes "
              "them).", f);
    if (g->other_cells)
        fprintf(f, " %d of its measured cells at this size are of other geometry (another scene&#8217;s levels) and "
                   "are left out.", g->other_cells);
    fputs("</p>\n", f);
}

static void write_row_head(FILE *f, const report_lod_grid *g, int l, int kind) {
    if (kind)
        fprintf(f, "<div class=\"lodhead\">level %d soft<br><span>%u strands, %g&#215; wide at 1/%g the "
                   "opacity</span></div>\n", l, g->strands[l], (double)g->soften[kind - 1], (double)g->soften[kind - 1]);
    else if (g->cards[l])
        fprintf(f, "<div class=\"lodhead\">cards<br><span>level %d: %u cards of %u strands</span></div>\n", l,
                g->strands[l], g->strands_per_card[l]);
    else
        fprintf(f, "<div class=\"lodhead\">level %d<br><span>%u strands</span></div>\n", l, g->strands[l]);
}

void report_write_lod_grid(FILE *f, const report *r) {
    const report_lod_grid *g = &r->lods;
    if (g->levels == 0) return;
    write_intro(f, r);
    /* a cell is as wide as its image, or its two lines of numbers */
    const int cell_w = g->width > 150 ? g->width : 150;
    fputs("<div class=\"lods\">\n", f);
    const int kinds = 1 + g->soften_count;
    for (int row = 0; row < kinds * g->levels; row++) {
        const int l = row / kinds, kind = row % kinds;
        if (!report_lod_has_row(g, l, kind)) continue;
        fputs("<div class=\"lodrow\">\n", f);
        write_row_head(f, g, l, kind);
        for (int t = 0; t < r->tier_count; t++) {
            const report_lod_cell *c = report_lod_row_cell(g, l, kind, t);
            if (!g->cells[0][t].ran) continue;
            fprintf(f, "<figure class=\"lod\" style=\"width:%dpx\"><p class=\"cap\"><b>", cell_w);
            report_escape(f, r->tiers[t].name);
            fputs("</b></p>", f);
            if (!c->ran) {
                fprintf(f, "<div class=\"box\" style=\"width:%dpx;height:%dpx\">not drawn</div></figure>\n", g->width,
                        g->height);
                continue;
            }
            fputs("<img src=\"", f);
            report_escape(f, c->image);
            fprintf(f, "\" width=\"%d\" height=\"%d\" alt=\"%s %d", g->width, g->height,
                    g->cards[l] ? "cards, level" : "level", l);
            if (kind) fprintf(f, " soft %g", (double)g->soften[kind - 1]);
            fputs(", ", f);
            report_escape(f, r->tiers[t].name);
            fputs("\"><p>", f);
            write_db(f, c->whole.psnr_db);
            fprintf(f, " dB, %.2f&#215;", c->cost_ratio);
            if (c->measured) {
                fputs("<br><span class=\"measured\">bundle ", f);
                write_db(f, c->measured_psnr_db);
                fprintf(f, " dB, %.2f&#215;</span>", c->measured_cost_ratio);
            } else if (g->measured_cells) {
                fputs("<br><span class=\"measured\">bundle: not measured</span>", f);
            }
            fputs("</p></figure>\n", f);
        }
        fputs("</div>\n", f);
    }
    fputs("</div>\n", f);
}

/* lod_build.c — one LOD of a hair mesh (lod.h says what a LOD keeps).

   Width rule: every kept ribbon is widened about its centre line by
   f = (area of all ribbons) / (area of the kept ones after decimation),
   about n / kept, opacity kept, so the summed ribbon area is the full
   mesh's; where ribbons overlap little, the
   covered area and mean opacity follow (tests/test_lod.c measures the
   covered fraction per level). Decimation: row r (not the root, not the
   tip) goes when the direction from the last kept row to r and the
   direction from r to r + 1 differ by less than max_turn_deg; a kept row's
   tangent is the mean of the kept segments meeting there (root: the first,
   tip: the last), unit and root to tip; normal, uv and ao are the row's
   own. Components keep the full mesh's order (its inside-out sort). A soft
   level (lod.h) is the same LOD widened again by its soften factor, which
   its caller's opacity scale takes back. */
#include <stdlib.h>
#include <string.h>

#include "lod_internal.h"

#define MAX_TURN_DEG 90.0f
#define WIDTH_ROUNDS 8 /* refits of the width to the area */

void ht_lod_level(int level, ht_lod_desc *out) {
    if (!out) return;
    if (level < 0) level = 0;
    if (level > HT_LOD_LEVELS - 1) level = HT_LOD_LEVELS - 1;
    out->strand_stride = 1u << level;
    /* 4 degrees past level 0: on the dense groom at a quarter size 8
       instead costs 1.5-2 dB against the truth, under 4 wins < 0.4 dB. */
    out->max_turn_deg = level ? 4.0f : 0.0f;
    out->soften = 0.0f;
}

void ht_lod_soft_level(int level, ht_lod_desc *out) {
    if (!out) return;
    ht_lod_level(level, out);
    out->soften = out->strand_stride > 1 ? HT_LOD_SOFTEN : 0.0f;
}

static bool soft(const ht_lod_desc *desc) { return desc->soften > 1.0f; }

float ht_lod_opacity(const ht_lod_desc *desc) { return desc && soft(desc) ? 1.0f / desc->soften : 1.0f; }

int ht_lod_max_level(const ht_mesh *mesh) {
    int level = 0;
    if (!mesh) return 0;
    while (level + 1 < HT_LOD_LEVELS &&
           mesh->component_count / (1u << (level + 1)) + (mesh->component_count % (1u << (level + 1)) != 0) >=
               HT_LOD_MIN_STRANDS)
        level++;
    return level;
}

ht_result ht_lod_runs(const ht_mesh *m, ht_lod_run *runs) {
    for (uint32_t c = 0; c < m->component_count; c++) {
        const ht_component *comp = &m->components[c];
        if (comp->index_count < 6 || comp->index_count % 6 ||
            (uint64_t)comp->first_index + comp->index_count > m->index_count)
            return HT_ERR_INVALID_ARGUMENT;
        uint32_t lo = UINT32_MAX, hi = 0;
        for (uint32_t i = 0; i < comp->index_count; i++) {
            const uint32_t v = m->indices[comp->first_index + i];
            if (v < lo) lo = v;
            if (v > hi) hi = v;
        }
        const uint64_t span = (uint64_t)hi - lo + 1;
        if (hi >= m->vertex_count || span % 2 || span / 2 - 1 != comp->index_count / 6)
            return HT_ERR_INVALID_ARGUMENT;
        runs[c] = (ht_lod_run){ lo, (uint32_t)(span / 2) };
    }
    return HT_OK;
}

void ht_lod_sides(const ht_mesh *m, float (*sides)[3]) {
    memset(sides, 0, (size_t)m->vertex_count * sizeof *sides);
    for (uint32_t c = 0; c < m->component_count; c++) {
        ht_mesh one = *m;
        one.components = &m->components[c];
        one.component_count = 1;
        ht_lod_run run;
        if (ht_lod_runs(&one, &run) != HT_OK) continue;
        for (uint32_t v = run.first_vertex; v + 1 < run.first_vertex + 2 * run.rows; v += 2)
            for (int k = 0; k < 3; k++) {
                const float half = 0.5f * (m->vertices[v].position[k] - m->vertices[v + 1].position[k]);
                sides[v][k] = half;
                sides[v + 1][k] = -half;
            }
    }
}

static void centre(const ht_mesh *m, const ht_lod_run *run, uint32_t row, double out[3]) {
    const ht_vertex *a = &m->vertices[run->first_vertex + 2 * row];
    for (int k = 0; k < 3; k++) out[k] = 0.5 * ((double)a[0].position[k] + a[1].position[k]);
}

/* The unit direction from row a to row b of a run; false when they meet. */
static bool direction(const ht_mesh *m, const ht_lod_run *run, uint32_t a, uint32_t b, double out[3]) {
    double pa[3], pb[3];
    centre(m, run, a, pa);
    centre(m, run, b, pb);
    ht_vec3_mad(out, pb, -1.0, pa);
    return ht_vec3_normalize(out);
}

static double triangle_area(const float *p0, const float *p1, const float *p2) {
    double u[3], w[3], c[3];
    for (int k = 0; k < 3; k++) { u[k] = (double)p1[k] - p0[k]; w[k] = (double)p2[k] - p0[k]; }
    ht_vec3_cross(c, u, w);
    return 0.5 * ht_vec3_length(c);
}

/* The ribbon's area through the rows marked in keep (NULL: all of them):
   the two triangles of each quad between kept rows, as they are drawn. */
static double run_area(const ht_mesh *m, const ht_lod_run *run, const bool *keep) {
    double a = 0;
    uint32_t prev = 0;
    for (uint32_t r = 1; r < run->rows; r++) {
        if (keep && !keep[r]) continue;
        const ht_vertex *p = &m->vertices[run->first_vertex + 2 * prev], *q = &m->vertices[run->first_vertex + 2 * r];
        a += triangle_area(p[0].position, q[1].position, p[1].position) +
             triangle_area(p[0].position, q[0].position, q[1].position);
        prev = r;
    }
    return a;
}

/* Marks the rows of a run to keep; returns how many. */
static uint32_t keep_rows(const ht_mesh *m, const ht_lod_run *run, double cos_turn, bool *keep) {
    uint32_t kept = 1, last = 0;
    keep[0] = true;
    for (uint32_t r = 1; r + 1 < run->rows; r++) {
        double in[3], out[3];
        keep[r] = cos_turn >= 1.0 || !direction(m, run, last, r, in) || !direction(m, run, r, r + 1, out) ||
                  ht_vec3_dot(in, out) < cos_turn;
        if (keep[r]) { last = r; kept++; }
    }
    keep[run->rows - 1] = true;
    return kept + 1;
}

static void write_rows(const ht_mesh *m, const ht_lod_run *run, const bool *keep, double widen, ht_vertex *out) {
    uint32_t n = 0, prev = 0;
    for (uint32_t r = 0; r < run->rows; r++) {
        if (!keep[r]) continue;
        const ht_vertex *src = &m->vertices[run->first_vertex + 2 * r];
        double c[3];
        centre(m, run, r, c);
        /* Tangent: mean of the kept segments meeting at the row. */
        uint32_t next = r + 1;
        while (next < run->rows && !keep[next]) next++;
        double t[3] = { 0, 0, 0 }, d[3];
        if (r > 0 && direction(m, run, prev, r, d)) ht_vec3_mad(t, t, 1.0, d);
        if (next < run->rows && direction(m, run, r, next, d)) ht_vec3_mad(t, t, 1.0, d);
        if (!ht_vec3_normalize(t)) ht_vec3_from_float(t, src[0].tangent);
        for (int side = 0; side < 2; side++) {
            ht_vertex *v = &out[2 * n + side];
            *v = src[side];
            double p[3];
            for (int k = 0; k < 3; k++) p[k] = c[k] + widen * ((double)src[side].position[k] - c[k]);
            ht_vec3_store(v->position, p);
            ht_vec3_store(v->tangent, t);
            /* The row's normal made perpendicular to the new tangent (the
               tiers' frame); kept as it was where they run parallel. */
            double nrm[3];
            ht_vec3_from_float(nrm, src[side].normal);
            if (ht_vec3_orthonormalize(nrm, t)) ht_vec3_store(v->normal, nrm);
        }
        prev = r;
        n++;
    }
}

/* Writes the kept rows of every kept strand (rows[c] of them, 0: dropped)
   widened by widen, in the full mesh's component order. */
static void write_lod(const ht_mesh *full, const ht_lod_run *runs, const uint32_t *rows, double cos_turn, bool *keep,
                      double widen, ht_mesh *out) {
    uint32_t v = 0, i = 0, k = 0;
    for (uint32_t c = 0; c < full->component_count; c++) {
        if (!rows[c]) continue;
        keep_rows(full, &runs[c], cos_turn, keep);
        write_rows(full, &runs[c], keep, widen, out->vertices + v);
        for (uint32_t q = 0; q + 1 < rows[c]; q++) {
            const uint32_t a0 = v + 2 * q, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
            const uint32_t tri[6] = { a0, b1, a1, a0, b0, b1 };
            memcpy(out->indices + i + 6 * q, tri, sizeof tri);
        }
        out->components[k++] = (ht_component){ i, 6 * (rows[c] - 1), full->components[c].sort_key };
        v += 2 * rows[c];
        i += 6 * (rows[c] - 1);
    }
}

static double mesh_area(const ht_mesh *m) {
    double a = 0;
    for (uint32_t t = 0; t + 2 < m->index_count; t += 3)
        a += triangle_area(m->vertices[m->indices[t]].position, m->vertices[m->indices[t + 1]].position,
                           m->vertices[m->indices[t + 2]].position);
    return a;
}

/* A LOD, every ribbon `extra` times wider again after the area rule (the
   width rule's factor; 1: none). */
static ht_result build_lod(const ht_mesh *full, const ht_lod_desc *desc, double extra, ht_mesh *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (!full || !desc || !full->vertices || !full->indices || !full->components || full->component_count == 0 ||
        !(desc->max_turn_deg >= 0 && desc->max_turn_deg <= MAX_TURN_DEG) || !(extra >= 1 && extra <= HT_LOD_MAX_WIDEN))
        return HT_ERR_INVALID_ARGUMENT;
    const uint32_t n = full->component_count, stride = desc->strand_stride ? desc->strand_stride : 1;
    const uint32_t kept = n / stride + (n % stride != 0);
    double widen = 1.0;
    const double cos_turn = cos(desc->max_turn_deg * M_PI / 180.0);

    ht_lod_run *runs = malloc(sizeof *runs * n);
    uint32_t *rank = malloc(sizeof *rank * n), *rows = malloc(sizeof *rows * n);
    uint32_t longest = 0;
    bool *keep = NULL;
    ht_result r = runs && rank && rows ? ht_lod_runs(full, runs) : HT_ERR_OUT_OF_MEMORY;
    if (r == HT_OK) r = ht_mesh_strand_order(full, rank);
    if (r != HT_OK) goto done;
    for (uint32_t c = 0; c < n; c++) longest = runs[c].rows > longest ? runs[c].rows : longest;
    keep = malloc(sizeof *keep * longest);
    if (!keep) { r = HT_ERR_OUT_OF_MEMORY; goto done; }

    /* The width rule: the kept, decimated ribbons' area made the whole mesh's. */
    double area_all = 0, area_kept = 0;
    uint64_t vertices = 0, indices = 0;
    for (uint32_t c = 0; c < n; c++) {
        area_all += run_area(full, &runs[c], NULL);
        rows[c] = rank[c] < kept ? keep_rows(full, &runs[c], cos_turn, keep) : 0;
        if (rows[c]) area_kept += run_area(full, &runs[c], keep);
        vertices += 2ull * rows[c];
        indices += rows[c] ? 6ull * (rows[c] - 1) : 0;
    }
    if (area_kept > 0 && isfinite(area_all / area_kept)) widen = area_all / area_kept;
    r = ht_mesh_alloc(out, vertices, indices, kept);
    if (r != HT_OK) goto done;
    memcpy(out->center, full->center, sizeof out->center);

    /* The width rule's or a soft level's factor on top (lod.h): the drawn
       area grows by it, and the opacity the caller sets shrinks by it.
       Twisted quads grow faster than their width: refit it to the drawn
       triangles' area (a few rounds converge well within 1%). */
    const double target = area_all * extra;
    widen *= extra;
    for (int round = 0; round < WIDTH_ROUNDS; round++) {
        write_lod(full, runs, rows, cos_turn, keep, widen, out);
        const double drawn = mesh_area(out);
        if (!(drawn > 0) || fabs(drawn / target - 1) < 0.002) break;
        widen *= target / drawn;
    }
done:
    free(runs);
    free(rank);
    free(rows);
    free(keep);
    return r;
}

ht_result ht_mesh_build_lod(const ht_mesh *full, const ht_lod_desc *desc, ht_mesh *out) {
    if (desc && !(desc->soften == 0.0f || (desc->soften >= 1.0f && desc->soften <= HT_LOD_MAX_SOFTEN))) {
        if (out) memset(out, 0, sizeof *out);
        return HT_ERR_INVALID_ARGUMENT;
    }
    return build_lod(full, desc, desc && soft(desc) ? desc->soften : 1.0, out);
}

ht_result ht_mesh_widen(const ht_mesh *mesh, double factor, ht_mesh *out) {
    return build_lod(mesh, &(ht_lod_desc){ .strand_stride = 1, .max_turn_deg = 0 }, factor, out);
}

ht_result ht_mesh_width_rule(const ht_mesh *mesh, double strand_px, int samples, const float eye[3], ht_mesh *out,
                             double *factor) {
    if (out) memset(out, 0, sizeof *out);
    if (!mesh || !eye || !out || !factor) return HT_ERR_INVALID_ARGUMENT;
    *factor = ht_width_rule_applies(strand_px, samples) ? ht_width_rule_widen(strand_px) : 1.0;
    if (*factor <= 1.0) return HT_OK;
    return ht_mesh_widen_back_to_front(mesh, *factor, eye, out);
}

double ht_mesh_mean_width(const ht_mesh *m) {
    if (!m || !m->vertices || m->vertex_count < 2) return 0;
    double sum = 0;
    for (uint32_t v = 0; v + 1 < m->vertex_count; v += 2) {
        double d[3];
        for (int k = 0; k < 3; k++) d[k] = (double)m->vertices[v + 1].position[k] - m->vertices[v].position[k];
        sum += ht_vec3_length(d);
    }
    return sum / (m->vertex_count / 2);
}

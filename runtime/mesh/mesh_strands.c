/* mesh_strands.c — strands read from a file (strands.h) as hair ribbons,
   one component per strand, then sorted inside out like the generated
   meshes.

   Position: p = (file point - center) x scale.
   Per point i of a strand of n points (root i = 0):
     tangent  the mean of the unit directions of the segments meeting at
              the point (root: the first, tip: the last), root to tip. A
              zero-length segment (repeated points, common in exported
              files) takes the direction of the nearest real one before it,
              else after it; a strand with no length at all points away from
              the head. Always unit.
     facing   o = the unit direction from the head centre to the point
              (or the desc's facing direction when it is not zero).
              Widening axis w = o x t / |o x t|, normal n = t x w: the part
              of o across the strand, so every ribbon faces away from the
              head and the static sort and the tiers see the same ribbon
              side from outside. Where t runs along o (|o x t| < 0.05, hair
              standing straight out) w is the previous point's w made
              perpendicular to t (at the root: any perpendicular), and n
              flipped with w if it faced the head.
     width    width x (1 - (1 - tip_width) v), or with use_thickness the
              file's thickness x scale; the ribbon spans ±width/2 along w.
     uv       u = 0 on the -w edge, 1 on the +w edge; v = arc length from
              the root / the strand's length (the point's index / (n - 1)
              for a strand of no length).
     ao       0.25 + 0.75 exp(-ao x τ) (the floor of the other builders:
              light still scatters into the densest hair), τ the hair
              above the point: a grid of
              AO_GRID cells along the longest side of the hair's box counts
              the points in each cell; τ sums, along the ray from the point
              away from the head centre (one cell a step, the point's own
              cell left out), each cell's count over the mean count of the
              occupied cells. O(points x AO_GRID) and one pass to fill the
              grid: outer hair 1, hair under k typical cells of hair
              0.25 + 0.75 exp(-ao k); ao 0: 1 everywhere.
   Sort key: distance of the strand's vertex centroid from the head centre
   (ht_mesh.center), so inner strands draw first.
   Vertices of point i: 2 i + {0: -w, 1: +w} from the strand's first;
   triangles counter-clockwise seen from the normal's side. */
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "mesh_internal.h"
#include <hairtier/strands.h>

#define AO_GRID 64
#define AO_FLOOR 0.25
#define STANDING_OUT 0.05 /* |o x t| below: the ribbon keeps the previous point's axis */
#define MAX_SCALE 1e4f
#define MIN_SCALE 1e-6f

typedef struct density_grid {
    double lo[3], cell; /* box corner and cell side, scene units */
    int n[3];
    float *count;       /* n[0] x n[1] x n[2], normalised by the mean occupied count */
} density_grid;

static void to_scene(const ht_strands_ribbon_desc *d, const float p[3], double out[3]) {
    for (int k = 0; k < 3; k++) out[k] = ((double)p[k] - d->center[k]) * d->scale;
}

static bool cell_of(const density_grid *g, const double p[3], int c[3]) {
    for (int k = 0; k < 3; k++) {
        const double x = (p[k] - g->lo[k]) / g->cell;
        if (!(x >= 0) || x >= g->n[k]) return false;
        c[k] = (int)x;
    }
    return true;
}

static size_t cell_index(const density_grid *g, const int c[3]) {
    return ((size_t)c[2] * g->n[1] + c[1]) * g->n[0] + c[0];
}

static ht_result build_grid(const ht_strands *s, const ht_strands_ribbon_desc *d, density_grid *g) {
    double lo[3], hi[3], p[3];
    to_scene(d, s->points[0], lo);
    ht_vec3_copy(hi, lo);
    for (uint32_t i = 1; i < s->point_count; i++) {
        to_scene(d, s->points[i], p);
        for (int k = 0; k < 3; k++) { lo[k] = fmin(lo[k], p[k]); hi[k] = fmax(hi[k], p[k]); }
    }
    double extent = 0;
    for (int k = 0; k < 3; k++) extent = fmax(extent, hi[k] - lo[k]);
    g->cell = extent > 0 ? extent / AO_GRID * (1.0 + 1e-9) : 1.0;
    for (int k = 0; k < 3; k++) {
        g->lo[k] = lo[k];
        g->n[k] = (int)fmin(AO_GRID, floor((hi[k] - lo[k]) / g->cell) + 1);
    }
    const size_t cells = (size_t)g->n[0] * g->n[1] * g->n[2];
    g->count = calloc(cells, sizeof *g->count);
    if (!g->count) return HT_ERR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < s->point_count; i++) {
        int c[3];
        to_scene(d, s->points[i], p);
        if (cell_of(g, p, c)) g->count[cell_index(g, c)] += 1.0f;
    }
    size_t occupied = 0;
    double total = 0;
    for (size_t i = 0; i < cells; i++)
        if (g->count[i] > 0) { occupied++; total += g->count[i]; }
    const double mean = occupied ? total / occupied : 1.0;
    for (size_t i = 0; i < cells; i++) g->count[i] = (float)(g->count[i] / mean);
    return HT_OK;
}

/* τ of the header: the hair above p along the unit direction o. */
static double hair_above(const density_grid *g, const double p[3], const double o[3]) {
    int own[3], c[3];
    if (!cell_of(g, p, own)) return 0;
    double tau = 0, q[3];
    for (int step = 1; step <= 2 * AO_GRID; step++) {
        ht_vec3_mad(q, p, step * g->cell, o);
        if (!cell_of(g, q, c)) break;
        if (c[0] == own[0] && c[1] == own[1] && c[2] == own[2]) continue;
        tau += g->count[cell_index(g, c)];
    }
    return tau;
}

typedef struct strand_scratch {
    double (*p)[3], (*segment)[3], *arc;
} strand_scratch;

/* Unit directions of the n - 1 segments; zero-length ones copy a real
   neighbour (before, else after). False when the strand has no length. */
static bool segment_directions(strand_scratch *s, uint32_t n) {
    int64_t last_real = -1;
    for (uint32_t i = 0; i + 1 < n; i++) {
        ht_vec3_mad(s->segment[i], s->p[i + 1], -1.0, s->p[i]);
        if (ht_vec3_normalize(s->segment[i])) {
            if (last_real < 0)
                for (uint32_t j = 0; j < i; j++) ht_vec3_copy(s->segment[j], s->segment[i]);
            last_real = i;
        } else if (last_real >= 0) {
            ht_vec3_copy(s->segment[i], s->segment[last_real]);
        }
    }
    return last_real >= 0;
}

static void outward_from_head(const ht_strands_ribbon_desc *d, const double p[3], double o[3]) {
    double h[3];
    ht_vec3_from_float(h, d->head_center);
    ht_vec3_mad(o, p, -1.0, h);
    if (!ht_vec3_normalize(o)) ht_vec3_set(o, 0, 1, 0);
}

static void build_strand(const ht_strands *st, uint32_t strand, const ht_strands_ribbon_desc *d,
                         const density_grid *g, strand_scratch *s, ht_vertex *out) {
    const uint32_t first = st->first_point[strand], n = st->first_point[strand + 1] - first;
    for (uint32_t i = 0; i < n; i++) to_scene(d, st->points[first + i], s->p[i]);
    double o[3];
    if (!segment_directions(s, n)) {
        outward_from_head(d, s->p[0], o);
        for (uint32_t i = 0; i + 1 < n; i++) ht_vec3_copy(s->segment[i], o);
    }
    s->arc[0] = 0;
    for (uint32_t i = 1; i < n; i++) {
        double e[3];
        ht_vec3_mad(e, s->p[i], -1.0, s->p[i - 1]);
        s->arc[i] = s->arc[i - 1] + ht_vec3_length(e);
    }
    const double length = s->arc[n - 1];

    double prev_w[3] = { 0, 0, 0 }, facing_dir[3];
    ht_vec3_from_float(facing_dir, d->facing);
    const bool facing = ht_vec3_normalize(facing_dir);
    for (uint32_t i = 0; i < n; i++) {
        double t[3], w[3], nrm[3];
        if (i == 0) ht_vec3_copy(t, s->segment[0]);
        else if (i == n - 1) ht_vec3_copy(t, s->segment[i - 1]);
        else {
            ht_vec3_mad(t, s->segment[i - 1], 1.0, s->segment[i]);
            /* A strand that turns right round: follow the outgoing segment. */
            if (!(ht_vec3_length(t) > 1e-6 && ht_vec3_normalize(t))) ht_vec3_copy(t, s->segment[i]);
        }
        double away[3]; /* faced by the ribbon; o stays the AO ray's direction */
        outward_from_head(d, s->p[i], o);
        ht_vec3_copy(away, facing ? facing_dir : o);
        ht_vec3_cross(w, away, t);
        if (!(ht_vec3_length(w) >= STANDING_OUT && ht_vec3_normalize(w))) {
            ht_vec3_copy(w, prev_w);
            if (i == 0 || !ht_vec3_orthonormalize(w, t)) ht_vec3_any_perpendicular(w, t);
        }
        ht_vec3_cross(nrm, t, w);
        ht_vec3_normalize(nrm);
        if (ht_vec3_dot(nrm, away) < 0)
            for (int k = 0; k < 3; k++) { nrm[k] = -nrm[k]; w[k] = -w[k]; }
        ht_vec3_copy(prev_w, w);

        const double v = length > 0 ? s->arc[i] / length : (double)i / (n - 1);
        const double width = d->use_thickness ? (double)st->thickness[first + i] * d->scale
                                              : d->width * (1.0 - (1.0 - d->tip_width) * v);
        const float ao =
            d->ao > 0 ? (float)(AO_FLOOR + (1.0 - AO_FLOOR) * exp(-d->ao * hair_above(g, s->p[i], o))) : 1.0f;
        for (int side = 0; side < 2; side++) {
            ht_vertex *vx = &out[2 * i + side];
            double pos[3];
            ht_vec3_mad(pos, s->p[i], (side ? 0.5 : -0.5) * width, w);
            ht_vec3_store(vx->position, pos);
            ht_vec3_store(vx->normal, nrm);
            ht_vec3_store(vx->tangent, t);
            vx->uv[0] = (float)side;
            vx->uv[1] = (float)v;
            vx->ao = ao;
        }
    }
}

static ht_result check_desc(const ht_strands *s, const ht_strands_ribbon_desc *d, char *err, size_t err_size) {
    if (!s || !d || !s->first_point || !s->points || s->strand_count < 1)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "strands: none");
    for (uint32_t i = 0; i < s->strand_count; i++)
        if (s->first_point[i + 1] < s->first_point[i] + 2 || s->first_point[i + 1] > s->point_count)
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "strands: strand %u has fewer than 2 points", i);
    if (!(d->scale >= MIN_SCALE && d->scale <= MAX_SCALE))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "scale: %g, must be %g to %g", (double)d->scale,
                       (double)MIN_SCALE, (double)MAX_SCALE);
    if (!ht_all_finite(d->center, 3) || !ht_all_finite(d->head_center, 3) || !ht_all_finite(d->facing, 3))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "center: not finite");
    if (d->use_thickness && !s->thickness)
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "thickness: the strand file carries none");
    if (!d->use_thickness && !(d->width > 0 && d->width <= MAX_SCALE && d->tip_width >= 0 && d->tip_width <= 1))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "width: %g (tip %g), must be above 0 (tip 0 to 1)",
                       (double)d->width, (double)d->tip_width);
    if (!(d->ao >= 0 && d->ao <= 100))
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ao: %g, must be 0 to 100", (double)d->ao);
    return HT_OK;
}

ht_result ht_mesh_build_strands(const ht_strands *strands, const ht_strands_ribbon_desc *desc, ht_mesh *out,
                                char *err, size_t err_size) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    ht_result r = check_desc(strands, desc, err, err_size);
    if (r != HT_OK) return r;
    const uint64_t points = strands->point_count, count = strands->strand_count;
    r = ht_mesh_alloc(out, points * 2, (points - count) * 6, count);
    if (r != HT_OK) return r;
    memcpy(out->center, desc->head_center, sizeof out->center);

    uint32_t longest = 0;
    for (uint32_t i = 0; i < count; i++)
        if (strands->first_point[i + 1] - strands->first_point[i] > longest)
            longest = strands->first_point[i + 1] - strands->first_point[i];
    density_grid g = { 0 };
    strand_scratch s = { malloc(sizeof *s.p * longest), malloc(sizeof *s.segment * longest),
                         malloc(sizeof *s.arc * longest) };
    if (!s.p || !s.segment || !s.arc || build_grid(strands, desc, &g) != HT_OK) {
        r = HT_ERR_OUT_OF_MEMORY;
        ht_mesh_free(out);
        goto done;
    }

    uint32_t next_index = 0;
    for (uint32_t c = 0; c < count; c++) {
        const uint32_t first = strands->first_point[c], n = strands->first_point[c + 1] - first;
        const uint32_t base = 2 * first;
        build_strand(strands, c, desc, &g, &s, out->vertices + base);
        for (uint32_t i = 0; i + 1 < n; i++) {
            const uint32_t a0 = base + 2 * i, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
            const uint32_t tri[6] = { a0, b1, a1, a0, b0, b1 };
            memcpy(out->indices + next_index + 6 * i, tri, sizeof tri);
        }
        out->components[c] = (ht_component){
            .first_index = next_index,
            .index_count = 6 * (n - 1),
            .sort_key = ht_mesh_centroid_distance(out, base, 2 * n),
        };
        next_index += 6 * (n - 1);
    }
    ht_mesh_sort_inside_out(out);
done:
    free(g.count);
    free(s.p);
    free(s.segment);
    free(s.arc);
    return r;
}

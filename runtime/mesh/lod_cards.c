/* lod_cards.c — clumps of strands as textured cards, their atlas baked
   from the strands they replace (lod.h says what a card is and what the
   atlas holds).

   Frame of card row r (rows R = the clump's longest strand's, parameter
   t = r / (R - 1)): C = mean of the strands' centres at t (each strand
   resampled linearly at its own t), T = the centre line's direction there
   (unit, root to tip), d_i = strand i's centre − C made perpendicular to
   T; the width axis W = e made perpendicular to T, e the dominant
   eigenvector of the d_i's covariance over every row (the first strand's
   own width where the clump has no spread); half width = max |d_i · W| +
   the strand's own half width. A strand's vertex p at its t lands at
   (u, v) = (0.5 + (p − C(t)) · W(t) / (2 hw(t)), t) on the card. */
#include <stdlib.h>
#include <string.h>

#include "lod_internal.h"

#define SUB 4            /* samples a texel side */
#define CELL_MIN_W 2
#define CELL_MIN_H 4
#define CELL_ASPECT 4.0  /* cells as tall as a card is long against wide */
#define MAX_SHIFT 0.5    /* the shift texture's range: 0.5 + s in [0, 1] */
#define POWER_ROUNDS 32

typedef struct card_frame {
    double c[3], t[3], w[3], n[3], hw;
} card_frame;

/* Strand run `run` resampled at parameter t in [0, 1]: centre, half-width
   vector, tangent, normal (tangent and normal not normalized). */
typedef struct strand_sample {
    double c[3], half[3], t[3], n[3];
} strand_sample;

static void sample_strand(const ht_mesh *m, const ht_lod_run *run, double t, strand_sample *s) {
    const double f = t * (run->rows - 1);
    uint32_t r0 = (uint32_t)f;
    if (r0 + 1 >= run->rows) r0 = run->rows > 1 ? run->rows - 2 : 0;
    const double a = run->rows > 1 ? f - r0 : 0;
    const uint32_t r1 = run->rows > 1 ? r0 + 1 : r0;
    const ht_vertex *p = &m->vertices[run->first_vertex + 2 * r0], *q = &m->vertices[run->first_vertex + 2 * r1];
    for (int k = 0; k < 3; k++) {
        const double c0 = 0.5 * ((double)p[0].position[k] + p[1].position[k]);
        const double c1 = 0.5 * ((double)q[0].position[k] + q[1].position[k]);
        const double h0 = 0.5 * ((double)p[1].position[k] - p[0].position[k]);
        const double h1 = 0.5 * ((double)q[1].position[k] - q[0].position[k]);
        s->c[k] = c0 + a * (c1 - c0);
        s->half[k] = h0 + a * (h1 - h0);
        s->t[k] = p[0].tangent[k] + a * ((double)q[0].tangent[k] - p[0].tangent[k]);
        s->n[k] = p[0].normal[k] + a * ((double)q[0].normal[k] - p[0].normal[k]);
    }
}

/* The frames of one card's rows from its strands (clump[0..count)). */
static void card_frames(const ht_mesh *m, const ht_lod_run *runs, const uint32_t *clump, uint32_t count, uint32_t R,
                        card_frame *f) {
    strand_sample s;
    for (uint32_t r = 0; r < R; r++) {
        const double t = R > 1 ? (double)r / (R - 1) : 0;
        double ref[3] = { 0, 0, 0 };
        memset(&f[r], 0, sizeof f[r]);
        for (uint32_t i = 0; i < count; i++) {
            sample_strand(m, &runs[clump[i]], t, &s);
            if (i == 0) ht_vec3_copy(ref, s.n);
            ht_vec3_mad(f[r].c, f[r].c, 1.0 / count, s.c);
            ht_vec3_mad(f[r].n, f[r].n, ht_vec3_dot(s.n, ref) < 0 ? -1.0 : 1.0, s.n);
        }
    }
    for (uint32_t r = 0; r < R; r++) {
        const uint32_t a = r ? r - 1 : 0, b = r + 1 < R ? r + 1 : r;
        ht_vec3_mad(f[r].t, f[b].c, -1.0, f[a].c);
        if (!ht_vec3_normalize(f[r].t)) {
            sample_strand(m, &runs[clump[0]], R > 1 ? (double)r / (R - 1) : 0, &s);
            ht_vec3_copy(f[r].t, s.t);
            if (!ht_vec3_normalize(f[r].t)) ht_vec3_set(f[r].t, 0, 1, 0);
        }
    }
    /* The spread's dominant direction: power iteration on the covariance,
       started from the first strand's own width at its root. */
    double cov[3][3] = { { 0 } }, e[3];
    sample_strand(m, &runs[clump[0]], 0, &s);
    ht_vec3_copy(e, s.half);
    for (uint32_t r = 0; r < R; r++)
        for (uint32_t i = 0; i < count; i++) {
            sample_strand(m, &runs[clump[i]], R > 1 ? (double)r / (R - 1) : 0, &s);
            double d[3];
            ht_vec3_mad(d, s.c, -1.0, f[r].c);
            ht_vec3_mad(d, d, -ht_vec3_dot(d, f[r].t), f[r].t);
            for (int j = 0; j < 3; j++)
                for (int k = 0; k < 3; k++) cov[j][k] += d[j] * d[k];
        }
    const double scale = cov[0][0] + cov[1][1] + cov[2][2];
    if (scale > 1e-20) {
        for (int round = 0; round < POWER_ROUNDS; round++) {
            double x[3];
            for (int j = 0; j < 3; j++) x[j] = (cov[j][0] * e[0] + cov[j][1] * e[1] + cov[j][2] * e[2]) / scale;
            if (!ht_vec3_normalize(x)) break;
            ht_vec3_copy(e, x);
        }
    }
    for (uint32_t r = 0; r < R; r++) {
        ht_vec3_copy(f[r].w, e);
        if (!ht_vec3_orthonormalize(f[r].w, f[r].t)) {
            if (r) ht_vec3_copy(f[r].w, f[r - 1].w);
            if (!r || !ht_vec3_orthonormalize(f[r].w, f[r].t)) ht_vec3_any_perpendicular(f[r].w, f[r].t);
        }
        if (!ht_vec3_orthonormalize(f[r].n, f[r].t)) ht_vec3_cross(f[r].n, f[r].t, f[r].w);
        double hw = 0;
        for (uint32_t i = 0; i < count; i++) {
            sample_strand(m, &runs[clump[i]], R > 1 ? (double)r / (R - 1) : 0, &s);
            double d[3];
            ht_vec3_mad(d, s.c, -1.0, f[r].c);
            hw = fmax(hw, fabs(ht_vec3_dot(d, f[r].w)) + ht_vec3_length(s.half));
        }
        f[r].hw = hw > 0 ? hw : 1e-6;
    }
}

/* The card frame at parameter t, between rows. */
static void frame_at(const card_frame *f, uint32_t R, double t, card_frame *out) {
    const double x = t * (R - 1);
    uint32_t r0 = (uint32_t)fmax(0, x);
    if (r0 + 1 >= R) r0 = R > 1 ? R - 2 : 0;
    const uint32_t r1 = R > 1 ? r0 + 1 : 0;
    const double a = R > 1 ? ht_clamp01(x - r0) : 0;
    for (int k = 0; k < 3; k++) {
        out->c[k] = f[r0].c[k] + a * (f[r1].c[k] - f[r0].c[k]);
        out->t[k] = f[r0].t[k] + a * (f[r1].t[k] - f[r0].t[k]);
        out->w[k] = f[r0].w[k] + a * (f[r1].w[k] - f[r0].w[k]);
        out->n[k] = f[r0].n[k] + a * (f[r1].n[k] - f[r0].n[k]);
    }
    out->hw = f[r0].hw + a * (f[r1].hw - f[r0].hw);
    ht_vec3_normalize(out->t);
    ht_vec3_normalize(out->w);
    ht_vec3_normalize(out->n);
}

/* ---- the bake ---- */

/* One material image as row prefix sums per channel (wrapping in u), so a
   box across u of any width is two reads. */
typedef struct prefiltered {
    int w, h;
    double *sum; /* h rows of (w + 1) x 4 */
} prefiltered;

static bool prefilter(const ht_image *img, prefiltered *p) {
    p->w = img->width;
    p->h = img->height;
    p->sum = malloc(sizeof *p->sum * (size_t)(p->w + 1) * 4 * p->h);
    if (!p->sum) return false;
    for (int y = 0; y < p->h; y++) {
        double *row = p->sum + (size_t)y * (p->w + 1) * 4;
        for (int c = 0; c < 4; c++) row[c] = 0;
        for (int x = 0; x < p->w; x++)
            for (int c = 0; c < 4; c++)
                row[4 * (x + 1) + c] = row[4 * x + c] + img->pixels[((size_t)y * p->w + x) * 4 + c] / 255.0;
    }
    return true;
}

/* Sum over texels [0, x) of a row, x any real (whole periods wrap). */
static double row_sum(const prefiltered *p, const double *row, double x, int c) {
    const double period = floor(x / p->w);
    x -= period * p->w;
    const int i = (int)x;
    const double frac = x - i;
    const double base = period * row[4 * p->w + c] + row[4 * i + c];
    return base + (i < p->w ? frac * (row[4 * (i + 1) + c] - row[4 * i + c]) : 0);
}

/* Channel c at (u, v), the mean across u over width du (in u units). */
static double sample_box(const prefiltered *p, double u, double v, double du, int c) {
    int y = (int)floor(ht_clamp01(v) * p->h);
    if (y >= p->h) y = p->h - 1;
    const double *row = p->sum + (size_t)y * (p->w + 1) * 4;
    const double half = fmax(0.5, 0.5 * du * p->w);
    const double x = u * p->w;
    return (row_sum(p, row, x + half, c) - row_sum(p, row, x - half, c)) / (2 * half);
}

/* What a strand vertex carries into the bake. */
typedef struct bake_vertex {
    double x, y;        /* texel coordinates in the atlas (sample centres at +0.5) */
    double u, v;        /* the strand's own uv */
    double du;          /* the filter width across u */
    double shift, ao;
} bake_vertex;

typedef struct bake {
    int W, H;
    float *transmit;    /* W x H x SUB x SUB: prod(1 - alpha) */
    double *acc;        /* W x H x ACC: alpha-weighted sums */
    const prefiltered *albedo, *detail;
} bake;

#define ACC 7 /* weight, base r g b, shift, sparkle, ao */

static void bake_triangle(bake *b, const bake_vertex *v0, const bake_vertex *v1, const bake_vertex *v2, int cx0,
                          int cy0, int cx1, int cy1) {
    const double area = (v1->x - v0->x) * (v2->y - v0->y) - (v1->y - v0->y) * (v2->x - v0->x);
    if (fabs(area) < 1e-12) return;
    const double x0 = fmax(cx0, floor(fmin(v0->x, fmin(v1->x, v2->x)))),
                 x1 = fmin(cx1 - 1, floor(fmax(v0->x, fmax(v1->x, v2->x))));
    const double y0 = fmax(cy0, floor(fmin(v0->y, fmin(v1->y, v2->y)))),
                 y1 = fmin(cy1 - 1, floor(fmax(v0->y, fmax(v1->y, v2->y))));
    for (int ty = (int)y0; ty <= (int)y1; ty++)
        for (int tx = (int)x0; tx <= (int)x1; tx++)
            for (int s = 0; s < SUB * SUB; s++) {
                const double px = tx + (s % SUB + 0.5) / SUB, py = ty + (s / SUB + 0.5) / SUB;
                const double l1 = ((px - v0->x) * (v2->y - v0->y) - (py - v0->y) * (v2->x - v0->x)) / area;
                const double l2 = ((v1->x - v0->x) * (py - v0->y) - (v1->y - v0->y) * (px - v0->x)) / area;
                const double l0 = 1 - l1 - l2;
                if (l0 < 0 || l1 < 0 || l2 < 0) continue;
                const double u = l0 * v0->u + l1 * v1->u + l2 * v2->u, v = l0 * v0->v + l1 * v1->v + l2 * v2->v;
                const double du = l0 * v0->du + l1 * v1->du + l2 * v2->du;
                const double alpha = b->albedo ? sample_box(b->albedo, u, v, du, 3) : 1.0;
                if (!(alpha > 0)) continue;
                const size_t texel = (size_t)ty * b->W + tx;
                b->transmit[texel * SUB * SUB + s] *= (float)(1 - alpha);
                double *a = b->acc + texel * ACC;
                const double shift = l0 * v0->shift + l1 * v1->shift + l2 * v2->shift +
                                     (b->detail ? sample_box(b->detail, u, v, du, 0) - 0.5 : 0);
                a[0] += alpha;
                for (int c = 0; c < 3; c++) a[1 + c] += alpha * (b->albedo ? sample_box(b->albedo, u, v, du, c) : 1);
                a[4] += alpha * shift;
                a[5] += alpha * (b->detail ? sample_box(b->detail, u, v, du, 1) : 1);
                a[6] += alpha * (l0 * v0->ao + l1 * v1->ao + l2 * v2->ao);
            }
}

/* Card k's cell in texels: [x0, x1) x [y0, y1). */
static void cell_of(const ht_cards *cards, int W, int H, uint32_t k, int *x0, int *y0, int *x1, int *y1) {
    const int cw = W / cards->columns, ch = (H - cards->first_row) / cards->rows;
    *x0 = (int)(k % (uint32_t)cards->columns) * cw;
    *y0 = cards->first_row + (int)(k / (uint32_t)cards->columns) * ch;
    *x1 = *x0 + cw;
    *y1 = *y0 + ch;
}

/* Card-local (u, v) in [0, 1]^2 to atlas texel coordinates: the ends fall
   on the cell's edge texel centres, so filtering stays inside the cell. */
static void local_to_texel(int x0, int y0, int x1, int y1, double u, double v, double *x, double *y) {
    *x = x0 + 0.5 + u * (x1 - x0 - 1);
    *y = y0 + 0.5 + v * (y1 - y0 - 1);
}

/* The strand's vertex (row r, side) as the bake sees it on card frames f. */
static bake_vertex strand_vertex(const ht_mesh *m, const ht_lod_run *run, uint32_t r, int side, const card_frame *f,
                                 uint32_t R, const int cell[4]) {
    const ht_vertex *sv = &m->vertices[run->first_vertex + 2 * r + side];
    const double t = run->rows > 1 ? (double)r / (run->rows - 1) : 0;
    card_frame at;
    frame_at(f, R, t, &at);
    double p[3], tan[3], width[3];
    ht_vec3_from_float(p, sv->position);
    ht_vec3_mad(p, p, -1.0, at.c);
    const double u = 0.5 + ht_vec3_dot(p, at.w) / (2 * at.hw);
    bake_vertex b;
    local_to_texel(cell[0], cell[1], cell[2], cell[3], u, t, &b.x, &b.y);
    ht_vec3_from_float(tan, sv->tangent);
    const double along = ht_vec3_dot(tan, at.t);
    b.shift = along > 0.25 ? ht_clamp_unit(ht_vec3_dot(tan, at.n) / along) * MAX_SHIFT : 0;
    b.u = sv->uv[0];
    b.v = sv->uv[1];
    b.ao = sv->ao;
    /* The strand's width in texels: the material's u over it is boxed. */
    const ht_vertex *o = &m->vertices[run->first_vertex + 2 * r + (1 - side)];
    for (int k = 0; k < 3; k++) width[k] = (double)sv->position[k] - o->position[k];
    const double texels = fabs(ht_vec3_dot(width, at.w)) / (2 * at.hw) * (cell[2] - cell[0] - 1);
    b.du = texels > 1 ? 1.0 / texels : 1.0;
    return b;
}

static void bake_clump(bake *b, const ht_mesh *m, const ht_lod_run *runs, const uint32_t *clump, uint32_t count,
                       const card_frame *f, uint32_t R, const int cell[4]) {
    for (uint32_t i = 0; i < count; i++) {
        const ht_lod_run *run = &runs[clump[i]];
        bake_vertex prev[2] = { strand_vertex(m, run, 0, 0, f, R, cell), strand_vertex(m, run, 0, 1, f, R, cell) };
        for (uint32_t r = 1; r < run->rows; r++) {
            const bake_vertex next[2] = { strand_vertex(m, run, r, 0, f, R, cell),
                                          strand_vertex(m, run, r, 1, f, R, cell) };
            bake_triangle(b, &prev[0], &next[1], &prev[1], cell[0], cell[1], cell[2], cell[3]);
            bake_triangle(b, &prev[0], &next[0], &next[1], cell[0], cell[1], cell[2], cell[3]);
            prev[0] = next[0];
            prev[1] = next[1];
        }
    }
}

static uint8_t byte_of(double x) { return (uint8_t)lrint(ht_clamp01(x) * 255.0); }

/* The accumulations into the three images; a texel no strand covers takes
   its card's mean (bilinear filtering at the edges then blends like with
   like). */
static void resolve_cell(const bake *b, const int cell[4], ht_cards *out) {
    double mean[ACC] = { 0 };
    for (int y = cell[1]; y < cell[3]; y++)
        for (int x = cell[0]; x < cell[2]; x++)
            for (int c = 0; c < ACC; c++) mean[c] += b->acc[((size_t)y * b->W + x) * ACC + c];
    for (int y = cell[1]; y < cell[3]; y++)
        for (int x = cell[0]; x < cell[2]; x++) {
            const size_t texel = (size_t)y * b->W + x;
            const double *a = b->acc[texel * ACC] > 0 ? b->acc + texel * ACC : mean;
            const double w = a[0] > 0 ? a[0] : 1;
            /* The samples inside the card: its edges run through the edge
               texels' centres (local_to_texel), where GL's bilinear filter
               reads them. */
            double cover = 0;
            int inside = 0;
            for (int s = 0; s < SUB * SUB; s++) {
                const double px = x + (s % SUB + 0.5) / SUB, py = y + (s / SUB + 0.5) / SUB;
                if (px < cell[0] + 0.5 || px > cell[2] - 0.5 || py < cell[1] + 0.5 || py > cell[3] - 0.5) continue;
                cover += 1 - b->transmit[texel * SUB * SUB + s];
                inside++;
            }
            const double ao = a[0] > 0 ? a[6] / w : 1;
            uint8_t *al = out->albedo.pixels + texel * 4, *de = out->detail.pixels + texel * 4;
            for (int c = 0; c < 3; c++) al[c] = byte_of(a[0] > 0 ? a[1 + c] / w * ao : 1);
            al[3] = byte_of(inside ? cover / inside : 0);
            de[0] = byte_of(a[0] > 0 ? 0.5 + a[4] / w : 0.5);
            de[1] = byte_of(a[0] > 0 ? a[5] / w : 1);
            de[2] = 0;
            de[3] = 255;
            out->ao.pixels[texel] = byte_of(ao);
        }
}

/* ---- the clumps ---- */

#define FEATURE 9       /* the centre at t = 0, 1/2, 1 */
#define KMEANS_ROUNDS 4

static void feature_of(const ht_mesh *m, const ht_lod_run *run, double f[FEATURE]) {
    strand_sample s;
    for (int j = 0; j < 3; j++) {
        sample_strand(m, run, 0.5 * j, &s);
        for (int k = 0; k < 3; k++) f[3 * j + k] = s.c[k];
    }
}

/* Clumps of strands whose centre lines run close together: k-means over
   (root, middle, tip), seeded with runs of `per` neighbours on the
   Z-order curve (a run alone can jump across the curve's seams). Writes
   the strands clump by clump into order and each clump's first position
   into first[0..clumps]; returns the clumps (empty ones dropped). */
static uint32_t clump(const ht_mesh *m, const ht_lod_run *runs, const uint32_t *curve, uint32_t per, uint32_t k,
                      uint32_t *order, uint32_t *first, double *feat, double *centre, uint32_t *label) {
    const uint32_t n = m->component_count;
    for (uint32_t c = 0; c < n; c++) feature_of(m, &runs[c], feat + (size_t)c * FEATURE);
    for (uint32_t i = 0; i < n; i++) label[curve[i]] = i / per;
    for (int round = 0; round <= KMEANS_ROUNDS; round++) {
        memset(centre, 0, sizeof *centre * (size_t)k * FEATURE);
        memset(first, 0, sizeof *first * (k + 1));
        for (uint32_t c = 0; c < n; c++) {
            first[label[c]]++;
            for (int j = 0; j < FEATURE; j++) centre[(size_t)label[c] * FEATURE + j] += feat[(size_t)c * FEATURE + j];
        }
        for (uint32_t j = 0; j < k; j++)
            for (int d = 0; d < FEATURE && first[j]; d++) centre[(size_t)j * FEATURE + d] /= first[j];
        if (round == KMEANS_ROUNDS) break;
        for (uint32_t c = 0; c < n; c++) {
            double best = INFINITY;
            for (uint32_t j = 0; j < k; j++) {
                if (!first[j]) continue;
                double d2 = 0;
                for (int d = 0; d < FEATURE; d++) {
                    const double x = feat[(size_t)c * FEATURE + d] - centre[(size_t)j * FEATURE + d];
                    d2 += x * x;
                }
                if (d2 < best) { best = d2; label[c] = j; }
            }
        }
    }
    /* Counting sort by label, in curve order within a clump; empties go. */
    uint32_t clumps = 0, at = 0;
    uint32_t *start = centre ? (uint32_t *)centre : NULL; /* reuse: k + 1 slots fit in k * FEATURE doubles */
    for (uint32_t j = 0; j < k; j++) {
        start[j] = at;
        at += first[j];
    }
    for (uint32_t j = 0; j < k; j++)
        if (first[j]) first[clumps++] = start[j];
    first[clumps] = n;
    for (uint32_t i = 0; i < n; i++) order[start[label[curve[i]]]++] = curve[i];
    return clumps;
}

/* ---- the cards ---- */

static bool check_rgba(const ht_image *img) { return !img || (img->pixels && img->channels == 4 && img->width > 0 && img->height > 0); }

ht_result ht_mesh_build_cards(const ht_mesh *full, const ht_cards_desc *desc, ht_cards *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (!full || !desc || !full->vertices || !full->indices || !full->components || !full->component_count ||
        !check_rgba(desc->strand_albedo) || !check_rgba(desc->strand_detail) || desc->atlas_width < 0 ||
        desc->atlas_height < 0 || desc->reserve_rows < 0)
        return HT_ERR_INVALID_ARGUMENT;
    const uint32_t n = full->component_count;
    const uint32_t per = desc->strands_per_card ? desc->strands_per_card : HT_CARDS_DEFAULT_STRANDS;
    const uint32_t seeds = n / per + (n % per != 0);
    const int W = desc->atlas_width ? desc->atlas_width : desc->strand_albedo ? desc->strand_albedo->width : 256;
    const int H = desc->atlas_height ? desc->atlas_height : desc->strand_albedo ? desc->strand_albedo->height : 256;

    ht_lod_run *runs = malloc(sizeof *runs * n);
    uint32_t *curve = malloc(sizeof *curve * n), *order = malloc(sizeof *order * n), *label = malloc(sizeof *label * n);
    uint32_t *first = malloc(sizeof *first * (seeds + 1));
    double *feat = malloc(sizeof *feat * (size_t)n * FEATURE), *centres = malloc(sizeof *centres * (size_t)seeds * FEATURE);
    card_frame *frames = NULL;
    prefiltered pa = { 0 }, pd = { 0 };
    bake b = { .W = W, .H = H };
    ht_result r = runs && curve && order && label && first && feat && centres ? ht_lod_runs(full, runs)
                                                                               : HT_ERR_OUT_OF_MEMORY;
    if (r == HT_OK) r = ht_lod_curve_order(full, runs, curve);
    if (r != HT_OK) goto done;
    const uint32_t cards = clump(full, runs, curve, per, seeds, order, first, feat, centres, label);
    /* Cells CELL_ASPECT times taller than wide: rows of cells first. */
    const int cells_h = H - desc->reserve_rows;
    int grid_rows = cells_h > 0 ? (int)ceil(sqrt(cards * (double)W / cells_h / CELL_ASPECT)) : 1;
    if (grid_rows < 1) grid_rows = 1;
    const int grid_cols = (int)((cards + (uint32_t)grid_rows - 1) / (uint32_t)grid_rows);
    if (cells_h <= 0 || W / grid_cols < CELL_MIN_W || cells_h / grid_rows < CELL_MIN_H) {
        r = HT_ERR_INVALID_ARGUMENT;
        goto done;
    }
    out->columns = grid_cols;
    out->rows = grid_rows;
    out->first_row = desc->reserve_rows;
    uint32_t longest = 0;
    uint64_t vertices = 0;
    for (uint32_t k = 0; k < cards; k++) {
        uint32_t R = 0;
        for (uint32_t i = first[k]; i < first[k + 1]; i++) R = runs[order[i]].rows > R ? runs[order[i]].rows : R;
        longest = R > longest ? R : longest;
        vertices += 2ull * R;
    }
    frames = malloc(sizeof *frames * longest);
    b.transmit = malloc(sizeof *b.transmit * (size_t)W * H * SUB * SUB);
    b.acc = calloc((size_t)W * H * ACC, sizeof *b.acc);
    if (!frames || !b.transmit || !b.acc || (desc->strand_albedo && !prefilter(desc->strand_albedo, &pa)) ||
        (desc->strand_detail && !prefilter(desc->strand_detail, &pd))) {
        r = HT_ERR_OUT_OF_MEMORY;
        goto done;
    }
    for (size_t i = 0; i < (size_t)W * H * SUB * SUB; i++) b.transmit[i] = 1;
    b.albedo = desc->strand_albedo ? &pa : NULL;
    b.detail = desc->strand_detail ? &pd : NULL;
    if ((r = ht_mesh_alloc(&out->mesh, vertices, 6 * (vertices / 2 - cards), cards)) != HT_OK) goto done;
    if ((r = ht_image_alloc(&out->albedo, W, H, 4)) != HT_OK || (r = ht_image_alloc(&out->detail, W, H, 4)) != HT_OK ||
        (r = ht_image_alloc(&out->ao, W, H, 1)) != HT_OK)
        goto done;
    memcpy(out->mesh.center, full->center, sizeof out->mesh.center);

    uint32_t v = 0, idx = 0;
    for (uint32_t k = 0; k < cards; k++) {
        const uint32_t *members = order + first[k], count = first[k + 1] - first[k];
        uint32_t R = 0;
        for (uint32_t i = 0; i < count; i++) R = runs[members[i]].rows > R ? runs[members[i]].rows : R;
        card_frames(full, runs, members, count, R, frames);
        int cell[4];
        cell_of(out, W, H, k, &cell[0], &cell[1], &cell[2], &cell[3]);
        bake_clump(&b, full, runs, members, count, frames, R, cell);
        resolve_cell(&b, cell, out);
        for (uint32_t row = 0; row < R; row++) {
            const double t = R > 1 ? (double)row / (R - 1) : 0;
            for (int side = 0; side < 2; side++) {
                ht_vertex *vx = &out->mesh.vertices[v + 2 * row + side];
                double p[3], x, y;
                ht_vec3_mad(p, frames[row].c, side ? frames[row].hw : -frames[row].hw, frames[row].w);
                ht_vec3_store(vx->position, p);
                ht_vec3_store(vx->tangent, frames[row].t);
                ht_vec3_store(vx->normal, frames[row].n);
                local_to_texel(cell[0], cell[1], cell[2], cell[3], side, t, &x, &y);
                vx->uv[0] = (float)(x / W);
                vx->uv[1] = (float)(y / H);
                vx->ao = 1.0f;
            }
            if (row + 1 < R) {
                const uint32_t a0 = v + 2 * row, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
                const uint32_t tri[6] = { a0, b1, a1, a0, b0, b1 };
                memcpy(out->mesh.indices + idx + 6 * row, tri, sizeof tri);
            }
        }
        out->mesh.components[k] = (ht_component){ idx, 6 * (R - 1), ht_mesh_centroid_distance(&out->mesh, v, 2 * R) };
        v += 2 * R;
        idx += 6 * (R - 1);
    }
    out->mesh.vertex_count = v;
    out->mesh.index_count = idx;
    out->mesh.component_count = cards;
    ht_mesh_sort_inside_out(&out->mesh);
done:
    free(runs);
    free(curve);
    free(order);
    free(label);
    free(first);
    free(feat);
    free(centres);
    free(frames);
    free(pa.sum);
    free(pd.sum);
    free(b.transmit);
    free(b.acc);
    if (r != HT_OK) ht_cards_free(out);
    return r;
}

void ht_cards_free(ht_cards *c) {
    if (!c) return;
    ht_mesh_free(&c->mesh);
    ht_image_free(&c->albedo);
    ht_image_free(&c->detail);
    ht_image_free(&c->ao);
    memset(c, 0, sizeof *c);
}

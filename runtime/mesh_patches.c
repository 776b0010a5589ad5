/* mesh_patches.c — layered hair strips around a head sphere, after
   Scheuermann's ATI hair: `layers` shells of `strips` ribbons each, every
   ribbon `segments` quads from the scalp down, plus the opaque head.

   Frame: head centred at the origin, y up, the face towards +z. A point on
   a sphere of radius r is r * (sin θ sin φ, cos θ, sin θ cos φ): θ is the
   polar angle from the crown, φ the azimuth from the face (φ = π: the back).

   Strip s of layer l (both counted from 0, inner layer first):
     azimuth  φ = 2π (s + l / layers + jitter) / strips, jitter in ±0.2, so
              layers interleave; plus a seeded sideways wave of up to 0.3
              spacing that is 0 at the root and the tip.
     polar    from θ0 in [0.08, 0.2) near the crown down to θ1 = 1.0 at the
              face, 2.3 at the back (nape), mixed by (1 - cos φ) / 2, ±0.075.
     radius   R (1.02 + 0.03 l + 0.012 v + lift), lift in [0, 0.004): each
              layer a shell above the last, tips lifted off the hair below.
     width    the ribbon spans ±hw along the azimuth direction,
              hw = 0.75 · 2π r max(sin θ, 0.35) / strips (≤ 0.6 r): 1.5 times
              the spacing of strips, so neighbours overlap. The ribbon is
              flat in the sphere's tangent plane, so it never dips into the
              head.
   Per vertex: tangent = mean of the adjacent segment directions of the
   strip's centre line (root to tip); the widening axis is the azimuth
   direction made perpendicular to the tangent; normal = cross(tangent,
   widening axis), which points away from the head centre. uv: u 0 → 1
   across, v = row / segments, root 0 → tip 1.
   ao = 0.25 + 0.75 · (clamp(h / h_max, 0, 1) + v) / 2 with h the height of the
   centre line above the head surface and h_max that of the outermost
   layer's lifted tip: inner layers and roots (near the scalp, under the
   others) are darker, outer tips brightest.

   The head is a UV sphere of HEAD_SLICES × HEAD_STACKS, normals radial,
   tangent the azimuth direction, uv = (φ / 2π, θ / π), ao = 1, one
   component. Triangles are counter-clockwise seen from outside.

   Limits (else HT_ERR_INVALID_ARGUMENT, after defaults): head_radius in
   [1e-4, 1e4], 1 <= layers <= 256, 1 <= strips <= 2^20,
   1 <= segments <= 4096, vertex and index counts that fit uint32. On any
   failure both `out` and `head` are left zeroed. */
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"
#include "rng.h"

/* Outside these the float positions lose the shell offsets (too small) or
   every precision the renderer has (too large). */
#define PATCHES_MIN_RADIUS 1e-4f
#define PATCHES_MAX_RADIUS 1e4f
#define PATCHES_MAX_LAYERS 256
#define PATCHES_MAX_STRIPS (1 << 20)
#define PATCHES_MAX_SEGMENTS 4096
#define HEAD_SLICES 48
#define HEAD_STACKS 24

#define SHELL_BASE 0.02  /* inner layer's height above the head / R */
#define SHELL_STEP 0.03  /* between layers / R */
#define TIP_LIFT 0.012   /* extra height at the tip / R */
#define MAX_JITTER_LIFT 0.004

static ht_result resolve(const ht_patches_desc *in, ht_patches_desc *d) {
    if (!in) return HT_ERR_INVALID_ARGUMENT;
    *d = *in;
    if (d->head_radius == 0) d->head_radius = 1.0f;
    if (d->layers == 0) d->layers = 3;
    if (d->strips == 0) d->strips = 64;
    if (d->segments == 0) d->segments = 12;
    if (!isfinite(d->head_radius) || d->head_radius < PATCHES_MIN_RADIUS ||
        d->head_radius > PATCHES_MAX_RADIUS)
        return HT_ERR_INVALID_ARGUMENT;
    if (d->layers < 1 || d->layers > PATCHES_MAX_LAYERS || d->strips < 1 ||
        d->strips > PATCHES_MAX_STRIPS || d->segments < 1 || d->segments > PATCHES_MAX_SEGMENTS)
        return HT_ERR_INVALID_ARGUMENT;
    return HT_OK;
}

static void sphere_point(double p[3], double r, double theta, double phi) {
    v3_set(p, r * sin(theta) * sin(phi), r * cos(theta), r * sin(theta) * cos(phi));
}

static void azimuth_direction(double e[3], double phi) { v3_set(e, cos(phi), 0.0, -sin(phi)); }

typedef struct strip_params {
    double phi, wave, theta0, theta1, lift, shell;
} strip_params;

static strip_params draw_strip(const ht_patches_desc *d, ht_rng *rng, int layer, int strip) {
    strip_params p;
    const double spacing = 2.0 * M_PI / d->strips;
    p.phi = spacing * (strip + (double)layer / d->layers + ht_rng_range(rng, -0.2, 0.2));
    p.wave = spacing * ht_rng_range(rng, -0.3, 0.3);
    p.theta0 = ht_rng_range(rng, 0.08, 0.2);
    const double back = 0.5 * (1.0 - cos(p.phi));
    p.theta1 = 1.0 + 1.3 * back + ht_rng_range(rng, -0.075, 0.075);
    p.lift = ht_rng_range(rng, 0.0, MAX_JITTER_LIFT);
    p.shell = 1.0 + SHELL_BASE + SHELL_STEP * layer;
    return p;
}

/* Centre line of the strip at row i, v = i / segments. */
static void centre_point(const ht_patches_desc *d, const strip_params *p, double v, double c[3],
                         double *phi) {
    *phi = p->phi + p->wave * sin(M_PI * v);
    const double theta = p->theta0 + (p->theta1 - p->theta0) * v;
    const double r = d->head_radius * (p->shell + TIP_LIFT * v + p->lift);
    sphere_point(c, r, theta, *phi);
}

static void build_strip(const ht_patches_desc *d, const strip_params *p, double (*centre)[3],
                        double (*segment)[3], double *phis, ht_vertex *out) {
    const int rows = d->segments + 1;
    const double R = d->head_radius;
    const double h_max = R * (SHELL_BASE + SHELL_STEP * (d->layers - 1) + TIP_LIFT + MAX_JITTER_LIFT);
    for (int i = 0; i < rows; i++) centre_point(d, p, (double)i / d->segments, centre[i], &phis[i]);
    /* θ1 - θ0 > 0.6, so no segment is empty; the fallback is for safety. */
    for (int i = 0; i + 1 < rows; i++) {
        v3_mad(segment[i], centre[i + 1], -1.0, centre[i]);
        if (!v3_normalize(segment[i])) v3_set(segment[i], 0, -1, 0);
    }

    for (int i = 0; i < rows; i++) {
        double t[3];
        if (i == 0) v3_copy(t, segment[0]);
        else if (i == rows - 1) v3_copy(t, segment[i - 1]);
        else {
            v3_mad(t, segment[i - 1], 1.0, segment[i]);
            if (!v3_normalize(t)) v3_copy(t, segment[i]);
        }

        const double r = v3_length(centre[i]);
        double w[3], n[3];
        azimuth_direction(w, phis[i]);
        if (!v3_orthonormalize(w, t)) v3_any_perpendicular(w, t);
        v3_cross(n, t, w);
        v3_normalize(n);
        if (v3_dot(n, centre[i]) < 0) {
            /* Keep the normal outward and the winding with it. */
            for (int k = 0; k < 3; k++) { n[k] = -n[k]; w[k] = -w[k]; }
        }

        const double theta = p->theta0 + (p->theta1 - p->theta0) * i / d->segments;
        double hw = 0.75 * 2.0 * M_PI * r * fmax(sin(theta), 0.35) / d->strips;
        hw = fmin(hw, 0.6 * r);
        const double v = (double)i / d->segments;
        const float ao = (float)(0.25 + 0.75 * 0.5 * (clamp01((r - R) / h_max) + v));
        for (int side = 0; side < 2; side++) {
            ht_vertex *vx = &out[2 * i + side];
            double pos[3];
            v3_mad(pos, centre[i], side ? hw : -hw, w);
            v3_store(vx->position, pos);
            v3_store(vx->normal, n);
            v3_store(vx->tangent, t);
            vx->uv[0] = (float)side;
            vx->uv[1] = (float)v;
            vx->ao = ao;
        }
    }
}

static void build_head(float radius, ht_vertex *v, uint32_t *idx) {
    for (int i = 0; i <= HEAD_STACKS; i++) {
        const double theta = M_PI * i / HEAD_STACKS;
        for (int j = 0; j <= HEAD_SLICES; j++) {
            const double phi = 2.0 * M_PI * j / HEAD_SLICES;
            double n[3], e[3], pos[3];
            sphere_point(n, 1.0, theta, phi);
            azimuth_direction(e, phi);
            v3_mad(pos, (const double[3]){ 0, 0, 0 }, radius, n);
            ht_vertex *vx = &v[i * (HEAD_SLICES + 1) + j];
            v3_store(vx->position, pos);
            v3_store(vx->normal, n);
            v3_store(vx->tangent, e);
            vx->uv[0] = (float)j / HEAD_SLICES;
            vx->uv[1] = (float)i / HEAD_STACKS;
            vx->ao = 1.0f;
        }
    }
    /* Quads between rows i and i + 1; at the poles one triangle of each
       quad would have zero area and is left out. */
    uint32_t k = 0;
    for (uint32_t i = 0; i < HEAD_STACKS; i++)
        for (uint32_t j = 0; j < HEAD_SLICES; j++) {
            const uint32_t a = i * (HEAD_SLICES + 1) + j, b = a + HEAD_SLICES + 1;
            if (i != 0) { idx[k++] = a; idx[k++] = b; idx[k++] = a + 1; }
            if (i != HEAD_STACKS - 1) { idx[k++] = a + 1; idx[k++] = b; idx[k++] = b + 1; }
        }
}

#define HEAD_VERTICES ((HEAD_STACKS + 1) * (HEAD_SLICES + 1))
#define HEAD_INDICES (6 * HEAD_SLICES * (HEAD_STACKS - 1))

ht_result ht_mesh_build_patches(const ht_patches_desc *desc, ht_mesh *out, ht_mesh *head) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    if (head) memset(head, 0, sizeof *head);
    ht_patches_desc d;
    ht_result res = resolve(desc, &d);
    if (res != HT_OK) return res;

    const uint64_t strips = (uint64_t)d.layers * (uint64_t)d.strips;
    const uint32_t rows = (uint32_t)d.segments + 1;
    res = ht_mesh_alloc(out, strips * rows * 2, strips * (uint64_t)d.segments * 6, strips);
    if (res != HT_OK) return res;
    double (*centre)[3] = malloc(sizeof *centre * rows);
    double (*segment)[3] = malloc(sizeof *segment * rows);
    double *phis = malloc(sizeof *phis * rows);
    if (!centre || !segment || !phis) {
        res = HT_ERR_OUT_OF_MEMORY;
        goto fail;
    }
    if (head) {
        res = ht_mesh_alloc(head, HEAD_VERTICES, HEAD_INDICES, 1);
        if (res != HT_OK) goto fail;
        build_head(d.head_radius, head->vertices, head->indices);
        head->components[0] = (ht_component){ 0, HEAD_INDICES, 0.0f };
    }

    ht_rng rng = ht_rng_seed(d.seed);
    const uint32_t verts_per_strip = rows * 2, idx_per_strip = (uint32_t)d.segments * 6;
    uint32_t c = 0;
    for (int l = 0; l < d.layers; l++)
        for (int s = 0; s < d.strips; s++, c++) {
            const strip_params p = draw_strip(&d, &rng, l, s);
            const uint32_t base = c * verts_per_strip;
            build_strip(&d, &p, centre, segment, phis, out->vertices + base);
            uint32_t *idx = out->indices + (uint64_t)c * idx_per_strip;
            for (uint32_t i = 0; i + 1 < rows; i++) {
                const uint32_t a0 = base + 2 * i, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
                const uint32_t tri[6] = { a0, b1, a1, a0, b0, b1 };
                memcpy(idx + 6 * i, tri, sizeof tri);
            }
            out->components[c] = (ht_component){
                .first_index = c * idx_per_strip,
                .index_count = idx_per_strip,
                .sort_key = ht_mesh_centroid_distance(out, base, verts_per_strip),
            };
        }
    free(centre);
    free(segment);
    free(phis);
    return HT_OK;

fail:
    free(centre);
    free(segment);
    free(phis);
    ht_mesh_free(out);
    if (head) ht_mesh_free(head);
    return res;
}

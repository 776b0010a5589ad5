/* mesh_patches.c — layered hair strips around a head sphere, after
   Scheuermann's ATI hair: `layers` shells of `strips` ribbons each, every
   ribbon `segments` quads from the scalp down, plus the opaque head.

   Frame: head of radius R centred at the origin, y up, the face towards +z.
   A point on a sphere of radius r is r (sin θ sin φ, cos θ, sin θ cos φ): θ
   is the polar angle from the crown, φ the azimuth from the face (φ = ±π:
   the back). The head's "hull" is the head sphere above the equator (y > 0)
   and the vertical cylinder of radius R under it: hair lies on the first
   and hangs beside the second.

   Strip s of layer l (both counted from 0, inner layer first), spacing
   Δ = 2π / strips:
     root     azimuth φ = Δ (s + l / layers + jitter), jitter in ±0.2, so
              layers interleave, taken into [-π, π]; polar θ0 in
              [0.08, 0.2): every strip starts near the crown.
     shell    r = R (1.02 + 0.03 l + lift), lift in [0, 0.004): each layer a
              shell outside the last.
     kind     a fringe strip when |φ| < FACE + m, FACE = 0.7 half the face's
              azimuth and m = a + WAVE + MAX_DRIFT the most a strip's edge
              strays sideways (a, WAVE, d below): it runs over the scalp to
              its tip at θ1 in [1.0, 1.15), the hairline, and stops there,
              so the face (|φ| < FACE under the hairline) stays bare.
              Otherwise a long strip: over the scalp to the equator
              θ1 = π/2, then hanging under gravity.
     scalp    arc length S1 = r (θ1 - θ0); at x in [0, 1] along it the
              centre is the sphere point of radius r (fringe: r (1 + 0.012
              x²), its tip lifted off the hair below) at θ = θ0 + (θ1 - θ0)
              x, φ + d sin(πx), d in ±0.3 min(Δ, 0.25) (MAX_DRIFT = 0.075) a
              seeded sideways drift that is 0 at both ends, + w x² with w
              = ±0.6 (1 - smoothstep((|φ| - FACE - m) / 0.45)) away from
              the face (0 for fringes): the long strips beside the face
              sweep back towards the ears, so their front edge runs from
              the hairline diagonally back, not down a meridian.
     hang     length S2 = R (0.55 + (L - 0.55) g), L = 0.8 + 0.5 b + 0.04 l
              + k, b = (1 - cos φ) / 2 (0 at the face, 1 at the back), k in
              [0, 0.2): back hair longest, outer layers a little longer so
              they cover the inner tips; g = smoothstep((|φ| - FACE - m) /
              0.8) frames the face: the strips beside it hang 0.55 R and
              lengthen over 0.8 radians to L, so the hair's edge beside the
              face runs diagonally back instead of down in one hard line. At u in [0, 1] down it the centre is
              ρ h + A u sin(2π f u + ψ) e + (0, -u S2, 0), h = (sin φ', 0,
              cos φ'), e = (cos φ', 0, -sin φ'), φ' = φ + w (the swept azimuth), ρ = r + R F u² (F in [0.04, 0.14): the
              tips fan out), A in [0.02, 0.05) R (WAVE = 0.05), f in
              [0.5, 1.2), ψ in [0, 2π): a seeded wave across the strip.
              It continues the scalp path at the equator, where the
              meridian runs straight down.
     rows     row i is at s = i / segments · (S1 + S2) (fringe: S2 = 0) along
              the path, x = s / S1 on the scalp, u = (s - S1) / S2 below.
     width    the ribbon spans ±hw along w, hw = a · max(|c_h|, 0.35 r),
              a = min(1.5π / strips, 0.6), c_h the centre's horizontal part:
              1.5 times the strip spacing, so neighbours overlap.
   Per vertex: tangent t = mean of the adjacent segment directions of the
   centre line (root to tip); o = the outward direction of the hull (on the
   scalp c / |c|, hanging c_h / |c_h|); widening axis w = o × t / |o × t|,
   normal n = t × w (= the part of o perpendicular to t), flipped with w if
   it faced the head centre. w ⊥ o keeps both edges at least as far from
   the hull as the centre: nothing is inside the head. uv: u 0 → 1 across,
   v = row / segments, root 0 → tip 1.
   ao = 0.25 + 0.75 · (clamp(h / h_max, 0, 1) + v) / 2 with h the height of
   the centre above the hull (|c| - R on the scalp, |c_h| - R hanging) and
   h_max = R (0.02 + 0.03 (layers - 1) + 0.004 + 0.14), the outermost
   layer's fanned tip: inner layers and roots (under the others) are
   darker, outer tips brightest.

   With few segments the chords between rows cut corners (a single segment
   runs straight from crown to tip, through the head); every vertex is
   still outside the head.

   The head is mesh_head.c's sphere of radius R at the origin with a neck
   under it.

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

#define SHELL_BASE 0.02  /* inner layer's height above the head / R */
#define SHELL_STEP 0.03  /* between layers / R */
#define MAX_JITTER_LIFT 0.004
#define FRINGE_LIFT 0.012 /* fringe tip's extra height / its shell */
#define FACE 0.7          /* half the azimuth the face spans, radians */
#define WAVE 0.05         /* largest sideways wave of hanging hair / R */
#define MAX_DRIFT 0.075   /* 0.3 × 0.25, the largest scalp drift, radians */
#define MAX_FAN 0.14      /* largest outward spread of a tip / R */
#define FRAME_MIN 0.55    /* hang / R of the long strips beside the face */
#define FRAME_RAMP 0.8    /* radians over which they lengthen to the rest */
#define SWEEP 0.6         /* radians the strips beside the face sweep back by the equator */
#define SWEEP_RAMP 0.45   /* radians from the face over which the sweep fades */

static double smoothstep01(double x) {
    x = ht_clamp01(x);
    return x * x * (3.0 - 2.0 * x);
}

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
    ht_vec3_set(p, r * sin(theta) * sin(phi), r * cos(theta), r * sin(theta) * cos(phi));
}

static void azimuth_direction(double e[3], double phi) { ht_vec3_set(e, cos(phi), 0.0, -sin(phi)); }

/* `a` of the header: the ribbon's half width over its distance from the
   y axis (0.35 r near the crown), 0.75 of the strip spacing, at most 0.6. */
static double half_angle(int strips) { return fmin(1.5 * M_PI / strips, 0.6); }

typedef struct strip_params {
    double phi, drift, sweep, theta0, theta1, r;      /* scalp */
    double hang, fan, wave, wave_freq, wave_phase;    /* hanging; hang 0: a fringe */
    double scalp_length;
} strip_params;

static strip_params draw_strip(const ht_patches_desc *d, ht_rng *rng, int layer, int strip) {
    strip_params p;
    const double R = d->head_radius, spacing = 2.0 * M_PI / d->strips;
    /* Every draw is made whatever the strip's kind, so a strip's shape
       depends only on the seed and its place. */
    const double phi = spacing * (strip + (double)layer / d->layers + ht_rng_range(rng, -0.2, 0.2));
    p.phi = remainder(phi, 2.0 * M_PI);
    p.drift = fmin(spacing, 0.25) * ht_rng_range(rng, -0.3, 0.3);
    p.theta0 = ht_rng_range(rng, 0.08, 0.2);
    const double hairline = ht_rng_range(rng, 1.0, 1.15);
    const double lift = ht_rng_range(rng, 0.0, MAX_JITTER_LIFT);
    const double length_jitter = ht_rng_range(rng, 0.0, 0.2);
    p.fan = R * ht_rng_range(rng, 0.04, MAX_FAN);
    p.wave = R * ht_rng_range(rng, 0.02, WAVE);
    p.wave_freq = ht_rng_range(rng, 0.5, 1.2);
    p.wave_phase = ht_rng_range(rng, 0.0, 2.0 * M_PI);
    p.r = R * (1.0 + SHELL_BASE + SHELL_STEP * layer + lift);

    const double face_edge = FACE + half_angle(d->strips) + WAVE + MAX_DRIFT;
    const int fringe = fabs(p.phi) < face_edge;
    p.theta1 = fringe ? hairline : 0.5 * M_PI;
    const double back = 0.5 * (1.0 - cos(p.phi));
    const double frame = smoothstep01((fabs(p.phi) - face_edge) / FRAME_RAMP);
    const double full = 0.8 + 0.5 * back + 0.04 * layer + length_jitter;
    p.hang = fringe ? 0.0 : R * (FRAME_MIN + (full - FRAME_MIN) * frame);
    const double sweep = 1.0 - smoothstep01((fabs(p.phi) - face_edge) / SWEEP_RAMP);
    p.sweep = fringe ? 0.0 : copysign(SWEEP * sweep, p.phi);
    p.scalp_length = p.r * (p.theta1 - p.theta0);
    return p;
}

/* Centre line at v in [0, 1] (root to tip); *out receives the hull's
   outward direction there. */
static void centre_point(const strip_params *p, double v, double c[3], double out[3]) {
    const double s = v * (p->scalp_length + p->hang);
    if (s <= p->scalp_length || p->hang <= 0) {
        const double x = fmin(s / p->scalp_length, 1.0);
        const double r = p->hang > 0 ? p->r : p->r * (1.0 + FRINGE_LIFT * x * x);
        sphere_point(c, r, p->theta0 + (p->theta1 - p->theta0) * x,
                     p->phi + p->drift * sin(M_PI * x) + p->sweep * x * x);
        ht_vec3_copy(out, c);
        ht_vec3_normalize(out);
        return;
    }
    const double u = (s - p->scalp_length) / p->hang;
    const double rho = p->r + p->fan * u * u;
    const double side = p->wave * u * sin(2.0 * M_PI * p->wave_freq * u + p->wave_phase);
    double h[3], e[3];
    const double phi = p->phi + p->sweep;
    ht_vec3_set(h, sin(phi), 0.0, cos(phi));
    azimuth_direction(e, phi);
    ht_vec3_set(c, rho * h[0] + side * e[0], -u * p->hang, rho * h[2] + side * e[2]);
    ht_vec3_set(out, c[0], 0.0, c[2]);
    ht_vec3_normalize(out);
}

static void build_strip(const ht_patches_desc *d, const strip_params *p, double (*centre)[3],
                        double (*outward)[3], double (*segment)[3], ht_vertex *out) {
    const int rows = d->segments + 1;
    const double R = d->head_radius;
    const double h_max = R * (SHELL_BASE + SHELL_STEP * (d->layers - 1) + MAX_JITTER_LIFT + MAX_FAN);
    const double a = half_angle(d->strips);
    for (int i = 0; i < rows; i++) centre_point(p, (double)i / d->segments, centre[i], outward[i]);
    /* Rows are at least 0.8 R / segments apart along the path, so no
       segment is empty; the fallback is for safety. */
    for (int i = 0; i + 1 < rows; i++) {
        ht_vec3_mad(segment[i], centre[i + 1], -1.0, centre[i]);
        if (!ht_vec3_normalize(segment[i])) ht_vec3_set(segment[i], 0, -1, 0);
    }

    for (int i = 0; i < rows; i++) {
        double t[3];
        if (i == 0) ht_vec3_copy(t, segment[0]);
        else if (i == rows - 1) ht_vec3_copy(t, segment[i - 1]);
        else {
            ht_vec3_mad(t, segment[i - 1], 1.0, segment[i]);
            if (!ht_vec3_normalize(t)) ht_vec3_copy(t, segment[i]);
        }

        const double *c = centre[i];
        const double horizontal = hypot(c[0], c[2]);
        const int hanging = c[1] < 0 && p->hang > 0;
        double w[3], n[3];
        ht_vec3_cross(w, outward[i], t);
        if (!ht_vec3_normalize(w)) ht_vec3_any_perpendicular(w, t);
        ht_vec3_cross(n, t, w);
        ht_vec3_normalize(n);
        if (ht_vec3_dot(n, c) < 0) {
            /* Keep the normal outward and the winding with it. */
            for (int k = 0; k < 3; k++) { n[k] = -n[k]; w[k] = -w[k]; }
        }

        const double hw = a * fmax(horizontal, 0.35 * p->r);
        const double v = (double)i / d->segments;
        const double h = (hanging ? horizontal : ht_vec3_length(c)) - R;
        const float ao = (float)(0.25 + 0.75 * 0.5 * (ht_clamp01(h / h_max) + v));
        for (int side = 0; side < 2; side++) {
            ht_vertex *vx = &out[2 * i + side];
            double pos[3];
            ht_vec3_mad(pos, c, side ? hw : -hw, w);
            ht_vec3_store(vx->position, pos);
            ht_vec3_store(vx->normal, n);
            ht_vec3_store(vx->tangent, t);
            vx->uv[0] = (float)side;
            vx->uv[1] = (float)v;
            vx->ao = ao;
        }
    }
}

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
    double (*outward)[3] = malloc(sizeof *outward * rows);
    if (!centre || !segment || !outward) {
        res = HT_ERR_OUT_OF_MEMORY;
        goto fail;
    }
    if (head) {
        res = ht_mesh_build_head(d.head_radius, (const float[3]){ 0, 0, 0 }, true, head);
        if (res != HT_OK) goto fail;
    }

    ht_rng rng = ht_rng_seed(d.seed);
    const uint32_t verts_per_strip = rows * 2, idx_per_strip = (uint32_t)d.segments * 6;
    uint32_t c = 0;
    for (int l = 0; l < d.layers; l++)
        for (int s = 0; s < d.strips; s++, c++) {
            const strip_params p = draw_strip(&d, &rng, l, s);
            const uint32_t base = c * verts_per_strip;
            build_strip(&d, &p, centre, outward, segment, out->vertices + base);
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
    free(outward);
    return HT_OK;

fail:
    free(centre);
    free(segment);
    free(outward);
    ht_mesh_free(out);
    if (head) ht_mesh_free(head);
    return res;
}

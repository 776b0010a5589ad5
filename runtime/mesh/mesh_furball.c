/* mesh_furball.c — the fur ball of the Meshuggah demo: hairs growing from
   the origin, bent by gravity and inertia, each a ribbon of joints - 1 quads.

   A hair starts at the origin along d0, uniform on the unit sphere. At each
   joint the step direction becomes normalize(direction + gravity + inertia)
   (kept as it was when that sum is zero within rounding) and the position advances by
   `length` along it.

   Ribbon: the hair is widened along w = normalize(cross(d0, gravity)), one
   axis for the whole hair. When gravity is zero or parallel to d0 that cross
   product has no direction; w is then cross(d0, the world axis least aligned
   with d0), normalized — stable for a given d0, never degenerate. Width
   tapers linearly from `width` at the root to width / 4 at the tip.

   Per vertex:
     tangent  mean of the unit directions of the segments meeting at the
              joint (root: first segment, tip: last), root to tip.
     normal   normalize(cross(tangent, w)): perpendicular to the tangent and
              to the widening axis. The sign of w is chosen once per hair so
              the root normal faces away from gravity (up, +y when gravity is
              zero), i.e. ribbons are lit from above. If the tangent turns
              parallel to w the previous joint's normal, orthogonalized, is
              kept.
     uv       u = the hair's streak coordinate, uniform in [0,1) per hair
              (each hair samples its own column of the streak texture);
              v = joint / (joints - 1), root 0 to tip 1.
     ao       0.25 + 0.75 * (v + r) / 2, with r = |joint| / hair length
              clamped to [0,1]: dark at the crowded root, bright at the tip,
              and darker where gravity folds a hair back towards the ball.

   Vertices of hair h, joint j: 2 * (h * joints + j) + {0: -w side, 1: +w}.
   Triangles are wound counter-clockwise seen from the normal's side.

   Limits (else HT_ERR_INVALID_ARGUMENT, after defaults): hairs >= 1,
   2 <= joints <= 65536, length and width in [1e-6, 1e3], every component of
   gravity and inertia finite and within ±1e3, vertex and index counts that
   fit uint32. */
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"
#include "rng.h"

#define FURBALL_MAX_JOINTS 65536
#define FURBALL_MAX_SCALAR 1e3f /* length, width, |gravity|, |inertia| components */
#define FURBALL_MIN_SIZE 1e-6f  /* length, width: below, float positions collapse */
#define FURBALL_TIP_WIDTH 0.25  /* tip width / root width */

static int size_ok(float x) { return isfinite(x) && x >= FURBALL_MIN_SIZE && x <= FURBALL_MAX_SCALAR; }
static int vector_ok(const float v[3]) {
    for (int i = 0; i < 3; i++)
        if (!isfinite(v[i]) || fabsf(v[i]) > FURBALL_MAX_SCALAR) return 0;
    return 1;
}

static ht_result resolve(const ht_furball_desc *in, ht_furball_desc *d) {
    if (!in) return HT_ERR_INVALID_ARGUMENT;
    *d = *in;
    if (d->hairs == 0) d->hairs = 2000;
    if (d->joints == 0) d->joints = 16;
    if (d->length == 0) d->length = 0.08f;
    if (d->width == 0) d->width = 0.01f;
    if (d->hairs < 1 || d->joints < 2 || d->joints > FURBALL_MAX_JOINTS) return HT_ERR_INVALID_ARGUMENT;
    if (!size_ok(d->length) || !size_ok(d->width)) return HT_ERR_INVALID_ARGUMENT;
    if (!vector_ok(d->gravity) || !vector_ok(d->inertia)) return HT_ERR_INVALID_ARGUMENT;
    return HT_OK;
}

static void random_direction(ht_rng *rng, double d[3]) {
    double z = 2.0 * ht_rng_unit(rng) - 1.0;
    double phi = 2.0 * M_PI * ht_rng_unit(rng);
    double r = sqrt(fmax(0.0, 1.0 - z * z));
    ht_vec3_set(d, r * cos(phi), r * sin(phi), z);
}

static void widening_axis(const double d0[3], const double gravity[3], double w[3]) {
    ht_vec3_cross(w, d0, gravity);
    /* Relative test: a nearly parallel gravity gives a w of rounding noise. */
    if (ht_vec3_length(w) <= 1e-6 * ht_vec3_length(gravity) || !ht_vec3_normalize(w)) ht_vec3_any_perpendicular(w, d0);
}

typedef struct hair_scratch {
    double (*joint)[3];   /* joints positions */
    double (*segment)[3]; /* joints - 1 unit directions */
} hair_scratch;

static void build_hair(const ht_furball_desc *d, ht_rng *rng, const hair_scratch *s,
                       ht_vertex *out) {
    const int joints = d->joints;
    const double gravity[3] = { d->gravity[0], d->gravity[1], d->gravity[2] };
    const double pull[3] = { d->gravity[0] + d->inertia[0], d->gravity[1] + d->inertia[1],
                             d->gravity[2] + d->inertia[2] };
    double d0[3], w[3], dir[3];
    random_direction(rng, d0);
    const float streak_u = (float)ht_rng_unit(rng);
    widening_axis(d0, gravity, w);
    /* Flipping w flips the normal cross(t, w) and keeps the winding
       counter-clockwise seen from the normal's side. */
    double up[3] = { -gravity[0], -gravity[1], -gravity[2] }, n0[3];
    if (!ht_vec3_normalize(up)) ht_vec3_set(up, 0, 1, 0);
    ht_vec3_cross(n0, d0, w);
    if (ht_vec3_dot(n0, up) < 0)
        for (int k = 0; k < 3; k++) w[k] = -w[k];

    ht_vec3_copy(dir, d0);
    ht_vec3_set(s->joint[0], 0, 0, 0);
    /* A sum within rounding of zero has no direction worth following. */
    const double zero_step = 1e-6 * (1.0 + ht_vec3_length(pull));
    for (int j = 1; j < joints; j++) {
        double next[3];
        ht_vec3_mad(next, dir, 1.0, pull);
        if (ht_vec3_length(next) > zero_step && ht_vec3_normalize(next)) ht_vec3_copy(dir, next);
        ht_vec3_copy(s->segment[j - 1], dir);
        ht_vec3_mad(s->joint[j], s->joint[j - 1], d->length, dir);
    }

    const double hair_length = (double)d->length * (joints - 1);
    double prev_n[3] = { 0, 0, 0 };

    for (int j = 0; j < joints; j++) {
        double t[3], n[3];
        if (j == 0) ht_vec3_copy(t, s->segment[0]);
        else if (j == joints - 1) ht_vec3_copy(t, s->segment[j - 1]);
        else {
            ht_vec3_mad(t, s->segment[j - 1], 1.0, s->segment[j]);
            /* A hair that turned right round: follow the outgoing segment. */
            if (!(ht_vec3_length(t) > 1e-6 && ht_vec3_normalize(t))) ht_vec3_copy(t, s->segment[j]);
        }

        ht_vec3_cross(n, t, w);
        /* Never falls back at the root (t = d0 ⟂ w), so prev_n is set
           before the fallback needs it. */
        if (!(ht_vec3_length(n) > 1e-6 && ht_vec3_normalize(n))) {
            ht_vec3_copy(n, prev_n);
            if (!ht_vec3_orthonormalize(n, t)) ht_vec3_any_perpendicular(n, t);
        }
        ht_vec3_copy(prev_n, n);

        const double v = (double)j / (joints - 1);
        const double half = 0.5 * d->width * (1.0 - (1.0 - FURBALL_TIP_WIDTH) * v);
        const double r = ht_clamp01(ht_vec3_length(s->joint[j]) / hair_length);
        const float ao = (float)(0.25 + 0.75 * 0.5 * (v + r));
        for (int side = 0; side < 2; side++) {
            ht_vertex *vx = &out[2 * j + side];
            double p[3];
            ht_vec3_mad(p, s->joint[j], side ? half : -half, w);
            ht_vec3_store(vx->position, p);
            ht_vec3_store(vx->normal, n);
            ht_vec3_store(vx->tangent, t);
            vx->uv[0] = streak_u;
            vx->uv[1] = (float)v;
            vx->ao = ao;
        }
    }
}

ht_result ht_mesh_build_furball(const ht_furball_desc *desc, ht_mesh *out) {
    if (!out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    ht_furball_desc d;
    ht_result res = resolve(desc, &d);
    if (res != HT_OK) return res;

    const uint64_t hairs = (uint64_t)d.hairs, joints = (uint64_t)d.joints;
    res = ht_mesh_alloc(out, hairs * joints * 2, hairs * (joints - 1) * 6, hairs);
    if (res != HT_OK) return res;

    hair_scratch s = { malloc(sizeof *s.joint * joints), malloc(sizeof *s.segment * joints) };
    if (!s.joint || !s.segment) {
        free(s.joint);
        free(s.segment);
        ht_mesh_free(out);
        return HT_ERR_OUT_OF_MEMORY;
    }

    ht_rng rng = ht_rng_seed(d.seed);
    const uint32_t verts_per_hair = (uint32_t)joints * 2, idx_per_hair = ((uint32_t)joints - 1) * 6;
    for (uint32_t h = 0; h < (uint32_t)hairs; h++) {
        const uint32_t base = h * verts_per_hair;
        build_hair(&d, &rng, &s, out->vertices + base);

        uint32_t *idx = out->indices + (uint64_t)h * idx_per_hair;
        for (uint32_t j = 0; j + 1 < (uint32_t)joints; j++) {
            uint32_t a0 = base + 2 * j, a1 = a0 + 1, b0 = a0 + 2, b1 = a0 + 3;
            const uint32_t tri[6] = { a0, b1, a1, a0, b0, b1 };
            memcpy(idx + 6 * j, tri, sizeof tri);
        }
        out->components[h] = (ht_component){
            .first_index = h * idx_per_hair,
            .index_count = idx_per_hair,
            .sort_key = ht_mesh_centroid_distance(out, base, verts_per_hair),
        };
    }
    free(s.joint);
    free(s.segment);
    return HT_OK;
}

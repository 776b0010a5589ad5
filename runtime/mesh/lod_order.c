/* lod_order.c — the one stratified order of a mesh's strands that every
   LOD keeps a prefix of (lod.h).

   Each strand's key point is the midpoint of its first two rows' centres
   (a little way up from the root, so the fur ball's hairs, which all grow
   from the origin, are told apart by direction). The key points are
   sorted along a 3D Z-order (Morton) curve over their bounding box, 21
   bits an axis; position i on the curve gets rank = the rank of i among
   the bit-reversed positions (reverse over the next power of two, the
   positions past n skipped). A prefix of m ranks then takes about every
   (n / m)-th strand along the curve: strata of neighbours, one strand
   each, so no prefix leaves a bald patch and LOD n + 1 is a subset of
   LOD n. O(n log n). */
#include <stdlib.h>
#include <string.h>

#include "lod_internal.h"

typedef struct keyed {
    uint64_t morton;
    uint32_t component;
} keyed;

static int compare_keyed(const void *pa, const void *pb) {
    const keyed *a = pa, *b = pb;
    if (a->morton != b->morton) return a->morton < b->morton ? -1 : 1;
    return (a->component > b->component) - (a->component < b->component);
}

/* The 21 low bits of x, two zero bits after each. */
static uint64_t spread3(uint64_t x) {
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
}

static uint64_t reverse_bits(uint64_t x, int bits) {
    uint64_t r = 0;
    for (int b = 0; b < bits; b++) r |= ((x >> b) & 1u) << (bits - 1 - b);
    return r;
}

static void key_point(const ht_mesh *m, const ht_lod_run *run, double out[3]) {
    const uint32_t rows_used = run->rows > 1 ? 2 : 1;
    for (int k = 0; k < 3; k++) {
        double s = 0;
        for (uint32_t r = 0; r < rows_used; r++)
            s += m->vertices[run->first_vertex + 2 * r].position[k] + m->vertices[run->first_vertex + 2 * r + 1].position[k];
        out[k] = s / (2.0 * rows_used);
    }
}

ht_result ht_lod_curve_order(const ht_mesh *mesh, const ht_lod_run *runs, uint32_t *curve) {
    const uint32_t n = mesh->component_count;
    keyed *k = malloc(sizeof *k * n);
    double (*p)[3] = malloc(sizeof *p * n);
    if (!k || !p) {
        free(k);
        free(p);
        return HT_ERR_OUT_OF_MEMORY;
    }
    double lo[3] = { INFINITY, INFINITY, INFINITY }, hi[3] = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t c = 0; c < n; c++) {
        key_point(mesh, &runs[c], p[c]);
        for (int a = 0; a < 3; a++) { lo[a] = fmin(lo[a], p[c][a]); hi[a] = fmax(hi[a], p[c][a]); }
    }
    for (uint32_t c = 0; c < n; c++) {
        uint64_t code = 0;
        for (int a = 0; a < 3; a++) {
            const double span = hi[a] - lo[a];
            const double x = span > 0 ? (p[c][a] - lo[a]) / span : 0;
            code |= spread3((uint64_t)(ht_clamp01(x) * 2097151.0)) << a;
        }
        k[c] = (keyed){ code, c };
    }
    qsort(k, n, sizeof *k, compare_keyed);
    for (uint32_t i = 0; i < n; i++) curve[i] = k[i].component;
    free(k);
    free(p);
    return HT_OK;
}

ht_result ht_mesh_strand_order(const ht_mesh *mesh, uint32_t *rank) {
    if (!mesh || !rank || mesh->component_count == 0) return HT_ERR_INVALID_ARGUMENT;
    const uint32_t n = mesh->component_count;
    ht_lod_run *runs = malloc(sizeof *runs * n);
    uint32_t *curve = malloc(sizeof *curve * n);
    ht_result r = runs && curve ? ht_lod_runs(mesh, runs) : HT_ERR_OUT_OF_MEMORY;
    if (r == HT_OK) r = ht_lod_curve_order(mesh, runs, curve);
    if (r != HT_OK) goto done;

    /* Curve position i → rank: walk the bit-reversed sequence over the next
       power of two; each value below n is the next curve position taken. */
    int bits = 0;
    while ((1ull << bits) < n) bits++;
    uint32_t next = 0;
    for (uint64_t j = 0; j < (1ull << bits); j++) {
        const uint64_t i = reverse_bits(j, bits);
        if (i < n) rank[curve[i]] = next++;
    }
done:
    free(runs);
    free(curve);
    return r;
}

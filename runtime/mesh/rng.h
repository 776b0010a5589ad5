/* rng.h — the one pseudo-random generator of hairtier (splitmix64), so that
   meshes and procedural textures are the same bytes on every machine for a
   given seed. Header-only: a few lines do not earn a library. */
#ifndef HT_RNG_H
#define HT_RNG_H

#include <stdint.h>

typedef struct ht_rng { uint64_t state; } ht_rng;

static inline ht_rng ht_rng_seed(uint64_t seed) { return (ht_rng){ seed * 0x9E3779B97F4A7C15ull + 1 }; }

static inline uint64_t ht_rng_next(ht_rng *r) {
    uint64_t z = (r->state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [0,1), 53 random bits. */
static inline double ht_rng_unit(ht_rng *r) { return (double)(ht_rng_next(r) >> 11) * 0x1.0p-53; }

/* Uniform in [lo,hi). */
static inline double ht_rng_range(ht_rng *r, double lo, double hi) { return lo + (hi - lo) * ht_rng_unit(r); }

#endif

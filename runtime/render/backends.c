/* backends.c — the table of tier backends: the one place the runtime
   names each tier's implementation (and the only runtime file that
   includes fallback/), so adding a tier is a row here and a backend. */
#include <stddef.h>

#include "fixed.h"
#include "fixed4.h"
#include "vertex.h"
#include "gl11.h"
#include "tier.h"

static const ht_tier_backend *const backends[] = {
    &ht_tier_glsl_marschner_backend,
    &ht_tier_glsl_full_backend,
    &ht_tier_vertex_backend,
    &ht_tier_fixed_backend,
    &ht_tier_fixed4_backend,
    &ht_tier_gl11_backend,
};

const ht_tier_backend *ht_tier_backend_find(ht_tier tier) {
    for (size_t i = 0; i < sizeof backends / sizeof backends[0]; i++)
        if (backends[i]->tier == tier) return backends[i];
    return NULL;
}

/* gl11.h — the `gl11` tier's backend, the last resort: OpenGL 1.1, one
   texture unit (the albedo, GL_MODULATE), the model evaluated per vertex
   on the CPU into the colour array (gl11_program.h).

   Needs: GL 1.1, one texture unit; no extension. */
#ifndef HT_GL11_H
#define HT_GL11_H

#include <stdint.h>

#include "tier.h"

extern const ht_tier_backend ht_tier_gl11_backend;

/* Vertices whose colour every gl11 backend of this process has computed
   (one per vertex per recompute): a static frame recomputes nothing, so
   tests and benchmarks read this before and after a frame. */
uint64_t ht_gl11_cpu_vertices(void);

#endif

/* tier.h — the interface a tier backend implements: the renderer owns the
   pass list, the depth/cull/blend/alpha-test state of every pass, the
   matrices and the vertex arrays; a backend owns its programs, textures and
   texture-environment state. Internal to libhairtier.

   A frame, as renderer.c and passes.c drive it:
       begin_frame(state, frame)                 lights, eye, matrices
       for pass in PRIME_Z, OPAQUE, BACK, FRONT:
           renderer sets the pass's fixed state
           for sub in 0 .. sub_passes(pass) - 1:
               bind_pass(state, pass, sub)
               set_arrays(state, pass, sub)      optional: arrays of its own
               the renderer's glDrawElements over the whole sorted index range
       end_frame(state)                          unbind, restore defaults

   Around the frame the renderer saves the application's GL state and sets a
   baseline (no lighting, fog, colour material or texgen; every texture
   target off and GL_MODULATE on every unit; identity texture matrices; no
   program; no client arrays but its own), so a backend starts from known
   state and may leave what it touched: the renderer restores the app's.

   The backends: ht_tier_glsl_full_backend (tier_glsl.c, declared below;
   glsl_program.h holds what the GLSL tiers share), ht_tier_vertex_backend
   (fallback/vertex.h: a vertex program in front of fixed4's combiner stages),
   ht_tier_fixed4_backend (fallback/fixed4.h), ht_tier_fixed_backend
   (fallback/fixed.h), ht_tier_gl11_backend (fallback/gl11.h);
   backends.c is their table, and the only runtime file that names
   fallback/. The renderer knows a tier only through its backend's fields. */
#ifndef HT_TIER_H
#define HT_TIER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "manifest.h"
#include "gl_api.h"
#include <hairtier/hairtier.h>

/* What the renderer hands a backend at creation. All pointers outlive it. */
typedef struct ht_tier_context {
    const ht_gl *gl;               /* restricted to what caps allows */
    const ht_caps *caps;           /* after the device profile */
    const ht_manifest *bundle;
    const ht_manifest_tier *tier;    /* this backend's manifest entry */
    ht_log_fn log;                 /* never NULL */
    void *log_user;
    bool device_variant;           /* run the device-only variant where the backend has one (ht_variant) */
} ht_tier_context;

typedef struct ht_tier_frame {
    float eye[3];
    const ht_light *lights;
    int light_count;               /* 0..HT_MAX_LIGHTS */
    float view[16];                /* column-major, as loaded into GL_MODELVIEW */
    float projection[16];          /* column-major, as loaded into GL_PROJECTION */
    /* The width rule (docs/lod.md): every pass's hair alpha x (1 - this),
       in [0, 1); 0 draws alpha as it is. Each backend scales its own final
       alpha (a uniform, a combiner constant, the colour array). */
    float opacity_cut;
    /* The width rule per vertex (shader_interface.h's u_width_rule): the
       world length a pixel spans at clip w = 1; 0: off. Set only for a
       backend whose vertex_width_rule says yes. */
    float width_rule;
    /* The vertices this frame's draw range indexes (a superset, within
       vertex_count of the mesh): per-vertex CPU work covers these only, a
       chain's other levels none. */
    uint32_t first_vertex, vertex_count;
} ht_tier_frame;

typedef struct ht_tier_backend {
    ht_tier tier;
    /* The renderer feeds tangent and ao as generic attributes at
       shader_interface.h's locations (programs read them; fixed-function
       stages cannot). */
    bool generic_attributes;
    /* Compiles/loads everything. A failure (HT_ERR_COMPILE, HT_ERR_IO, ...)
       makes the renderer drop to the next tier with err as the reason, so err
       is one line: "compile failed: full.frag: 0:12(3): error: ...". */
    ht_result (*create)(const ht_tier_context *ctx, void **state, char *err, size_t err_size);
    /* Optional: per-vertex data of its own (CPU-computed coordinates). */
    ht_result (*set_mesh)(void *state, const ht_mesh *mesh);
    void (*begin_frame)(void *state, const ht_tier_frame *frame);
    /* Optional: NULL → 1. A tier with too few units may split a pass. */
    int (*sub_passes)(void *state, ht_pass pass);
    void (*bind_pass)(void *state, ht_pass pass, int sub_pass);
    /* Optional: points the client arrays its stages read beyond the
       renderer's (position, normal, uv) before the renderer draws; false
       when it has nothing valid to draw with, and the draw is skipped. */
    bool (*set_arrays)(void *state, ht_pass pass, int sub_pass);
    void (*end_frame)(void *state);
    void (*destroy)(void *state);
    /* Optional: vertices whose data the CPU computed so far (NULL: none). */
    uint64_t (*cpu_vertices)(void *state);
    /* Optional: true when this state widens each vertex to a pixel and
       scales its alpha itself (the width rule per vertex, docs/lod.md:
       its programs from a_side, or, without generic attributes, on the
       CPU from set_mesh's mesh; NULL: it cannot, the rule stays per draw). */
    bool (*vertex_width_rule)(void *state);
    /* Optional: true when this state runs the device-only variant (NULL:
       the tier has none). */
    bool (*device_variant)(void *state);
} ht_tier_backend;

extern const ht_tier_backend ht_tier_glsl_full_backend;
/* The marschner tier: the same backend (a program and the manifest's
   samplers; its lookup textures are two of them). */
extern const ht_tier_backend ht_tier_glsl_marschner_backend;

/* The backend of a tier (backends.c); NULL for one this runtime lacks. */
const ht_tier_backend *ht_tier_backend_find(ht_tier tier);

#endif

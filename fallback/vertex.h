/* vertex.h — the `vertex` tier's backend: a GLSL 1.10 vertex program
   (runtime/render/glsl_program.h builds it) in front of fixed4's four combiner
   stages over LUTs the runtime bakes (fixed4_stages.h), so the highlights
   are looked up per pixel without a fragment shader.

   Needs: GLSL vertex shaders, GL_ARB_multitexture,
   GL_ARB_texture_env_combine and ht_fixed4_units() texture units. */
#ifndef HT_VERTEX_H
#define HT_VERTEX_H

#include "tier.h"

extern const ht_tier_backend ht_tier_vertex_backend;

#endif

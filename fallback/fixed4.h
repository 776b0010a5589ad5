/* fixed4.h — the `fixed4` tier's backend: GL 1.3 texture combiners on four
   units with every coordinate made by the device (fixed4_program.h).

   Needs: GL_ARB_multitexture, GL_ARB_texture_env_combine, ht_fixed4_units()
   texture units (4 for Scheuermann; Kajiya-Kay 3 with one light). */
#ifndef HT_FIXED4_H
#define HT_FIXED4_H

#include "tier.h"

extern const ht_tier_backend ht_tier_fixed4_backend;

#endif

/* fixed.h — the `fixed` tier backend (fallback/fixed.c): a GL 1.3
   texture-combiner program and its lookup texture from a hairgen bundle,
   no shaders. Internal to libhairtier; the renderer drives it like any
   backend (runtime/render/tier.h):

       ht_tier_fixed_backend.create(&ctx, &state, err, sizeof err);
       // fails with one line: "LUT 32x128x64 needs GL_MAX_3D_TEXTURE_SIZE 128, have 16",
       // "DIR/fixed.json: line 3: malformed JSON near ...", "DIR/fixed-lut.png: cannot open: ..."
       set_mesh, then per frame begin_frame, bind_pass + draw per pass, end_frame.

   Needs: GL_ARB_texture_env_combine, one texture unit per program stage
   (glActiveTexture beyond one), and for a 3D LUT glTexImage3D with
   GL_MAX_3D_TEXTURE_SIZE at least the LUT's largest axis (a device
   profile's max_3d_texture_size lowers what counts). */
#ifndef HT_FIXED_H
#define HT_FIXED_H

#include "tier.h"

extern const ht_tier_backend ht_tier_fixed_backend;

#endif

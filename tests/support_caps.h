/* support_caps.h — synthetic device capabilities for selection tests. */
#ifndef HT_SUPPORT_CAPS_H
#define HT_SUPPORT_CAPS_H

#include "caps.h"

/* A device of GL major.minor with what that version brings (shaders from
   2.0, multitexture and combine from 1.3, crossbar from 1.4, 3D textures
   from 1.2, buffer objects from 1.5), GLSL glsl_major.glsl_minor when it
   has shaders, and units texture units. */
ht_caps ht_test_caps(int major, int minor, int glsl_major, int glsl_minor, int units);

#endif

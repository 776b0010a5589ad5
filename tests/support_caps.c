/* support_caps.c — see support_caps.h. */
#include "support_caps.h"

#include <string.h>

ht_caps ht_test_caps(int major, int minor, int glsl_major, int glsl_minor, int units) {
    ht_caps c;
    memset(&c, 0, sizeof c);
    c.gl_major = major;
    c.gl_minor = minor;
    int v = major * 10 + minor;
    c.has_shaders = c.has_vertex_shaders = c.has_fragment_shaders = v >= 20;
    c.glsl_major = c.has_shaders ? glsl_major : 0;
    c.glsl_minor = c.has_shaders ? glsl_minor : 0;
    c.texture_units = units;
    c.has_multitexture = v >= 13;
    c.has_combine = v >= 13;
    c.has_crossbar = v >= 14;
    c.has_3d_textures = v >= 12;
    c.has_vbo = v >= 15;
    return c;
}

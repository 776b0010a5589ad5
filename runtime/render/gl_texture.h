/* gl_texture.h — uploads one decoded image as a GL texture, for every
   backend that has textures (tier_glsl.c, fallback/fixed.c), so formats,
   unpack alignment, parameters and error reporting are decided once.
   Internal to libhairtier.

   Usage:
       GLuint id;
       if (ht_gl_texture_upload(gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D,
               .image = &img, .filter = GL_LINEAR, .wrap = GL_REPEAT, .name = path },
               &id, err, sizeof err) != HT_OK) ...;   // err: "PATH: glTexImage2D: GL_OUT_OF_MEMORY"

   Leaves the target's binding 0 and GL_UNPACK_ALIGNMENT 4 (hairtier.h
   promises both after ht_renderer_create). */
#ifndef HT_GL_TEXTURE_H
#define HT_GL_TEXTURE_H

#include "gl_api.h"
#include "caps.h"
#include <hairtier/image.h>

typedef struct ht_gl_texture_desc {
    GLenum target;           /* GL_TEXTURE_2D or GL_TEXTURE_3D */
    const ht_image *image;   /* required; a 3D texture's slices stacked vertically */
    int depth;               /* 0 → 1; slices in image for GL_TEXTURE_3D */
    GLenum filter;           /* min and mag; no mipmaps */
    GLenum wrap;             /* s, t (and r for 3D) */
    const char *name;        /* what err names: the file */
} ht_gl_texture_desc;

/* HT_OK with *out a new texture; HT_ERR_GL / HT_ERR_OUT_OF_MEMORY with one
   line in err (and *out, if created, still set for the caller to delete). */
ht_result ht_gl_texture_upload(const ht_gl *gl, const ht_gl_texture_desc *desc, GLuint *out,
                               char *err, size_t err_size);

/* GL 1.x samples only power-of-two sizes unless GL 2.0 or
   ARB_texture_non_power_of_two allows others (GL_INVALID_VALUE, or garbage
   on old drivers). HT_ERR_UNSUPPORTED with one line naming `name` when
   caps cannot take a width x height x depth texture. */
ht_result ht_gl_texture_check_size(const ht_caps *caps, int width, int height, int depth, const char *name,
                                   char *err, size_t err_size);

#endif

/* gl_texture.c — one image to one GL texture (gl_texture.h). */
#include <stdio.h>

#include "gl_error.h"
#include "gl_texture.h"

ht_result ht_gl_texture_upload(const ht_gl *gl, const ht_gl_texture_desc *d, GLuint *out,
                               char *err, size_t err_size) {
    /* Sized formats: an unsized GL_RGBA lets an old driver pick 4 bits. */
    static const GLenum formats[5] = { 0, GL_LUMINANCE, GL_LUMINANCE_ALPHA, GL_RGB, GL_RGBA };
    static const GLint sized[5] = { 0, GL_LUMINANCE8, GL_LUMINANCE8_ALPHA8, GL_RGB8, GL_RGBA8 };
    const ht_image *img = d->image;
    const int ch = img->channels >= 1 && img->channels <= 4 ? img->channels : 4;
    const int depth = d->depth > 0 ? d->depth : 1;
    const bool is_3d = d->target == GL_TEXTURE_3D;
    /* GL ES 2.0 takes only unsized formats, equal to the data's (ES 3 too
       for luminance); ES drivers store them at 8 bits. */
    const GLint internal = gl->es ? (GLint)formats[ch] : sized[ch];
    while (gl->GetError() != GL_NO_ERROR) {}
    gl->GenTextures(1, out);
    gl->BindTexture(d->target, *out);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* Slices stacked vertically are exactly glTexImage3D's layout: image z
       starts at row z * height. PNG row 0 lands at t = 0. */
    if (is_3d)
        gl->TexImage3D(GL_TEXTURE_3D, 0, sized[ch], img->width, img->height / depth, depth, 0, formats[ch],
                       GL_UNSIGNED_BYTE, img->pixels);
    else
        gl->TexImage2D(GL_TEXTURE_2D, 0, internal, img->width, img->height, 0, formats[ch], GL_UNSIGNED_BYTE,
                       img->pixels);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl->TexParameteri(d->target, GL_TEXTURE_MIN_FILTER, (GLint)d->filter);
    gl->TexParameteri(d->target, GL_TEXTURE_MAG_FILTER, (GLint)d->filter);
    gl->TexParameteri(d->target, GL_TEXTURE_WRAP_S, (GLint)d->wrap);
    gl->TexParameteri(d->target, GL_TEXTURE_WRAP_T, (GLint)d->wrap);
    if (is_3d) gl->TexParameteri(d->target, GL_TEXTURE_WRAP_R, (GLint)d->wrap);
    gl->BindTexture(d->target, 0);
    GLenum e = gl->GetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, err_size, "%s: %s: %s", d->name ? d->name : "texture",
                 is_3d ? "glTexImage3D" : "glTexImage2D", ht_gl_error_name(e));
        return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
    }
    return HT_OK;
}

static bool is_pow2(int v) { return v > 0 && (v & (v - 1)) == 0; }

ht_result ht_gl_texture_check_size(const ht_caps *caps, int width, int height, int depth, const char *name,
                                   char *err, size_t err_size) {
    if ((is_pow2(width) && is_pow2(height) && is_pow2(depth)) || ht_caps_gl_at_least(caps, 2, 0) ||
        ht_caps_lists_extension(caps, "GL_ARB_texture_non_power_of_two"))
        return HT_OK;
    snprintf(err, err_size, "%s: %dx%d is not a power of two; needs GL 2.0 or GL_ARB_texture_non_power_of_two, "
             "have GL %d.%d without it", name, width, height, caps->gl_major, caps->gl_minor);
    return HT_ERR_UNSUPPORTED;
}

/* support_osmesa.h — an offscreen GL compatibility context for tests:
   RGBA8 colour, 24-bit depth, a given size, made by the one context module
   the programs use too (platform/offscreen.h). OSMesa unless
   HAIRTIER_CONTEXT=egl (then EGL + a pbuffer; `make test` runs a set of
   render tests that way with EGL_PLATFORM=surfaceless).

   Usage:
       ht_test_gl gl;
       char err[256];
       if (!ht_test_gl_create(&gl, 256, 256, NULL, err, sizeof err)) fail(err);
       ... ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, ... })
       ht_image img;
       ht_test_gl_read(&gl, &img);      // rows top to bottom, RGBA
       ht_test_gl_destroy(&gl);

   gl_version ("1.3", "2.0", NULL for the driver's best) is applied through
   MESA_GL_VERSION_OVERRIDE before the context is created. Mesa reads that
   variable once per process, at the first context: a test that needs a
   second version runs in a fresh process (re-exec itself). The context is
   a compatibility context with no version attributes (OSMESA_COMPAT_PROFILE;
   EGL without a profile mask), which is what lets the override (and
   MESA_EXTENSION_OVERRIDE) take effect. */
#ifndef HT_SUPPORT_OSMESA_H
#define HT_SUPPORT_OSMESA_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/image.h>

struct offscreen;

typedef struct ht_test_gl {
    struct offscreen *context;   /* platform/offscreen.h */
    int width, height;
} ht_test_gl;

bool ht_test_gl_create(ht_test_gl *out, int width, int height, const char *gl_version,
                       char *err, size_t err_size);
void ht_test_gl_destroy(ht_test_gl *gl);
/* The current context's entry points, as ht_renderer_desc.getproc wants. */
void *ht_test_getproc(const char *name);
/* glFinish, then the colour buffer as an RGBA image, rows top to bottom. */
ht_result ht_test_gl_read(const ht_test_gl *gl, ht_image *out);

#endif

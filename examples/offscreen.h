/* offscreen.h — what the OSMesa examples share (header only: every
   example .c file is a program of its own): an RGBA8 compatibility context
   with a 24-bit depth buffer over the caller's pixels, the getproc
   ht_renderer_desc wants, and the top-down rows of GL's bottom-up buffer. */
#ifndef HT_EXAMPLES_OFFSCREEN_H
#define HT_EXAMPLES_OFFSCREEN_H

#include <stddef.h>
#include <string.h>

#include <GL/osmesa.h>

/* OSMesaGetProcAddress with the signature ht_renderer_desc.getproc wants. */
static inline void *offscreen_getproc(const char *name) {
    OSMESAproc p = OSMesaGetProcAddress(name);
    void *out;
    memcpy(&out, &p, sizeof out); /* function to data pointer: same size on POSIX */
    return out;
}

/* A context drawing into rgba (width * height * 4 bytes, rows bottom-up),
   current, with the viewport covering it; NULL when rgba is NULL or Mesa
   refuses. Destroy it with OSMesaDestroyContext; rgba stays the caller's. */
static inline OSMesaContext offscreen_create(unsigned char *rgba, int width, int height) {
    static const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                                   OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0 };
    if (!rgba) return NULL;
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (ctx && !OSMesaMakeCurrent(ctx, rgba, GL_UNSIGNED_BYTE, width, height)) {
        OSMesaDestroyContext(ctx);
        return NULL;
    }
    if (ctx) glViewport(0, 0, width, height);
    return ctx;
}

/* Row y, counted from the top, of a width x height RGBA buffer GL filled
   bottom row first. */
static inline const unsigned char *offscreen_row(const unsigned char *rgba, int width, int height, int y) {
    return rgba + (size_t)(height - 1 - y) * (size_t)width * 4;
}

#endif

/* offscreen_osmesa.c — the OSMesa backend of offscreen.h. libOSMesa is
   loaded with dlopen, not linked: a program built here still starts where
   there is no OSMesa (Mesa 25.1 and later, another vendor's driver) and
   draws through EGL instead. */
#include <stdio.h>
#include <string.h>

#include <GL/osmesa.h>

#include "offscreen_backend.h"

#define OSMESA_LIBRARY "libOSMesa.so.8"

typedef OSMesaContext (*create_attribs_fn)(const int *attribs, OSMesaContext share);
typedef GLboolean (*make_current_fn)(OSMesaContext ctx, void *buffer, GLenum type, GLsizei w, GLsizei h);
typedef void (*destroy_fn)(OSMesaContext ctx);
typedef OSMESAproc (*get_proc_fn)(const char *name);

static struct {
    void *library;
    create_attribs_fn create_attribs;
    make_current_fn make_current;
    destroy_fn destroy;
    get_proc_fn get_proc;
} osmesa;

bool offscreen_osmesa_available(const char *library, char *err, size_t err_size) {
    if (osmesa.library) return true;
    const offscreen_symbol symbols[] = {
        { "OSMesaCreateContextAttribs", &osmesa.create_attribs, sizeof osmesa.create_attribs },
        { "OSMesaMakeCurrent", &osmesa.make_current, sizeof osmesa.make_current },
        { "OSMesaDestroyContext", &osmesa.destroy, sizeof osmesa.destroy },
        { "OSMesaGetProcAddress", &osmesa.get_proc, sizeof osmesa.get_proc },
    };
    osmesa.library = offscreen_load_library("osmesa", library ? library : OSMESA_LIBRARY, symbols,
                                            (int)(sizeof symbols / sizeof symbols[0]), err, err_size);
    return osmesa.library != NULL;
}

static void *osmesa_getproc(const char *name) {
    if (!osmesa.library) return NULL;
    OSMESAproc p = osmesa.get_proc(name);
    void *out;
    memcpy(&out, &p, sizeof out); /* function to data pointer: same size on POSIX */
    return out;
}

static bool osmesa_open(offscreen *o, const offscreen_desc *desc, char *err, size_t err_size) {
    if (desc->egl_device >= 0) {
        snprintf(err, err_size, "osmesa: an EGL device (%d) was asked for: use the egl context", desc->egl_device);
        return false;
    }
    if (!offscreen_osmesa_available(desc->osmesa_library, err, err_size)) return false;
    static const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                                   OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0 };
    OSMesaContext ctx = osmesa.create_attribs(attribs, NULL);
    if (!ctx) {
        snprintf(err, err_size, "osmesa: OSMesaCreateContextAttribs failed");
        return false;
    }
    if (!osmesa.make_current(ctx, o->pixels, GL_UNSIGNED_BYTE, o->width, o->height)) {
        osmesa.destroy(ctx);
        snprintf(err, err_size, "osmesa: OSMesaMakeCurrent failed for %dx%d", o->width, o->height);
        return false;
    }
    o->backend = ctx;
    snprintf(o->display, sizeof o->display, "osmesa");
    return true;
}

static bool osmesa_make_current(offscreen *o) {
    return o->backend && osmesa.make_current((OSMesaContext)o->backend, o->pixels, GL_UNSIGNED_BYTE, o->width,
                                             o->height);
}

static void osmesa_close(offscreen *o) {
    if (!o->backend) return;
    osmesa.make_current(NULL, NULL, 0, 0, 0);
    osmesa.destroy((OSMesaContext)o->backend);
    o->backend = NULL;
}

const offscreen_backend offscreen_osmesa_backend = {
    .open = osmesa_open, .close = osmesa_close, .make_current = osmesa_make_current, .getproc = osmesa_getproc,
    .draws_into_pixels = true,
};

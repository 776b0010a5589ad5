/* support_osmesa.c — see support_osmesa.h. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/osmesa.h>

#include "support_osmesa.h"

void *ht_test_getproc(const char *name) {
    OSMESAproc p = OSMesaGetProcAddress(name);
    void *out;
    memcpy(&out, &p, sizeof out); /* function to data pointer: same size on POSIX */
    return out;
}

bool ht_test_gl_create(ht_test_gl *out, int width, int height, const char *gl_version,
                       char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    if (width <= 0 || height <= 0 || width > 8192 || height > 8192) {
        snprintf(err, err_size, "osmesa: size %dx%d outside 1..8192", width, height);
        return false;
    }
    if (gl_version) setenv("MESA_GL_VERSION_OVERRIDE", gl_version, 1);
    const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                            OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0 };
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx) {
        snprintf(err, err_size, "osmesa: OSMesaCreateContextAttribs failed");
        return false;
    }
    out->buffer = calloc((size_t)width * (size_t)height, 4);
    if (!out->buffer) {
        OSMesaDestroyContext(ctx);
        snprintf(err, err_size, "osmesa: out of memory");
        return false;
    }
    if (!OSMesaMakeCurrent(ctx, out->buffer, GL_UNSIGNED_BYTE, width, height)) {
        OSMesaDestroyContext(ctx);
        free(out->buffer);
        out->buffer = NULL;
        snprintf(err, err_size, "osmesa: OSMesaMakeCurrent failed");
        return false;
    }
    out->context = ctx;
    out->width = width;
    out->height = height;
    return true;
}

void ht_test_gl_destroy(ht_test_gl *gl) {
    if (!gl) return;
    if (gl->context) {
        OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
        OSMesaDestroyContext((OSMesaContext)gl->context);
    }
    free(gl->buffer);
    memset(gl, 0, sizeof *gl);
}

ht_result ht_test_gl_read(const ht_test_gl *gl, ht_image *out) {
    glFinish();
    ht_result r = ht_image_alloc(out, gl->width, gl->height, 4);
    if (r != HT_OK) return r;
    size_t row = (size_t)gl->width * 4;
    /* OSMesa's buffer is bottom row first, like glReadPixels. */
    for (int y = 0; y < gl->height; y++)
        memcpy(out->pixels + (size_t)y * row, gl->buffer + (size_t)(gl->height - 1 - y) * row, row);
    return HT_OK;
}

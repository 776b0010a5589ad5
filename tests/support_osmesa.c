/* support_osmesa.c — see support_osmesa.h. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "offscreen.h"
#include "support_osmesa.h"

void *ht_test_getproc(const char *name) { return offscreen_getproc(name); }

bool ht_test_gl_create(ht_test_gl *out, int width, int height, const char *gl_version,
                       char *err, size_t err_size) {
    memset(out, 0, sizeof *out);
    if (gl_version) setenv("MESA_GL_VERSION_OVERRIDE", gl_version, 1);
    /* OSMesa unless HAIRTIER_CONTEXT says otherwise: the tests' default does
       not move when OSMesa is missing, they fail instead. */
    const char *env = getenv("HAIRTIER_CONTEXT");
    offscreen_desc desc = { .kind = env && env[0] ? OFFSCREEN_AUTO : OFFSCREEN_OSMESA, .width = width,
                            .height = height, .egl_device = -1 };
    out->context = offscreen_open(&desc, err, err_size);
    if (!out->context) return false;
    static bool said;   /* which context this process draws on, once (make test runs some on both) */
    if (!said) fprintf(stderr, "context: %s\n", out->context->display);
    said = true;
    out->width = width;
    out->height = height;
    return true;
}

void ht_test_gl_destroy(ht_test_gl *gl) {
    if (!gl) return;
    offscreen_close(gl->context);
    memset(gl, 0, sizeof *gl);
}

ht_result ht_test_gl_read(const ht_test_gl *gl, ht_image *out) {
    const unsigned char *rgba = offscreen_read(gl->context);
    ht_result r = ht_image_alloc(out, gl->width, gl->height, 4);
    if (r != HT_OK) return r;
    size_t row = (size_t)gl->width * 4;
    for (int y = 0; y < gl->height; y++)
        memcpy(out->pixels + (size_t)y * row, offscreen_row(rgba, gl->width, gl->height, y), row);
    return HT_OK;
}

/* install_smoke.c — an application of libhairtier as installed: built by
   tests/install_test.sh with only `pkg-config --cflags --libs --static
   hairtier` (and -lOSMesa, its own context's library), no path into the
   source tree. It draws one frame of a bundle through OSMesa and exits 0
   only when the renderer picked a tier and hair covers part of the frame.
   Built with -DSMOKE_HEADER='"H.h"' -DSMOKE_ENTRY=SYMBOL it first draws the
   bundle a `hairgen --emit-header H.h --header-symbol SYMBOL` compiled in,
   then BUNDLE_DIR's when one is given (one build, one context for both).

   usage: install_smoke BUNDLE_DIR
          install_smoke [BUNDLE_DIR]   (built with SMOKE_HEADER) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/osmesa.h>

#include <hairtier/hairtier.h>
#ifdef SMOKE_HEADER
#include SMOKE_HEADER
#endif

enum { SIZE = 64 };

static void *getproc(const char *name) {
    OSMESAproc p = OSMesaGetProcAddress(name);
    void *out;
    memcpy(&out, &p, sizeof out); /* function to data pointer: same size on POSIX */
    return out;
}

static int fail(const char *what, ht_result r) {
    fprintf(stderr, "install_smoke: %s: %s\n", what, ht_result_string(r));
    return 1;
}

/* One frame of the bundle desc names, in the current SIZE x SIZE context
   over rgba; 0 when the renderer picked a tier and hair covers part of it. */
static int draw(ht_renderer_desc desc, const char *label, const unsigned char *rgba) {
    ht_mesh mesh;
    ht_result r = ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 300, .joints = 8, .length = 0.125f,
                                                       .width = 0.02f, .seed = 7 }, &mesh);
    if (r != HT_OK) return fail("ht_mesh_build_furball", r);
    ht_mesh_sort_inside_out(&mesh);
    ht_renderer *renderer;
    desc.getproc = getproc;
    r = ht_renderer_create(&desc, &renderer);
    if (r != HT_OK) return fail("ht_renderer_create", r);
    if ((r = ht_renderer_set_mesh(renderer, &mesh)) != HT_OK) return fail("ht_renderer_set_mesh", r);

    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_light light = { .type = HT_LIGHT_DIRECTIONAL, .vector = { 0.3f, 0.8f, 0.5f }, .color = { 1, 1, 1 } };
    ht_frame_desc frame = { .camera = { .eye = { 0.82f, 1.63f, 2.75f }, .up = { 0, 1, 0 }, .fov_y = 40 },
                            .lights = &light, .light_count = 1 };
    if ((r = ht_renderer_draw(renderer, &frame)) != HT_OK) return fail("ht_renderer_draw", r);
    glFinish();

    int lit = 0;
    for (int i = 0; i < SIZE * SIZE; i++)
        lit += rgba[4 * i] + rgba[4 * i + 1] + rgba[4 * i + 2] > 0;
    printf("install_smoke: %s: tier=%s, %d of %d pixels hair\n", label, ht_tier_name(ht_renderer_tier(renderer)),
           lit, SIZE * SIZE);
    ht_renderer_destroy(renderer);
    ht_mesh_free(&mesh);
    /* The fur ball covers about a ninth of the frame (462 pixels on
       llvmpipe); half of that proves hair was drawn. */
    return lit >= SIZE * SIZE / 18 ? 0 : 1;
}

int main(int argc, char **argv) {
#ifdef SMOKE_HEADER
    const int min_args = 1;
#else
    const int min_args = 2;
#endif
    if (argc < min_args || argc > 2) {
        fprintf(stderr, "usage: %s\n", min_args == 1 ? "install_smoke [BUNDLE_DIR]" : "install_smoke BUNDLE_DIR");
        return 2;
    }
    static const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                                   OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0 };
    static unsigned char rgba[SIZE * SIZE * 4];
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx || !OSMesaMakeCurrent(ctx, rgba, GL_UNSIGNED_BYTE, SIZE, SIZE)) {
        fprintf(stderr, "install_smoke: no OSMesa context\n");
        return 1;
    }
    glViewport(0, 0, SIZE, SIZE);
    int status = 0;
#ifdef SMOKE_HEADER
    status |= draw((ht_renderer_desc){ .bundle_memory = &SMOKE_ENTRY }, "compiled-in header", rgba);
#endif
    if (argc == 2) status |= draw((ht_renderer_desc){ .bundle_dir = argv[1] }, argv[1], rgba);
    OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
    OSMesaDestroyContext(ctx);
    return status;
}

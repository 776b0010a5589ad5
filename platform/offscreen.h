/* offscreen.h — the one place the programs, hairgen --measure and the tests
   make a GL context:
   an RGBA8 compatibility-profile context with a 24-bit depth buffer, a
   given size, no window, through OSMesa or EGL.

   Usage:
       offscreen_kind kind;
       if (!offscreen_kind_parse(arg_of_context, &kind)) usage();   // "osmesa" | "egl"
       char err[512];
       offscreen *o = offscreen_open(&(offscreen_desc){ .kind = kind, .width = 512, .height = 512,
                                                        .egl_device = -1 }, err, sizeof err);
       if (!o) { fprintf(stderr, "prog: %s\n", err); return 1; }   // one line, e.g. "egl: no display: ..."
       ... ht_renderer_create(&(ht_renderer_desc){ .getproc = offscreen_getproc, ... })
       o->gl.ClearColor(0, 0, 0, 1); o->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
       ... ht_renderer_draw(...)
       const unsigned char *rgba = offscreen_read(o);   // glFinish, rows bottom-up like GL
       ... offscreen_row(rgba, o->width, o->height, y) is row y from the top
       offscreen_close(o);

   Backends (offscreen_osmesa.c, offscreen_egl.c): both libraries are
   loaded at run time (dlopen of libOSMesa.so.8, libEGL.so.1), so a program
   runs where Mesa has no OSMesa (removed in Mesa 25.1) or on another
   vendor's driver, and one that links no GL (hairgen) starts without
   loading Mesa. OFFSCREEN_AUTO takes HAIRTIER_CONTEXT=osmesa|egl when set,
   else OSMesa where it loads, else EGL. EGL: eglBindAPI(
   EGL_OPENGL_API) and a context with no version or profile attributes (the
   driver's compatibility profile, which MESA_GL_VERSION_OVERRIDE still
   lowers), drawing into a pbuffer surface (a default framebuffer like
   OSMesa's: no FBO, so GL 1.1 contexts work too). Display: with
   egl_device >= 0 device N of EGL_EXT_device_enumeration through
   EGL_EXT_platform_device; else the default display (EGL_PLATFORM=
   surfaceless picks Mesa's headless platform), then
   EGL_MESA_platform_surfaceless, then device 0, the first that
   initialises.

   Programs call GL only through the context (o->gl, offscreen_getproc):
   they link neither libGL, libEGL nor libOSMesa, so the same binary runs on
   either backend. Several contexts may be open; the one opened or made
   current last is current, and offscreen_getproc answers for it. */
#ifndef HT_PLATFORM_OFFSCREEN_H
#define HT_PLATFORM_OFFSCREEN_H

#include <stdbool.h>
#include <stddef.h>

#include <GL/gl.h>

typedef enum offscreen_kind {
    OFFSCREEN_AUTO = 0,   /* HAIRTIER_CONTEXT, else osmesa where libOSMesa loads, else egl */
    OFFSCREEN_OSMESA,
    OFFSCREEN_EGL,
} offscreen_kind;

/* Which API the context speaks: desktop GL (compatibility profile) or
   OpenGL ES 1.x, 2.0 or 3.x (EGL only: EGL_OPENGL_ES_API with
   EGL_CONTEXT_CLIENT_VERSION 1, 2 or 3; Mesa's ES 2 request gets its
   highest ES, which still serves ES 2.0 programs). */
typedef enum offscreen_api {
    OFFSCREEN_API_GL = 0,
    OFFSCREEN_API_GLES1,
    OFFSCREEN_API_GLES2,
    OFFSCREEN_API_GLES3,
} offscreen_api;

typedef struct offscreen_desc {
    offscreen_kind kind;    /* OFFSCREEN_AUTO; an ES api needs egl (AUTO becomes egl) */
    offscreen_api api;      /* OFFSCREEN_API_GL */
    int width, height;      /* 1..8192 each */
    int egl_device;         /* -1 → the default display chain above; N → EGL device N (egl only) */
    const char *osmesa_library, *egl_library;   /* NULL → libOSMesa.so.8, libEGL.so.1 */
    int samples;            /* 0 or 1: none; N: draw into an N-sample framebuffer (offscreen_msaa.h) */
} offscreen_desc;

/* The GL calls the programs make themselves, loaded through the context. */
typedef struct offscreen_gl {
    void (*ClearColor)(GLclampf r, GLclampf g, GLclampf b, GLclampf a);
    void (*Clear)(GLbitfield mask);
    void (*Finish)(void);
    void (*Viewport)(GLint x, GLint y, GLsizei w, GLsizei h);
    const GLubyte *(*GetString)(GLenum name);
    void (*ReadPixels)(GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void *pixels);
} offscreen_gl;

typedef struct offscreen {
    offscreen_kind kind;        /* OFFSCREEN_OSMESA or OFFSCREEN_EGL, never AUTO */
    offscreen_api api;
    int width, height;
    offscreen_gl gl;
    char display[128];          /* how it was made: "osmesa", "egl: EGL_MESA_platform_surfaceless, Mesa Project" */
    unsigned char *pixels;      /* width * height * 4, rows bottom-up; offscreen_read fills it */
    void *backend;              /* the backend's own state */
    void *msaa;                 /* the multisampled framebuffer (offscreen_msaa.c); NULL without samples */
} offscreen;

/* "osmesa" or "egl" into *out; false for anything else (NULL included). */
bool offscreen_kind_parse(const char *text, offscreen_kind *out);
const char *offscreen_kind_name(offscreen_kind kind);

/* The values of the two options every drawing program takes, `--context
   osmesa|egl` and `--egl-device N` (0..255): NULL, or why the value is
   refused (one line naming the option). */
const char *offscreen_context_value(const char *value, offscreen_kind *kind);
const char *offscreen_device_value(const char *value, int *egl_device);
/* `--api gl|gles1|gles2|gles3`: NULL, or why the value is refused. */
const char *offscreen_api_value(const char *value, offscreen_api *api);
const char *offscreen_api_name(offscreen_api api);
/* After the options: --egl-device and an ES --api imply egl (true), and
   are refused with --context osmesa (false, *why set). egl_device < 0:
   not given. */
bool offscreen_options_check(offscreen_kind *kind, int egl_device, const char **why);
bool offscreen_api_check(offscreen_kind *kind, offscreen_api api, const char **why);

/* A current context with the viewport covering it; NULL with one line in
   err ("egl: no display: ...", "osmesa: libOSMesa.so.8: cannot open ...",
   "HAIRTIER_CONTEXT: \"x\" is not osmesa or egl"; with OFFSCREEN_AUTO
   and neither library loading, both reasons) when it cannot be made. */
offscreen *offscreen_open(const offscreen_desc *desc, char *err, size_t err_size);
/* Makes o current again (after another was opened or made current). */
bool offscreen_make_current(offscreen *o);
void offscreen_close(offscreen *o);
/* The current context's entry point for name (ht_renderer_desc.getproc). */
void *offscreen_getproc(const char *name);
/* How long to draw before timing frames on o: ht_timing_warmup_ms of its
   GL_RENDERER (a GPU's clock; 0 on a software rasterizer). */
double offscreen_warmup_ms(const offscreen *o);
/* glFinish, then the colour buffer: width * height * 4 bytes, bottom row
   first (OSMesa draws into it; EGL reads it back with glReadPixels); with
   samples, resolved first. */
const unsigned char *offscreen_read(offscreen *o);

/* o's colour buffer (offscreen_read) box-filtered down k times a side:
   each out pixel the rounded mean of its k x k, `channels` (3: RGB, 4:
   RGBA) bytes each, rows top first (top_down: a PNG's) or bottom first as
   GL's; out holds (width / k) x (height / k) pixels. A supersampled
   reference (hairview --supersample, hairgen's 16x truth). */
void offscreen_read_box(offscreen *o, int k, int channels, bool top_down, unsigned char *out);

/* Row y, counted from the top, of a width x height RGBA buffer GL filled
   bottom row first. */
static inline const unsigned char *offscreen_row(const unsigned char *rgba, int width, int height, int y) {
    return rgba + (size_t)(height - 1 - y) * (size_t)width * 4;
}

#endif

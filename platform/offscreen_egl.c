/* offscreen_egl.c — the EGL backend of offscreen.h: a compatibility-profile
   GL context (egl.BindAPI(EGL_OPENGL_API), no version or profile attributes)
   or a GL ES 1/2/3 one (EGL_OPENGL_ES_API, EGL_CONTEXT_CLIENT_VERSION),
   drawing into an RGBA8 + 24-bit depth pbuffer. A pbuffer rather than an
   FBO on a surfaceless context: it is a default framebuffer like OSMesa's,
   so nothing changes for the runtime, and it needs no GL 3.0 entry points
   (the gl11 tier runs under MESA_GL_VERSION_OVERRIDE=1.1). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "offscreen_backend.h"

#define MAX_DEVICES 16

/* A display stays initialised for the life of the process (no
   eglTerminate): terminating unloads Mesa's driver, whose per-thread
   allocations then live on with no library to name them (leak checkers
   can no longer tell them from ours, tests/lsan.supp), and the next context
   would load the driver again. eglInitialize on an initialised display is
   a no-op. */
typedef struct egl_state {
    EGLDisplay display;
    EGLSurface surface;
    EGLContext context;
} egl_state;

/* libEGL is loaded with dlopen like libOSMesa, so that a program that
   links no GL (hairgen, whose --measure draws) starts without it. */
#define EGL_LIBRARY "libEGL.so.1"

static struct {
    void *library;
    PFNEGLGETPROCADDRESSPROC GetProcAddress;
    PFNEGLGETDISPLAYPROC GetDisplay;
    PFNEGLINITIALIZEPROC Initialize;
    PFNEGLQUERYSTRINGPROC QueryString;
    PFNEGLGETPLATFORMDISPLAYPROC GetPlatformDisplay;
    PFNEGLGETERRORPROC GetError;
    PFNEGLCHOOSECONFIGPROC ChooseConfig;
    PFNEGLGETCONFIGATTRIBPROC GetConfigAttrib;
    PFNEGLBINDAPIPROC BindAPI;
    PFNEGLCREATEPBUFFERSURFACEPROC CreatePbufferSurface;
    PFNEGLCREATECONTEXTPROC CreateContext;
    PFNEGLMAKECURRENTPROC MakeCurrent;
    PFNEGLDESTROYCONTEXTPROC DestroyContext;
    PFNEGLDESTROYSURFACEPROC DestroySurface;
} egl;

bool offscreen_egl_available(const char *library, char *err, size_t err_size) {
    if (egl.library) return true;
#define SYMBOL(n) { "egl" #n, &egl.n, sizeof egl.n }
    const offscreen_symbol symbols[] = {
        SYMBOL(GetProcAddress),
        SYMBOL(GetDisplay),
        SYMBOL(Initialize),
        SYMBOL(QueryString),
        SYMBOL(GetPlatformDisplay),
        SYMBOL(GetError),
        SYMBOL(ChooseConfig),
        SYMBOL(GetConfigAttrib),
        SYMBOL(BindAPI),
        SYMBOL(CreatePbufferSurface),
        SYMBOL(CreateContext),
        SYMBOL(MakeCurrent),
        SYMBOL(DestroyContext),
        SYMBOL(DestroySurface),
    };
#undef SYMBOL
    egl.library = offscreen_load_library("egl", library ? library : EGL_LIBRARY, symbols,
                                         (int)(sizeof symbols / sizeof symbols[0]), err, err_size);
    return egl.library != NULL;
}

static const char *egl_error_name(EGLint e) {
    switch (e) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
    }
}

static void *egl_getproc(const char *name) {
    if (!egl.library) return NULL;
    __eglMustCastToProperFunctionPointerType p = egl.GetProcAddress(name);
    void *out;
    memcpy(&out, &p, sizeof out); /* function to data pointer: same size on POSIX */
    return out;
}

static bool has_extension(const char *list, const char *name) {
    size_t n = strlen(name);
    for (const char *p = list; p && (p = strstr(p, name)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

static bool initialise(EGLDisplay d) {
    EGLint major, minor;
    return d != EGL_NO_DISPLAY && egl.Initialize(d, &major, &minor);
}

/* Device `index` of EGL_EXT_device_enumeration as a display (EGL_EXT_platform_device). */
static EGLDisplay device_display(int index, char *err, size_t err_size) {
    const char *client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    PFNEGLQUERYDEVICESEXTPROC query_devices = (PFNEGLQUERYDEVICESEXTPROC)egl.GetProcAddress("eglQueryDevicesEXT");
    if (!has_extension(client, "EGL_EXT_platform_device") || !query_devices) {
        snprintf(err, err_size, "egl: device %d: the EGL library has no EGL_EXT_platform_device / eglQueryDevicesEXT",
                 index);
        return EGL_NO_DISPLAY;
    }
    EGLDeviceEXT devices[MAX_DEVICES];
    EGLint count = 0;
    if (!query_devices(MAX_DEVICES, devices, &count) || count < 1) {
        snprintf(err, err_size, "egl: device %d: eglQueryDevicesEXT found no device (%s)", index,
                 egl_error_name(egl.GetError()));
        return EGL_NO_DISPLAY;
    }
    if (index >= count) {
        snprintf(err, err_size, "egl: device %d: there %s %d device%s (0..%d)", index, count == 1 ? "is" : "are",
                 count, count == 1 ? "" : "s", count - 1);
        return EGL_NO_DISPLAY;
    }
    EGLDisplay d = egl.GetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[index], NULL);
    if (!initialise(d)) {
        snprintf(err, err_size, "egl: device %d: eglInitialize failed (%s)", index, egl_error_name(egl.GetError()));
        return EGL_NO_DISPLAY;
    }
    return d;
}

/* The default display, else Mesa's surfaceless platform, else device 0:
   the first that initialises. */
static EGLDisplay any_display(char *how, size_t how_size, char *err, size_t err_size) {
    EGLDisplay d = egl.GetDisplay(EGL_DEFAULT_DISPLAY);
    if (initialise(d)) {
        snprintf(how, how_size, "default display");
        return d;
    }
    EGLint default_error = egl.GetError();
    const char *client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
        d = egl.GetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (initialise(d)) {
            snprintf(how, how_size, "EGL_MESA_platform_surfaceless");
            return d;
        }
    }
    char device_err[256];
    d = device_display(0, device_err, sizeof device_err);
    if (d != EGL_NO_DISPLAY) {
        snprintf(how, how_size, "EGL_EXT_platform_device 0");
        return d;
    }
    snprintf(err, err_size, "egl: no display: the default display failed (%s), %s, and %s",
             egl_error_name(default_error),
             has_extension(client, "EGL_MESA_platform_surfaceless") ? "so did EGL_MESA_platform_surfaceless"
                                                                    : "no EGL_MESA_platform_surfaceless",
             device_err + strlen("egl: "));
    return EGL_NO_DISPLAY;
}

/* Exactly RGBA8, depth 24 (else the least above), no multisampling:
   eglChooseConfig sorts deeper colour first, so pick by hand. */
static bool choose_config(EGLDisplay d, EGLint renderable, EGLConfig *out) {
    const EGLint want[] = { EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, renderable,
                                   EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
                                   EGL_DEPTH_SIZE, 24, EGL_NONE };
    EGLConfig configs[256];
    EGLint count = 0, best_depth = 1 << 30;
    if (!egl.ChooseConfig(d, want, configs, 256, &count)) return false;
    bool found = false;
    for (EGLint i = 0; i < count; i++) {
        EGLint r, g, b, a, depth, samples;
        egl.GetConfigAttrib(d, configs[i], EGL_RED_SIZE, &r);
        egl.GetConfigAttrib(d, configs[i], EGL_GREEN_SIZE, &g);
        egl.GetConfigAttrib(d, configs[i], EGL_BLUE_SIZE, &b);
        egl.GetConfigAttrib(d, configs[i], EGL_ALPHA_SIZE, &a);
        egl.GetConfigAttrib(d, configs[i], EGL_DEPTH_SIZE, &depth);
        egl.GetConfigAttrib(d, configs[i], EGL_SAMPLES, &samples);
        if (r == 8 && g == 8 && b == 8 && a == 8 && samples == 0 && depth < best_depth) {
            *out = configs[i];
            best_depth = depth;
            found = true;
        }
    }
    return found;
}

static bool egl_open(offscreen *o, const offscreen_desc *desc, char *err, size_t err_size) {
    if (!offscreen_egl_available(desc->egl_library, err, err_size)) return false;
    const int egl_device = desc->egl_device;
    egl_state *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, err_size, "egl: out of memory");
        return false;
    }
    char how[64];
    if (egl_device >= 0) {
        s->display = device_display(egl_device, err, err_size);
        snprintf(how, sizeof how, "EGL_EXT_platform_device %d", egl_device);
    } else {
        s->display = any_display(how, sizeof how, err, err_size);
    }
    if (s->display == EGL_NO_DISPLAY) {
        free(s);
        return false;
    }
    EGLConfig config;
    const char *failed = NULL;
    /* Desktop: no attributes (the compatibility profile). ES: the client
       version, and a config that renders it. */
    const bool es = desc->api != OFFSCREEN_API_GL;
    const EGLint es_version = desc->api == OFFSCREEN_API_GLES1 ? 1 : desc->api == OFFSCREEN_API_GLES2 ? 2 : 3;
    const EGLint renderable = !es ? EGL_OPENGL_BIT : es_version == 1 ? EGL_OPENGL_ES_BIT
                            : es_version == 2 ? EGL_OPENGL_ES2_BIT : EGL_OPENGL_ES3_BIT_KHR;
    const EGLint es_attribs[] = { EGL_CONTEXT_CLIENT_VERSION, es_version, EGL_NONE };
    if (!egl.BindAPI(es ? EGL_OPENGL_ES_API : EGL_OPENGL_API))
        failed = es ? "egl.BindAPI(EGL_OPENGL_ES_API)" : "egl.BindAPI(EGL_OPENGL_API)";
    else if (!choose_config(s->display, renderable, &config))
        failed = es ? "no RGBA8 + depth 24 pbuffer config for this GL ES version"
                    : "no RGBA8 + depth 24 pbuffer config for desktop GL";
    else {
        const EGLint size[] = { EGL_WIDTH, o->width, EGL_HEIGHT, o->height, EGL_NONE };
        s->surface = egl.CreatePbufferSurface(s->display, config, size);
        if (s->surface == EGL_NO_SURFACE) failed = "eglCreatePbufferSurface";
        else if ((s->context = egl.CreateContext(s->display, config, EGL_NO_CONTEXT, es ? es_attribs : NULL)) ==
                 EGL_NO_CONTEXT)
            failed = es ? "eglCreateContext (GL ES)" : "eglCreateContext (compatibility profile)";
        else if (!egl.MakeCurrent(s->display, s->surface, s->surface, s->context)) failed = "eglMakeCurrent";
    }
    if (failed) {
        snprintf(err, err_size, "egl: %s: %s failed (%s) for %dx%d", how, failed, egl_error_name(egl.GetError()),
                 o->width, o->height);
        o->backend = s;
        offscreen_egl_backend.close(o);
        return false;
    }
    o->backend = s;
    const char *vendor = egl.QueryString(s->display, EGL_VENDOR);
    snprintf(o->display, sizeof o->display, "egl: %s, %s%s%s", how, vendor ? vendor : "unknown vendor",
             es ? ", " : "", es ? offscreen_api_name(desc->api) : "");
    return true;
}

static bool egl_make_current(offscreen *o) {
    const egl_state *s = o->backend;
    return s && egl.MakeCurrent(s->display, s->surface, s->surface, s->context);
}

static void egl_close(offscreen *o) {
    egl_state *s = o->backend;
    if (!s) return;
    egl.MakeCurrent(s->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (s->context != EGL_NO_CONTEXT) egl.DestroyContext(s->display, s->context);
    if (s->surface != EGL_NO_SURFACE) egl.DestroySurface(s->display, s->surface);
    free(s);
    o->backend = NULL;
}

const offscreen_backend offscreen_egl_backend = {
    .open = egl_open, .close = egl_close, .make_current = egl_make_current, .getproc = egl_getproc,
    .draws_into_pixels = false,
};

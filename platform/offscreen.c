/* offscreen.c — see offscreen.h: picks the backend, owns the pixels and the
   few GL calls the programs make, answers getproc for the current context. */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairtier.h>

#include "offscreen_backend.h"
#include "offscreen_msaa.h"

#define MAX_SIDE 8192

static const offscreen_backend *current;   /* the backend of the context opened last */

bool offscreen_kind_parse(const char *text, offscreen_kind *out) {
    if (!text) return false;
    if (strcmp(text, "osmesa") == 0) *out = OFFSCREEN_OSMESA;
    else if (strcmp(text, "egl") == 0) *out = OFFSCREEN_EGL;
    else return false;
    return true;
}

const char *offscreen_context_value(const char *value, offscreen_kind *kind) {
    return offscreen_kind_parse(value, kind) ? NULL : "--context: expected osmesa or egl";
}

const char *offscreen_device_value(const char *value, int *egl_device) {
    char *end;
    long n = strtol(value, &end, 10);
    if (*end || end == value || n < 0 || n > 255) return "--egl-device: expected an integer in 0..255";
    *egl_device = (int)n;
    return NULL;
}

bool offscreen_options_check(offscreen_kind *kind, int egl_device, const char **why) {
    if (egl_device < 0) return true;
    if (*kind == OFFSCREEN_OSMESA) {
        *why = "--egl-device: needs --context egl";
        return false;
    }
    *kind = OFFSCREEN_EGL;
    return true;
}

static const char *const api_names[] = { "gl", "gles1", "gles2", "gles3" };

const char *offscreen_api_value(const char *value, offscreen_api *api) {
    for (int i = 0; value && i < 4; i++)
        if (strcmp(value, api_names[i]) == 0) {
            *api = (offscreen_api)i;
            return NULL;
        }
    return "--api: expected gl, gles1, gles2 or gles3";
}

const char *offscreen_api_name(offscreen_api api) {
    return api >= OFFSCREEN_API_GL && api <= OFFSCREEN_API_GLES3 ? api_names[api] : "gl";
}

/* OSMesa makes desktop contexts only. */
bool offscreen_api_check(offscreen_kind *kind, offscreen_api api, const char **why) {
    if (api == OFFSCREEN_API_GL) return true;
    if (*kind == OFFSCREEN_OSMESA) {
        *why = "--api: GL ES contexts come from EGL, not --context osmesa";
        return false;
    }
    *kind = OFFSCREEN_EGL;
    return true;
}

const char *offscreen_kind_name(offscreen_kind kind) {
    return kind == OFFSCREEN_OSMESA ? "osmesa" : kind == OFFSCREEN_EGL ? "egl" : "auto";
}

void *offscreen_load_library(const char *who, const char *library, const offscreen_symbol *symbols, int count,
                             char *err, size_t err_size) {
    void *handle = dlopen(library, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char *why = dlerror();
        snprintf(err, err_size, "%s: %s", who, why ? why : library);
        return NULL;
    }
    for (int i = 0; i < count; i++) {
        void *p = dlsym(handle, symbols[i].name);
        if (!p) {
            snprintf(err, err_size, "%s: %s: no symbol %s", who, library, symbols[i].name);
            dlclose(handle);
            return NULL;
        }
        memcpy(symbols[i].fn, &p, symbols[i].fn_size); /* data to function pointer: same size on POSIX */
    }
    return handle;
}

/* OFFSCREEN_AUTO: HAIRTIER_CONTEXT, else osmesa where it loads, else egl
   (osmesa_why then says why not osmesa). */
static bool resolve(const offscreen_desc *desc, offscreen_kind *out, char *osmesa_why, size_t why_size, char *err,
                    size_t err_size) {
    if (desc->kind != OFFSCREEN_AUTO || desc->api != OFFSCREEN_API_GL) {
        *out = desc->api != OFFSCREEN_API_GL ? OFFSCREEN_EGL : desc->kind;
        if (desc->kind == OFFSCREEN_OSMESA && desc->api != OFFSCREEN_API_GL) {
            snprintf(err, err_size, "osmesa: no %s context (OSMesa makes desktop GL only; use egl)",
                     offscreen_api_name(desc->api));
            return false;
        }
        return true;
    }
    const char *env = getenv("HAIRTIER_CONTEXT");
    if (env && env[0]) {
        if (offscreen_kind_parse(env, out)) return true;
        snprintf(err, err_size, "HAIRTIER_CONTEXT: \"%.40s\" is not osmesa or egl", env);
        return false;
    }
    *out = offscreen_osmesa_available(desc->osmesa_library, osmesa_why, why_size) ? OFFSCREEN_OSMESA : OFFSCREEN_EGL;
    return true;
}

static const offscreen_backend *backend_of(offscreen_kind kind) {
    return kind == OFFSCREEN_OSMESA ? &offscreen_osmesa_backend : &offscreen_egl_backend;
}

static void *load(const offscreen *o, const char *name, char *err, size_t err_size, bool *ok) {
    void *p = current->getproc(name);
    if (!p && *ok) {
        snprintf(err, err_size, "%s: the context has no %s", offscreen_kind_name(o->kind), name);
        *ok = false;
    }
    return p;
}

/* Function pointers from getproc's data pointers (same size on POSIX). */
#define LOAD(field, name) \
    do { void *p_ = load(o, name, err, err_size, &ok); memcpy(&o->gl.field, &p_, sizeof p_); } while (0)

offscreen *offscreen_open(const offscreen_desc *desc, char *err, size_t err_size) {
    offscreen_kind kind;
    char osmesa_why[512] = "";
    if (!resolve(desc, &kind, osmesa_why, sizeof osmesa_why, err, err_size)) return NULL;
    if (desc->width < 1 || desc->height < 1 || desc->width > MAX_SIDE || desc->height > MAX_SIDE) {
        snprintf(err, err_size, "%s: size %dx%d outside 1..%d", offscreen_kind_name(kind), desc->width, desc->height,
                 MAX_SIDE);
        return NULL;
    }
    offscreen *o = calloc(1, sizeof *o);
    if (o) o->pixels = malloc((size_t)desc->width * (size_t)desc->height * 4);
    if (!o || !o->pixels) {
        if (o) free(o);
        snprintf(err, err_size, "%s: out of memory for a %dx%d buffer", offscreen_kind_name(kind), desc->width,
                 desc->height);
        return NULL;
    }
    o->kind = kind;
    o->api = desc->api;
    o->width = desc->width;
    o->height = desc->height;
    const offscreen_backend *b = backend_of(kind);
    if (!b->open(o, desc, err, err_size)) {
        /* Neither backend: the one line says why not either. */
        if (osmesa_why[0]) {
            char egl_why[1024];
            snprintf(egl_why, sizeof egl_why, "%s", err);
            snprintf(err, err_size, "no offscreen context: %s; %s", osmesa_why, egl_why);
        }
        free(o->pixels);
        free(o);
        return NULL;
    }
    current = b;
    bool ok = true;
    LOAD(ClearColor, "glClearColor");
    LOAD(Clear, "glClear");
    LOAD(Finish, "glFinish");
    LOAD(Viewport, "glViewport");
    LOAD(GetString, "glGetString");
    LOAD(ReadPixels, "glReadPixels");
    if (!ok) {
        offscreen_close(o);
        return NULL;
    }
    o->gl.Viewport(0, 0, o->width, o->height);
    if (desc->samples > 1 && !offscreen_msaa_open(o, desc->samples, err, err_size)) {
        offscreen_close(o);
        return NULL;
    }
    return o;
}

bool offscreen_make_current(offscreen *o) {
    const offscreen_backend *b = backend_of(o->kind);
    if (!b->make_current(o)) return false;
    current = b;
    return true;
}

double offscreen_warmup_ms(const offscreen *o) {
    return ht_timing_warmup_ms((const char *)o->gl.GetString(GL_RENDERER));
}

void offscreen_close(offscreen *o) {
    if (!o) return;
    const offscreen_backend *b = backend_of(o->kind);
    if (o->msaa) offscreen_msaa_close(o);
    b->close(o);
    if (current == b) current = NULL;
    free(o->pixels);
    free(o);
}

void *offscreen_getproc(const char *name) { return current ? current->getproc(name) : NULL; }

const unsigned char *offscreen_read(offscreen *o) {
    offscreen_msaa_resolve(o);
    o->gl.Finish();
    if (!backend_of(o->kind)->draws_into_pixels)
        o->gl.ReadPixels(0, 0, o->width, o->height, GL_RGBA, GL_UNSIGNED_BYTE, o->pixels);
    if (o->msaa) offscreen_msaa_rebind(o);
    return o->pixels;
}

void offscreen_read_box(offscreen *o, int k, int channels, bool top_down, unsigned char *out) {
    const unsigned char *rgba = offscreen_read(o);
    const int w = o->width / k, h = o->height / k;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int c = 0; c < channels; c++) {
                unsigned sum = 0;
                for (int j = 0; j < k; j++) {
                    const unsigned char *row = offscreen_row(rgba, o->width, o->height, y * k + j);
                    for (int i = 0; i < k; i++) sum += row[4 * (x * k + i) + c];
                }
                const int out_y = top_down ? y : h - 1 - y;
                out[((size_t)out_y * w + x) * channels + c] = (unsigned char)((sum + k * k / 2) / (k * k));
            }
}

/* offscreen_backend.h — what offscreen.c asks of a backend (OSMesa, EGL);
   private to the offscreen module. */
#ifndef HT_PLATFORM_OFFSCREEN_BACKEND_H
#define HT_PLATFORM_OFFSCREEN_BACKEND_H

#include "offscreen.h"

typedef struct offscreen_backend {
    /* Makes a width x height context current (o->width, o->height set;
       o->pixels allocated), sets o->backend and o->display; false with one
       line in err, everything it made released. */
    bool (*open)(offscreen *o, const offscreen_desc *desc, char *err, size_t err_size);
    void (*close)(offscreen *o);
    bool (*make_current)(offscreen *o);
    void *(*getproc)(const char *name);
    bool draws_into_pixels;   /* true: the colour buffer is o->pixels (OSMesa); false: read it back */
} offscreen_backend;

extern const offscreen_backend offscreen_osmesa_backend;
extern const offscreen_backend offscreen_egl_backend;

/* Whether the backend's library loads here (library: NULL for the default
   name); err says why not. The first library that loads stays loaded. */
bool offscreen_osmesa_available(const char *library, char *err, size_t err_size);
bool offscreen_egl_available(const char *library, char *err, size_t err_size);

/* A function the backends load from their library: its name and where its
   pointer goes (a function pointer of fn_size bytes). */
typedef struct offscreen_symbol {
    const char *name;
    void *fn;
    size_t fn_size;
} offscreen_symbol;

/* dlopen(library) and every symbol into its pointer; the handle, or NULL
   with one line in err ("WHO: LIBRARY: ...") and nothing left open. */
void *offscreen_load_library(const char *who, const char *library, const offscreen_symbol *symbols, int count,
                             char *err, size_t err_size);

#endif

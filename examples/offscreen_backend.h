/* offscreen_backend.h — what offscreen.c asks of a backend (OSMesa, EGL);
   private to the offscreen module. */
#ifndef HT_EXAMPLES_OFFSCREEN_BACKEND_H
#define HT_EXAMPLES_OFFSCREEN_BACKEND_H

#include "offscreen.h"

typedef struct offscreen_backend {
    /* Makes a width x height context current (o->width, o->height set;
       o->pixels allocated), sets o->backend and o->display; false with one
       line in err, everything it made released. */
    bool (*open)(offscreen *o, int egl_device, char *err, size_t err_size);
    void (*close)(offscreen *o);
    void *(*getproc)(const char *name);
    bool draws_into_pixels;   /* true: the colour buffer is o->pixels (OSMesa); false: read it back */
} offscreen_backend;

extern const offscreen_backend offscreen_osmesa_backend;
extern const offscreen_backend offscreen_egl_backend;

/* Whether libOSMesa loads here (what OFFSCREEN_AUTO asks first); err says
   why not. */
bool offscreen_osmesa_available(char *err, size_t err_size);

#endif

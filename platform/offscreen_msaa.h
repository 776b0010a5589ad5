/* offscreen_msaa.h — multisampling for an offscreen context (offscreen.h's
   desc.samples): a framebuffer object with multisampled colour (RGBA8) and
   depth (24-bit) renderbuffers is bound for drawing, and offscreen_read
   resolves it into the default framebuffer with glBlitFramebuffer first.
   The same on EGL and OSMesa: pbuffer configs with samples are rare on
   software drivers, framebuffer objects are not. Needs GL 3.0 or
   ARB_framebuffer_object (glRenderbufferStorageMultisample,
   glBlitFramebuffer). Internal to platform/. */
#ifndef HT_PLATFORM_OFFSCREEN_MSAA_H
#define HT_PLATFORM_OFFSCREEN_MSAA_H

#include <stdbool.h>
#include <stddef.h>

#include "offscreen.h"

/* Binds the multisampled framebuffer on o's current context; false with
   one line in err ("samples: 8: the driver allows at most 4", ...). */
bool offscreen_msaa_open(offscreen *o, int samples, char *err, size_t err_size);
/* Resolves the samples into the default framebuffer and binds it, for
   glReadPixels; offscreen_msaa_rebind binds the multisampled one again for
   the next frame. Both do nothing without samples. */
void offscreen_msaa_resolve(offscreen *o);
void offscreen_msaa_rebind(offscreen *o);
void offscreen_msaa_close(offscreen *o);

#endif

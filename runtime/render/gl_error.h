/* gl_error.h — a GL error code by name, for messages: every line
   libhairtier writes says "GL_OUT_OF_MEMORY", never "GL error 0x0505".
   Internal to libhairtier.

   Usage:
       GLenum e = gl->GetError();
       if (e) log("glBufferData: %s", ht_gl_error_name(e));  // "GL_OUT_OF_MEMORY"

   A code GL does not define reads "GL error 0xNNNN" (a static buffer per
   call site is not needed: the text is built into a thread-local one). */
#ifndef HT_GL_ERROR_H
#define HT_GL_ERROR_H

#include <GL/gl.h>

const char *ht_gl_error_name(GLenum e);

#endif

/* gl_error.c — see gl_error.h. */
#include "gl_error.h"

#include <stdio.h>

#include <GL/glext.h>

const char *ht_gl_error_name(GLenum e) {
    switch (e) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_TABLE_TOO_LARGE: return "GL_TABLE_TOO_LARGE";
    default: {
        static _Thread_local char unknown[32];
        snprintf(unknown, sizeof unknown, "GL error 0x%04x", (unsigned)e);
        return unknown;
    }
    }
}

/* offscreen_msaa.c — offscreen_msaa.h: the multisampled framebuffer. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "offscreen_msaa.h"

#define FRAMEBUFFER 0x8D40
#define READ_FRAMEBUFFER 0x8CA8
#define DRAW_FRAMEBUFFER 0x8CA9
#define RENDERBUFFER 0x8D41
#define COLOR_ATTACHMENT0 0x8CE0
#define DEPTH_ATTACHMENT 0x8D00
#define RGBA8 0x8058
#define DEPTH_COMPONENT24 0x81A6
#define FRAMEBUFFER_COMPLETE 0x8CD5
#define MAX_SAMPLES 0x8D57

typedef struct msaa {
    void (*GenFramebuffers)(GLsizei, GLuint *);
    void (*DeleteFramebuffers)(GLsizei, const GLuint *);
    void (*BindFramebuffer)(GLenum, GLuint);
    void (*GenRenderbuffers)(GLsizei, GLuint *);
    void (*DeleteRenderbuffers)(GLsizei, const GLuint *);
    void (*BindRenderbuffer)(GLenum, GLuint);
    void (*RenderbufferStorageMultisample)(GLenum, GLsizei, GLenum, GLsizei, GLsizei);
    void (*FramebufferRenderbuffer)(GLenum, GLenum, GLenum, GLuint);
    GLenum (*CheckFramebufferStatus)(GLenum);
    void (*BlitFramebuffer)(GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLbitfield, GLenum);
    void (*GetIntegerv)(GLenum, GLint *);
    GLuint fbo, color, depth;
} msaa;

#define LOAD(field, name)                                   \
    do {                                                    \
        void *p_ = offscreen_getproc(name);                 \
        if (!p_) missing = name;                            \
        memcpy(&m->field, &p_, sizeof p_);                  \
    } while (0)

bool offscreen_msaa_open(offscreen *o, int samples, char *err, size_t err_size) {
    msaa *m = calloc(1, sizeof *m);
    if (!m) {
        snprintf(err, err_size, "samples: out of memory");
        return false;
    }
    const char *missing = NULL;
    LOAD(GenFramebuffers, "glGenFramebuffers");
    LOAD(DeleteFramebuffers, "glDeleteFramebuffers");
    LOAD(BindFramebuffer, "glBindFramebuffer");
    LOAD(GenRenderbuffers, "glGenRenderbuffers");
    LOAD(DeleteRenderbuffers, "glDeleteRenderbuffers");
    LOAD(BindRenderbuffer, "glBindRenderbuffer");
    LOAD(RenderbufferStorageMultisample, "glRenderbufferStorageMultisample");
    LOAD(FramebufferRenderbuffer, "glFramebufferRenderbuffer");
    LOAD(CheckFramebufferStatus, "glCheckFramebufferStatus");
    LOAD(BlitFramebuffer, "glBlitFramebuffer");
    LOAD(GetIntegerv, "glGetIntegerv");
    if (missing) {
        snprintf(err, err_size, "samples: %d: the context has no %s (GL 3.0 or ARB_framebuffer_object)", samples,
                 missing);
        free(m);
        return false;
    }
    GLint max = 0;
    m->GetIntegerv(MAX_SAMPLES, &max);
    if (samples > max) {
        snprintf(err, err_size, "samples: %d: the driver allows at most %d", samples, (int)max);
        free(m);
        return false;
    }
    m->GenFramebuffers(1, &m->fbo);
    m->GenRenderbuffers(1, &m->color);
    m->GenRenderbuffers(1, &m->depth);
    m->BindFramebuffer(FRAMEBUFFER, m->fbo);
    m->BindRenderbuffer(RENDERBUFFER, m->color);
    m->RenderbufferStorageMultisample(RENDERBUFFER, samples, RGBA8, o->width, o->height);
    m->FramebufferRenderbuffer(FRAMEBUFFER, COLOR_ATTACHMENT0, RENDERBUFFER, m->color);
    m->BindRenderbuffer(RENDERBUFFER, m->depth);
    m->RenderbufferStorageMultisample(RENDERBUFFER, samples, DEPTH_COMPONENT24, o->width, o->height);
    m->FramebufferRenderbuffer(FRAMEBUFFER, DEPTH_ATTACHMENT, RENDERBUFFER, m->depth);
    o->msaa = m;
    if (m->CheckFramebufferStatus(FRAMEBUFFER) != FRAMEBUFFER_COMPLETE) {
        snprintf(err, err_size, "samples: %d: the multisampled framebuffer is incomplete", samples);
        offscreen_msaa_close(o);
        return false;
    }
    return true;
}

void offscreen_msaa_resolve(offscreen *o) {
    msaa *m = o->msaa;
    if (!m) return;
    m->BindFramebuffer(READ_FRAMEBUFFER, m->fbo);
    m->BindFramebuffer(DRAW_FRAMEBUFFER, 0);
    m->BlitFramebuffer(0, 0, o->width, o->height, 0, 0, o->width, o->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    m->BindFramebuffer(FRAMEBUFFER, 0);
}

void offscreen_msaa_rebind(offscreen *o) {
    msaa *m = o->msaa;
    if (m) m->BindFramebuffer(FRAMEBUFFER, m->fbo);
}

void offscreen_msaa_close(offscreen *o) {
    msaa *m = o->msaa;
    if (!m) return;
    m->BindFramebuffer(FRAMEBUFFER, 0);
    m->DeleteFramebuffers(1, &m->fbo);
    m->DeleteRenderbuffers(1, &m->color);
    m->DeleteRenderbuffers(1, &m->depth);
    free(m);
    o->msaa = NULL;
}

/* support_gl_fault.h — a fault-injecting GL layer for tests: a getproc
   that hands the runtime a wrapper for every entry point it loads
   (runtime/render/gl_api.h's HT_GL_FUNCTIONS), each forwarding to OSMesa's, and
   that counts the GL objects the runtime creates and deletes.

   Usage:
       ht_fault_arm(HT_FAULT_COMPILE, 2);      // the 2nd glCompileShader fails
       ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_fault_getproc, ... }, &r);
       ...
       ht_renderer_destroy(r);
       assert_int_equal(ht_fault_live_total(), 0);   // every object made was deleted

   Fault classes (one armed at a time; it fires once, at the n-th call of
   its class counted from ht_fault_arm, and ht_fault_state()->fired says
   whether it did):
       COMPILE      glCompileShader runs, then glGetShaderiv says
                    GL_COMPILE_STATUS false and the info log is
                    HT_FAULT_COMPILE_LOG
       LINK         glLinkProgram runs, then GL_LINK_STATUS false, info log
                    HT_FAULT_LINK_LOG
       TEX_IMAGE    glTexImage2D or glTexImage3D is not forwarded (nothing
                    uploaded); the next glGetError says GL_OUT_OF_MEMORY
       BUFFER_DATA  glBufferData or glBufferSubData (an upload either way)
                    is not forwarded; GL_OUT_OF_MEMORY
       ANY_CALL     any entry point but glGetError is forwarded, then the
                    next glGetError says GL_OUT_OF_MEMORY
   An injected error is reported before the driver's own.

   Objects: names returned by glGenTextures, glGenBuffers, glCreateShader
   and glCreateProgram are kept in a set per kind until glDelete* names
   them; deleting 0 is ignored, deleting a name not in the set (a double
   delete, or one never made here) is counted apart as a stray delete.
   Vertex arrays: every gl*Pointer call is counted, and counted apart when
   no buffer is bound to GL_ARRAY_BUFFER (the array is client memory, which
   a discrete GPU copies across the bus at every draw). Which tier draws:
   glUseProgram of a program and glTexEnvi(GL_TEXTURE_ENV_MODE, GL_COMBINE)
   are counted.
   The layer is process-global (one GL context at a time, as the tests). */
#ifndef HT_SUPPORT_GL_FAULT_H
#define HT_SUPPORT_GL_FAULT_H

#include <stdbool.h>

#define HT_FAULT_COMPILE_LOG "0:1(1): error: injected compile failure (fault test)"
#define HT_FAULT_LINK_LOG "error: injected link failure (fault test)"

typedef enum ht_fault_class {
    HT_FAULT_NONE = 0,
    HT_FAULT_COMPILE,
    HT_FAULT_LINK,
    HT_FAULT_TEX_IMAGE,
    HT_FAULT_BUFFER_DATA,
    HT_FAULT_ANY_CALL,
    HT_FAULT_CLASS_COUNT
} ht_fault_class;

typedef enum ht_fault_object {
    HT_FAULT_TEXTURES = 0,
    HT_FAULT_BUFFERS,
    HT_FAULT_SHADERS,
    HT_FAULT_PROGRAMS,
    HT_FAULT_OBJECT_COUNT
} ht_fault_object;

typedef struct ht_fault_state {
    ht_fault_class armed;
    long at;                                   /* 1-based; 0: never fires */
    bool fired;
    long calls[HT_FAULT_CLASS_COUNT];          /* calls of each class since ht_fault_arm */
    int created[HT_FAULT_OBJECT_COUNT];        /* since ht_fault_arm */
    int deleted[HT_FAULT_OBJECT_COUNT];        /* live names deleted, since ht_fault_arm */
    int live[HT_FAULT_OBJECT_COUNT];           /* names made and not yet deleted (kept across arms) */
    int stray_deletes;                         /* deletes of names not live, since ht_fault_arm */
    long array_pointers;                       /* gl*Pointer calls, since ht_fault_arm */
    long client_array_pointers;                /* those with no GL_ARRAY_BUFFER bound */
    long programs_bound;                       /* glUseProgram of a program (not 0), since ht_fault_arm */
    long combiner_stages;                      /* glTexEnvi(GL_TEXTURE_ENV_MODE, GL_COMBINE), since then */
    long buffer_sub_data;                      /* the glBufferSubData among calls[HT_FAULT_BUFFER_DATA] */
} ht_fault_state;

/* Arms cls at its n-th call (n >= 1; HT_FAULT_NONE or n = 0: count only)
   and zeroes the counters; the live sets are kept. */
void ht_fault_arm(ht_fault_class cls, long n);
const ht_fault_state *ht_fault_state_get(void);
int ht_fault_live_total(void);
const char *ht_fault_class_name(ht_fault_class cls);
const char *ht_fault_object_name(ht_fault_object kind);
/* The wrapping getproc (ht_renderer_desc.getproc): a wrapper for every
   name gl_api.h loads, OSMesa's own entry point for any other name. */
void *ht_test_fault_getproc(const char *name);

#endif

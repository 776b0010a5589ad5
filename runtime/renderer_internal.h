/* renderer_internal.h — the renderer's state and its matrix helpers, shared
   by renderer.c and the tests that check the projection. */
#ifndef HT_RENDERER_INTERNAL_H
#define HT_RENDERER_INTERNAL_H

#include "manifest.h"
#include "gl_api.h"
#include "hairtier.h"
#include "select.h"
#include "tier.h"

/* What the renderer saves and resets per frame, at most (renderer.c). */
#define HT_RENDERER_MAX_UNITS 32      /* GL_TEXTURE0 .. GL_TEXTURE31 */
#define HT_RENDERER_MAX_ATTRIBS 32
#define HT_RENDERER_MAX_LIGHTS 64

struct ht_renderer {
    ht_gl gl;
    ht_caps caps;
    ht_manifest bundle;
    bool have_bundle;
    ht_log_fn log;
    void *log_user;
    bool record_trace;
    bool flat;
    float flat_color[3];
    ht_tier tier;                     /* HT_TIER_COUNT in flat mode */
    char reason[HT_SELECT_REASON];
    const ht_tier_backend *backend;   /* NULL in flat mode */
    void *backend_state;
    /* the hair mesh: buffers when the GL has them, else a private copy */
    GLuint vbo, ibo;
    ht_vertex *vertices;
    uint32_t *indices;
    uint32_t vertex_count, index_count;
    bool has_mesh;
    int vertex_attribs;               /* GL_MAX_VERTEX_ATTRIBS (capped), 0 without shaders */
    int max_lights;                   /* GL_MAX_LIGHTS (capped): the head turns off the ones it does not use */
    unsigned warned;                  /* frame warnings already logged once (renderer.c) */
    ht_trace trace;
};

/* gluPerspective and gluLookAt, column-major. False (out untouched) for
   degenerate input: fov outside (0,180), aspect <= 0, near <= 0,
   far <= near, eye on target, up parallel to the view direction. */
bool ht_mat4_perspective(float out[16], float fov_y_degrees, float aspect, float z_near, float z_far);
bool ht_mat4_look_at(float out[16], const float eye[3], const float target[3], const float up[3]);

#endif

/* renderer_internal.h — the renderer's state, shared by the files the
   renderer is split into (renderer.c names them), and what each of them
   lends the others. Internal to libhairtier. */
#ifndef HT_RENDERER_INTERNAL_H
#define HT_RENDERER_INTERNAL_H

#include "manifest.h"
#include "gl_api.h"
#include <hairtier/hairtier.h>
#include "select.h"
#include "tier.h"

/* What the renderer saves and resets per frame, at most (gl_state.c). */
#define HT_RENDERER_MAX_UNITS 32      /* GL_TEXTURE0 .. GL_TEXTURE31 */
#define HT_RENDERER_MAX_ATTRIBS 32
#define HT_RENDERER_MAX_LIGHTS 64

struct ht_renderer {
    ht_gl gl;
    uint64_t frames;                  /* drawn, for ht_renderer_get_stats */
    ht_caps caps;
    char *extensions;                 /* the device's whole list, after the profile (caps.h) */
    ht_manifest bundle;
    bool have_bundle;
    ht_log_fn log;
    void *log_user;
    bool record_trace;
    bool flat;
    float flat_color[3];
    float opacity_cut;                /* the width rule: hair alpha x (1 - this); ht_renderer_set_opacity_scale */
    bool back_to_front;               /* the mesh is ordered far to near (ht_renderer_set_back_to_front) */
    bool width_vertex;                /* the width rule per vertex asked for (ht_renderer_set_width_rule) */
    GLuint side_vbo;                  /* the mesh's a_side per vertex (shader_interface.h), made while */
    float (*sides)[3];                /* width_vertex is on: a buffer, or this copy without buffers */
    bool has_sides;                   /* the mesh was set with width_vertex on (and a_side made, where
                                         programs may read it) */
    ht_tier tier;                     /* HT_TIER_COUNT in flat mode */
    char reason[HT_SELECT_REASON];
    const ht_tier_backend *backend;   /* NULL in flat mode */
    void *backend_state;
    int backend_index;                /* backend's bundle tier, an index into made */
    /* Every tier's backend made so far (the drawing one among them), by
       bundle tier: ht_renderer_set_tier switches between them; mesh_serial
       says which ht_renderer_set_mesh a backend's per-vertex data is of. */
    struct {
        const ht_tier_backend *backend;
        void *state;
        uint32_t mesh_serial;
    } made[HT_MANIFEST_MAX_TIERS];
    uint32_t mesh_serial;             /* ht_renderer_set_mesh's successful calls */
    /* the hair mesh: buffers when the GL has them, else a private copy */
    GLuint vbo, ibo;
    ht_vertex *vertices;
    uint32_t *indices;
    uint32_t vertex_count, index_count;
    uint32_t draw_first, draw_count;  /* the indices the passes draw (ht_renderer_set_draw_range) */
    uint32_t draw_vertex_first, draw_vertex_count; /* their vertices when named (set_draw_range_vertices); count 0: not */
    uint32_t *span;                   /* per HT_SPAN_INDICES indices of the mesh: the least and the */
    uint32_t span_count;              /* largest vertex they index (2 a block); NULL: unknown */
    bool has_mesh;
    GLenum index_type;                /* GL_UNSIGNED_INT; GL_UNSIGNED_SHORT on GL ES 2.0 without
                                         GL_OES_element_index_uint (mesh_gpu.c) */
    struct ht_index_chunk *chunks;    /* 16-bit draws of a mesh over 65536 vertices (index_chunks.h); */
    uint32_t chunk_count;             /* 0: one draw of the whole index list */
    int vertex_attribs;               /* GL_MAX_VERTEX_ATTRIBS (capped), 0 without shaders */
    int max_lights;                   /* GL_MAX_LIGHTS (capped): the head turns off the ones it does not use */
    unsigned warned;                  /* frame warnings already logged once (validate.c) */
    /* what selection reads again when frame:MS re-chooses (renderer.c) */
    ht_tier requested;
    bool strict;
    ht_policy policy;
    ht_variant variant_request;       /* desc.variant, else HAIRTIER_VARIANT */
    ht_time_tier_fn time_tier;
    void *time_tier_user;
    double frame_ms[HT_MANIFEST_MAX_TIERS]; /* per bundle tier, 0 → not timed */
    ht_trace trace;
    /* GL ES: the head's program (opaque_scene_es.c), 0 until needed */
    GLuint opaque_program, flat_program;
    GLint opaque_u_mvp, opaque_u_light_vector, opaque_u_light_color, opaque_u_light_count;
    bool opaque_failed;               /* its build failed once (logged): no head on ES */
};

/* The files the renderer is split into, and what each lends the others. */

/* validate.c: each refusal logs one line and returns HT_ERR_INVALID_ARGUMENT. */
__attribute__((format(printf, 4, 5)))
ht_result ht_renderer_reject(const ht_renderer *r, const char *what, const char *field, const char *fmt, ...);
ht_result ht_renderer_check_mesh(const ht_renderer *r, const char *what, const ht_mesh *m);
/* Fills out's camera, eye and matrices (lights are plan_lights' job). */
ht_result ht_renderer_check_frame(const ht_renderer *r, const ht_frame_desc *f, ht_tier_frame *out);
/* The lights every backend and the head see; returns how many. */
int ht_renderer_plan_lights(ht_renderer *r, const ht_frame_desc *f, ht_light out[HT_MAX_LIGHTS]);

/* mesh_gpu.c */
void ht_renderer_release_mesh(ht_renderer *r);
/* The vertices the draw range indexes, a superset within a block of
   HT_SPAN_INDICES indices at each end (the fixed-function tiers' per-vertex
   CPU work covers these only). */
#define HT_SPAN_INDICES 768u
void ht_renderer_draw_vertices(const ht_renderer *r, uint32_t *first_vertex, uint32_t *vertex_count);
/* Whether meshes are drawn with 16-bit indices (the one rule: GL ES 2.0
   without GL_OES_element_index_uint), and a mesh's indices as 16 bits
   (malloc'd; NULL when out of memory). */
bool ht_renderer_short_indices(const ht_renderer *r);
uint16_t *ht_renderer_indices16(const uint32_t *indices, uint32_t count);
/* m's triangles from client memory with the arrays already pointed, as
   16-bit indices where the device has no others (nothing drawn when m is
   too big for them or memory is short). */
void ht_renderer_draw_client_elements(ht_renderer *r, const ht_mesh *m);
/* base: NULL with the hair VBO bound, else the vertices; hair_attributes:
   uv and the backend's generic attributes too (the head needs neither). */
void ht_renderer_set_arrays(ht_renderer *r, const ht_vertex *base, bool hair_attributes);
/* The same from vertex first on (a chunk of a split mesh). */
void ht_renderer_set_arrays_from(ht_renderer *r, const ht_vertex *base, uint32_t first, bool hair_attributes);
void ht_renderer_clear_arrays(ht_renderer *r);
/* Whether the hair can be widened per vertex: asked for, the drawing
   tier's programs do it, and the mesh has its sides. */
bool ht_renderer_width_rule_active(const ht_renderer *r);
/* Whether this frame's is: active, and the mesh drawn back to front (lod.h:
   the rule applies only so). */
bool ht_renderer_width_rule_drawn(const ht_renderer *r);

/* gl_state.c: save (HT_ERR_GL with one line and nothing changed when an
   attribute stack is full), baseline, restore. */
/* The vertex arrays a frame points on GL ES (gl_state_es.c restores them). */
#define HT_ES_STATE_ATTRIBS 8
typedef struct ht_gl_es_attrib {
    GLint enabled, size, type, normalized, stride, buffer;
    void *pointer;
} ht_gl_es_attrib;
/* GL ES 1.1 (gl_state_es1.c): a client array, a unit, the whole set. */
#define HT_ES1_ENABLES 11
#define HT_ES1_ENV_INTS 15
#define HT_ES1_ENV_FLOATS 6
#define HT_ES1_LIGHT_FLOATS 24
#define HT_ES1_MATERIAL_FLOATS 17
#define HT_ES1_MAX_LIGHTS 8
typedef struct ht_gl_es1_array {
    GLboolean enabled;
    GLint size, type, stride, buffer;
    void *pointer;
} ht_gl_es1_array;
typedef struct ht_gl_es1_unit {
    GLboolean texture_2d;
    GLint binding, env_int[HT_ES1_ENV_INTS];
    GLfloat env_float[HT_ES1_ENV_FLOATS];
    ht_gl_es1_array coords;
} ht_gl_es1_unit;
typedef struct ht_gl_es1_state {
    GLboolean enabled[HT_ES1_ENABLES], light_enabled[HT_ES1_MAX_LIGHTS];
    GLfloat light[HT_ES1_MAX_LIGHTS][HT_ES1_LIGHT_FLOATS], material[HT_ES1_MATERIAL_FLOATS];
    GLfloat model_ambient[4], two_side, alpha_ref, color[4];
    GLint matrix_mode, client_texture, shade_model, alpha_func;
    ht_gl_es1_array vertex, normal, color_array;
    ht_gl_es1_unit units[HT_RENDERER_MAX_UNITS];
} ht_gl_es1_state;
typedef struct ht_gl_state {
    GLint program;
    GLfloat projection[16], modelview[16];
    GLfloat texture[HT_RENDERER_MAX_UNITS][16];
    /* GL ES 2.0+ (no attribute stacks): what a frame may change, read back */
    GLboolean depth_test, blend, cull, polygon_offset, depth_mask, color_mask[4];
    GLint depth_func, cull_face, front_face, blend_func[4], active_texture, array_buffer, element_buffer, vao;
    GLint texture_2d[HT_RENDERER_MAX_UNITS];
    ht_gl_es_attrib attribs[HT_ES_STATE_ATTRIBS];
    GLint attrib_enabled[HT_RENDERER_MAX_ATTRIBS];
    ht_gl_es1_state es1;
} ht_gl_state;
ht_result ht_gl_state_save(ht_renderer *r, ht_gl_state *s);
void ht_gl_state_set_baseline(ht_renderer *r);
void ht_gl_state_restore(ht_renderer *r, const ht_gl_state *s);
/* gl_state_es.c: the same contract on GL ES 2.0+, by reading back each
   piece of state a frame changes (hairtier.h: ht_renderer_draw);
   gl_state_es1.c: on GL ES 1.1, the fixed-function state the same way. */
void ht_gl_state_save_es(ht_renderer *r, ht_gl_state *s);
void ht_gl_state_set_baseline_es(ht_renderer *r);
void ht_gl_state_restore_es(ht_renderer *r, const ht_gl_state *s);
void ht_gl_state_save_es1(ht_renderer *r, ht_gl_state *s);
void ht_gl_state_set_baseline_es1(ht_renderer *r);
void ht_gl_state_restore_es1(ht_renderer *r, const ht_gl_state *s);

/* opaque_scene.c; on GL ES opaque_scene_es.c (a program of the runtime's
   own lighting the head as GL's fixed-function lighting does, made at the
   first frame with a head and freed with the renderer). */
/* The state the head is drawn with on desktop GL and ES alike: client
   arrays (no buffers bound), no culling or blending, depth test and
   writes, every colour channel. */
void ht_renderer_opaque_state(const ht_gl *gl);
void ht_renderer_draw_opaque(ht_renderer *r, const ht_mesh *m, const ht_tier_frame *f);
void ht_renderer_draw_opaque_es(ht_renderer *r, const ht_mesh *m, const ht_tier_frame *f);
void ht_renderer_release_opaque_es(ht_renderer *r);
/* Flat mode's program, used with the frame's transform; false (logged)
   when it does not build. */
bool ht_renderer_bind_flat_es(ht_renderer *r, const ht_tier_frame *f);

/* passes.c: the alpha test of a pass, the one rule: GL's on desktop, the
   ES texts' discard uniforms on ES (func GL_GEQUAL keeps alpha >= ref,
   GL_LESS keeps alpha < ref). */
void ht_pass_alpha_rule(const ht_renderer *r, ht_pass pass, GLenum *func, float *ref);

/* passes.c: the four passes over the hair mesh, recording the trace. */
ht_result ht_renderer_draw_passes(ht_renderer *r, const ht_tier_frame *tf);

#endif

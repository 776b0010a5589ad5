/* gl_state_es.c — the GL-state contract of ht_renderer_draw on GL ES 2.0
   and later, which has no glPushAttrib: every piece of state a frame
   changes is read back before it and set again after it. The pieces: the
   enables and functions of depth, blend, cull and polygon offset, the
   depth and colour masks, the program, the active unit and each unit's 2D
   texture, both buffer bindings, the vertex array object (ES 3: the frame
   draws with object 0, so the application's stays untouched) and, on
   that object, every attribute's enable and the arrays the frame points. */
#include "renderer_internal.h"

static int units(const ht_renderer *r) {
    return r->caps.texture_units < HT_RENDERER_MAX_UNITS ? r->caps.texture_units : HT_RENDERER_MAX_UNITS;
}

static int pointed_attribs(const ht_renderer *r) {
    return r->vertex_attribs < HT_ES_STATE_ATTRIBS ? r->vertex_attribs : HT_ES_STATE_ATTRIBS;
}

void ht_gl_state_save_es(ht_renderer *r, ht_gl_state *s) {
    const ht_gl *gl = &r->gl;
    s->vao = 0;
    if (gl->has_vao && r->caps.gl_major >= 3) {
        gl->GetIntegerv(GL_VERTEX_ARRAY_BINDING, &s->vao);
        gl->BindVertexArray(0);
    }
    s->depth_test = gl->IsEnabled(GL_DEPTH_TEST);
    s->blend = gl->IsEnabled(GL_BLEND);
    s->cull = gl->IsEnabled(GL_CULL_FACE);
    s->polygon_offset = gl->IsEnabled(GL_POLYGON_OFFSET_FILL);
    gl->GetBooleanv(GL_DEPTH_WRITEMASK, &s->depth_mask);
    gl->GetBooleanv(GL_COLOR_WRITEMASK, s->color_mask);
    gl->GetIntegerv(GL_DEPTH_FUNC, &s->depth_func);
    gl->GetIntegerv(GL_CULL_FACE_MODE, &s->cull_face);
    gl->GetIntegerv(GL_FRONT_FACE, &s->front_face);
    static const GLenum blend[4] = { GL_BLEND_SRC_RGB, GL_BLEND_DST_RGB, GL_BLEND_SRC_ALPHA, GL_BLEND_DST_ALPHA };
    for (int i = 0; i < 4; i++) gl->GetIntegerv(blend[i], &s->blend_func[i]);
    gl->GetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    gl->GetIntegerv(GL_ACTIVE_TEXTURE, &s->active_texture);
    for (int u = 0; u < units(r); u++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &s->texture_2d[u]);
    }
    gl->GetIntegerv(GL_ARRAY_BUFFER_BINDING, &s->array_buffer);
    gl->GetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &s->element_buffer);
    for (int i = 0; i < r->vertex_attribs; i++)
        gl->GetVertexAttribiv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &s->attrib_enabled[i]);
    for (int i = 0; i < pointed_attribs(r); i++) {
        ht_gl_es_attrib *a = &s->attribs[i];
        gl->GetVertexAttribiv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_SIZE, &a->size);
        gl->GetVertexAttribiv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_TYPE, &a->type);
        gl->GetVertexAttribiv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_NORMALIZED, &a->normalized);
        gl->GetVertexAttribiv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_STRIDE, &a->stride);
        gl->GetVertexAttribiv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &a->buffer);
        gl->GetVertexAttribPointerv((GLuint)i, GL_VERTEX_ATTRIB_ARRAY_POINTER, &a->pointer);
    }
}

/* What the application may have left that would reach the hair or the
   head; where and how deep to draw (viewport, scissor, stencil, depth
   range, framebuffer) stay the application's, as on desktop GL. */
void ht_gl_state_set_baseline_es(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    gl->Disable(GL_BLEND);
    gl->Disable(GL_CULL_FACE);
    gl->Disable(GL_POLYGON_OFFSET_FILL);
    gl->UseProgram(0);
    for (int i = 0; i < r->vertex_attribs; i++) gl->DisableVertexAttribArray((GLuint)i);
    gl->ActiveTexture(GL_TEXTURE0);
}

static void set_enabled(const ht_gl *gl, GLenum cap, GLboolean on) {
    if (on) gl->Enable(cap);
    else gl->Disable(cap);
}

void ht_gl_state_restore_es(ht_renderer *r, const ht_gl_state *s) {
    const ht_gl *gl = &r->gl;
    set_enabled(gl, GL_DEPTH_TEST, s->depth_test);
    set_enabled(gl, GL_BLEND, s->blend);
    set_enabled(gl, GL_CULL_FACE, s->cull);
    set_enabled(gl, GL_POLYGON_OFFSET_FILL, s->polygon_offset);
    gl->DepthMask(s->depth_mask);
    gl->ColorMask(s->color_mask[0], s->color_mask[1], s->color_mask[2], s->color_mask[3]);
    gl->DepthFunc((GLenum)s->depth_func);
    gl->CullFace((GLenum)s->cull_face);
    gl->FrontFace((GLenum)s->front_face);
    gl->BlendFuncSeparate((GLenum)s->blend_func[0], (GLenum)s->blend_func[1], (GLenum)s->blend_func[2],
                          (GLenum)s->blend_func[3]);
    gl->UseProgram((GLuint)s->program);
    for (int u = 0; u < units(r); u++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->BindTexture(GL_TEXTURE_2D, (GLuint)s->texture_2d[u]);
    }
    gl->ActiveTexture((GLenum)s->active_texture);
    for (int i = 0; i < pointed_attribs(r); i++) {
        const ht_gl_es_attrib *a = &s->attribs[i];
        gl->BindBuffer(GL_ARRAY_BUFFER, (GLuint)a->buffer);
        gl->VertexAttribPointer((GLuint)i, a->size, (GLenum)a->type, (GLboolean)a->normalized, a->stride, a->pointer);
    }
    for (int i = 0; i < r->vertex_attribs; i++) {
        if (s->attrib_enabled[i]) gl->EnableVertexAttribArray((GLuint)i);
        else gl->DisableVertexAttribArray((GLuint)i);
    }
    gl->BindBuffer(GL_ARRAY_BUFFER, (GLuint)s->array_buffer);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, (GLuint)s->element_buffer);
    if (gl->has_vao && r->caps.gl_major >= 3) gl->BindVertexArray((GLuint)s->vao);
}

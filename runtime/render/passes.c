/* passes.c — Scheuermann's four passes (docs/DESIGN.md "Passes and sort
   order"): the fixed depth/cull/blend/alpha state of each, the loop that
   hands each (sub-)pass to the backend and draws, and the trace read back
   from GL. Once, here, so every tier draws the same passes. */
#include <stdint.h>

#include "caps.h"
#include "gl_error.h"
#include "errfmt.h"
#include "index_chunks.h"
#include "renderer_internal.h"
#include "shader_interface.h"
#include <hairtier/lod.h>

#define DEFAULT_CUTOFF 0.98f

void ht_pass_alpha_rule(const ht_renderer *r, ht_pass pass, GLenum *func, float *ref) {
    /* The width rule's scaled strands all blend (lod.h says why). Per
       vertex most strands are not scaled: the reference stays the
       material's, at least HT_WIDTH_RULE_VERTEX_REF, so a fragment drawn
       opaque lost at most 1 - that of its scale. */
    const float cutoff = r->have_bundle ? r->bundle.opaque_cutoff : DEFAULT_CUTOFF;
    *ref = r->opacity_cut > 0.0f                 ? 1.0f
         : !ht_renderer_width_rule_drawn(r)      ? cutoff
         : cutoff > HT_WIDTH_RULE_VERTEX_REF     ? cutoff
                                                 : HT_WIDTH_RULE_VERTEX_REF;
    *func = pass == HT_PASS_PRIME_Z || pass == HT_PASS_OPAQUE ? GL_GEQUAL : GL_LESS;
}

/* GL ES has no alpha test: the ES texts discard against two uniforms of
   the program the backend bound (shader_interface.h). */
static void set_es_alpha(const ht_renderer *r, ht_pass pass) {
    const ht_gl *gl = &r->gl;
    GLint program = 0;
    gl->GetIntegerv(GL_CURRENT_PROGRAM, &program);
    if (!program) return;
    GLenum func;
    float ref;
    ht_pass_alpha_rule(r, pass, &func, &ref);
    GLint u_ref = gl->GetUniformLocation((GLuint)program, HT_ES_U_ALPHA_REF);
    GLint u_pass = gl->GetUniformLocation((GLuint)program, HT_ES_U_ALPHA_PASS_OPAQUE);
    if (u_ref >= 0) gl->Uniform1f(u_ref, ref);
    if (u_pass >= 0) gl->Uniform1f(u_pass, func == GL_GEQUAL ? 1.0f : 0.0f);
}

/* Under an opacity scale (the width rule, soft levels: lod.h), or with the
   mesh said to be back to front (ht_renderer_set_back_to_front), the
   caller sorted the mesh, so the back pass blends both faces in that
   order and the front pass nothing: split by facing, the far strands'
   front faces were blended over the near strands' back faces (the dense
   groom lost 16 % of its ink). */
static bool blend_in_mesh_order(const ht_renderer *r) { return r->opacity_cut > 0.0f || r->back_to_front; }

/* The fixed state of each pass; the numbers are Scheuermann's scheme. */
static void set_pass_state(ht_renderer *r, ht_pass pass) {
    const ht_gl *gl = &r->gl;
    GLenum alpha_func;
    float cutoff;
    ht_pass_alpha_rule(r, pass, &alpha_func, &cutoff);
    gl->Enable(GL_DEPTH_TEST);
    if (!ht_caps_es_programs(&r->caps)) {
        gl->Enable(GL_ALPHA_TEST);
        gl->AlphaFunc(alpha_func, cutoff);
    }
    gl->FrontFace(GL_CCW);
    switch (pass) {
    case HT_PASS_PRIME_Z:
        gl->Disable(GL_CULL_FACE);
        gl->DepthMask(GL_TRUE);
        gl->DepthFunc(GL_LESS);
        gl->ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        gl->Disable(GL_BLEND);
        break;
    case HT_PASS_OPAQUE:
        gl->Disable(GL_CULL_FACE);
        gl->DepthMask(GL_FALSE);
        gl->DepthFunc(GL_EQUAL);
        gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl->Disable(GL_BLEND);
        break;
    case HT_PASS_BACK:
    case HT_PASS_FRONT:
        gl->Enable(GL_CULL_FACE);
        gl->CullFace(pass == HT_PASS_BACK ? GL_FRONT : GL_BACK);
        if (blend_in_mesh_order(r)) {
            if (pass == HT_PASS_BACK) gl->Disable(GL_CULL_FACE);
            else gl->CullFace(GL_FRONT_AND_BACK);
        }
        gl->DepthMask(pass == HT_PASS_FRONT && !blend_in_mesh_order(r) ? GL_TRUE : GL_FALSE);
        gl->DepthFunc(GL_LESS);
        gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl->Enable(GL_BLEND);
        gl->BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        break;
    case HT_PASS_COUNT:
        break;
    }
}

/* Read back from GL, so the trace shows what was set, not what was meant. */
static void record_state(ht_renderer *r, ht_trace_entry *e) {
    const ht_gl *gl = &r->gl;
    GLint v = 0;
    GLboolean b[4] = { 0 };
    GLfloat f = 0;
    e->cull = gl->IsEnabled(GL_CULL_FACE) == GL_TRUE;
    gl->GetIntegerv(GL_CULL_FACE_MODE, &v);
    e->cull_face = (unsigned)v;
    gl->GetIntegerv(GL_DEPTH_FUNC, &v);
    e->depth_func = (unsigned)v;
    gl->GetBooleanv(GL_DEPTH_WRITEMASK, b);
    e->depth_write = b[0] == GL_TRUE;
    gl->GetBooleanv(GL_COLOR_WRITEMASK, b);
    e->color_write = b[0] || b[1] || b[2] || b[3];
    e->blend = gl->IsEnabled(GL_BLEND) == GL_TRUE;
    e->opacity_scale = 1.0f - r->opacity_cut;
    if (ht_caps_es_programs(&r->caps)) {
        /* The ES texts' discard, which the rule above set. */
        GLenum func;
        ht_pass_alpha_rule(r, e->pass, &func, &e->alpha_ref);
        e->alpha_test = true;
        e->alpha_func = func;
        return;
    }
    e->alpha_test = gl->IsEnabled(GL_ALPHA_TEST) == GL_TRUE;
    gl->GetIntegerv(GL_ALPHA_TEST_FUNC, &v);
    e->alpha_func = (unsigned)v;
    gl->GetFloatv(GL_ALPHA_TEST_REF, &f);
    e->alpha_ref = f;
}

/* Flat mode: the baseline has no texture, lighting or program; GL ES
   draws the colour with a program of the runtime's (opaque_scene_es.c). */
static bool bind_flat(ht_renderer *r, const ht_tier_frame *tf) {
    if (ht_caps_es_programs(&r->caps)) return ht_renderer_bind_flat_es(r, tf);
    r->gl.Color4f(r->flat_color[0], r->flat_color[1], r->flat_color[2], 1.0f - tf->opacity_cut);
    return true;
}

/* The index list of a chunk: an offset into the bound buffer, or the
   address in the private copy. */
static const void *indices_at(const ht_renderer *r, uint32_t first_index) {
    const size_t offset = (size_t)first_index * (r->index_type == GL_UNSIGNED_SHORT ? 2u : 4u);
    return r->caps.has_vbo ? (const void *)(uintptr_t)offset : (const void *)((const char *)r->indices + offset);
}

/* The hair, pass by pass over the draw range (the whole sorted index
   buffer unless ht_renderer_set_draw_range chose a level's; in its order,
   chunk by chunk where a split mesh has chunks): every tier draws the same
   passes and ranges; only the shading differs. */
ht_result ht_renderer_draw_passes(ht_renderer *r, const ht_tier_frame *tf) {
    const ht_gl *gl = &r->gl;
    if (!r->has_mesh || r->draw_count == 0) return HT_OK;
    const ht_index_chunk whole = { 0, r->index_count, 0 };
    const ht_index_chunk *chunks = r->chunk_count ? r->chunks : &whole;
    const uint32_t chunk_count = r->chunk_count ? r->chunk_count : 1;
    const ht_vertex *vertices = r->caps.has_vbo ? NULL : r->vertices;
    const uint32_t range_end = r->draw_first + r->draw_count;
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, r->vbo);
    ht_gl_bind_buffer(gl, GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    ht_renderer_set_arrays(r, vertices, true);

    if (r->backend) r->backend->begin_frame(r->backend_state, tf);
    ht_result result = HT_OK;
    for (int p = 0; p < HT_PASS_COUNT; p++) {
        ht_pass pass = (ht_pass)p;
        set_pass_state(r, pass);
        int subs = r->backend && r->backend->sub_passes ? r->backend->sub_passes(r->backend_state, pass) : 1;
        for (int sub = 0; sub < subs; sub++) {
            bool flat_ok = true;
            if (r->backend) r->backend->bind_pass(r->backend_state, pass, sub);
            else flat_ok = bind_flat(r, tf);
            if (ht_caps_es_programs(&r->caps)) set_es_alpha(r, pass);
            ht_trace_entry e = { .pass = pass, .sub_pass = sub };
            if (r->record_trace) record_state(r, &e);
            /* the front pass culls every face there: its vertices are not sent */
            bool draw = flat_ok && !(pass == HT_PASS_FRONT && blend_in_mesh_order(r)) &&
                        (!r->backend || !r->backend->set_arrays || r->backend->set_arrays(r->backend_state, pass, sub));
            for (uint32_t c = 0; c < chunk_count; c++) {
                /* the chunk's part of the draw range */
                const uint32_t lo = chunks[c].first_index > r->draw_first ? chunks[c].first_index : r->draw_first;
                const uint32_t chunk_end = chunks[c].first_index + chunks[c].index_count;
                const uint32_t hi = chunk_end < range_end ? chunk_end : range_end;
                if (lo >= hi) continue;
                if (chunk_count > 1) ht_renderer_set_arrays_from(r, vertices, chunks[c].first_vertex, true);
                if (draw) gl->DrawElements(GL_TRIANGLES, (GLsizei)(hi - lo), r->index_type, indices_at(r, lo));
                e.first_index = lo;
                e.index_count = hi - lo;
                e.gl_error = gl->GetError();
                if (e.gl_error != GL_NO_ERROR) {
                    ht_log_linef(r->log, r->log_user, "hairtier: pass %d.%d (%s): %s", p, sub,
                                 r->backend ? ht_tier_name(r->tier) : "flat", ht_gl_error_name(e.gl_error));
                    result = HT_ERR_GL;
                    while (gl->GetError() != GL_NO_ERROR) {}
                }
                if (r->record_trace && r->trace.count < HT_TRACE_MAX) r->trace.entries[r->trace.count++] = e;
            }
        }
    }
    if (r->backend) r->backend->end_frame(r->backend_state);
    ht_renderer_clear_arrays(r);
    return result;
}

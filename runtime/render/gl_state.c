/* gl_state.c — the application's GL state around a frame: saved,
   replaced by a known baseline, restored (hairtier.h: ht_renderer_draw
   lists what is covered and what is taken as the application left it). */
#include "gl_error.h"
#include "caps.h"
#include "errfmt.h"
#include "renderer_internal.h"

/* The units the baseline covers: every one the device has (as far as the
   profile lets the runtime see). */
static int baseline_units(const ht_renderer *r) {
    if (!r->gl.ActiveTexture) return 1;
    return r->caps.texture_units < HT_RENDERER_MAX_UNITS ? r->caps.texture_units : HT_RENDERER_MAX_UNITS;
}

/* glPushAttrib and glPushClientAttrib, the program and the matrices (read,
   not pushed: the projection and texture stacks may be only 2 deep). A full
   attribute stack is HT_ERR_GL with one line and nothing changed. */
ht_result ht_gl_state_save(ht_renderer *r, ht_gl_state *s) {
    const ht_gl *gl = &r->gl;
    const char *failed = "glPushAttrib";
    gl->PushAttrib(GL_ALL_ATTRIB_BITS);
    GLenum e = gl->GetError();
    if (e == GL_NO_ERROR) {
        failed = "glPushClientAttrib";
        gl->PushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS);
        e = gl->GetError();
        if (e != GL_NO_ERROR) gl->PopAttrib();
    }
    if (e != GL_NO_ERROR) {
        ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_draw: %s: %s (is the application's "
                     "attribute stack full?); nothing drawn", failed, ht_gl_error_name(e));
        while (gl->GetError() != GL_NO_ERROR) {}
        return HT_ERR_GL;
    }
    s->program = 0;
    if (gl->UseProgram) gl->GetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    gl->GetFloatv(GL_PROJECTION_MATRIX, s->projection);
    gl->GetFloatv(GL_MODELVIEW_MATRIX, s->modelview);
    for (int u = 0; u < baseline_units(r); u++) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->GetFloatv(GL_TEXTURE_MATRIX, s->texture[u]);
    }
    return HT_OK;
}

/* Fixed-function state the application may have left that would reach the
   hair or the head: off, or GL's initial value. Where and how deep to draw
   (viewport, scissor, stencil, clip planes, depth range, framebuffer) stay
   the application's. */
void ht_gl_state_set_baseline(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    const ht_caps *c = &r->caps;
    static const GLenum off[] = { GL_LIGHTING, GL_FOG, GL_COLOR_MATERIAL, GL_NORMALIZE, GL_POLYGON_OFFSET_FILL,
                                  GL_POLYGON_STIPPLE, GL_COLOR_LOGIC_OP, GL_BLEND, GL_ALPHA_TEST, GL_CULL_FACE };
    for (size_t i = 0; i < sizeof off / sizeof off[0]; i++) gl->Disable(off[i]);
    if (ht_caps_gl_at_least(c, 1, 4)) gl->Disable(GL_COLOR_SUM);
    gl->ShadeModel(GL_SMOOTH);
    gl->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (gl->UseProgram) gl->UseProgram(0);

    const bool cube = ht_caps_gl_at_least(c, 1, 3) || ht_caps_lists_extension(c, "GL_ARB_texture_cube_map") ||
                      ht_caps_lists_extension(c, "GL_EXT_texture_cube_map");
    const bool rectangle = ht_caps_gl_at_least(c, 3, 1) ||
                           ht_caps_lists_extension(c, "GL_ARB_texture_rectangle") ||
                           ht_caps_lists_extension(c, "GL_NV_texture_rectangle") ||
                           ht_caps_lists_extension(c, "GL_EXT_texture_rectangle");
    static const GLenum texgen[4] = { GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q };
    gl->MatrixMode(GL_TEXTURE);
    for (int u = baseline_units(r) - 1; u >= 0; u--) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->Disable(GL_TEXTURE_1D);
        gl->Disable(GL_TEXTURE_2D);
        if (c->has_3d_textures) gl->Disable(GL_TEXTURE_3D);
        if (cube) gl->Disable(GL_TEXTURE_CUBE_MAP);
        if (rectangle) gl->Disable(GL_TEXTURE_RECTANGLE);
        for (int k = 0; k < 4; k++) gl->Disable(texgen[k]);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        gl->LoadIdentity();
        if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    gl->MatrixMode(GL_MODELVIEW);

    /* No array but the renderer's own: an app's array left enabled would be
       read past its end. */
    gl->DisableClientState(GL_COLOR_ARRAY);
    gl->DisableClientState(GL_INDEX_ARRAY);
    gl->DisableClientState(GL_EDGE_FLAG_ARRAY);
    if (ht_caps_gl_at_least(c, 1, 4)) {
        gl->DisableClientState(GL_SECONDARY_COLOR_ARRAY);
        gl->DisableClientState(GL_FOG_COORD_ARRAY);
    }
    for (int i = 0; i < r->vertex_attribs; i++) gl->DisableVertexAttribArray((GLuint)i);
}

/* Reloads the matrices and program, then pops both attribute stacks (which
   bring back the matrix mode, active units, enables, bindings, arrays). */
void ht_gl_state_restore(ht_renderer *r, const ht_gl_state *s) {
    const ht_gl *gl = &r->gl;
    gl->MatrixMode(GL_TEXTURE);
    for (int u = 0; u < baseline_units(r); u++) {
        if (gl->ActiveTexture) gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->LoadMatrixf(s->texture[u]);
    }
    gl->MatrixMode(GL_PROJECTION);
    gl->LoadMatrixf(s->projection);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadMatrixf(s->modelview);
    if (gl->UseProgram) gl->UseProgram((GLuint)s->program);
    gl->PopClientAttrib();
    gl->PopAttrib();
}

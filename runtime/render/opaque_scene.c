/* opaque_scene.c — the opaque scene (the head) drawn before the hair, lit
   by plain fixed-function lighting from the frame's lights, whatever tier
   shades the hair. */
#include "renderer_internal.h"

/* The head: simple fixed-function lighting from the frame's lights. Every
   lighting parameter that shapes it is set here, not inherited. */
void ht_renderer_opaque_state(const ht_gl *gl) {
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, 0);
    ht_gl_bind_buffer(gl, GL_ELEMENT_ARRAY_BUFFER, 0);
    gl->Disable(GL_CULL_FACE);
    gl->Disable(GL_BLEND);
    gl->DepthFunc(GL_LESS);
    gl->DepthMask(GL_TRUE);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
}

void ht_renderer_draw_opaque(ht_renderer *r, const ht_mesh *m, const ht_tier_frame *f) {
    const ht_gl *gl = &r->gl;
    if (!m->vertices || !m->indices || m->index_count == 0) return;
    ht_renderer_opaque_state(gl);
    gl->Disable(GL_ALPHA_TEST);
    gl->Enable(GL_LIGHTING);
    gl->Enable(GL_NORMALIZE);
    const float ambient[4] = { 0.08f, 0.08f, 0.08f, 1 }, zero[4] = { 0, 0, 0, 1 };
    const float material[4] = { 0.55f, 0.5f, 0.45f, 1 };
    gl->LightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    gl->LightModelf(GL_LIGHT_MODEL_TWO_SIDE, 0.0f);
    if (!gl->es) gl->LightModelf(GL_LIGHT_MODEL_LOCAL_VIEWER, 0.0f); /* ES 1.x: always an infinite viewer */
    gl->Materialfv(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE, material);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_SPECULAR, zero);
    gl->Materialfv(GL_FRONT_AND_BACK, GL_EMISSION, zero);
    for (int i = 0; i < r->max_lights; i++) {
        GLenum light = GL_LIGHT0 + (GLenum)i;
        if (i >= f->light_count) {
            gl->Disable(light);
            continue;
        }
        const ht_light *l = &f->lights[i];
        /* glLightfv transforms the position by the current modelview (the view). */
        float pos[4] = { l->vector[0], l->vector[1], l->vector[2], l->type == HT_LIGHT_POINT ? 1.0f : 0.0f };
        float color[4] = { l->color[0], l->color[1], l->color[2], 1 };
        gl->Lightfv(light, GL_POSITION, pos);
        gl->Lightfv(light, GL_DIFFUSE, color);
        gl->Lightfv(light, GL_SPECULAR, zero);
        gl->Lightfv(light, GL_AMBIENT, zero);
        gl->Lightf(light, GL_SPOT_CUTOFF, 180.0f);
        gl->Lightf(light, GL_CONSTANT_ATTENUATION, 1.0f);
        gl->Lightf(light, GL_LINEAR_ATTENUATION, 0.0f);
        gl->Lightf(light, GL_QUADRATIC_ATTENUATION, 0.0f);
        gl->Enable(light);
    }
    ht_renderer_set_arrays(r, m->vertices, false);
    ht_renderer_draw_client_elements(r, m);
    ht_renderer_clear_arrays(r);
    for (int i = 0; i < HT_MAX_LIGHTS; i++) gl->Disable(GL_LIGHT0 + (GLenum)i);
    gl->Disable(GL_LIGHTING);
    gl->Disable(GL_NORMALIZE);
}

/* gl_state_es1.c — the GL-state contract of ht_renderer_draw on GL ES 1.1,
   which is fixed function without glPushAttrib: every piece of state a
   frame changes is read back before it and set again after it (as
   gl_state_es.c does for ES 2.0+). The pieces: the enables below, depth,
   cull, blend and alpha functions, masks, shade model, current colour, the
   projection, modelview and every unit's texture matrix and matrix mode,
   the lights the device has and the light model, the material, per unit
   the 2D enable and binding and the whole texture environment (combiner
   state included), the vertex, normal, colour and every unit's texture
   coordinate array, the active and client-active units and both buffer
   bindings. */
#include "caps.h"
#include "renderer_internal.h"

static const GLenum enables[HT_ES1_ENABLES] = {
    GL_DEPTH_TEST, GL_BLEND, GL_CULL_FACE, GL_POLYGON_OFFSET_FILL, GL_ALPHA_TEST, GL_LIGHTING,
    GL_COLOR_MATERIAL, GL_NORMALIZE, GL_RESCALE_NORMAL, GL_FOG, GL_COLOR_LOGIC_OP,
};
/* The baseline turns off all but the first (the frame sets the depth test). */
enum { BASELINE_OFF_FROM = 1 };

static const GLenum env_ints[HT_ES1_ENV_INTS] = {
    GL_TEXTURE_ENV_MODE, GL_COMBINE_RGB, GL_COMBINE_ALPHA, GL_SOURCE0_RGB, GL_SOURCE1_RGB, GL_SOURCE2_RGB,
    GL_SOURCE0_ALPHA, GL_SOURCE1_ALPHA, GL_SOURCE2_ALPHA, GL_OPERAND0_RGB, GL_OPERAND1_RGB, GL_OPERAND2_RGB,
    GL_OPERAND0_ALPHA, GL_OPERAND1_ALPHA, GL_OPERAND2_ALPHA,
};

/* pname and float count; positions and the spot direction last: GL
   transforms them by the modelview, which is identity while they go back. */
static const struct { GLenum pname; int n; } light_params[] = {
    { GL_AMBIENT, 4 }, { GL_DIFFUSE, 4 }, { GL_SPECULAR, 4 }, { GL_SPOT_EXPONENT, 1 }, { GL_SPOT_CUTOFF, 1 },
    { GL_CONSTANT_ATTENUATION, 1 }, { GL_LINEAR_ATTENUATION, 1 }, { GL_QUADRATIC_ATTENUATION, 1 },
    { GL_POSITION, 4 }, { GL_SPOT_DIRECTION, 3 },
};
static const struct { GLenum pname; int n; } material_params[] = {
    { GL_AMBIENT, 4 }, { GL_DIFFUSE, 4 }, { GL_SPECULAR, 4 }, { GL_EMISSION, 4 }, { GL_SHININESS, 1 },
};

static int units(const ht_renderer *r) {
    return r->caps.texture_units < HT_RENDERER_MAX_UNITS ? r->caps.texture_units : HT_RENDERER_MAX_UNITS;
}

static int lights(const ht_renderer *r) {
    return r->max_lights < HT_ES1_MAX_LIGHTS ? r->max_lights : HT_ES1_MAX_LIGHTS;
}

static void set_enabled(const ht_gl *gl, GLenum cap, GLboolean on) {
    if (on) gl->Enable(cap);
    else gl->Disable(cap);
}

/* A client array: enable, layout, buffer and pointer (the normal array's
   size is always 3: size_pname 0). */
static void save_array(const ht_gl *gl, GLenum array, GLenum size_pname, GLenum type_pname, GLenum stride_pname,
                       GLenum buffer_pname, GLenum pointer_pname, ht_gl_es1_array *a) {
    a->enabled = gl->IsEnabled(array);
    a->size = 3;
    if (size_pname) gl->GetIntegerv(size_pname, &a->size);
    gl->GetIntegerv(type_pname, &a->type);
    gl->GetIntegerv(stride_pname, &a->stride);
    gl->GetIntegerv(buffer_pname, &a->buffer);
    gl->GetPointerv(pointer_pname, &a->pointer);
}

static void restore_array(const ht_gl *gl, GLenum array, const ht_gl_es1_array *a) {
    gl->BindBuffer(GL_ARRAY_BUFFER, (GLuint)a->buffer);
    switch (array) {
    case GL_VERTEX_ARRAY: gl->VertexPointer(a->size, (GLenum)a->type, a->stride, a->pointer); break;
    case GL_NORMAL_ARRAY: gl->NormalPointer((GLenum)a->type, a->stride, a->pointer); break;
    case GL_COLOR_ARRAY: gl->ColorPointer(a->size, (GLenum)a->type, a->stride, a->pointer); break;
    default: gl->TexCoordPointer(a->size, (GLenum)a->type, a->stride, a->pointer); break;
    }
    if (a->enabled) gl->EnableClientState(array);
    else gl->DisableClientState(array);
}

void ht_gl_state_save_es1(ht_renderer *r, ht_gl_state *s) {
    const ht_gl *gl = &r->gl;
    ht_gl_es1_state *e = &s->es1;
    for (int i = 0; i < HT_ES1_ENABLES; i++) e->enabled[i] = gl->IsEnabled(enables[i]);
    gl->GetBooleanv(GL_DEPTH_WRITEMASK, &s->depth_mask);
    gl->GetBooleanv(GL_COLOR_WRITEMASK, s->color_mask);
    gl->GetIntegerv(GL_DEPTH_FUNC, &s->depth_func);
    gl->GetIntegerv(GL_CULL_FACE_MODE, &s->cull_face);
    gl->GetIntegerv(GL_FRONT_FACE, &s->front_face);
    gl->GetIntegerv(GL_BLEND_SRC, &s->blend_func[0]);
    gl->GetIntegerv(GL_BLEND_DST, &s->blend_func[1]);
    gl->GetIntegerv(GL_ALPHA_TEST_FUNC, &e->alpha_func);
    gl->GetFloatv(GL_ALPHA_TEST_REF, &e->alpha_ref);
    gl->GetIntegerv(GL_SHADE_MODEL, &e->shade_model);
    gl->GetFloatv(GL_CURRENT_COLOR, e->color);
    gl->GetIntegerv(GL_MATRIX_MODE, &e->matrix_mode);
    gl->GetFloatv(GL_PROJECTION_MATRIX, s->projection);
    gl->GetFloatv(GL_MODELVIEW_MATRIX, s->modelview);
    gl->GetFloatv(GL_LIGHT_MODEL_AMBIENT, e->model_ambient);
    gl->GetFloatv(GL_LIGHT_MODEL_TWO_SIDE, &e->two_side);
    for (int l = 0; l < lights(r); l++) {
        const GLenum light = GL_LIGHT0 + (GLenum)l;
        e->light_enabled[l] = gl->IsEnabled(light);
        GLfloat *v = e->light[l];
        for (size_t p = 0; p < sizeof light_params / sizeof light_params[0]; v += light_params[p++].n)
            gl->GetLightfv(light, light_params[p].pname, v);
    }
    GLfloat *m = e->material;
    for (size_t p = 0; p < sizeof material_params / sizeof material_params[0]; m += material_params[p++].n)
        gl->GetMaterialfv(GL_FRONT, material_params[p].pname, m);
    gl->GetIntegerv(GL_ACTIVE_TEXTURE, &s->active_texture);
    gl->GetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &e->client_texture);
    for (int u = 0; u < units(r); u++) {
        ht_gl_es1_unit *t = &e->units[u];
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        t->texture_2d = gl->IsEnabled(GL_TEXTURE_2D);
        gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &t->binding);
        gl->GetFloatv(GL_TEXTURE_MATRIX, s->texture[u]);
        for (int i = 0; i < HT_ES1_ENV_INTS; i++) gl->GetTexEnviv(GL_TEXTURE_ENV, env_ints[i], &t->env_int[i]);
        gl->GetTexEnvfv(GL_TEXTURE_ENV, GL_RGB_SCALE, &t->env_float[0]);
        gl->GetTexEnvfv(GL_TEXTURE_ENV, GL_ALPHA_SCALE, &t->env_float[1]);
        gl->GetTexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, &t->env_float[2]);
        save_array(gl, GL_TEXTURE_COORD_ARRAY, GL_TEXTURE_COORD_ARRAY_SIZE, GL_TEXTURE_COORD_ARRAY_TYPE,
                   GL_TEXTURE_COORD_ARRAY_STRIDE, GL_TEXTURE_COORD_ARRAY_BUFFER_BINDING,
                   GL_TEXTURE_COORD_ARRAY_POINTER, &t->coords);
    }
    save_array(gl, GL_VERTEX_ARRAY, GL_VERTEX_ARRAY_SIZE, GL_VERTEX_ARRAY_TYPE, GL_VERTEX_ARRAY_STRIDE,
               GL_VERTEX_ARRAY_BUFFER_BINDING, GL_VERTEX_ARRAY_POINTER, &e->vertex);
    save_array(gl, GL_NORMAL_ARRAY, 0, GL_NORMAL_ARRAY_TYPE, GL_NORMAL_ARRAY_STRIDE,
               GL_NORMAL_ARRAY_BUFFER_BINDING, GL_NORMAL_ARRAY_POINTER, &e->normal);
    save_array(gl, GL_COLOR_ARRAY, GL_COLOR_ARRAY_SIZE, GL_COLOR_ARRAY_TYPE, GL_COLOR_ARRAY_STRIDE,
               GL_COLOR_ARRAY_BUFFER_BINDING, GL_COLOR_ARRAY_POINTER, &e->color_array);
    gl->GetIntegerv(GL_ARRAY_BUFFER_BINDING, &s->array_buffer);
    gl->GetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &s->element_buffer);
}

/* gl_state.c's baseline in ES 1.1's terms (no 1D, 3D or cube targets, no
   texgen, polygon mode or stipple): what would reach the hair or the
   head is off or GL's initial value; viewport, scissor, stencil, clip
   planes, depth range and framebuffer stay the application's. */
void ht_gl_state_set_baseline_es1(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    for (int i = BASELINE_OFF_FROM; i < HT_ES1_ENABLES; i++) gl->Disable(enables[i]);
    gl->ShadeModel(GL_SMOOTH);
    gl->MatrixMode(GL_TEXTURE);
    for (int u = units(r) - 1; u >= 0; u--) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->Disable(GL_TEXTURE_2D);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        gl->LoadIdentity();
        gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    gl->MatrixMode(GL_MODELVIEW);
    gl->DisableClientState(GL_COLOR_ARRAY);
}

void ht_gl_state_restore_es1(ht_renderer *r, const ht_gl_state *s) {
    const ht_gl *gl = &r->gl;
    const ht_gl_es1_state *e = &s->es1;
    for (int i = 0; i < HT_ES1_ENABLES; i++) set_enabled(gl, enables[i], e->enabled[i]);
    gl->DepthMask(s->depth_mask);
    gl->ColorMask(s->color_mask[0], s->color_mask[1], s->color_mask[2], s->color_mask[3]);
    gl->DepthFunc((GLenum)s->depth_func);
    gl->CullFace((GLenum)s->cull_face);
    gl->FrontFace((GLenum)s->front_face);
    gl->BlendFunc((GLenum)s->blend_func[0], (GLenum)s->blend_func[1]);
    gl->AlphaFunc((GLenum)e->alpha_func, e->alpha_ref);
    gl->ShadeModel((GLenum)e->shade_model);
    gl->Color4f(e->color[0], e->color[1], e->color[2], e->color[3]);
    gl->LightModelfv(GL_LIGHT_MODEL_AMBIENT, e->model_ambient);
    gl->LightModelf(GL_LIGHT_MODEL_TWO_SIDE, e->two_side);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadIdentity(); /* the saved positions are in eye space already */
    for (int l = 0; l < lights(r); l++) {
        const GLenum light = GL_LIGHT0 + (GLenum)l;
        set_enabled(gl, light, e->light_enabled[l]);
        const GLfloat *v = e->light[l];
        for (size_t p = 0; p < sizeof light_params / sizeof light_params[0]; v += light_params[p++].n)
            gl->Lightfv(light, light_params[p].pname, v);
    }
    const GLfloat *m = e->material;
    for (size_t p = 0; p < sizeof material_params / sizeof material_params[0]; m += material_params[p++].n)
        gl->Materialfv(GL_FRONT_AND_BACK, material_params[p].pname, m);
    for (int u = 0; u < units(r); u++) {
        const ht_gl_es1_unit *t = &e->units[u];
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        set_enabled(gl, GL_TEXTURE_2D, t->texture_2d);
        gl->BindTexture(GL_TEXTURE_2D, (GLuint)t->binding);
        gl->MatrixMode(GL_TEXTURE);
        gl->LoadMatrixf(s->texture[u]);
        for (int i = 0; i < HT_ES1_ENV_INTS; i++) gl->TexEnvi(GL_TEXTURE_ENV, env_ints[i], t->env_int[i]);
        gl->TexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE, t->env_float[0]);
        gl->TexEnvf(GL_TEXTURE_ENV, GL_ALPHA_SCALE, t->env_float[1]);
        gl->TexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, &t->env_float[2]);
        restore_array(gl, GL_TEXTURE_COORD_ARRAY, &t->coords);
    }
    gl->ActiveTexture((GLenum)s->active_texture);
    gl->ClientActiveTexture((GLenum)e->client_texture);
    restore_array(gl, GL_VERTEX_ARRAY, &e->vertex);
    restore_array(gl, GL_NORMAL_ARRAY, &e->normal);
    restore_array(gl, GL_COLOR_ARRAY, &e->color_array);
    gl->BindBuffer(GL_ARRAY_BUFFER, (GLuint)s->array_buffer);
    gl->BindBuffer(GL_ELEMENT_ARRAY_BUFFER, (GLuint)s->element_buffer);
    gl->MatrixMode(GL_PROJECTION);
    gl->LoadMatrixf(s->projection);
    gl->MatrixMode(GL_MODELVIEW);
    gl->LoadMatrixf(s->modelview);
    gl->MatrixMode((GLenum)e->matrix_mode);
}

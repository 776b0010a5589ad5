/* opaque_scene_es.c — the runtime's own programs on GL ES 2.0+, which has
   no fixed function: the opaque scene (the head), lit per vertex exactly
   as opaque_scene.c's GL lighting does (the same material, global ambient
   and per-light diffuse, colour clamped per vertex, interpolated), so a
   scene's head matches desktop GL; and flat mode's one colour, alpha 1
   under the passes' alpha rule as glColor is on desktop GL. */
#include <stdio.h>
#include <stdlib.h>

#include "errfmt.h"
#include "glsl_program.h"
#include "renderer_internal.h"
#include "shader_interface.h"

/* ESSL 1.00 (ES 3.x runs it too). Light vectors as in shader_interface.h. */
#define HT_STR2(x) #x
#define HT_STR(x) HT_STR2(x)
static const char vertex_text[] =
    "#version 100\n"
    "uniform mat4 u_mvp;\n"
    "uniform vec4 u_light_vector[" HT_STR(HT_MAX_LIGHTS) "];\n"
    "uniform vec3 u_light_color[" HT_STR(HT_MAX_LIGHTS) "];\n"
    "uniform int u_light_count;\n"
    "attribute vec3 " HT_ES_ATTR_POSITION ";\n"
    "attribute vec3 " HT_ES_ATTR_NORMAL ";\n"
    "varying vec4 v_color;\n"
    "void main() {\n"
    "    gl_Position = u_mvp * vec4(" HT_ES_ATTR_POSITION ", 1.0);\n"
    "    vec3 material = vec3(0.55, 0.5, 0.45);\n"
    "    vec3 n = " HT_ES_ATTR_NORMAL ";\n"
    "    n = dot(n, n) > 0.0 ? normalize(n) : n;\n"
    "    vec3 c = vec3(0.08) * material;\n"
    "    for (int i = 0; i < " HT_STR(HT_MAX_LIGHTS) "; i++) {\n"
    "        if (i >= u_light_count) break;\n"
    "        vec3 l = u_light_vector[i].w > 0.5 ? u_light_vector[i].xyz - " HT_ES_ATTR_POSITION " : u_light_vector[i].xyz;\n"
    "        l = dot(l, l) > 0.0 ? normalize(l) : l;\n"
    "        c += u_light_color[i] * material * max(dot(n, l), 0.0);\n"
    "    }\n"
    "    v_color = vec4(clamp(c, 0.0, 1.0), 1.0);\n"
    "}\n";
static const char fragment_text[] =
    "#version 100\n"
    "precision mediump float;\n"
    "varying vec4 v_color;\n"
    "void main() { gl_FragColor = v_color; }\n";

static const char flat_vertex_text[] =
    "#version 100\n"
    "uniform mat4 u_mvp;\n"
    "attribute vec3 " HT_ES_ATTR_POSITION ";\n"
    "void main() { gl_Position = u_mvp * vec4(" HT_ES_ATTR_POSITION ", 1.0); }\n";
static const char flat_fragment_text[] =
    "#version 100\n"
    "precision mediump float;\n"
    "uniform vec3 u_color;\n"
    "uniform float " HT_ES_U_ALPHA_REF ";\n"
    "uniform float " HT_ES_U_ALPHA_PASS_OPAQUE ";\n"
    "void main() {\n"
    "    if ((1.0 >= " HT_ES_U_ALPHA_REF ") != (" HT_ES_U_ALPHA_PASS_OPAQUE " > 0.5)) discard;\n"
    "    gl_FragColor = vec4(u_color, 1.0);\n"
    "}\n";

static GLuint compile(const ht_gl *gl, GLenum stage, const char *text) {
    GLuint sh = gl->CreateShader(stage);
    if (!sh) return 0;
    gl->ShaderSource(sh, 1, &text, NULL);
    gl->CompileShader(sh);
    GLint ok = GL_FALSE;
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (ok == GL_TRUE) return sh;
    gl->DeleteShader(sh);
    return 0;
}

/* A program of two of the texts above, its attributes where the arrays
   are (mesh_gpu.c); 0 when it does not build. */
static GLuint program_of(const ht_gl *gl, const char *vertex, const char *fragment) {
    GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex), fs = compile(gl, GL_FRAGMENT_SHADER, fragment);
    GLuint prog = vs && fs ? gl->CreateProgram() : 0;
    if (prog) {
        gl->AttachShader(prog, vs);
        gl->AttachShader(prog, fs);
        gl->BindAttribLocation(prog, HT_ES_ATTR_POSITION_LOCATION, HT_ES_ATTR_POSITION);
        gl->BindAttribLocation(prog, HT_ES_ATTR_NORMAL_LOCATION, HT_ES_ATTR_NORMAL);
        gl->LinkProgram(prog);
        GLint ok = GL_FALSE;
        gl->GetProgramiv(prog, GL_LINK_STATUS, &ok);
        if (ok != GL_TRUE) {
            gl->DeleteProgram(prog);
            prog = 0;
        }
    }
    if (vs) gl->DeleteShader(vs);
    if (fs) gl->DeleteShader(fs);
    return prog;
}

static bool build(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    GLuint prog = program_of(gl, vertex_text, fragment_text);
    if (!prog) {
        ht_log_linef(r->log, r->log_user, "hairtier: the opaque scene's GL ES program did not build; no head drawn");
        r->opaque_failed = true;
        return false;
    }
    r->opaque_program = prog;
    r->opaque_u_mvp = gl->GetUniformLocation(prog, HT_ES_U_MVP);
    r->opaque_u_light_vector = gl->GetUniformLocation(prog, HT_U_LIGHT_VECTOR);
    r->opaque_u_light_color = gl->GetUniformLocation(prog, HT_U_LIGHT_COLOR);
    r->opaque_u_light_count = gl->GetUniformLocation(prog, "u_light_count");
    return true;
}

void ht_renderer_release_opaque_es(ht_renderer *r) {
    if (r->opaque_program) r->gl.DeleteProgram(r->opaque_program);
    if (r->flat_program) r->gl.DeleteProgram(r->flat_program);
    r->opaque_program = r->flat_program = 0;
}

bool ht_renderer_bind_flat_es(ht_renderer *r, const ht_tier_frame *f) {
    const ht_gl *gl = &r->gl;
    if (!r->flat_program && !(r->flat_program = program_of(gl, flat_vertex_text, flat_fragment_text))) {
        ht_log_linef(r->log, r->log_user, "hairtier: flat: the GL ES program did not build");
        return false;
    }
    float mvp[16];
    ht_glsl_mvp(f, mvp);
    gl->UseProgram(r->flat_program);
    gl->UniformMatrix4fv(gl->GetUniformLocation(r->flat_program, HT_ES_U_MVP), 1, GL_FALSE, mvp);
    gl->Uniform3fv(gl->GetUniformLocation(r->flat_program, "u_color"), 1, r->flat_color);
    return true;
}

void ht_renderer_draw_opaque_es(ht_renderer *r, const ht_mesh *m, const ht_tier_frame *f) {
    const ht_gl *gl = &r->gl;
    if (!m->vertices || !m->indices || m->index_count == 0 || r->opaque_failed) return;
    if (!r->opaque_program && !build(r)) return;
    ht_renderer_opaque_state(gl);
    gl->UseProgram(r->opaque_program);
    float vectors[HT_MAX_LIGHTS * 4] = { 0 }, colors[HT_MAX_LIGHTS * 3] = { 0 };
    for (int i = 0; i < f->light_count && i < HT_MAX_LIGHTS; i++) {
        const ht_light *l = &f->lights[i];
        for (int k = 0; k < 3; k++) {
            vectors[4 * i + k] = l->vector[k];
            colors[3 * i + k] = l->color[k];
        }
        vectors[4 * i + 3] = l->type == HT_LIGHT_POINT ? 1.0f : 0.0f;
    }
    float mvp[16];
    ht_glsl_mvp(f, mvp);
    gl->UniformMatrix4fv(r->opaque_u_mvp, 1, GL_FALSE, mvp);
    gl->Uniform4fv(r->opaque_u_light_vector, HT_MAX_LIGHTS, vectors);
    gl->Uniform3fv(r->opaque_u_light_color, HT_MAX_LIGHTS, colors);
    gl->Uniform1i(r->opaque_u_light_count, f->light_count);
    ht_renderer_set_arrays(r, m->vertices, false);
    ht_renderer_draw_client_elements(r, m);
    ht_renderer_clear_arrays(r);
    gl->UseProgram(0);
}

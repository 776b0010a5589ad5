/* gl_api.h — the GL entry points libhairtier calls, loaded glad-style into a
   struct of function pointers from the caller's getproc (so the library links
   against no GL library and works on any context the app made current).

   Usage:
       ht_gl gl;
       char err[256];
       if (ht_gl_load(&gl, getproc, err, sizeof err) != HT_OK) ...; // GL 1.1 missing
       gl.Enable(GL_DEPTH_TEST);
       if (gl.has_vbo) gl.GenBuffers(1, &vbo);

   GL 1.1 entry points are required (OSMesaGetProcAddress, wglGetProcAddress
   wrappers and eglGetProcAddress with core-symbol lookup return them), the
   fixed-function and desktop-only ones on desktop GL only (gl.es). Every later group is
   optional: a group whose entry point is missing is cleared
   (its has_ flag is false, its pointers NULL) instead of failing the load.
   ARB-suffixed names are tried when the core name is missing.
   Whether the context's version allows a group is decided by caps.c. */
#ifndef HT_GL_API_H
#define HT_GL_API_H

#include <stdbool.h>
#include <stddef.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include <hairtier/hairtier.h>

/* X(group, return type, Name without "gl", parameter list) */
#define HT_GL_FUNCTIONS(X) \
    X(core, const GLubyte *, GetString, (GLenum name)) \
    X(core, void, GetIntegerv, (GLenum pname, GLint *data)) \
    X(core, void, GetFloatv, (GLenum pname, GLfloat *data)) \
    X(core, void, GetBooleanv, (GLenum pname, GLboolean *data)) \
    X(core, GLenum, GetError, (void)) \
    X(core, void, Finish, (void)) \
    X(core, void, Enable, (GLenum cap)) \
    X(core, void, Disable, (GLenum cap)) \
    X(core, GLboolean, IsEnabled, (GLenum cap)) \
    X(core, void, DepthFunc, (GLenum func)) \
    X(core, void, DepthMask, (GLboolean flag)) \
    X(core, void, ColorMask, (GLboolean r, GLboolean g, GLboolean b, GLboolean a)) \
    X(core, void, CullFace, (GLenum mode)) \
    X(core, void, FrontFace, (GLenum mode)) \
    X(fixed, void, AlphaFunc, (GLenum func, GLfloat ref)) \
    X(core, void, BlendFunc, (GLenum sfactor, GLenum dfactor)) \
    X(fixed, void, MatrixMode, (GLenum mode)) \
    X(fixed, void, LoadMatrixf, (const GLfloat *m)) \
    X(fixed, void, LoadIdentity, (void)) \
    X(fixed, void, EnableClientState, (GLenum array)) \
    X(fixed, void, DisableClientState, (GLenum array)) \
    X(fixed, void, VertexPointer, (GLint size, GLenum type, GLsizei stride, const void *ptr)) \
    X(fixed, void, NormalPointer, (GLenum type, GLsizei stride, const void *ptr)) \
    X(fixed, void, TexCoordPointer, (GLint size, GLenum type, GLsizei stride, const void *ptr)) \
    X(fixed, void, ColorPointer, (GLint size, GLenum type, GLsizei stride, const void *ptr)) \
    X(core, void, DrawElements, (GLenum mode, GLsizei count, GLenum type, const void *indices)) \
    X(fixed, void, Color4f, (GLfloat r, GLfloat g, GLfloat b, GLfloat a)) \
    X(fixed, void, Lightfv, (GLenum light, GLenum pname, const GLfloat *params)) \
    X(fixed, void, LightModelfv, (GLenum pname, const GLfloat *params)) \
    X(fixed, void, Materialfv, (GLenum face, GLenum pname, const GLfloat *params)) \
    X(desktop, void, ColorMaterial, (GLenum face, GLenum mode)) \
    X(fixed, void, Lightf, (GLenum light, GLenum pname, GLfloat param)) \
    X(fixed, void, LightModelf, (GLenum pname, GLfloat param)) \
    X(fixed, void, GetLightfv, (GLenum light, GLenum pname, GLfloat *params)) \
    X(fixed, void, GetMaterialfv, (GLenum face, GLenum pname, GLfloat *params)) \
    X(fixed, void, GetTexEnviv, (GLenum target, GLenum pname, GLint *params)) \
    X(fixed, void, GetTexEnvfv, (GLenum target, GLenum pname, GLfloat *params)) \
    X(fixed, void, GetPointerv, (GLenum pname, void **params)) \
    X(desktop, void, PolygonMode, (GLenum face, GLenum mode)) \
    X(desktop, void, PushAttrib, (GLbitfield mask)) \
    X(desktop, void, PopAttrib, (void)) \
    X(desktop, void, PushClientAttrib, (GLbitfield mask)) \
    X(desktop, void, PopClientAttrib, (void)) \
    X(fixed, void, ShadeModel, (GLenum mode)) \
    X(core, void, GenTextures, (GLsizei n, GLuint *textures)) \
    X(core, void, DeleteTextures, (GLsizei n, const GLuint *textures)) \
    X(core, void, BindTexture, (GLenum target, GLuint texture)) \
    X(core, void, TexImage2D, (GLenum target, GLint level, GLint internalformat, GLsizei w, GLsizei h, GLint border, GLenum format, GLenum type, const void *pixels)) \
    X(core, void, TexParameteri, (GLenum target, GLenum pname, GLint param)) \
    X(fixed, void, TexEnvi, (GLenum target, GLenum pname, GLint param)) \
    X(fixed, void, TexEnvf, (GLenum target, GLenum pname, GLfloat param)) \
    X(fixed, void, TexEnvfv, (GLenum target, GLenum pname, const GLfloat *params)) \
    X(core, void, PixelStorei, (GLenum pname, GLint param)) \
    X(tex3d, void, TexImage3D, (GLenum target, GLint level, GLint internalformat, GLsizei w, GLsizei h, GLsizei d, GLint border, GLenum format, GLenum type, const void *pixels)) \
    X(multitexture, void, ActiveTexture, (GLenum texture)) \
    X(client_units, void, ClientActiveTexture, (GLenum texture)) \
    X(vbo, void, GenBuffers, (GLsizei n, GLuint *buffers)) \
    X(vbo, void, DeleteBuffers, (GLsizei n, const GLuint *buffers)) \
    X(vbo, void, BindBuffer, (GLenum target, GLuint buffer)) \
    X(vbo, void, BufferData, (GLenum target, GLsizeiptr size, const void *data, GLenum usage)) \
    X(vbo, void, BufferSubData, (GLenum target, GLintptr offset, GLsizeiptr size, const void *data)) \
    X(shaders, GLuint, CreateShader, (GLenum type)) \
    X(shaders, void, ShaderSource, (GLuint shader, GLsizei count, const GLchar *const *string, const GLint *length)) \
    X(shaders, void, CompileShader, (GLuint shader)) \
    X(shaders, void, GetShaderiv, (GLuint shader, GLenum pname, GLint *params)) \
    X(shaders, void, GetShaderInfoLog, (GLuint shader, GLsizei size, GLsizei *length, GLchar *log)) \
    X(shaders, void, DeleteShader, (GLuint shader)) \
    X(shaders, GLuint, CreateProgram, (void)) \
    X(shaders, void, AttachShader, (GLuint program, GLuint shader)) \
    X(shaders, void, BindAttribLocation, (GLuint program, GLuint index, const GLchar *name)) \
    X(shaders, void, LinkProgram, (GLuint program)) \
    X(shaders, void, GetProgramiv, (GLuint program, GLenum pname, GLint *params)) \
    X(shaders, void, GetProgramInfoLog, (GLuint program, GLsizei size, GLsizei *length, GLchar *log)) \
    X(shaders, void, DeleteProgram, (GLuint program)) \
    X(shaders, void, UseProgram, (GLuint program)) \
    X(shaders, GLint, GetUniformLocation, (GLuint program, const GLchar *name)) \
    X(shaders, void, Uniform1i, (GLint location, GLint v0)) \
    X(shaders, void, Uniform1f, (GLint location, GLfloat v0)) \
    X(shaders, void, Uniform3fv, (GLint location, GLsizei count, const GLfloat *value)) \
    X(shaders, void, Uniform4fv, (GLint location, GLsizei count, const GLfloat *value)) \
    X(shaders, void, UniformMatrix4fv, (GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(shaders, void, VertexAttribPointer, (GLuint index, GLint size, GLenum type, GLboolean normalized, GLsizei stride, const void *ptr)) \
    X(shaders, void, EnableVertexAttribArray, (GLuint index)) \
    X(shaders, void, DisableVertexAttribArray, (GLuint index)) \
    X(shaders, void, GetVertexAttribiv, (GLuint index, GLenum pname, GLint *params)) \
    X(shaders, void, GetVertexAttribPointerv, (GLuint index, GLenum pname, void **pointer)) \
    X(shaders, void, BlendFuncSeparate, (GLenum src_rgb, GLenum dst_rgb, GLenum src_alpha, GLenum dst_alpha)) \
    X(stringi, const GLubyte *, GetStringi, (GLenum name, GLuint index)) \
    X(precision, void, GetShaderPrecisionFormat, (GLenum shader, GLenum type, GLint *range, GLint *precision)) \
    X(vao, void, BindVertexArray, (GLuint array))

typedef struct ht_gl {
#define HT_GL_MEMBER(group, ret, name, args) ret (APIENTRYP name) args;
    HT_GL_FUNCTIONS(HT_GL_MEMBER)
#undef HT_GL_MEMBER
    /* entry points present (not: allowed by the context's version) */
    bool has_tex3d, has_multitexture, has_vbo, has_shaders, has_stringi, has_precision, has_vao;
    /* An OpenGL ES context (GL_VERSION "OpenGL ES ..."): the fixed-function
       group (GL 1.1's matrices, lighting, client arrays, alpha test,
       texture environments) is optional there (has_fixed: all of it
       present; ES 1.x draws with it, ES 2.0 on never calls it), and the
       desktop group (attribute stacks, glPolygonMode, glColorMaterial) is
       never called on ES; everywhere else both are required. */
    bool es, has_fixed;
} ht_gl;

/* Fills gl from getproc. HT_ERR_UNSUPPORTED when a GL 1.1 entry point is
   missing (err names it); optional groups are cleared, never an error. */
ht_result ht_gl_load(ht_gl *gl, ht_getproc_fn getproc, char *err, size_t err_size);

/* Drops the groups the context may not use (caps.c decides from versions and
   extensions): their pointers become NULL, their flag false. */
void ht_gl_restrict(ht_gl *gl, bool tex3d, bool multitexture, bool vbo, bool shaders);

/* The one place buffer-object bindings are made or read. Without buffer
   objects GL reads every array from client memory, which is what binding 0
   means: buffer must be 0 there, and nothing is called. */
static inline void ht_gl_bind_buffer(const ht_gl *gl, GLenum target, GLuint buffer) {
    if (gl->has_vbo) gl->BindBuffer(target, buffer);
}
static inline GLuint ht_gl_array_buffer_binding(const ht_gl *gl) {
    GLint bound = 0;
    if (gl->has_vbo) gl->GetIntegerv(GL_ARRAY_BUFFER_BINDING, &bound);
    return (GLuint)bound;
}

#endif

/* support_gl_fault.c — see support_gl_fault.h. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_api.h"
#include "support_gl_fault.h"
#include "support_osmesa.h"

/* The arguments of each entry point, by the names gl_api.h gives them:
   a wrapper forwards them. An entry point added to HT_GL_FUNCTIONS without
   a line here fails to compile. */
#define ARGS_GetString name
#define ARGS_GetIntegerv pname, data
#define ARGS_GetFloatv pname, data
#define ARGS_GetBooleanv pname, data
#define ARGS_GetError
#define ARGS_Finish
#define ARGS_Enable cap
#define ARGS_Disable cap
#define ARGS_IsEnabled cap
#define ARGS_DepthFunc func
#define ARGS_DepthMask flag
#define ARGS_ColorMask r, g, b, a
#define ARGS_CullFace mode
#define ARGS_FrontFace mode
#define ARGS_AlphaFunc func, ref
#define ARGS_BlendFunc sfactor, dfactor
#define ARGS_MatrixMode mode
#define ARGS_LoadMatrixf m
#define ARGS_LoadIdentity
#define ARGS_EnableClientState array
#define ARGS_DisableClientState array
#define ARGS_VertexPointer size, type, stride, ptr
#define ARGS_NormalPointer type, stride, ptr
#define ARGS_TexCoordPointer size, type, stride, ptr
#define ARGS_ColorPointer size, type, stride, ptr
#define ARGS_DrawElements mode, count, type, indices
#define ARGS_Color4f r, g, b, a
#define ARGS_Lightfv light, pname, params
#define ARGS_LightModelfv pname, params
#define ARGS_Materialfv face, pname, params
#define ARGS_ColorMaterial face, mode
#define ARGS_Lightf light, pname, param
#define ARGS_LightModelf pname, param
#define ARGS_GetLightfv light, pname, params
#define ARGS_GetMaterialfv face, pname, params
#define ARGS_GetTexEnviv target, pname, params
#define ARGS_GetTexEnvfv target, pname, params
#define ARGS_GetPointerv pname, params
#define ARGS_PolygonMode face, mode
#define ARGS_PushAttrib mask
#define ARGS_PopAttrib
#define ARGS_PushClientAttrib mask
#define ARGS_PopClientAttrib
#define ARGS_ShadeModel mode
#define ARGS_GenTextures n, textures
#define ARGS_DeleteTextures n, textures
#define ARGS_BindTexture target, texture
#define ARGS_TexImage2D target, level, internalformat, w, h, border, format, type, pixels
#define ARGS_TexParameteri target, pname, param
#define ARGS_TexEnvi target, pname, param
#define ARGS_TexEnvf target, pname, param
#define ARGS_TexEnvfv target, pname, params
#define ARGS_PixelStorei pname, param
#define ARGS_TexImage3D target, level, internalformat, w, h, d, border, format, type, pixels
#define ARGS_ActiveTexture texture
#define ARGS_ClientActiveTexture texture
#define ARGS_GenBuffers n, buffers
#define ARGS_DeleteBuffers n, buffers
#define ARGS_BindBuffer target, buffer
#define ARGS_BufferData target, size, data, usage
#define ARGS_BufferSubData target, offset, size, data
#define ARGS_CreateShader type
#define ARGS_ShaderSource shader, count, string, length
#define ARGS_CompileShader shader
#define ARGS_GetShaderiv shader, pname, params
#define ARGS_GetShaderInfoLog shader, size, length, log
#define ARGS_DeleteShader shader
#define ARGS_CreateProgram
#define ARGS_AttachShader program, shader
#define ARGS_BindAttribLocation program, index, name
#define ARGS_LinkProgram program
#define ARGS_GetProgramiv program, pname, params
#define ARGS_GetProgramInfoLog program, size, length, log
#define ARGS_DeleteProgram program
#define ARGS_UseProgram program
#define ARGS_GetUniformLocation program, name
#define ARGS_Uniform1i location, v0
#define ARGS_Uniform1f location, v0
#define ARGS_Uniform3fv location, count, value
#define ARGS_Uniform4fv location, count, value
#define ARGS_UniformMatrix4fv location, count, transpose, value
#define ARGS_VertexAttribPointer index, size, type, normalized, stride, ptr
#define ARGS_EnableVertexAttribArray index
#define ARGS_DisableVertexAttribArray index
#define ARGS_GetStringi name, index
#define ARGS_GetVertexAttribiv index, pname, params
#define ARGS_GetVertexAttribPointerv index, pname, pointer
#define ARGS_BlendFuncSeparate src_rgb, dst_rgb, src_alpha, dst_alpha
#define ARGS_GetShaderPrecisionFormat shader, type, range, precision
#define ARGS_BindVertexArray array

static ht_fault_state st;
static GLenum pending;   /* an injected error the next glGetError reports */

#define MAX_NAMES 4096
static GLuint live_names[HT_FAULT_OBJECT_COUNT][MAX_NAMES];
/* shaders whose compile, programs whose link, was made to fail */
static GLuint failed_shaders[64], failed_programs[64];
static int failed_shader_count, failed_program_count;

void ht_fault_arm(ht_fault_class cls, long n) {
    int live[HT_FAULT_OBJECT_COUNT];
    memcpy(live, st.live, sizeof live);
    memset(&st, 0, sizeof st);
    memcpy(st.live, live, sizeof live);
    st.armed = cls;
    st.at = cls == HT_FAULT_NONE ? 0 : n;
    pending = GL_NO_ERROR;
}

const ht_fault_state *ht_fault_state_get(void) { return &st; }

int ht_fault_live_total(void) {
    int n = 0;
    for (int k = 0; k < HT_FAULT_OBJECT_COUNT; k++) n += st.live[k];
    return n;
}

const char *ht_fault_class_name(ht_fault_class cls) {
    static const char *const names[HT_FAULT_CLASS_COUNT] = { "none", "shader compile", "program link",
                                                             "texture upload", "buffer upload",
                                                             "GL_OUT_OF_MEMORY at any call" };
    return cls >= 0 && cls < HT_FAULT_CLASS_COUNT ? names[cls] : "?";
}

const char *ht_fault_object_name(ht_fault_object kind) {
    static const char *const names[HT_FAULT_OBJECT_COUNT] = { "textures", "buffers", "shaders", "programs" };
    return kind >= 0 && kind < HT_FAULT_OBJECT_COUNT ? names[kind] : "?";
}

/* Counts a call of cls; true when it is the armed one (which fires once). */
static bool hit(ht_fault_class cls) {
    long n = ++st.calls[cls];
    if (st.armed != cls || st.fired || n != st.at) return false;
    st.fired = true;
    return true;
}

/* Every call but glGetError's. */
static void any_call(void) {
    if (hit(HT_FAULT_ANY_CALL)) pending = GL_OUT_OF_MEMORY;
}

static void name_made(ht_fault_object kind, GLuint name) {
    if (!name) return;
    if (st.live[kind] >= MAX_NAMES) {
        fprintf(stderr, "support_gl_fault: more than %d live %s\n", MAX_NAMES, ht_fault_object_name(kind));
        abort();
    }
    live_names[kind][st.live[kind]++] = name;
    st.created[kind]++;
}

static void name_deleted(ht_fault_object kind, GLuint name) {
    if (!name) return;
    for (int i = 0; i < st.live[kind]; i++)
        if (live_names[kind][i] == name) {
            live_names[kind][i] = live_names[kind][--st.live[kind]];
            st.deleted[kind]++;
            return;
        }
    st.stray_deletes++;
}

static bool in_list(const GLuint *list, int count, GLuint name) {
    for (int i = 0; i < count; i++)
        if (list[i] == name) return true;
    return false;
}

static void list_add(GLuint *list, int *count, int cap, GLuint name) {
    if (name && !in_list(list, *count, name) && *count < cap) list[(*count)++] = name;
}

static void list_remove(GLuint *list, int *count, GLuint name) {
    for (int i = 0; i < *count; i++)
        if (list[i] == name) {
            list[i] = list[--*count];
            return;
        }
}

/* The driver's entry points. */
#define REAL(group, ret, name, params) static ret (APIENTRYP real_##name) params;
HT_GL_FUNCTIONS(REAL)
#undef REAL

/* The plain wrappers: count the call, forward. */
#define FORWARD(group, ret, name, params) \
    static ret APIENTRY fwd_##name params { any_call(); return real_##name(ARGS_##name); }
HT_GL_FUNCTIONS(FORWARD)
#undef FORWARD

/* ---- the wrappers that do more ---- */

static GLenum APIENTRY wrap_GetError(void) {
    GLenum e = pending;
    pending = GL_NO_ERROR;
    return e != GL_NO_ERROR ? e : real_GetError();
}

static void APIENTRY wrap_GenTextures(GLsizei n, GLuint *names) {
    any_call();
    real_GenTextures(n, names);
    for (GLsizei i = 0; i < n; i++) name_made(HT_FAULT_TEXTURES, names[i]);
}

static void APIENTRY wrap_DeleteTextures(GLsizei n, const GLuint *names) {
    any_call();
    for (GLsizei i = 0; i < n; i++) name_deleted(HT_FAULT_TEXTURES, names[i]);
    real_DeleteTextures(n, names);
}

static void APIENTRY wrap_GenBuffers(GLsizei n, GLuint *names) {
    any_call();
    real_GenBuffers(n, names);
    for (GLsizei i = 0; i < n; i++) name_made(HT_FAULT_BUFFERS, names[i]);
}

static void APIENTRY wrap_DeleteBuffers(GLsizei n, const GLuint *names) {
    any_call();
    for (GLsizei i = 0; i < n; i++) name_deleted(HT_FAULT_BUFFERS, names[i]);
    real_DeleteBuffers(n, names);
}

static GLuint APIENTRY wrap_CreateShader(GLenum type) {
    any_call();
    GLuint name = real_CreateShader(type);
    name_made(HT_FAULT_SHADERS, name);
    return name;
}

static void APIENTRY wrap_DeleteShader(GLuint shader) {
    any_call();
    name_deleted(HT_FAULT_SHADERS, shader);
    list_remove(failed_shaders, &failed_shader_count, shader);
    real_DeleteShader(shader);
}

static GLuint APIENTRY wrap_CreateProgram(void) {
    any_call();
    GLuint name = real_CreateProgram();
    name_made(HT_FAULT_PROGRAMS, name);
    return name;
}

static void APIENTRY wrap_DeleteProgram(GLuint program) {
    any_call();
    name_deleted(HT_FAULT_PROGRAMS, program);
    list_remove(failed_programs, &failed_program_count, program);
    real_DeleteProgram(program);
}

static void APIENTRY wrap_CompileShader(GLuint shader) {
    any_call();
    real_CompileShader(shader);
    if (hit(HT_FAULT_COMPILE)) list_add(failed_shaders, &failed_shader_count, 64, shader);
}

/* An info log answered from text: GL's rules for size, length and the NUL. */
static void answer_log(const char *text, GLsizei size, GLsizei *length, GLchar *out) {
    GLsizei n = (GLsizei)strlen(text);
    if (size <= 0) {
        if (length) *length = 0;
        return;
    }
    if (n > size - 1) n = size - 1;
    memcpy(out, text, (size_t)n);
    out[n] = '\0';
    if (length) *length = n;
}

static void APIENTRY wrap_GetShaderiv(GLuint shader, GLenum pname, GLint *params) {
    any_call();
    real_GetShaderiv(shader, pname, params);
    if (!in_list(failed_shaders, failed_shader_count, shader)) return;
    if (pname == GL_COMPILE_STATUS) *params = GL_FALSE;
    if (pname == GL_INFO_LOG_LENGTH) *params = (GLint)sizeof HT_FAULT_COMPILE_LOG;
}

static void APIENTRY wrap_GetShaderInfoLog(GLuint shader, GLsizei size, GLsizei *length, GLchar *log) {
    any_call();
    if (in_list(failed_shaders, failed_shader_count, shader)) answer_log(HT_FAULT_COMPILE_LOG, size, length, log);
    else real_GetShaderInfoLog(shader, size, length, log);
}

static void APIENTRY wrap_LinkProgram(GLuint program) {
    any_call();
    real_LinkProgram(program);
    if (hit(HT_FAULT_LINK)) list_add(failed_programs, &failed_program_count, 64, program);
}

static void APIENTRY wrap_GetProgramiv(GLuint program, GLenum pname, GLint *params) {
    any_call();
    real_GetProgramiv(program, pname, params);
    if (!in_list(failed_programs, failed_program_count, program)) return;
    if (pname == GL_LINK_STATUS) *params = GL_FALSE;
    if (pname == GL_INFO_LOG_LENGTH) *params = (GLint)sizeof HT_FAULT_LINK_LOG;
}

static void APIENTRY wrap_GetProgramInfoLog(GLuint program, GLsizei size, GLsizei *length, GLchar *log) {
    any_call();
    if (in_list(failed_programs, failed_program_count, program)) answer_log(HT_FAULT_LINK_LOG, size, length, log);
    else real_GetProgramInfoLog(program, size, length, log);
}

static void APIENTRY wrap_TexImage2D(GLenum target, GLint level, GLint internalformat, GLsizei w, GLsizei h,
                                     GLint border, GLenum format, GLenum type, const void *pixels) {
    any_call();
    if (hit(HT_FAULT_TEX_IMAGE)) {
        pending = GL_OUT_OF_MEMORY;
        return;
    }
    real_TexImage2D(target, level, internalformat, w, h, border, format, type, pixels);
}

static void APIENTRY wrap_TexImage3D(GLenum target, GLint level, GLint internalformat, GLsizei w, GLsizei h,
                                     GLsizei d, GLint border, GLenum format, GLenum type, const void *pixels) {
    any_call();
    if (hit(HT_FAULT_TEX_IMAGE)) {
        pending = GL_OUT_OF_MEMORY;
        return;
    }
    real_TexImage3D(target, level, internalformat, w, h, d, border, format, type, pixels);
}

/* Vertex arrays: whether each pointer names buffer memory or client
   memory (no buffer bound to GL_ARRAY_BUFFER). GL_ARRAY_BUFFER_BINDING is
   asked only once the runtime has bound a buffer (the context has them);
   before that every array is client memory. */
static bool buffers_seen;

static void array_pointer_set(void) {
    GLint bound = 0;
    if (buffers_seen) real_GetIntegerv(GL_ARRAY_BUFFER_BINDING, &bound);
    st.array_pointers++;
    if (!bound) st.client_array_pointers++;
}

static void APIENTRY wrap_BindBuffer(GLenum target, GLuint buffer) {
    any_call();
    buffers_seen = true;
    real_BindBuffer(target, buffer);
}

#define POINTER_WRAPPER(name, params)                  \
    static void APIENTRY wrap_##name params {          \
        any_call();                                    \
        array_pointer_set();                           \
        real_##name(ARGS_##name);                      \
    }
POINTER_WRAPPER(VertexPointer, (GLint size, GLenum type, GLsizei stride, const void *ptr))
POINTER_WRAPPER(NormalPointer, (GLenum type, GLsizei stride, const void *ptr))
POINTER_WRAPPER(TexCoordPointer, (GLint size, GLenum type, GLsizei stride, const void *ptr))
POINTER_WRAPPER(ColorPointer, (GLint size, GLenum type, GLsizei stride, const void *ptr))
POINTER_WRAPPER(VertexAttribPointer,
                (GLuint index, GLint size, GLenum type, GLboolean normalized, GLsizei stride, const void *ptr))
#undef POINTER_WRAPPER

static void APIENTRY wrap_BufferData(GLenum target, GLsizeiptr size, const void *data, GLenum usage) {
    any_call();
    if (hit(HT_FAULT_BUFFER_DATA)) {
        pending = GL_OUT_OF_MEMORY;
        return;
    }
    real_BufferData(target, size, data, usage);
}

/* An upload too: the same class, counted apart as well. */
static void APIENTRY wrap_BufferSubData(GLenum target, GLintptr offset, GLsizeiptr size, const void *data) {
    any_call();
    st.buffer_sub_data++;
    if (hit(HT_FAULT_BUFFER_DATA)) {
        pending = GL_OUT_OF_MEMORY;
        return;
    }
    real_BufferSubData(target, offset, size, data);
}

/* Which tier draws: a program bound, or a combiner stage set up. */
static void APIENTRY wrap_UseProgram(GLuint program) {
    any_call();
    if (program) st.programs_bound++;
    real_UseProgram(program);
}

static void APIENTRY wrap_TexEnvi(GLenum target, GLenum pname, GLint param) {
    any_call();
    if (pname == GL_TEXTURE_ENV_MODE && param == GL_COMBINE) st.combiner_stages++;
    real_TexEnvi(target, pname, param);
}

/* ---- the getproc ---- */

typedef struct wrapper {
    const char *name;   /* without "gl" */
    void (*fn)(void);   /* cast back by the caller to the entry point's type */
    void *real;         /* where the driver's pointer goes */
} wrapper;

#define SPECIAL(name) { #name, (void (*)(void))wrap_##name, &real_##name },
static const wrapper specials[] = {
    SPECIAL(GetError) SPECIAL(GenTextures) SPECIAL(DeleteTextures) SPECIAL(GenBuffers) SPECIAL(DeleteBuffers)
    SPECIAL(CreateShader) SPECIAL(DeleteShader) SPECIAL(CreateProgram) SPECIAL(DeleteProgram)
    SPECIAL(CompileShader) SPECIAL(GetShaderiv) SPECIAL(GetShaderInfoLog) SPECIAL(LinkProgram)
    SPECIAL(GetProgramiv) SPECIAL(GetProgramInfoLog) SPECIAL(TexImage2D) SPECIAL(TexImage3D)
    SPECIAL(BufferData) SPECIAL(BindBuffer) SPECIAL(VertexPointer) SPECIAL(NormalPointer) SPECIAL(TexCoordPointer)
    SPECIAL(ColorPointer) SPECIAL(VertexAttribPointer) SPECIAL(UseProgram) SPECIAL(TexEnvi) SPECIAL(BufferSubData)
};
#undef SPECIAL

#define PLAIN(group, ret, name, params) { #name, (void (*)(void))fwd_##name, &real_##name },
static const wrapper plain[] = { HT_GL_FUNCTIONS(PLAIN) };
#undef PLAIN

static void *as_data(void (*fn)(void)) {
    void *p;
    memcpy(&p, &fn, sizeof p); /* function to data pointer: same size on POSIX */
    return p;
}

void *ht_test_fault_getproc(const char *name) {
    void *real = ht_test_getproc(name);
    if (!real || strncmp(name, "gl", 2) != 0) return real;
    const wrapper *lists[2] = { specials, plain };
    const size_t counts[2] = { sizeof specials / sizeof specials[0], sizeof plain / sizeof plain[0] };
    for (int l = 0; l < 2; l++)
        for (size_t i = 0; i < counts[l]; i++)
            if (strcmp(name + 2, lists[l][i].name) == 0) {
                memcpy(lists[l][i].real, &real, sizeof real);
                return as_data(lists[l][i].fn);
            }
    return real; /* a name the runtime does not load through gl_api.h (an ARB alias) */
}

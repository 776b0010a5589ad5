/* glsl_parse.cpp — glsl_parse.h: the one piece of hairgen in C++, because
   glslang's C API validates a text in two passes (glslang_shader_preprocess
   writes the preprocessed text, glslang_shader_parse parses that again),
   and TShader::parse does both in one (a third fewer instructions,
   docs/performance.md). The same arguments as the C API's preprocess step;
   no exception leaves this file. */
#include <cstdio>
#include <new>

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include "glsl_parse.h"

extern "C" bool ht_glslang_init(void) { return glslang::InitializeProcess(); }

static void copy_log(char *log, size_t log_size, const char *text) {
    if (log && log_size) std::snprintf(log, log_size, "%s", text && text[0] ? text : "glslang rejected the shader (no log)");
}

extern "C" bool ht_glslang_parse(const char *source, bool vertex, int version, bool es, char *log, size_t log_size) {
    try {
        const EShLanguage stage = vertex ? EShLangVertex : EShLangFragment;
        glslang::TShader shader(stage);
        shader.setStrings(&source, 1);
        shader.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientNone, version);
        glslang::TShader::ForbidIncluder no_includes;
        if (shader.parse(GetDefaultResources(), version, es ? EEsProfile : ENoProfile, false, false, EShMsgDefault,
                         no_includes))
            return true;
        copy_log(log, log_size, shader.getInfoLog());
    } catch (const std::bad_alloc &) {
        copy_log(log, log_size, "glslang: out of memory");
    } catch (...) {
        copy_log(log, log_size, "glslang: an exception");
    }
    return false;
}

/* glsl_validate.c — glslang in process: every emitted GLSL text is parsed at
   exactly its version and profile before it leaves the generator. */
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>

#include "emit.h"

/* glslang's process state is set up once and never torn down: finalizing
   while another thread validates would pull the tables from under it. */
static pthread_once_t init_once = PTHREAD_ONCE_INIT;
static int init_ok;

static void init_glslang(void) { init_ok = glslang_initialize_process(); }

static ht_result fail(char *log, size_t log_size, const char *fmt, const char *arg) {
    if (log && log_size) snprintf(log, log_size, fmt, arg);
    return HT_ERR_COMPILE;
}

/* The first line must be the #version line of the version asked for, so a
   file can never be validated at one version and compiled at another. */
static bool version_line_ok(const char *source, int version) {
    char want[32];
    int n = snprintf(want, sizeof want, "#version %d", version);
    if (strncmp(source, want, (size_t)n) != 0) return false;
    char next = source[n];
    return next == '\n' || (next == '\r' && source[n + 1] == '\n');
}

ht_result ht_glsl_validate(const char *source, ht_stage stage, int version, bool es,
                           char *log, size_t log_size) {
    if (log && log_size) log[0] = '\0';
    if (!source) return fail(log, log_size, "%s", "no source");
    if (stage != HT_STAGE_VERTEX && stage != HT_STAGE_FRAGMENT)
        return fail(log, log_size, "%s", "not a GLSL stage");
    if (!version_line_ok(source, version)) {
        char want[32];
        snprintf(want, sizeof want, "#version %d", version);
        return fail(log, log_size, "ERROR: the first line is not exactly \"%s\"", want);
    }
    pthread_once(&init_once, init_glslang);
    if (!init_ok) return fail(log, log_size, "%s", "glslang failed to initialize");

    const glslang_input_t input = {
        .language = GLSLANG_SOURCE_GLSL,
        .stage = stage == HT_STAGE_VERTEX ? GLSLANG_STAGE_VERTEX : GLSLANG_STAGE_FRAGMENT,
        .client = GLSLANG_CLIENT_NONE, /* no client: client and target versions unused */
        .target_language = GLSLANG_TARGET_NONE,
        .code = source,
        .default_version = version,
        .default_profile = es ? GLSLANG_ES_PROFILE : GLSLANG_NO_PROFILE,
        .force_default_version_and_profile = 0,
        .forward_compatible = 0,
        .messages = GLSLANG_MSG_DEFAULT_BIT,
        .resource = glslang_default_resource(),
    };
    glslang_shader_t *shader = glslang_shader_create(&input);
    if (!shader) return fail(log, log_size, "%s", "glslang could not create a shader");
    ht_result r = HT_OK;
    if (!glslang_shader_preprocess(shader, &input) || !glslang_shader_parse(shader, &input)) {
        const char *info = glslang_shader_get_info_log(shader);
        r = fail(log, log_size, "%s", info && info[0] ? info : "glslang rejected the shader (no log)");
    }
    glslang_shader_delete(shader);
    return r;
}

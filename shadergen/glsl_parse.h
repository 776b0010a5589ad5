/* glsl_parse.h — glslang's verdict on one GLSL text, through its C++ API
   (glsl_parse.cpp): one parse that preprocesses as it goes, where the C
   API can only preprocess to a string and then parse that string again. */
#ifndef HT_GLSL_PARSE_H
#define HT_GLSL_PARSE_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* glslang's process state (glslang_initialize_process); false if it failed. */
bool ht_glslang_init(void);

/* Parses source as a vertex (else fragment) shader, #version `version`,
   ES profile when es; false with glslang's info log in log (cut to fit).
   Needs ht_glslang_init first. */
bool ht_glslang_parse(const char *source, bool vertex, int version, bool es, char *log, size_t log_size);

#ifdef __cplusplus
}
#endif

#endif

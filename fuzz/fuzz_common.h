/* fuzz_common.h — what every libFuzzer target here shares: the input as a
   NUL-terminated string (the readers take text), and an error buffer.
   Targets: `make fuzz` builds them with clang -fsanitize=fuzzer,address,
   undefined and runs each for FUZZ_SECONDS on a corpus seeded from the
   shipped files (docs/robustness.md has the numbers). */
#ifndef HT_FUZZ_COMMON_H
#define HT_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* data as a malloc'd C string (a NUL inside ends it early, as a file
   reader would refuse it), or NULL when out of memory. */
static inline char *ht_fuzz_text(const uint8_t *data, size_t size) {
    char *text = malloc(size + 1);
    if (!text) return NULL;
    memcpy(text, data, size);
    text[size] = '\0';
    return text;
}

#endif

/* support_log.c — see support_log.h. */
#include <stdio.h>
#include <string.h>

#include "support_log.h"

char ht_test_log_text[16384];

void ht_test_log_clear(void) { ht_test_log_text[0] = '\0'; }

void ht_test_log_capture(void *user, const char *line) {
    (void)user;
    size_t used = strlen(ht_test_log_text);
    snprintf(ht_test_log_text + used, sizeof ht_test_log_text - used, "%s\n", line);
}

bool ht_test_logged(const char *what) { return strstr(ht_test_log_text, what) != NULL; }

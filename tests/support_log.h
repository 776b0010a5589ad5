/* support_log.h — the renderer's log, captured for a test to search: pass
   ht_test_log_capture as ht_renderer_desc.log and clear the buffer before
   the call the test watches. One buffer per process (cmocka runs one test
   at a time); a line that does not fit is cut, never overflows. */
#ifndef HT_SUPPORT_LOG_H
#define HT_SUPPORT_LOG_H

#include <stdbool.h>

extern char ht_test_log_text[16384];   /* every line so far, each ending in '\n' */

void ht_test_log_clear(void);
/* An ht_log_fn: appends line and a newline; user is unused. */
void ht_test_log_capture(void *user, const char *line);
bool ht_test_logged(const char *what);

#endif

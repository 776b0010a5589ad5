/* tempdir.h — the scratch directory the benchmarks generate bundles into
   (header only, like offscreen.h): made with mkdtemp, removed whole on every
   way out of the program, early errors included. */
#ifndef HT_EXAMPLES_TEMPDIR_H
#define HT_EXAMPLES_TEMPDIR_H

#include <stdio.h>
#include <stdlib.h>

/* dir and everything under it; 0 when it is gone. dir comes from mkdtemp,
   so it holds no quote. */
static inline int tempdir_remove(const char *dir) {
    char cmd[512];
    if (snprintf(cmd, sizeof cmd, "rm -rf -- '%s'", dir) >= (int)sizeof cmd) return -1;
    return system(cmd) == 0 ? 0 : -1;
}

#endif

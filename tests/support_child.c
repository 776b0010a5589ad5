/* support_child.c — see support_child.h. */
#define _POSIX_C_SOURCE 200809L
#include "support_child.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>

/* Mapped bytes now, from /proc/self/statm; -1 when it cannot be read. */
static long address_space_bytes(void) {
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = -1;
    if (!f) return -1;
    if (fscanf(f, "%ld", &pages) != 1) pages = -1;
    fclose(f);
    return pages < 0 ? -1 : pages * sysconf(_SC_PAGESIZE);
}

bool ht_test_limit_address_space(size_t spare) {
    long used = address_space_bytes();
    if (used < 0) return false;
    struct rlimit limit = { (rlim_t)used + spare, (rlim_t)used + spare };
    return setrlimit(RLIMIT_AS, &limit) == 0;
}

int ht_test_fill_memory(void *blocks[HT_TEST_FILL_BLOCKS]) {
    int n = 0;
    for (size_t size = 8 << 20; size >= 4096 && n < HT_TEST_FILL_BLOCKS;)
        if ((blocks[n] = malloc(size))) memset(blocks[n++], 1, size);
        else size /= 2;
    return n;
}

void ht_test_unfill(void *blocks[HT_TEST_FILL_BLOCKS], int count) {
    for (int i = 0; i < count; i++) free(blocks[i]);
}

void ht_test_fork_child(int (*child)(void)) {
    fflush(NULL); /* the child must not write the parent's buffered output again */
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) _exit(child());
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
}

/* support_child.h — run part of a test in a child process, for what must
   not happen in the test runner itself (an address-space limit, say).

   Usage:
       static int child(void) {
           if (!ht_test_limit_address_space(8 << 20)) return 11;
           ...; return 0;            (non-zero: which check failed)
       }
       ht_test_fork_child(child);      (fails the test unless it exits 0) */
#ifndef HT_SUPPORT_CHILD_H
#define HT_SUPPORT_CHILD_H

#include <stdbool.h>
#include <stddef.h>

/* Limits the process's address space to what it maps now plus spare
   bytes; false when the size or the limit cannot be had. */
bool ht_test_limit_address_space(size_t spare);
/* Under that limit: allocates (and touches) blocks of 8 MB halving to 4
   KB until none fits, so the next allocation of more than a page fails;
   at most HT_TEST_FILL_BLOCKS, into blocks, their count returned (free
   them with ht_test_unfill). */
#define HT_TEST_FILL_BLOCKS 64
int ht_test_fill_memory(void *blocks[HT_TEST_FILL_BLOCKS]);
void ht_test_unfill(void *blocks[HT_TEST_FILL_BLOCKS], int count);
/* Runs child() in a forked process and fails the running cmocka test
   unless it exits with status 0. */
void ht_test_fork_child(int (*child)(void));

/* Defined under AddressSanitizer, which reserves terabytes and aborts
   instead of returning NULL: a child that fills memory (above) cannot run
   there, so it is compiled #ifndef HT_UNDER_ASAN and run by
   HT_TEST_FORK_MEMORY_CHILD, which skips the test instead. */
#if defined(__SANITIZE_ADDRESS__)
#define HT_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HT_UNDER_ASAN 1
#endif
#endif
#ifdef HT_UNDER_ASAN
#define HT_TEST_FORK_MEMORY_CHILD(child) skip()
#else
#define HT_TEST_FORK_MEMORY_CHILD(child) ht_test_fork_child(child)
#endif

#endif

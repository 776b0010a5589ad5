/* huge_heap.c — huge_heap.h. A bundle touches about 6 MiB of fresh memory
   (glslang's symbol tables, textures, the LUT, PNG buffers); on a virtual
   machine a first touch of a 4 KiB page can cost 13 us (1500 page faults
   were a third of one material's CPU time), and a 2 MiB huge page costs
   about what one small page does. glibc's tunable glibc.malloc.hugetlb
   would do this from the environment; a program cannot set its own, so
   the heap is grown here once, with malloc's own calls, and the range
   advised with madvise(MADV_HUGEPAGE). */
#include "huge_heap.h"

#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#endif

void ht_huge_heap(unsigned reserve_mib) {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
    const size_t huge = (size_t)2 << 20;
    const size_t reserve = (size_t)reserve_mib << 20;
    /* One arena: a thread's own arena would be a separate mapping of small
       pages. Blocks up to glibc's limit (32 MiB) from the heap, not from
       mmap, and nothing returned to the system: a freed buffer is reused,
       not faulted in again. */
    mallopt(M_ARENA_MAX, 1);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, (int)(reserve + (64u << 20)));
    char *lo = sbrk(0);
    void *grow = malloc(reserve);
    char *hi = sbrk(0);
    free(grow);
    if (!grow || lo == (char *)-1 || hi == (char *)-1 || hi <= lo) return;
    uintptr_t from = ((uintptr_t)lo + huge - 1) & ~(uintptr_t)(huge - 1);
    uintptr_t to = (uintptr_t)hi & ~(uintptr_t)(huge - 1);
    if (to > from) madvise((void *)from, to - from, MADV_HUGEPAGE);
#else
    (void)reserve_mib;
#endif
}

/* huge_heap.c — huge_heap.h. hairgen's heap on transparent huge pages:
   where a first touch of a small page is expensive (a VM under nested
   paging), page faults were a third of one material's CPU time
   (docs/performance.md). A program cannot set glibc.malloc.hugetlb for
   itself, so the heap is laid out once with malloc's own calls: the break
   moved up to a 2 MiB boundary, the heap grown in one step and advised
   MADV_HUGEPAGE before anything touches it (a range touched before the
   advice stays in small pages), a first block never freed so every later
   allocation lands in advised memory, and the next populate_mib populated
   with MADV_POPULATE_WRITE (a first read maps the shared huge zero page,
   which a later write splits into small pages). */
#define _GNU_SOURCE /* MADV_POPULATE_WRITE */
#include "huge_heap.h"

#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>

#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#endif

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23 /* Linux 5.14; older kernels refuse it (EINVAL): no populating */
#endif

void ht_huge_heap(unsigned reserve_mib, unsigned populate_mib) {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
    const size_t huge = (size_t)2 << 20;
    const size_t reserve = (size_t)reserve_mib << 20;
    if (reserve < 3 * huge) return;
    /* One arena: a thread's own arena would be a separate mapping of small
       pages. Blocks up to glibc's limit (32 MiB) from the heap, not from
       mmap, and nothing returned to the system: a freed buffer is reused,
       not faulted in again. */
    mallopt(M_ARENA_MAX, 1);
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, (int)(reserve + (64u << 20)));
    char *lo = sbrk(0);
    if (lo == (char *)-1) return;
    uintptr_t from = ((uintptr_t)lo + huge - 1) & ~(uintptr_t)(huge - 1);
    if (from > (uintptr_t)lo && sbrk((intptr_t)(from - (uintptr_t)lo)) == (void *)-1) return;
    mallopt(M_TOP_PAD, (int)reserve);
    void *grow = malloc(huge);
    char *hi = sbrk(0);
    free(grow);
    mallopt(M_TOP_PAD, 128 * 1024); /* glibc's default again */
    if (!grow || hi == (char *)-1) return;
    uintptr_t to = (uintptr_t)hi & ~(uintptr_t)(huge - 1);
    const size_t kept = 2 * huge;
    if (to <= from + kept || madvise((void *)from, to - from, MADV_HUGEPAGE) != 0) return;
    void *filler = malloc(kept); /* never freed: see above */
    if (!filler) return;
    size_t populate = (size_t)populate_mib << 20;
    if (populate > to - from - kept) populate = to - from - kept;
    if (populate) madvise((void *)(from + kept), populate, MADV_POPULATE_WRITE);
#else
    (void)reserve_mib;
    (void)populate_mib;
#endif
}

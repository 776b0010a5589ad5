/* huge_heap.c — huge_heap.h. A bundle touches about 6 MiB of fresh memory
   (glslang's symbol tables, textures, the LUT, PNG buffers); on the 2-core
   virtual machine the first touch of a 4 KiB page costs about 13 us (1500
   page faults were a third of one material's CPU time), and a 2 MiB huge
   page costs about what one small page does (README). glibc's tunable
   glibc.malloc.hugetlb would do this from the environment; a program cannot
   set its own, so the heap is laid out here once with malloc's own calls:

     the break moved up to a huge-page boundary B (glibc takes a break it
       did not set as a new start for its top chunk, as when any other code
       calls sbrk; the gap below is never touched);
     the heap grown by reserve_mib in one step (a 2 MiB block with
       M_TOP_PAD at reserve_mib: one sbrk) and given back to malloc's top
       chunk, which leaves a small page touched at B and one at B + 2 MiB
       (the chunk headers);
     [B, end) advised MADV_HUGEPAGE, then the first 4 MiB at B filled by a
       block that is never freed, so that every later allocation is in
       untouched, advised memory (a range whose first touch happened before
       the advice stays in small pages);
     the next populate_mib populated as huge pages (MADV_POPULATE_WRITE):
       a range whose first touch is a read maps the shared huge zero page,
       and a write there then splits it into small pages, one fault each
       (without it, one of dark-brown's three 2 MiB ranges went to small
       pages in each of 8 runs; with 8 MiB, none). */
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

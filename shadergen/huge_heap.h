/* huge_heap.h — hairgen's process heap on transparent huge pages
   (huge_heap.c). A program's choice, not the library's: hairgen's main
   calls it first. */
#ifndef HT_HUGE_HEAP_H
#define HT_HUGE_HEAP_H

/* Every thread's malloc from one heap, large blocks from it too, never
   trimmed; reserve_mib of address space beyond its end advised for huge
   pages (4 MiB of it kept aside, see huge_heap.c) and the first
   populate_mib of that backed now. Where the system offers no huge pages
   (THP "never", not glibc, reserve_mib < 6) the heap works as before. */
void ht_huge_heap(unsigned reserve_mib, unsigned populate_mib);

#endif

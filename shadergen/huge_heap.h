/* huge_heap.h — hairgen's process heap on transparent huge pages
   (huge_heap.c). A program's choice, not the library's: hairgen's main
   calls it first. */
#ifndef HT_HUGE_HEAP_H
#define HT_HUGE_HEAP_H

/* Every thread's malloc from one heap, large blocks from it too, never
   trimmed, and reserve_mib of address space beyond its end advised for
   huge pages; where the system offers none (THP "never", not glibc), the
   heap is as it was. */
void ht_huge_heap(unsigned reserve_mib);

#endif

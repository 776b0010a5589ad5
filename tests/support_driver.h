/* support_driver.h — `make test` runs some render tests a second time on
   softpipe (an interpreter, slow) with HAIRTIER_DRIVER_CASES=1: there only
   the cases whose outcome depends on the driver run. A case that proves
   nothing about the driver (input checks, CPU-side arithmetic, more of the
   same shader with other constants) starts with
   HT_TEST_DRIVER_INDEPENDENT(), which skips it in such a run (cmocka
   prints it as skipped). Include after <cmocka.h>. */
#ifndef HT_SUPPORT_DRIVER_H
#define HT_SUPPORT_DRIVER_H

#include <stdbool.h>

/* HAIRTIER_DRIVER_CASES is "1". */
bool ht_test_driver_cases_only(void);

/* What a test draws in such a run: frames at most HT_TEST_DRIVER_SIDE² and
   fur balls of at most HT_TEST_DRIVER_HAIRS hairs. softpipe's cost
   is fragments times shader work plus one setup per (thin) triangle; this
   is the least at which every tier still shows its shading (coverage,
   highlights, the tiers' bounds: docs/performance.md, "Softpipe runs").
   Otherwise the value unchanged. */
#define HT_TEST_DRIVER_SIDE 96
#define HT_TEST_DRIVER_HAIRS 200
int ht_test_driver_side(int side);
int ht_test_driver_hairs(int hairs);

#define HT_TEST_DRIVER_INDEPENDENT()                 \
    do {                                             \
        if (ht_test_driver_cases_only()) skip();     \
    } while (0)

#endif

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

#define HT_TEST_DRIVER_INDEPENDENT()                 \
    do {                                             \
        if (ht_test_driver_cases_only()) skip();     \
    } while (0)

#endif

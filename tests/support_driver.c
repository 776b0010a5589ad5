/* support_driver.c — see support_driver.h. */
#include <stdlib.h>
#include <string.h>

#include "support_driver.h"

bool ht_test_driver_cases_only(void) {
    const char *v = getenv("HAIRTIER_DRIVER_CASES");
    return v && strcmp(v, "1") == 0;
}

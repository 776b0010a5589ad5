/* support_driver.c — see support_driver.h. */
#include <stdlib.h>
#include <string.h>

#include "support_driver.h"

bool ht_test_driver_cases_only(void) {
    const char *v = getenv("HAIRTIER_DRIVER_CASES");
    return v && strcmp(v, "1") == 0;
}

int ht_test_driver_side(int side) {
    return ht_test_driver_cases_only() && side > HT_TEST_DRIVER_SIDE ? HT_TEST_DRIVER_SIDE : side;
}

int ht_test_driver_hairs(int hairs) {
    return ht_test_driver_cases_only() && hairs > HT_TEST_DRIVER_HAIRS ? HT_TEST_DRIVER_HAIRS : hairs;
}

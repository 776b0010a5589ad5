/* header_use.c — the Makefile compiles this as C99 and as C++ with -Wall
   -Wextra -pedantic -Werror against a header hairgen --emit-header wrote:
   an application in either language includes it without a warning. */
#include "dark_brown_furball.h"

const ht_bundle_memory *header_use_entry(void);
const ht_bundle_memory *header_use_entry(void) { return &dark_brown_furball; }

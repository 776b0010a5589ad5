/* c_locale.h — the C locale on this thread for a scope: every number the
   generator prints (GLSL literals, manifest, program, error lines) must
   not depend on the caller's locale (same inputs, same bytes), and a
   thread does not inherit uselocale's. */
#ifndef HT_C_LOCALE_H
#define HT_C_LOCALE_H

#include <locale.h>

typedef struct ht_c_locale_scope { locale_t c, previous; } ht_c_locale_scope;

static inline ht_c_locale_scope ht_c_locale_enter(void) {
    ht_c_locale_scope s = { newlocale(LC_ALL_MASK, "C", (locale_t)0), (locale_t)0 };
    if (s.c) s.previous = uselocale(s.c);
    return s;
}

static inline void ht_c_locale_leave(ht_c_locale_scope s) {
    if (!s.c) return;
    uselocale(s.previous);
    freelocale(s.c);
}

#endif

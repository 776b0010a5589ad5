/* export.h — HT_API marks what libhairtier.so and libhairgen.so export.
   The libraries are built with -fvisibility=hidden, so only declarations
   carrying HT_API are visible to an application; the static archives are
   unaffected. Included by every public header; nothing to configure. */
#ifndef HT_EXPORT_H
#define HT_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define HT_API __attribute__((visibility("default")))
#else
#define HT_API
#endif

#endif

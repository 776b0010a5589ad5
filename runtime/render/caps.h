/* caps.h — what a GL context offers: probing it (ht_caps, public in
   hairtier.h), reading version strings, and the extensions libhairtier knows
   by name. Internal to libhairtier; everything about "does this device have
   X" lives here once, so selection (select.c), the renderer's GL-state
   baseline (gl_state.c) and the manifest reader only ask.

   Usage:
       ht_caps caps;
       char *extensions;                        // the device's whole list, heap
       if (ht_caps_probe_gl(&gl, &caps, &extensions) != HT_OK) ...;
       ht_caps_apply_profile(&caps, &profile);
       ht_caps_hide_extensions(extensions, profile.hide_extensions);
       if (ht_caps_satisfies_extension(&caps, extensions, "GL_ARB_multitexture")) ...;
       free(extensions);

   ht_caps.known_extensions holds one bit per name in caps.c's table (every
   extension a flag, a core version or the baseline depends on), so public
   caps stay small and a profile can lower them without the list; names
   outside the table (a manifest may list any) are looked up in the list. */
#ifndef HT_CAPS_H
#define HT_CAPS_H

#include <stdbool.h>
#include <stddef.h>

#include "gl_api.h"
#include <hairtier/hairtier.h>

/* ht_caps_probe through a table already loaded from the context, before
   any ht_gl_restrict. extensions (may be NULL) receives the device's whole
   space-separated list, malloc'd (NULL when out of memory: known names are
   still in caps); free() it. */
ht_result ht_caps_probe_gl(const ht_gl *gl, ht_caps *out, char **extensions);

/* Sets the known_extensions bit of every name in a space-separated list
   that caps.c's table knows; other names are ignored. */
void ht_caps_note_extensions(ht_caps *caps, const char *list);

/* The device lists name (and no profile hid it). False for a name outside
   caps.c's table: ask ht_extension_list_has with the whole list. */
bool ht_caps_lists_extension(const ht_caps *caps, const char *name);

/* In the list (known bit, or for other names the whole list, which may be
   NULL), or core since the context's GL version (and the matching
   capability flag still set, so device profiles take effect). */
bool ht_caps_satisfies_extension(const ht_caps *caps, const char *list, const char *name);

/* Removes from list, in place, every name in the space-separated hide list
   (NULL: none); ht_caps_apply_profile does the same to the known bits. */
void ht_caps_hide_extensions(char *list, const char *hide);

/* Exact, whole-name match in a space-separated list. */
bool ht_extension_list_has(const char *list, const char *name);

/* "M.m" from the first digit of s; glsl: "1.2" means minor 20. */
bool ht_parse_version(const char *s, bool glsl, int *major, int *minor);

static inline bool ht_version_at_least(int major, int minor, int want_major, int want_minor) {
    return major > want_major || (major == want_major && minor >= want_minor);
}

static inline bool ht_caps_gl_at_least(const ht_caps *c, int major, int minor) {
    return ht_version_at_least(c->gl_major, c->gl_minor, major, minor);
}

/* GL ES 1.x: fixed function, no shaders (the fixed4, fixed and gl11 tiers
   draw there); ES 2.0 and later: programs only, no fixed function. */
static inline bool ht_caps_es1(const ht_caps *c) { return c->es && c->gl_major < 2; }
static inline bool ht_caps_es_programs(const ht_caps *c) { return c->es && c->gl_major >= 2; }

#endif

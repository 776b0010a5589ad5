/* shading_check.h — the one check of a Scheuermann or Kajiya-Kay shading's
   constants (colours, wrap, exponents, shifts, the transmission lobe), shared by the material
   check (ht_material_check) and the readers of every tier program that
   carries them (fixed4.json, gl11.json): the same ranges (ht_limits.h) and
   the same words everywhere. Internal.

   Usage:
       if (!ht_shading_check(&shading, "gl11.json", err, sizeof err)) refuse(err);
       // err: "gl11.json: primary.shift: must be in [-100, 100], got 150" */
#ifndef HT_SHADING_CHECK_H
#define HT_SHADING_CHECK_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/model.h>

/* True when every constant of s is finite and in range (a Kajiya-Kay
   shading's secondary lobe is not looked at); else false and one line in
   err naming file and field. Marschner shadings are the caller's. */
bool ht_shading_check(const ht_shading *s, const char *file, char *err, size_t err_size);
/* One colour, each channel finite and in [0, 1]: "FILE: PARENT.color[i]: ...". */
bool ht_shading_check_color(const double color[3], const char *file, const char *parent, char *err, size_t err_size);

#endif

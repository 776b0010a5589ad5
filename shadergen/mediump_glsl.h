/* mediump_glsl.h — the mediump shading table (mediump.h) as ESSL 1.00
   text, for emit_glsl.c's full-es2-mediump.frag. */
#ifndef HT_MEDIUMP_GLSL_H
#define HT_MEDIUMP_GLSL_H

#include "hairgen_internal.h"
#include "mediump.h"
#include "strbuf.h"

/* The table's description for a plan: its shading, lights and inputs. */
ht_mp_desc ht_mp_desc_of_plan(const ht_plan *plan);
/* Every function of p, callees first, each step one statement; the
   shader's default precision (mediump) qualifies them all. */
void ht_mp_write_functions(ht_strbuf *sb, const ht_mp_program *p);

/* full-es2-mediump.frag (as ht_mp_write_functions and emit_glsl.c write
   it: one step a line) as desktop GLSL 1.20 for the full tier's passes,
   with every step's result and every input rounded to fp16 by a GLSL
   function: the mirror's rounding on a GPU, so a whole scene can be
   rendered as an fp16 device would shade it (tests/test_render_mediump.c).
   malloc'd. */
char *ht_mp_desktop_emulation(const char *es_text);

#endif

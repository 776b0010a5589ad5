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

#endif

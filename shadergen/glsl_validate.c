/* glsl_validate.c — glslang in process: every emitted GLSL text is parsed at
   exactly its version and profile before it leaves the generator, once per
   process: a text that passed is remembered (keyed by stage, version,
   profile and the whole text), so a batch of materials sharing shaders
   parses each distinct text once. Safe to call from several threads. */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "emit.h"
#include "glsl_parse.h"

/* glslang's process state is set up once and never torn down: finalizing
   while another thread validates would pull the tables from under it. */
static pthread_once_t init_once = PTHREAD_ONCE_INIT;
static int init_ok;

static void init_glslang(void) { init_ok = ht_glslang_init(); }

/* ---- texts that passed, for the rest of the process ---- */

/* A batch of 100 materials has about 300 distinct texts; past this many the
   cache stops growing (texts are still validated, just not remembered), so
   a long-lived process cannot grow it without bound. */
#define CACHE_SLOTS 8192
#define CACHE_MAX_ENTRIES (CACHE_SLOTS / 2)

typedef struct passed_text {
    uint64_t hash;   /* 0: empty slot */
    ht_stage stage;
    int version;
    bool es;
    char *text;
} passed_text;

static pthread_mutex_t cache_lock = PTHREAD_MUTEX_INITIALIZER;
static passed_text *cache;           /* CACHE_SLOTS, open addressing */
static int cache_entries;
static unsigned long parsed_count, reused_count;

static uint64_t text_key(const char *source, ht_stage stage, int version, bool es) {
    uint64_t h = 0xcbf29ce484222325ull;
    const int tag[3] = { (int)stage, version, es };
    const unsigned char *p = (const unsigned char *)tag;
    for (size_t i = 0; i < sizeof tag; i++) h = (h ^ p[i]) * 0x100000001b3ull;
    for (p = (const unsigned char *)source; *p; p++) h = (h ^ *p) * 0x100000001b3ull;
    return h ? h : 1;
}

/* The slot holding this text, or the empty slot where it would go; NULL
   when the table has no cache. Called with cache_lock held. */
static passed_text *cache_slot(uint64_t hash, const char *source, ht_stage stage, int version, bool es) {
    if (!cache) return NULL;
    for (size_t i = hash & (CACHE_SLOTS - 1);; i = (i + 1) & (CACHE_SLOTS - 1)) {
        passed_text *e = &cache[i];
        if (e->hash == 0) return e;
        if (e->hash == hash && e->stage == stage && e->version == version && e->es == es &&
            strcmp(e->text, source) == 0)
            return e;
    }
}

static bool cache_has(const char *source, uint64_t hash, ht_stage stage, int version, bool es) {
    pthread_mutex_lock(&cache_lock);
    passed_text *e = cache_slot(hash, source, stage, version, es);
    bool hit = e && e->hash != 0;
    if (hit) reused_count++;
    else parsed_count++;
    pthread_mutex_unlock(&cache_lock);
    return hit;
}

/* Out of memory only costs a later parse. */
static void cache_add(const char *source, uint64_t hash, ht_stage stage, int version, bool es) {
    pthread_mutex_lock(&cache_lock);
    if (!cache) cache = calloc(CACHE_SLOTS, sizeof *cache);
    passed_text *e = cache_entries < CACHE_MAX_ENTRIES ? cache_slot(hash, source, stage, version, es) : NULL;
    if (e && e->hash == 0 && (e->text = strdup(source)) != NULL) {
        e->hash = hash;
        e->stage = stage;
        e->version = version;
        e->es = es;
        cache_entries++;
    }
    pthread_mutex_unlock(&cache_lock);
}

void ht_glsl_validate_counts(unsigned long *parsed, unsigned long *reused) {
    pthread_mutex_lock(&cache_lock);
    if (parsed) *parsed = parsed_count;
    if (reused) *reused = reused_count;
    pthread_mutex_unlock(&cache_lock);
}

static ht_result fail(char *log, size_t log_size, const char *fmt, const char *arg) {
    if (log && log_size) snprintf(log, log_size, fmt, arg);
    return HT_ERR_COMPILE;
}

/* The first line must be the #version line of the version asked for, so a
   file can never be validated at one version and compiled at another
   (ESSL 3.00 and later name their profile: "#version 300 es"). */
static int version_line(char *want, size_t size, int version, bool es) {
    return snprintf(want, size, "#version %d%s", version, es && version >= 300 ? " es" : "");
}

static bool version_line_ok(const char *source, int version, bool es) {
    char want[32];
    int n = version_line(want, sizeof want, version, es);
    if (strncmp(source, want, (size_t)n) != 0) return false;
    char next = source[n];
    return next == '\n' || (next == '\r' && source[n + 1] == '\n');
}

/* glslang's verdict on one text (one pass: glsl_parse.h). */
static ht_result parse(const char *source, ht_stage stage, int version, bool es, char *log, size_t log_size) {
    pthread_once(&init_once, init_glslang);
    if (!init_ok) return fail(log, log_size, "%s", "glslang failed to initialize");
    return ht_glslang_parse(source, stage == HT_STAGE_VERTEX, version, es, log, log_size) ? HT_OK : HT_ERR_COMPILE;
}

ht_result ht_glsl_validate(const char *source, ht_stage stage, int version, bool es,
                           char *log, size_t log_size) {
    if (log && log_size) log[0] = '\0';
    if (!source) return fail(log, log_size, "%s", "no source");
    if (stage != HT_STAGE_VERTEX && stage != HT_STAGE_FRAGMENT)
        return fail(log, log_size, "%s", "not a GLSL stage");
    if (!version_line_ok(source, version, es)) {
        char want[32];
        version_line(want, sizeof want, version, es);
        return fail(log, log_size, "ERROR: the first line is not exactly \"%s\"", want);
    }
    const uint64_t key = text_key(source, stage, version, es);
    if (cache_has(source, key, stage, version, es)) return HT_OK;
    ht_result r = parse(source, stage, version, es, log, log_size);
    if (r == HT_OK) cache_add(source, key, stage, version, es);
    return r;
}

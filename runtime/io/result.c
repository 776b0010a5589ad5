/* result.c — names for result codes and tiers. */
#include <string.h>

#include <hairtier/hairtier.h>

const char *ht_result_string(ht_result r) {
    switch (r) {
    case HT_OK: return "ok";
    case HT_ERR_INVALID_ARGUMENT: return "invalid argument";
    case HT_ERR_IO: return "i/o error";
    case HT_ERR_PARSE: return "invalid input";
    case HT_ERR_UNSUPPORTED: return "unsupported by this device";
    case HT_ERR_COMPILE: return "shader compile/link failed";
    case HT_ERR_GL: return "GL error";
    case HT_ERR_NO_TIER: return "no tier runs on this device";
    case HT_ERR_OUT_OF_MEMORY: return "out of memory";
    }
    return "unknown result";
}

static const char *const tier_names[HT_TIER_COUNT] = { "auto", "marschner", "full", "vertex", "fixed", "fixed4", "gl11" };

const char *ht_tier_name(ht_tier t) {
    return (t >= 0 && t < HT_TIER_COUNT) ? tier_names[t] : "unknown";
}

ht_tier ht_tier_from_name(const char *name) {
    for (int t = 0; t < HT_TIER_COUNT; t++)
        if (name && strcmp(name, tier_names[t]) == 0) return (ht_tier)t;
    return HT_TIER_COUNT;
}

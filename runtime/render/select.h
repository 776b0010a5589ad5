/* select.h — tier selection as a pure function of (device caps, bundle,
   request): no GL calls, no getenv, so tests drive it with synthetic caps.
   Internal to libhairtier.

   Usage:
       ht_selection sel;
       ht_result r = ht_select_tier(&(ht_select_desc){
               .caps = &caps, .bundle = &bundle, .requested = desc->tier,
               .env_tier = getenv("HAIRTIER_TIER"), .strict = desc->strict },
           &sel, err, sizeof err);
       for (int i = 0; i < sel.skipped_count; i++) log(sel.skipped[i]);

   Rules: tiers are walked best first as the bundle lists them; a tier runs
   when the device meets its requirements (GL version, shader stages, GLSL
   version, extensions, texture units) and it has not failed at runtime
   (`failed`, e.g. "compile failed: ..."). An extension is met by the
   extension string or by the core GL version it entered. desc.tier forces a tier, else HAIRTIER_TIER does; a forced tier
   that cannot run drops to the next one that can, unless strict.
   Without a forced tier the policy picks among the tiers that run
   (hairtier.h lists them): best = the first; fastest = the least measured
   cost_ratio when every runnable tier has one (ties: the earlier), else
   the last; error:DB = the least cost_ratio among runnable tiers measured
   at >= DB (ties: the earlier; a runnable tier without numbers is skipped
   with a line), none → the highest PSNR, a bundle with no measured tier →
   HT_ERR_INVALID_ARGUMENT; error:flip:E = the same with the measured
   FLIP mean <= E, none → the least FLIP mean, no tier with FLIP numbers →
   HT_ERR_INVALID_ARGUMENT; frame:MS = the
   first runnable tier timed within MS, none → the fastest timed, no
   timings yet → best. */
#ifndef HT_SELECT_H
#define HT_SELECT_H

#include <stdbool.h>
#include <stddef.h>

#include "manifest.h"
#include "caps.h"
#include <hairtier/hairtier.h>

#define HT_SELECT_REASON 320

typedef struct ht_select_desc {
    const ht_caps *caps;                        /* required */
    const char *extensions;                     /* the device's whole list (caps.h), NULL → known names only */
    const ht_manifest *bundle;                    /* required */
    ht_tier requested;                          /* HT_TIER_AUTO → env_tier */
    const char *env_tier;                       /* HAIRTIER_TIER's value, NULL when unset */
    bool strict;                                /* a forced tier that cannot run is an error */
    const char *failed[HT_MANIFEST_MAX_TIERS];    /* per bundle tier: why it failed at runtime, or NULL */
    ht_policy policy;                           /* zero → best */
    double frame_ms[HT_MANIFEST_MAX_TIERS];     /* per bundle tier: ms a frame on this device; 0 → not timed */
} ht_select_desc;

typedef struct ht_selection {
    int index;                                  /* into bundle->tiers; -1 when none */
    ht_tier tier;                               /* HT_TIER_COUNT when none */
    ht_tier forced;                             /* HT_TIER_AUTO when nothing forced */
    char reason[HT_SELECT_REASON];              /* why this tier, one line */
    char skipped[HT_MANIFEST_MAX_TIERS][HT_SELECT_REASON]; /* "full: needs GLSL 1.20, have 1.10" */
    int skipped_count;
} ht_selection;

/* HT_OK with a tier; HT_ERR_NO_TIER when none runs; HT_ERR_UNSUPPORTED when
   strict refuses a downgrade; HT_ERR_INVALID_ARGUMENT for a bad request. err
   gets one line. out is filled in every case (skipped lines included). */
ht_result ht_select_tier(const ht_select_desc *desc, ht_selection *out, char *err, size_t err_size);

/* True when the device meets the tier's manifest requirements; otherwise
   why = "needs ..." (without the tier name). */
bool ht_select_check_requirements(const ht_caps *caps, const char *extensions, const ht_manifest_tier *tier,
                                  char *why, size_t why_size);

/* On a GL ES device (caps->es): the tier's "es" entry it runs, the first
   in the manifest's order (best first) whose ES version, ESSL version and
   fragment precision the device has, so a device without fragment highp
   gets a mediump text when the bundle has one. -1 when none, with why =
   "needs ..." (the highp text's refusal when precision is what failed). */
int ht_select_es_target(const ht_caps *caps, const ht_manifest_tier *tier, char *why, size_t why_size);

/* The variant of a tier (select_variant.c), a pure function: requested
   (EXACT or DEVICE) wins; AUTO takes the device variant only when the
   tier has both measured objects and: best, frame:MS: its PSNR is at most
   HT_VARIANT_DEVICE_DB below the exact one's; error:DB: it meets DB (or
   the exact one does not either and it is no worse); fastest: its
   cost_ratio is lower. reason gets one line ("device: 33.1 dB, exact
   33.4 dB: within 0.5 dB"). The backend may still lack the variant. */
ht_variant ht_select_variant(const ht_manifest_tier *tier, const ht_policy *policy, ht_variant requested,
                             char *reason, size_t reason_size);
/* "exact", "device" (HAIRTIER_VARIANT) into a variant; NULL or "" is
   AUTO; anything else HT_ERR_INVALID_ARGUMENT with one line. */
ht_result ht_variant_parse(const char *text, ht_variant *out, char *err, size_t err_size);

#endif

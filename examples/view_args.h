/* view_args.h — the options every program that draws a bundle takes
   (hairview, tier_sheet, haircompare): --bundle DIR, --scene FILE, -o OUT,
   --frames N and the context's --context / --egl-device, parsed by the
   one parser (platform/cli.h).

   Usage, in a program with options of its own:
       static const struct option longs[] = { VIEW_ARGS_LONG_OPTIONS, { "tier", ... }, { 0 } };
       ... .short_options = VIEW_ARGS_SHORT_OPTIONS ...
       in its cli_take_fn:
           bool taken;
           const char *why = view_args_take(&o->view, key, value, MAX_FRAMES, &taken);
           if (taken) return why;
           ... the program's own keys ...
       and after cli_parse:
           if ((why = view_args_check(&v, true))) return cli_usage_error(&program, why);
   A program with these options only: view_args_parse. */
#ifndef HT_VIEW_ARGS_H
#define HT_VIEW_ARGS_H

#include <stdbool.h>

#include "cli.h"
#include "offscreen.h"

typedef struct view_args {
    const char *bundle, *scene, *out;
    int frames;
    offscreen_kind context;
    offscreen_api api; /* --api gl|gles1|gles2|gles3 (ES: through EGL) */
    int egl_device; /* -1: the default display */
} view_args;

/* The keys of the long options (the programs' own start at VIEW_KEY_END). */
enum { VIEW_KEY_BUNDLE = CLI_LONG_ONLY, VIEW_KEY_SCENE, VIEW_KEY_FRAMES, VIEW_KEY_CONTEXT, VIEW_KEY_EGL_DEVICE,
       VIEW_KEY_API, VIEW_KEY_END };
#define VIEW_ARGS_SHORT_OPTIONS "o:"
#define VIEW_ARGS_LONG_OPTIONS \
    { "bundle", required_argument, NULL, VIEW_KEY_BUNDLE }, { "scene", required_argument, NULL, VIEW_KEY_SCENE }, \
    { "frames", required_argument, NULL, VIEW_KEY_FRAMES }, { "context", required_argument, NULL, VIEW_KEY_CONTEXT }, \
    { "egl-device", required_argument, NULL, VIEW_KEY_EGL_DEVICE }, { "api", required_argument, NULL, VIEW_KEY_API }

view_args view_args_defaults(int frames);
/* *taken: whether key is one of the options above; then NULL, or why its
   value is refused (--frames: an integer in 1..max_frames; static storage). */
const char *view_args_take(view_args *v, int key, const char *value, int max_frames, bool *taken);
/* A whole command line of these options only (p's short and long options
   are VIEW_ARGS_SHORT_OPTIONS and VIEW_ARGS_LONG_OPTIONS): what cli_parse
   returns, CLI_RUN only when view_args_check passed too. */
int view_args_parse(const cli_program *p, int argc, char **argv, view_args *v, int max_frames, bool need_bundle);
/* After the parse: NULL, or why the options do not go together (--bundle
   required when need_bundle, --scene and -o always). */
const char *view_args_check(view_args *v, bool need_bundle);
/* --soft[=F]'s factor into *soften (no value: lod.h's HT_LOD_SOFTEN): NULL,
   or why value is refused (a factor in (1, HT_LOD_MAX_SOFTEN]). */
const char *view_args_soften(const char *value, float *soften);

#endif

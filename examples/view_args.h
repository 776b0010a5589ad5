/* view_args.h — the options every program that draws a bundle takes
   (hairview, tier_sheet, haircompare): --bundle DIR, --scene FILE, -o OUT,
   --frames N and the context's --context / --egl-device.

   Usage, in a program's argument loop:
       view_args v = view_args_defaults(5);
       int taken = view_args_option(argc, argv, &i, &v, MAX_FRAMES, &why);
       if (taken < 0) return usage(why);
       if (taken == 0) ... the program's own options ...
   and after it:
       if ((why = view_args_check(&v, true))) return usage(why); */
#ifndef HT_VIEW_ARGS_H
#define HT_VIEW_ARGS_H

#include <stdbool.h>

#include "offscreen.h"

typedef struct view_args {
    const char *bundle, *scene, *out;
    int frames;
    offscreen_kind context;
    int egl_device; /* -1: the default display */
} view_args;

view_args view_args_defaults(int frames);
/* 1 when argv[*i] is one of the options above (its value taken, *i
   advanced past it), 0 when it is none of them, -1 with *why set when its
   value is missing or bad (--frames: an integer in 1..max_frames). *why
   points at static storage. */
int view_args_option(int argc, char **argv, int *i, view_args *v, int max_frames, const char **why);
/* A whole command line of these options and --help / -h only: 0 when
   parsed and checked (view_args_check), 1 when help was asked for, -1 with
   *why (static storage) on the first bad or unknown option. */
int view_args_parse(int argc, char **argv, view_args *v, int max_frames, bool need_bundle, const char **why);
/* After the loop: NULL, or why the options do not go together (--bundle
   required when need_bundle, --scene and -o always). */
const char *view_args_check(view_args *v, bool need_bundle);

#endif

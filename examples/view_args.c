/* view_args.c — see view_args.h. */
#include "view_args.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

view_args view_args_defaults(int frames) { return (view_args){ .frames = frames, .egl_device = -1 }; }

static bool named(const char *arg, const char *name) { return strcmp(arg, name) == 0; }

int view_args_option(int argc, char **argv, int *i, view_args *v, int max_frames, const char **why) {
    static char message[96];
    const char *a = argv[*i];
    const char **text = named(a, "--bundle") ? &v->bundle
                      : named(a, "--scene")  ? &v->scene
                      : named(a, "-o")       ? &v->out
                                             : NULL;
    if (text || named(a, "--frames")) {
        if (*i + 1 >= argc) {
            snprintf(message, sizeof message, "%s: missing value", a);
            *why = message;
            return -1;
        }
        const char *value = argv[++*i];
        if (text) {
            *text = value;
            return 1;
        }
        char *end;
        long n = strtol(value, &end, 10);
        if (*value == '\0' || *end || n < 1 || n > max_frames) {
            snprintf(message, sizeof message, "--frames: expected an integer in 1..%d", max_frames);
            *why = message;
            return -1;
        }
        v->frames = (int)n;
        return 1;
    }
    return offscreen_option(argc, argv, i, &v->context, &v->egl_device, why);
}

int view_args_parse(int argc, char **argv, view_args *v, int max_frames, bool need_bundle, const char **why) {
    static char message[300];
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (named(a, "--help") || named(a, "-h")) return 1;
        int taken = view_args_option(argc, argv, &i, v, max_frames, why);
        if (taken < 0) return -1;
        if (taken == 0) {
            snprintf(message, sizeof message, "%s: unknown option", a);
            *why = message;
            return -1;
        }
    }
    return (*why = view_args_check(v, need_bundle)) ? -1 : 0;
}

const char *view_args_check(view_args *v, bool need_bundle) {
    if (need_bundle && !v->bundle) return "--bundle: required";
    if (!v->scene) return "--scene: required";
    if (!v->out) return "-o: required";
    const char *why = NULL;
    if (!offscreen_options_check(&v->context, v->egl_device, &why)) return why;
    return NULL;
}

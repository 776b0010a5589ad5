/* view_args.c — see view_args.h. */
#include "view_args.h"

#include <stdio.h>
#include <stdlib.h>

#include <hairtier/lod.h>

view_args view_args_defaults(int frames) { return (view_args){ .frames = frames, .egl_device = -1 }; }

const char *view_args_take(view_args *v, int key, const char *value, int max_frames, bool *taken) {
    static char message[96];
    *taken = true;
    switch (key) {
    case VIEW_KEY_BUNDLE: v->bundle = value; return NULL;
    case VIEW_KEY_SCENE: v->scene = value; return NULL;
    case 'o': v->out = value; return NULL;
    case VIEW_KEY_CONTEXT: return offscreen_context_value(value, &v->context);
    case VIEW_KEY_EGL_DEVICE: return offscreen_device_value(value, &v->egl_device);
    case VIEW_KEY_API: return offscreen_api_value(value, &v->api);
    case VIEW_KEY_FRAMES: {
        char *end;
        long n = strtol(value, &end, 10);
        if (*value == '\0' || *end || n < 1 || n > max_frames) {
            snprintf(message, sizeof message, "--frames: expected an integer in 1..%d", max_frames);
            return message;
        }
        v->frames = (int)n;
        return NULL;
    }
    default: *taken = false; return NULL;
    }
}

typedef struct view_only {
    view_args *v;
    int max_frames;
} view_only;

static const char *take_view_only(void *user, int key, const char *value) {
    view_only *u = user;
    bool taken;
    const char *why = view_args_take(u->v, key, value, u->max_frames, &taken);
    return taken ? why : cli_unexpected(value);
}

int view_args_parse(const cli_program *p, int argc, char **argv, view_args *v, int max_frames, bool need_bundle) {
    int rc = cli_parse(p, argc, argv, take_view_only, &(view_only){ .v = v, .max_frames = max_frames });
    const char *why;
    if (rc == CLI_RUN && (why = view_args_check(v, need_bundle))) return cli_usage_error(p, why);
    return rc;
}

const char *view_args_check(view_args *v, bool need_bundle) {
    if (need_bundle && !v->bundle) return "--bundle: required";
    if (!v->scene) return "--scene: required";
    if (!v->out) return "-o: required";
    const char *why = NULL;
    if (!offscreen_options_check(&v->context, v->egl_device, &why)) return why;
    if (!offscreen_api_check(&v->context, v->api, &why)) return why;
    return NULL;
}

const char *view_args_soften(const char *value, float *soften) {
    char *end = NULL;
    *soften = value ? (float)strtod(value, &end) : HT_LOD_SOFTEN;
    if (value && (end == value || *end || !(*soften > 1.0f && *soften <= HT_LOD_MAX_SOFTEN)))
        return "--soft: expected a factor above 1, at most 16";
    return NULL;
}

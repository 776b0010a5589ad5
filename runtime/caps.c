/* caps.c — what the current GL context offers, and device profiles that
   pretend it offers less. */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "gl_api.h"
#include "select.h"

static int version_at_least(const ht_caps *c, int major, int minor) {
    return c->gl_major > major || (c->gl_major == major && c->gl_minor >= minor);
}

/* Reads "M.m" from the first digit on: "4.5 (Compatibility Profile) Mesa",
   "OpenGL ES 2.0 foo", "1.20 NVIDIA". GLSL minors are two digits: "1.2"
   means 1.20. False when there is no number. */
bool ht_parse_version(const char *s, bool glsl, int *major, int *minor) {
    *major = *minor = 0;
    if (!s) return false;
    while (*s && !isdigit((unsigned char)*s)) s++;
    if (!*s) return false;
    int ma = 0, mi = 0, digits = 0;
    while (isdigit((unsigned char)*s) && ma < 1000) ma = ma * 10 + (*s++ - '0');
    if (*s == '.') {
        s++;
        while (isdigit((unsigned char)*s) && digits < 3) { mi = mi * 10 + (*s++ - '0'); digits++; }
    }
    if (glsl && digits == 1) mi *= 10;
    *major = ma;
    *minor = mi;
    return true;
}

static void append_extension(char *list, size_t size, const char *name) {
    size_t used = strlen(list), n = strlen(name);
    if (n == 0 || used + n + 2 > size) return; /* truncate at a name boundary */
    if (used) list[used++] = ' ';
    memcpy(list + used, name, n + 1);
}

static void copy_extensions(char *list, size_t size, const char *all) {
    list[0] = '\0';
    char name[128];
    while (all && *all) {
        while (*all == ' ') all++;
        size_t n = strcspn(all, " ");
        if (n > 0 && n < sizeof name) {
            memcpy(name, all, n);
            name[n] = '\0';
            append_extension(list, size, name);
        }
        all += n;
    }
}

/* Derived flags from version, extension string and loaded entry points. */
static void derive_flags(ht_caps *c, const ht_gl *gl) {
    const char *e = c->extensions;
    c->has_multitexture = gl->has_multitexture &&
        (version_at_least(c, 1, 3) || ht_extension_list_has(e, "GL_ARB_multitexture"));
    c->has_combine = version_at_least(c, 1, 3) || ht_extension_list_has(e, "GL_ARB_texture_env_combine") ||
                     ht_extension_list_has(e, "GL_EXT_texture_env_combine");
    c->has_crossbar = version_at_least(c, 1, 4) || ht_extension_list_has(e, "GL_ARB_texture_env_crossbar");
    c->has_3d_textures = gl->has_tex3d &&
        (version_at_least(c, 1, 2) || ht_extension_list_has(e, "GL_EXT_texture3D"));
    c->has_vbo = gl->has_vbo &&
        (version_at_least(c, 1, 5) || ht_extension_list_has(e, "GL_ARB_vertex_buffer_object"));
    c->has_shaders = gl->has_shaders && version_at_least(c, 2, 0);
    c->has_vertex_shaders = c->has_fragment_shaders = c->has_shaders;
}

ht_result ht_caps_probe(ht_getproc_fn getproc, ht_caps *out) {
    if (!getproc || !out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    ht_gl gl;
    char err[160];
    ht_result r = ht_gl_load(&gl, getproc, err, sizeof err);
    if (r != HT_OK) return r;
    return ht_caps_probe_gl(&gl, out);
}

ht_result ht_caps_probe_gl(const ht_gl *gl, ht_caps *out) {
    if (!gl || !out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    while (gl->GetError() != GL_NO_ERROR) {}

    const char *version = (const char *)gl->GetString(GL_VERSION);
    if (!version || !ht_parse_version(version, false, &out->gl_major, &out->gl_minor))
        return HT_ERR_GL; /* no current context, or a driver that names no version */
    snprintf(out->version, sizeof out->version, "%s", version);
    const char *renderer = (const char *)gl->GetString(GL_RENDERER);
    snprintf(out->renderer, sizeof out->renderer, "%s", renderer ? renderer : "");

    /* GL 3.x core has no GL_EXTENSIONS string; compatibility contexts keep it
       but glGetStringi is the one that works on both. */
    if (out->gl_major >= 3 && gl->has_stringi) {
        GLint n = 0;
        gl->GetIntegerv(GL_NUM_EXTENSIONS, &n);
        for (GLint i = 0; i < n; i++) {
            const char *name = (const char *)gl->GetStringi(GL_EXTENSIONS, (GLuint)i);
            if (name) append_extension(out->extensions, sizeof out->extensions, name);
        }
    } else {
        copy_extensions(out->extensions, sizeof out->extensions,
                        (const char *)gl->GetString(GL_EXTENSIONS));
    }

    derive_flags(out, gl);
    out->texture_units = 1;
    if (out->has_multitexture) {
        GLint units = 1;
        gl->GetIntegerv(GL_MAX_TEXTURE_UNITS, &units);
        out->texture_units = units > 1 ? units : 1;
    }
    if (out->has_3d_textures) {
        GLint size = 0;
        gl->GetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &size);
        out->max_3d_texture_size = size > 0 ? size : 0;
    }
    if (out->has_shaders) {
        /* GL 2.0 guarantees GLSL 1.10; some drivers leave the string out. */
        const char *sl = (const char *)gl->GetString(GL_SHADING_LANGUAGE_VERSION);
        if (!ht_parse_version(sl, true, &out->glsl_major, &out->glsl_minor) || out->glsl_major < 1) {
            out->glsl_major = 1;
            out->glsl_minor = 10;
        }
    }
    while (gl->GetError() != GL_NO_ERROR) {}
    return HT_OK;
}

bool ht_caps_has_extension(ht_getproc_fn getproc, const char *name) {
    ht_caps caps;
    if (!name || ht_caps_probe(getproc, &caps) != HT_OK) return false;
    return ht_caps_satisfies_extension(&caps, name);
}

void ht_caps_apply_profile(ht_caps *c, const ht_device_profile *p) {
    if (!c || !p) return;
    if ((p->gl_major || p->gl_minor) &&
        (c->gl_major > p->gl_major || (c->gl_major == p->gl_major && c->gl_minor > p->gl_minor))) {
        c->gl_major = p->gl_major;
        c->gl_minor = p->gl_minor;
    }
    if ((p->glsl_major || p->glsl_minor) &&
        (c->glsl_major > p->glsl_major || (c->glsl_major == p->glsl_major && c->glsl_minor > p->glsl_minor))) {
        c->glsl_major = p->glsl_major;
        c->glsl_minor = p->glsl_minor;
    }
    if (p->texture_units > 0 && c->texture_units > p->texture_units) c->texture_units = p->texture_units;
    if (p->max_3d_texture_size > 0 && c->max_3d_texture_size > p->max_3d_texture_size)
        c->max_3d_texture_size = p->max_3d_texture_size;
    if (p->hide_extensions) {
        char kept[HT_CAPS_EXTENSIONS_SIZE];
        kept[0] = '\0';
        char name[128];
        const char *s = c->extensions;
        while (*s) {
            while (*s == ' ') s++;
            size_t n = strcspn(s, " ");
            if (n > 0 && n < sizeof name) {
                memcpy(name, s, n);
                name[n] = '\0';
                if (!ht_extension_list_has(p->hide_extensions, name))
                    append_extension(kept, sizeof kept, name);
            }
            s += n;
        }
        memcpy(c->extensions, kept, sizeof kept);
    }
    /* Re-derive from the lowered version and list; a flag never comes back. */
    ht_gl present = { .has_tex3d = c->has_3d_textures, .has_multitexture = c->has_multitexture,
                      .has_vbo = c->has_vbo && !p->no_vbo, .has_shaders = c->has_shaders && !p->no_shaders };
    bool combine = c->has_combine, crossbar = c->has_crossbar;
    bool fragment = c->has_fragment_shaders && !p->no_fragment_shaders;
    derive_flags(c, &present);
    c->has_combine = c->has_combine && combine;
    c->has_crossbar = c->has_crossbar && crossbar;
    c->has_fragment_shaders = c->has_shaders && fragment;
    /* A hidden extension is hidden even where its version made it core. */
    const char *h = p->hide_extensions;
    if (ht_extension_list_has(h, "GL_ARB_multitexture")) c->has_multitexture = false;
    if (ht_extension_list_has(h, "GL_ARB_texture_env_combine") || ht_extension_list_has(h, "GL_EXT_texture_env_combine"))
        c->has_combine = false;
    if (ht_extension_list_has(h, "GL_ARB_texture_env_crossbar")) c->has_crossbar = false;
    if (ht_extension_list_has(h, "GL_EXT_texture3D")) c->has_3d_textures = false;
    if (ht_extension_list_has(h, "GL_ARB_vertex_buffer_object")) c->has_vbo = false;
    if (ht_extension_list_has(h, "GL_ARB_shader_objects") || ht_extension_list_has(h, "GL_ARB_vertex_shader"))
        c->has_shaders = c->has_vertex_shaders = c->has_fragment_shaders = false;
    if (ht_extension_list_has(h, "GL_ARB_fragment_shader")) c->has_fragment_shaders = false;
    if (!c->has_shaders) c->glsl_major = c->glsl_minor = 0;
    if (!c->has_multitexture) c->texture_units = 1;
    if (!c->has_3d_textures) c->max_3d_texture_size = 0;
}

/* caps.c — what the current GL context offers, and device profiles that
   pretend it offers less. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "caps.h"

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

bool ht_extension_list_has(const char *list, const char *name) {
    if (!list || !name || !name[0]) return false;
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)) != NULL; p += n) {
        bool starts = p == list || p[-1] == ' ';
        bool ends = p[n] == '\0' || p[n] == ' ';
        if (starts && ends) return true;
    }
    return false;
}

typedef enum core_flag { FLAG_NONE, FLAG_MULTITEXTURE, FLAG_COMBINE, FLAG_CROSSBAR, FLAG_3D,
                         FLAG_VBO, FLAG_SHADERS, FLAG_FRAGMENT } core_flag;

/* Every extension the runtime asks about by name, one known_extensions bit
   each (at most 32). Those with a version became core then, and the flag
   says whether this context (after its profile) may use them; version 0.0:
   never core here, only the list counts. es1: core since GL ES 1.<es1>
   (multitexture and edge clamping in 1.0; combiners with DOT3 and VBOs in
   1.1), -1 never: the only way the desktop names are met on ES 1.x. */
static const struct { const char *name; int major, minor; core_flag flag; int es1; } known[] = {
    { "GL_EXT_texture3D", 1, 2, FLAG_3D, -1 },
    { "GL_EXT_texture_edge_clamp", 1, 2, FLAG_NONE, 0 },
    { "GL_SGIS_texture_edge_clamp", 1, 2, FLAG_NONE, 0 },
    { "GL_ARB_multitexture", 1, 3, FLAG_MULTITEXTURE, 0 },
    { "GL_ARB_texture_env_combine", 1, 3, FLAG_COMBINE, 1 },
    { "GL_EXT_texture_env_combine", 1, 3, FLAG_COMBINE, 1 },
    { "GL_ARB_texture_env_dot3", 1, 3, FLAG_COMBINE, 1 },
    { "GL_ARB_texture_cube_map", 1, 3, FLAG_NONE, -1 },
    { "GL_ARB_texture_border_clamp", 1, 3, FLAG_NONE, -1 },
    { "GL_ARB_texture_env_crossbar", 1, 4, FLAG_CROSSBAR, -1 },
    { "GL_ARB_vertex_buffer_object", 1, 5, FLAG_VBO, 1 },
    { "GL_ARB_shader_objects", 2, 0, FLAG_SHADERS, -1 },
    { "GL_ARB_vertex_shader", 2, 0, FLAG_SHADERS, -1 },
    { "GL_ARB_fragment_shader", 2, 0, FLAG_FRAGMENT, -1 },
    { "GL_ARB_shading_language_100", 2, 0, FLAG_SHADERS, -1 },
    { "GL_ARB_texture_non_power_of_two", 2, 0, FLAG_NONE, -1 },
    { "GL_EXT_texture_cube_map", 0, 0, FLAG_NONE, -1 },
    { "GL_ARB_texture_rectangle", 0, 0, FLAG_NONE, -1 },
    { "GL_NV_texture_rectangle", 0, 0, FLAG_NONE, -1 },
    { "GL_EXT_texture_rectangle", 0, 0, FLAG_NONE, -1 },
};
#define KNOWN_COUNT (int)(sizeof known / sizeof known[0])
_Static_assert(sizeof known / sizeof known[0] <= 32, "known_extensions is 32 bits");

static int known_index(const char *name, size_t n) {
    for (int i = 0; i < KNOWN_COUNT; i++)
        if (strlen(known[i].name) == n && memcmp(known[i].name, name, n) == 0) return i;
    return -1;
}

void ht_caps_note_extensions(ht_caps *c, const char *list) {
    while (list && *list) {
        while (*list == ' ') list++;
        size_t n = strcspn(list, " ");
        int k = n ? known_index(list, n) : -1;
        if (k >= 0) c->known_extensions |= 1u << k;
        list += n;
    }
}

bool ht_caps_lists_extension(const ht_caps *c, const char *name) {
    int k = name ? known_index(name, strlen(name)) : -1;
    return k >= 0 && (c->known_extensions & (1u << k));
}

static bool flag_set(const ht_caps *c, core_flag f) {
    switch (f) {
    case FLAG_NONE: return true;
    case FLAG_MULTITEXTURE: return c->has_multitexture;
    case FLAG_COMBINE: return c->has_combine;
    case FLAG_CROSSBAR: return c->has_crossbar;
    case FLAG_3D: return c->has_3d_textures;
    case FLAG_VBO: return c->has_vbo;
    case FLAG_SHADERS: return c->has_shaders;
    case FLAG_FRAGMENT: return c->has_shaders && c->has_fragment_shaders;
    }
    return false;
}

bool ht_caps_satisfies_extension(const ht_caps *c, const char *list, const char *name) {
    if (!c || !name) return false;
    int k = known_index(name, strlen(name));
    if (k < 0) return ht_extension_list_has(list, name);
    if (!flag_set(c, known[k].flag)) return false;
    bool core = c->es ? known[k].es1 >= 0 && ht_caps_es1(c) && ht_caps_gl_at_least(c, 1, known[k].es1)
                      : known[k].major > 0 && ht_caps_gl_at_least(c, known[k].major, known[k].minor);
    return (c->known_extensions & (1u << k)) || core;
}

void ht_caps_hide_extensions(char *list, const char *hide) {
    if (!list || !hide) return;
    char *out = list;
    const char *s = list;
    while (*s) {
        while (*s == ' ') s++;
        size_t n = strcspn(s, " ");
        if (n == 0) break;
        char name[128];
        bool hidden = n < sizeof name && (memcpy(name, s, n), name[n] = '\0', ht_extension_list_has(hide, name));
        if (!hidden) {
            if (out != list) *out++ = ' ';
            memmove(out, s, n);
            out += n;
        }
        s += n;
    }
    *out = '\0';
}

/* Appends name to a growing heap list; false when out of memory. */
static bool append_extension(char **list, size_t *used, size_t *cap, const char *name) {
    size_t n = strlen(name);
    if (n == 0) return true;
    if (*used + n + 2 > *cap) {
        size_t grow = (*cap ? *cap * 2 : 4096) + n;
        char *p = realloc(*list, grow);
        if (!p) return false;
        *list = p;
        *cap = grow;
    }
    if (*used) (*list)[(*used)++] = ' ';
    memcpy(*list + *used, name, n + 1);
    *used += n;
    return true;
}

/* GL ES: what its version makes core. ES 1.1 is fixed-function with
   multitexture, GL_COMBINE (DOT3 too) and VBOs core; ES 1.0 has neither
   combiners nor VBOs; ES 2.0 and later are shaders, VBOs and units for
   samplers, with neither combiners nor 3D textures the tiers could use.
   No ES has the crossbar (GL_TEXTUREn sources) or 3D textures here. */
static void derive_es_flags(ht_caps *c, const ht_gl *gl) {
    const bool programmable = c->gl_major >= 2, es11 = !programmable && ht_caps_gl_at_least(c, 1, 1);
    c->has_multitexture = gl->has_multitexture;
    c->has_combine = es11 && gl->has_fixed;
    c->has_crossbar = false;
    c->has_3d_textures = false;
    c->has_vbo = gl->has_vbo && (programmable || es11);
    c->has_shaders = programmable && gl->has_shaders;
    c->has_vertex_shaders = c->has_fragment_shaders = c->has_shaders;
}

/* Derived flags from version, known extensions and loaded entry points. */
static void derive_flags(ht_caps *c, const ht_gl *gl) {
    if (c->es) {
        derive_es_flags(c, gl);
        return;
    }
    c->has_multitexture = gl->has_multitexture &&
        (ht_caps_gl_at_least(c, 1, 3) || ht_caps_lists_extension(c, "GL_ARB_multitexture"));
    c->has_combine = ht_caps_gl_at_least(c, 1, 3) || ht_caps_lists_extension(c, "GL_ARB_texture_env_combine") ||
                     ht_caps_lists_extension(c, "GL_EXT_texture_env_combine");
    c->has_crossbar = ht_caps_gl_at_least(c, 1, 4) || ht_caps_lists_extension(c, "GL_ARB_texture_env_crossbar");
    c->has_3d_textures = gl->has_tex3d &&
        (ht_caps_gl_at_least(c, 1, 2) || ht_caps_lists_extension(c, "GL_EXT_texture3D"));
    c->has_vbo = gl->has_vbo &&
        (ht_caps_gl_at_least(c, 1, 5) || ht_caps_lists_extension(c, "GL_ARB_vertex_buffer_object"));
    c->has_shaders = gl->has_shaders && ht_caps_gl_at_least(c, 2, 0);
    c->has_vertex_shaders = c->has_fragment_shaders = c->has_shaders;
}

ht_result ht_caps_probe(ht_getproc_fn getproc, ht_caps *out) {
    if (!getproc || !out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    ht_gl gl;
    char err[160];
    ht_result r = ht_gl_load(&gl, getproc, err, sizeof err);
    if (r != HT_OK) return r;
    return ht_caps_probe_gl(&gl, out, NULL);
}

ht_result ht_caps_probe_gl(const ht_gl *gl, ht_caps *out, char **extensions) {
    if (extensions) *extensions = NULL;
    if (!gl || !out) return HT_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    while (gl->GetError() != GL_NO_ERROR) {}

    const char *version = (const char *)gl->GetString(GL_VERSION);
    if (!version || !ht_parse_version(version, false, &out->gl_major, &out->gl_minor))
        return HT_ERR_GL; /* no current context, or a driver that names no version */
    snprintf(out->version, sizeof out->version, "%s", version);
    /* "OpenGL ES 3.2 Mesa ...", "OpenGL ES-CM 1.1 ...": the number after the
       prefix is the ES version (ht_parse_version skips to it). */
    out->es = strncmp(version, "OpenGL ES", 9) == 0;
    const char *renderer = (const char *)gl->GetString(GL_RENDERER);
    snprintf(out->renderer, sizeof out->renderer, "%s", renderer ? renderer : "");

    /* GL 3.x core has no GL_EXTENSIONS string; compatibility contexts keep it
       but glGetStringi is the one that works on both. */
    char *list = NULL;
    size_t used = 0, cap = 0;
    bool keep = extensions != NULL;
    if (out->gl_major >= 3 && gl->has_stringi) {
        GLint n = 0;
        gl->GetIntegerv(GL_NUM_EXTENSIONS, &n);
        for (GLint i = 0; i < n; i++) {
            const char *name = (const char *)gl->GetStringi(GL_EXTENSIONS, (GLuint)i);
            if (!name || strchr(name, ' ')) continue;
            ht_caps_note_extensions(out, name);
            if (keep) keep = append_extension(&list, &used, &cap, name);
        }
    } else {
        const char *all = (const char *)gl->GetString(GL_EXTENSIONS);
        ht_caps_note_extensions(out, all);
        if (keep && all) keep = append_extension(&list, &used, &cap, all);
    }
    if (extensions && keep) *extensions = list ? list : calloc(1, 1);
    else free(list);

    derive_flags(out, gl);
    out->texture_units = 1;
    if (out->has_multitexture) {
        /* Shader units on ES 2.0+ (GL_MAX_TEXTURE_UNITS is the fixed-function
           count, ES 1.x's and desktop GL's). */
        GLint units = 1;
        gl->GetIntegerv(out->es && out->gl_major >= 2 ? GL_MAX_TEXTURE_IMAGE_UNITS : GL_MAX_TEXTURE_UNITS, &units);
        out->texture_units = units > 1 ? units : 1;
    }
    /* Desktop GLSL floats are 32-bit; an ES fragment stage says what it has
       (range and precision 0: no highp). */
    out->fragment_highp = !out->es;
    if (out->es && out->has_shaders && gl->GetShaderPrecisionFormat) {
        GLint range[2] = { 0, 0 }, precision = 0;
        gl->GetShaderPrecisionFormat(GL_FRAGMENT_SHADER, GL_HIGH_FLOAT, range, &precision);
        out->fragment_highp = precision > 0 && range[1] > 0;
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
            out->glsl_minor = out->es ? 0 : 10; /* ES 2.0 guarantees ESSL 1.00 */
        }
    }
    while (gl->GetError() != GL_NO_ERROR) {}
    return HT_OK;
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
    /* An ES device's version caps an ES context's (the renderer refuses an ES
       profile on desktop GL); its ESSL follows: 1.00 below ES 3.0. */
    if (c->es && (p->es_major || p->es_minor) &&
        (c->gl_major > p->es_major || (c->gl_major == p->es_major && c->gl_minor > p->es_minor))) {
        c->gl_major = p->es_major;
        c->gl_minor = p->es_minor;
        int essl_major = c->gl_major < 3 ? 1 : c->gl_major, essl_minor = c->gl_major < 3 ? 0 : c->gl_minor * 10;
        if (!ht_version_at_least(essl_major, essl_minor, c->glsl_major, c->glsl_minor)) {
            c->glsl_major = essl_major;
            c->glsl_minor = essl_minor;
        }
    }
    if (p->no_fragment_highp) c->fragment_highp = false;
    if (p->max_3d_texture_size > 0 && c->max_3d_texture_size > p->max_3d_texture_size)
        c->max_3d_texture_size = p->max_3d_texture_size;
    for (int k = 0; p->hide_extensions && k < KNOWN_COUNT; k++)
        if (ht_extension_list_has(p->hide_extensions, known[k].name)) c->known_extensions &= ~(1u << k);
    /* Re-derive from the lowered version and list; a flag never comes back. */
    ht_gl present = { .has_fixed = true, .has_tex3d = c->has_3d_textures, .has_multitexture = c->has_multitexture,
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

/* Named profiles (hairtier.h): what a GL 1.1, 1.3 or 2.0 device had. GL
   1.3 and 2.0 cap the version as MESA_GL_VERSION_OVERRIDE does (the
   driver's extensions and units stay); GL 1.1 also hides what made the
   combiner tiers possible on 1.1 drivers. */
static const struct { const char *name; ht_device_profile profile; } named_profiles[] = {
    { "gl11", { .gl_major = 1, .gl_minor = 1, .texture_units = 1,
                .hide_extensions = "GL_ARB_multitexture GL_ARB_texture_env_combine GL_EXT_texture_env_combine "
                                   "GL_ARB_vertex_buffer_object GL_ARB_shader_objects GL_ARB_vertex_shader "
                                   "GL_ARB_fragment_shader GL_EXT_texture3D" } },
    { "gl13", { .gl_major = 1, .gl_minor = 3 } },
    { "gl20", { .gl_major = 2, .gl_minor = 0, .glsl_major = 1, .glsl_minor = 10 } },
    /* GL ES devices (docs/materials.md "Device profiles" cites each):
       Raspberry Pi 1-3 (Mesa vc4: ES 2.0), Mali-400/450 (Mesa lima: ES 2.0,
       fp16 fragment stage), Raspberry Pi 4 (Mesa v3d: ES 3.1); units: the
       ES 2.0 minimum (8) where no driver number is cited, ES 3.x's 16. */
    { "videocore4", { .es_major = 2, .es_minor = 0, .texture_units = 8,
                      .hide_extensions = "GL_OES_element_index_uint" } },
    { "mali400", { .es_major = 2, .es_minor = 0, .texture_units = 8, .no_fragment_highp = true } },
    { "videocore6", { .es_major = 3, .es_minor = 1, .texture_units = 16 } },
};

ht_result ht_device_profile_parse(const char *text, ht_device_profile *out, char *err, size_t err_size) {
    *out = (ht_device_profile){ 0 };
    if (!text || !text[0] || strcmp(text, "none") == 0) return HT_OK;
    for (size_t i = 0; i < sizeof named_profiles / sizeof named_profiles[0]; i++)
        if (strcmp(text, named_profiles[i].name) == 0) {
            *out = named_profiles[i].profile;
            return HT_OK;
        }
    snprintf(err, err_size, "\"%.40s\" is not none, gl11, gl13, gl20, videocore4, mali400 or videocore6", text);
    return HT_ERR_INVALID_ARGUMENT;
}

bool ht_device_profile_is_zero(const ht_device_profile *p) {
    return !p->gl_major && !p->gl_minor && !p->glsl_major && !p->glsl_minor && !p->texture_units &&
           !p->max_3d_texture_size && !p->hide_extensions && !p->no_fragment_shaders && !p->no_shaders &&
           !p->no_vbo && !p->es_major && !p->es_minor && !p->no_fragment_highp;
}

double ht_timing_warmup_ms(const char *renderer) {
    static const char *const software[] = { "llvmpipe", "softpipe", "Software Rasterizer", "Mesa OffScreen", "SwiftShader" };
    for (size_t i = 0; renderer && i < sizeof software / sizeof software[0]; i++)
        if (strstr(renderer, software[i])) return 0.0;
    return renderer ? HT_TIMING_WARMUP_MS : 0.0;
}

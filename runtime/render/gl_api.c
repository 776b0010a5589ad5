/* gl_api.c — fills ht_gl from a getproc; see gl_api.h. */
#include <stdio.h>
#include <string.h>

#include "gl_api.h"

enum gl_group { GROUP_core, GROUP_fixed, GROUP_desktop, GROUP_tex3d, GROUP_multitexture, GROUP_client_units, GROUP_vbo, GROUP_shaders, GROUP_stringi,
                GROUP_precision, GROUP_vao, GROUP_LAST = GROUP_vao };

typedef struct gl_entry {
    const char *name;   /* without the "gl" prefix */
    enum gl_group group;
    size_t offset;
} gl_entry;

static const gl_entry entries[] = {
#define HT_GL_ENTRY(group, ret, name, args) { #name, GROUP_##group, offsetof(ht_gl, name) },
    HT_GL_FUNCTIONS(HT_GL_ENTRY)
#undef HT_GL_ENTRY
};

#define ENTRY_COUNT (sizeof entries / sizeof entries[0])

static void *lookup(ht_getproc_fn getproc, const char *name) {
    static const char *const suffixes[] = { "", "ARB", "EXT" };
    char full[96];
    for (size_t i = 0; i < sizeof suffixes / sizeof suffixes[0]; i++) {
        snprintf(full, sizeof full, "gl%s%s", name, suffixes[i]);
        void *p = getproc(full);
        if (p) return p;
    }
    return NULL;
}

static void clear_group(ht_gl *gl, enum gl_group group) {
    void *null = NULL;
    for (size_t i = 0; i < ENTRY_COUNT; i++)
        if (entries[i].group == group) memcpy((char *)gl + entries[i].offset, &null, sizeof null);
}

ht_result ht_gl_load(ht_gl *gl, ht_getproc_fn getproc, char *err, size_t err_size) {
    if (!gl || !getproc) {
        snprintf(err, err_size, "gl_api: getproc: required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    memset(gl, 0, sizeof *gl);
    bool group_ok[GROUP_LAST + 1];
    for (int g = 0; g <= GROUP_LAST; g++) group_ok[g] = true;
    /* GL_VERSION first: whether the fixed-function group is required. */
    void *get_string = lookup(getproc, "GetString");
    if (get_string) {
        const GLubyte *(APIENTRYP fn)(GLenum);
        memcpy(&fn, &get_string, sizeof fn);
        const char *version = (const char *)fn(GL_VERSION);
        gl->es = version && strncmp(version, "OpenGL ES", 9) == 0;
    }
    for (size_t i = 0; i < ENTRY_COUNT; i++) {
        void *p = lookup(getproc, entries[i].name);
        if (!p) {
            if (entries[i].group == GROUP_core ||
                ((entries[i].group == GROUP_fixed || entries[i].group == GROUP_desktop) && !gl->es)) {
                snprintf(err, err_size, "gl_api: gl%s: entry point missing (GL 1.1 required)",
                         entries[i].name);
                return HT_ERR_UNSUPPORTED;
            }
            group_ok[entries[i].group] = false;
            continue;
        }
        /* data and function pointers share a representation on every
           platform GL runs on (POSIX requires it for dlsym). */
        memcpy((char *)gl + entries[i].offset, &p, sizeof p);
    }
    for (int g = GROUP_fixed; g <= GROUP_LAST; g++)
        if (!group_ok[g]) clear_group(gl, (enum gl_group)g);
    gl->has_fixed = group_ok[GROUP_fixed];
    /* Never called on ES (gl_api.h), whatever getproc answered. */
    if (gl->es) clear_group(gl, GROUP_desktop);
    gl->has_tex3d = group_ok[GROUP_tex3d];
    /* glClientActiveTexture: GL 1.3's client side of the units (ES 2.0 has
       none); without glActiveTexture it is of no use either. */
    gl->has_multitexture = group_ok[GROUP_multitexture];
    if (!gl->has_multitexture) clear_group(gl, GROUP_client_units);
    gl->has_vbo = group_ok[GROUP_vbo];
    gl->has_shaders = group_ok[GROUP_shaders];
    gl->has_stringi = group_ok[GROUP_stringi];
    gl->has_precision = group_ok[GROUP_precision];
    gl->has_vao = group_ok[GROUP_vao];
    return HT_OK;
}

void ht_gl_restrict(ht_gl *gl, bool tex3d, bool multitexture, bool vbo, bool shaders) {
    if (!tex3d) { clear_group(gl, GROUP_tex3d); gl->has_tex3d = false; }
    if (!multitexture) {
        clear_group(gl, GROUP_multitexture);
        clear_group(gl, GROUP_client_units);
        gl->has_multitexture = false;
    }
    if (!vbo) { clear_group(gl, GROUP_vbo); gl->has_vbo = false; }
    if (!shaders) { clear_group(gl, GROUP_shaders); gl->has_shaders = false; }
}

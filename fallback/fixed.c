/* fixed.c — the `fixed` tier's backend (about 650 lines, one job: applying
   a combiner program and feeding its stages; the CPU coordinates live in
   fixed_soa.c, the texture matrix in fixed_coords.c): a GL 1.3 texture-combiner program
   (fixed.json, combiner.h) applied as data, over a lookup texture of the
   model's dot products (Heidrich-Seidel). No shader object anywhere: only
   glTexEnv, textures and vertex arrays (buffer objects where the device
   has them, client arrays where it has none).

   Per frame, by the LUT stage's rule (combiner.h): "cpu-dots" computes the
   LUT coordinates and primary colours per vertex of the draw range on the CPU
   (fixed_coords.h) for the frame's lights and eye; "texture-matrix" makes
   the LUT unit's texture matrix (16 floats, infinite viewer: the view
   matrix's view direction; loaded by each sub-pass for its light), points the unit's texture coordinates at the
   mesh's tangents (normalized once, in set_mesh, and uploaded there with
   the uv into a buffer object of its own) and recomputes the
   primary colours only when the light's colour changes. A frame whose key
   light is a point light cannot use the matrix (the renderer shades lights
   as the bundle plans them, so only a caller driving the backend directly
   gets there): it gets CPU coordinates, with one log line the first time.

   A program with "add_lights" (combiner.h) draws each further light as
   one more sub-pass of every pass that writes colour: the same stages,
   that light's coordinates (or texture matrix) and primary colours, kept
   per light exactly as the key light's are, added to the framebuffer
   (bind_pass sets the blend and depth test for it; the renderer's next
   pass sets its own state again).

   Per pass: every stage of the program is set up on its unit (bind_pass);
   the prime-Z pass enables only the stages its alpha depends on (the
   albedo's alpha; no LUT), since its colour writes are off. Before each
   draw (point_stage_arrays):
   stages read their texture coordinates from the CPU arrays ("cpu-dots"),
   the tangents ("texture-matrix") or the vertex uv ("uv"), the colour
   array is the primary colour, each from a buffer object uploaded only
   when it changed (a steady frame uploads nothing and points no client
   memory; NVIDIA copies client arrays across the bus at every draw); the
   renderer then draws with its index
   buffer over its range, so passes, state and draw ranges stay those of
   every other tier. end_frame puts GL's initial texture-environment state
   and identity texture matrix back on every unit it touched. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "caps.h"
#include "combiner.h"
#include "errfmt.h"
#include "fixed.h"
#include "fixed_coords.h"
#include "fixed_device.h"
#include "fixed_soa.h"
#include "fixed_split.h"
#include "gl_error.h"
#include "tier_program.h"
#include "gl_texture.h"
#include <hairtier/image.h>
#include "vecmath.h"

/* What one sub-pass's light needs per vertex: sub-pass 0 the key light,
   the others the program's add_lights. */
typedef struct light_slot {
    int light;                                /* index into the frame's lights */
    float *coords;                            /* 3 per vertex: CPU LUT texcoords (NULL until needed) */
    float *colors;                            /* 4 per vertex: primary colour */
    bool colors_valid;                        /* colors hold color_key's light */
    float color_key[4];                       /* lit (0/1), light colour rgb */
    bool coords_valid;                        /* coords hold coords_key's eye and light */
    float coords_key[8];                      /* eye, light vector, lit (0/1), point (0/1) */
    uint32_t coords_range[2], colors_range[2];  /* the vertices they were made for (first, count) */
    GLuint coord_buffer, color_buffer;        /* where the device reads them (VBOs, when it has them) */
    float matrix[16];                         /* "texture-matrix": this frame's */
    bool frame_matrix;                        /* this frame's matrix is valid */
    bool lit;                                 /* the frame has this light */
} light_slot;

typedef struct fixed_state {
    const ht_gl *gl;
    float opacity_cut;                        /* the frame's width rule (tier.h) */
    bool opacity_refused;                     /* logged once: the program's last alpha cannot take it */
    const ht_caps *caps;
    ht_combiner_program program;
    GLuint textures[HT_COMBINER_MAX_STAGES];  /* per stage */
    int prime_first;                          /* first stage the prime-Z pass enables */
    int lut_unit;                             /* the unit of the stage reading the LUT */
    bool matrix_rule;                         /* the program's LUT coords are "texture-matrix" */
    bool device_variant;                      /* the program is fixed_device.h's, over t1 (ht_variant) */
    int split_unit;                           /* no 3D textures: the split LUT's first unit (fixed_split.h), or -1 */
    int split_error;                          /* its largest texel error, 1/255 */
    bool matrix_loaded;                       /* the LUT unit's texture matrix is not identity */
    bool point_light_logged;
    ht_vertex *vertices;                      /* copy of the mesh's, for coords, tangents and uv */
    uint32_t vertex_count;
    light_slot slots[HT_MAX_LIGHTS];          /* per sub-pass */
    int slot_count;
    ht_fixed_soa soa;                         /* "cpu-dots": the static part, float, per mesh */
    /* What the draws read per vertex besides the renderer's positions:
       packed, (tangent, uv) under "texture-matrix", else uv alone, so a
       still frame fetches no more than it uses (VBO, when it has them) */
    float *statics;
    int static_width;                         /* floats per vertex: 5 or 2 */
    GLuint vertex_buffer;
    uint64_t cpu_vertices;                    /* per-vertex CPU work so far */
    uint32_t range[2];                        /* this frame's drawn vertices (tier.h): first, count */
    ht_log_fn log;
    void *log_user;
} fixed_state;

/* ---- creation ---- */

static int alpha_argument_count(GLenum fn) {
    switch (fn) {
    case GL_REPLACE: return 1;
    case GL_INTERPOLATE: return 3;
    default: return 2;
    }
}

static bool alpha_reads(const ht_combiner_stage *s, GLenum source) {
    for (int a = 0; a < alpha_argument_count(s->combine_alpha); a++)
        if (s->source_alpha[a] == source) return true;
    return false;
}

/* The prime-Z pass writes no colour: only the stages the final alpha
   depends on are needed. They are a suffix of the program (a stage not
   reading PREVIOUS alpha cuts off everything before it); its first stage
   is dropped too when it merely forwards the primary alpha, which a
   disabled unit does by itself. */
static int prime_first_stage(const ht_combiner_program *p) {
    int first = p->stage_count - 1;
    while (first > 0 && alpha_reads(&p->stages[first], GL_PREVIOUS)) first--;
    const ht_combiner_stage *s = &p->stages[first];
    bool forwards_primary = s->combine_alpha == GL_REPLACE && s->operand_alpha[0] == GL_SRC_ALPHA &&
                            s->alpha_scale == 1 &&
                            (s->source_alpha[0] == GL_PRIMARY_COLOR || s->source_alpha[0] == GL_PREVIOUS);
    return forwards_primary ? first + 1 : first;
}

static void destroy(void *state) {
    fixed_state *s = state;
    if (!s) return;
    for (int i = 0; i < HT_COMBINER_MAX_STAGES; i++)
        if (s->textures[i]) s->gl->DeleteTextures(1, &s->textures[i]);
    free(s->vertices);
    free(s->statics);
    for (int k = 0; k < s->slot_count; k++) {
        light_slot *slot = &s->slots[k];
        free(slot->coords);
        free(slot->colors);
        if (slot->coord_buffer) s->gl->DeleteBuffers(1, &slot->coord_buffer);
        if (slot->color_buffer) s->gl->DeleteBuffers(1, &slot->color_buffer);
    }
    ht_fixed_soa_free(&s->soa);
    if (s->vertex_buffer) s->gl->DeleteBuffers(1, &s->vertex_buffer);
    free(s);
}

static ht_result load_program(fixed_state *s, const ht_tier_context *ctx, char *path, size_t path_size,
                              char *err, size_t err_size) {
    ht_result r;
    char *text = ht_tier_program_read(ctx, path, path_size, &r, err, err_size);
    if (!text) return r;
    r = ht_combiner_parse(text, path, &s->program, err, err_size);
    free(text);
    return r;
}

/* What the device must offer for this program: refused with one line. */
static ht_result check_device(const fixed_state *s, const ht_tier_context *ctx, const char *path, bool device,
                              char *err, size_t err_size) {
    const ht_combiner_program *p = &s->program;
    const ht_caps *c = ctx->caps;
    const ht_gl *gl = ctx->gl;
    if (!c->has_combine) {
        snprintf(err, err_size, "needs GL_ARB_texture_env_combine");
        return HT_ERR_UNSUPPORTED;
    }
    if (p->stage_count > c->texture_units) {
        snprintf(err, err_size, "%s: %d stages need %d texture units, have %d%s", path, p->stage_count,
                 p->stage_count, c->texture_units,
                 s->split_unit >= 0 ? " (2 of them for the 3D LUT split in two 2D textures: no 3D textures)" : "");
        return HT_ERR_UNSUPPORTED;
    }
    if (p->stage_count > 1 && (!gl->ActiveTexture || !gl->ClientActiveTexture)) {
        snprintf(err, err_size, "needs GL_ARB_multitexture for %d stages", p->stage_count);
        return HT_ERR_UNSUPPORTED;
    }
    /* Every light the program draws must be one the bundle plans (defect
       F): a light beyond them is never set, and the hair would draw unlit. */
    for (int sub = 0; sub < ht_combiner_sub_passes(p); sub++) {
        const int light = ht_combiner_sub_pass_light(p, sub);
        if (light < ctx->bundle->light_count) continue;
        snprintf(err, err_size, "%s: %s: light %d, the bundle has %d light%s (%s/manifest.json: lights)", path,
                 sub == 0 ? "primary_color" : "add_lights", light, ctx->bundle->light_count,
                 ctx->bundle->light_count == 1 ? "" : "s", ctx->bundle->dir);
        return HT_ERR_PARSE;
    }
    const int *n = p->lut_size;
    int largest = n[0] > n[1] ? n[0] : n[1];
    if (n[2] > largest) largest = n[2];
    for (int i = 0; i < p->stage_count; i++) {
        if (p->stages[i].target != GL_TEXTURE_3D || device) continue;
        if (!c->has_3d_textures || !gl->TexImage3D) {
            snprintf(err, err_size, "LUT %dx%dx%d needs 3D textures (GL 1.2), have none", n[0], n[1], n[2]);
            return HT_ERR_UNSUPPORTED;
        }
        if (largest > c->max_3d_texture_size) {
            snprintf(err, err_size, "LUT %dx%dx%d needs GL_MAX_3D_TEXTURE_SIZE %d, have %d", n[0], n[1], n[2],
                     largest, c->max_3d_texture_size);
            return HT_ERR_UNSUPPORTED;
        }
    }
    return HT_OK;
}


/* Reads a stage's texture and checks it against the manifest (and, for the
   LUT, against the program): the image is width x (height * depth). */
static ht_result read_stage_image(const fixed_state *s, const ht_tier_context *ctx, int stage,
                                  ht_image *img, int *depth, char *path, size_t path_size,
                                  char *err, size_t err_size) {
    const ht_manifest *b = ctx->bundle;
    const ht_combiner_stage *st = &s->program.stages[stage];
    const ht_manifest_texture *t = ht_manifest_find_texture(b, ctx->tier, st->texture);
    if (!t) {
        snprintf(err, err_size, "%s/manifest.json: tiers.%s.textures: \"%s\" (stages[%d] of the program) is "
                 "not listed", b->dir, ctx->tier->name, st->texture, stage);
        return HT_ERR_PARSE;
    }
    const bool is_lut = strcmp(st->texture, s->program.lut_texture) == 0;
    const int *n = s->program.lut_size;
    if (is_lut && (t->width != n[0] || t->height != n[1] || t->depth != n[2])) {
        snprintf(err, err_size, "%s/manifest.json: textures.%s: %dx%dx%d, the program says %dx%dx%d", b->dir,
                 t->name, t->width, t->height, t->depth, n[0], n[1], n[2]);
        return HT_ERR_PARSE;
    }
    if ((st->target == GL_TEXTURE_2D) != (t->depth == 1)) {
        snprintf(err, err_size, "%s/manifest.json: textures.%s.depth: %d, stages[%d] samples a %s texture", b->dir,
                 t->name, t->depth, stage, st->target == GL_TEXTURE_2D ? "2D" : "3D");
        return HT_ERR_PARSE;
    }
    /* A 3D texture's slices are stacked: height x depth rows. */
    ht_result r = ht_bundle_read_png(ht_manifest_source(b), t->file, t->width, t->height * t->depth, img, path,
                                     path_size, err, err_size);
    if (r != HT_OK) return r;
    ht_result npot = ht_gl_texture_check_size(ctx->caps, img->width, img->height / t->depth, t->depth, path, err,
                                              err_size);
    if (npot != HT_OK) {
        ht_image_free(img);
        return npot;
    }
    *depth = t->depth;
    return HT_OK;
}

static ht_result upload_stage(fixed_state *s, const ht_tier_context *ctx, int stage, char *err, size_t err_size) {
    const ht_combiner_stage *st = &s->program.stages[stage];
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    ht_image img = { 0 };
    int depth = 1;
    ht_result r = read_stage_image(s, ctx, stage, &img, &depth, path, sizeof path, err, err_size);
    if (r != HT_OK) return r;
    /* No mipmaps: the LUT is indexed, not minified; albedo as the GLSL tiers. */
    r = ht_gl_texture_upload(s->gl, &(ht_gl_texture_desc){ .target = st->target, .image = &img, .depth = depth,
                                                           .filter = st->filter, .wrap = st->wrap, .name = path },
                             &s->textures[stage], err, err_size);
    ht_image_free(&img);
    return r;
}

/* The device-only variant's LUT: the bundle's 3D LUT resampled into 2D
   (fixed_device.h), uploaded on the stage's unit. */
static ht_result upload_device_lut(fixed_state *s, const ht_tier_context *ctx, int stage, char *err,
                                   size_t err_size) {
    const ht_combiner_stage *st = &s->program.stages[stage];
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    ht_image img = { 0 }, lut = { 0 };
    int depth = 1;
    ht_result r = read_stage_image(s, ctx, stage, &img, &depth, path, sizeof path, err, err_size);
    if (r != HT_OK) return r;
    r = ht_fixed_device_lut(&s->program, &img, &lut);
    ht_image_free(&img);
    if (r != HT_OK) return ht_fail(err, err_size, r, "%s: cannot resample the LUT for the device variant", path);
    r = ht_gl_texture_upload(s->gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D, .image = &lut, .depth = 1,
                                                           .filter = st->filter, .wrap = st->wrap, .name = path },
                             &s->textures[stage], err, err_size);
    ht_image_free(&lut);
    return r;
}

/* No 3D textures: the LUT stage rewritten as fixed_split.h's three stages,
   their two LUT images made from the bundle's 3D one. */
static ht_result split_lut(fixed_state *s, const ht_tier_context *ctx, int stage, ht_image split[2], char *err,
                           size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    ht_image img = { 0 };
    int depth = 1;
    ht_result r = ht_fixed_split_program(&s->program, stage, err, err_size);
    if (r != HT_OK) return r;
    /* the LUT's manifest entry is checked against the original stage */
    ht_combiner_program rewritten = s->program;
    s->program.stages[stage].target = GL_TEXTURE_3D;
    r = read_stage_image(s, ctx, stage, &img, &depth, path, sizeof path, err, err_size);
    s->program = rewritten;
    if (r != HT_OK) return r;
    r = ht_fixed_split_lut(s->program.lut_size, &img, &split[1], &split[0], &s->split_error);
    ht_image_free(&img);
    if (r != HT_OK) return ht_fail(err, err_size, r, "%s: cannot split the 3D LUT into 2D textures", path);
    s->split_unit = stage;
    return HT_OK;
}

/* Stage i's texture where the LUT is split: C, A, then a white texel. */
static ht_result upload_split_stage(fixed_state *s, int i, ht_image split[2], char *err, size_t err_size) {
    static const unsigned char white[4] = { 255, 255, 255, 255 };
    const ht_image texel = { .width = 1, .height = 1, .channels = 4, .pixels = (uint8_t *)white };
    const int part = i - s->split_unit;
    const ht_combiner_stage *st = &s->program.stages[i];
    static const char *const names[3] = { "fixed LUT, c axis", "fixed LUT, a-b slice", "white texel" };
    return ht_gl_texture_upload(s->gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D,
                                                              .image = part < 2 ? &split[part] : &texel,
                                                              .filter = st->filter, .wrap = GL_CLAMP_TO_EDGE,
                                                              .name = names[part] },
                                &s->textures[i], err, err_size);
}

static ht_result create(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    *out = NULL;
    fixed_state *s = calloc(1, sizeof *s);
    if (!s) return HT_ERR_OUT_OF_MEMORY;
    s->gl = ctx->gl;
    s->caps = ctx->caps;
    s->log = ctx->log;
    s->log_user = ctx->log_user;
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    s->split_unit = -1;
    ht_result r = load_program(s, ctx, path, sizeof path, err, err_size);
    const bool device = r == HT_OK && ctx->device_variant && ht_fixed_device_applies(&s->program);
    const int lut3d = r == HT_OK ? ht_fixed_split_lut_stage(&s->program) : -1;
    ht_image split[2] = { { 0 }, { 0 } };
    if (r == HT_OK && lut3d >= 0 && !device && !ctx->caps->has_3d_textures)
        r = split_lut(s, ctx, lut3d, split, err, err_size);
    if (r == HT_OK) r = check_device(s, ctx, path, device, err, err_size);
    s->device_variant = r == HT_OK && device;
    for (int i = 0; r == HT_OK && i < s->program.stage_count; i++)
        r = s->split_unit >= 0 && i >= s->split_unit && i < s->split_unit + 3
                ? upload_split_stage(s, i, split, err, err_size)
            : s->device_variant && s->program.stages[i].coords == HT_COORDS_CPU_DOTS
                ? upload_device_lut(s, ctx, i, err, err_size)
                : upload_stage(s, ctx, i, err, err_size);
    ht_image_free(&split[0]);
    ht_image_free(&split[1]);
    if (r != HT_OK) {
        destroy(s);
        return r;
    }
    if (s->device_variant) ht_fixed_device_program(&s->program, &s->program);
    s->slot_count = ht_combiner_sub_passes(&s->program);
    for (int k = 0; k < s->slot_count; k++) s->slots[k].light = ht_combiner_sub_pass_light(&s->program, k);
    s->prime_first = prime_first_stage(&s->program);
    s->matrix_rule = ht_combiner_lut_coords(&s->program) == HT_COORDS_TEXTURE_MATRIX;
    for (int i = 0; i < s->program.stage_count; i++)
        if (strcmp(s->program.stages[i].texture, s->program.lut_texture) == 0) s->lut_unit = s->program.stages[i].unit;
    const int *n = s->program.lut_size;
    char split_note[112] = "";
    if (s->split_unit >= 0)
        snprintf(split_note, sizeof split_note, ", LUT split into %dx%d + %dx1 2D textures (no 3D textures: texel "
                 "error up to %d/255)", n[0], n[1], n[2], s->split_error);
    char prime[48] = "no stage";
    if (s->prime_first < s->program.stage_count)
        snprintf(prime, sizeof prime, "stages %d..%d", s->prime_first, s->program.stage_count - 1);
    ht_log_linef(s->log, s->log_user, "hairtier: fixed: %d combiner stages, LUT %dx%dx%d scale %d light scale %g, "
                 "%d light%s (%d additive sub-pass%s), prime Z uses %s, coordinates %s%s", s->program.stage_count, n[0],
                 n[1], n[2], s->program.lut_scale, s->program.light_scale, s->slot_count, s->slot_count == 1 ? "" : "s",
                 s->slot_count - 1, s->slot_count == 2 ? "" : "es", prime,
                 s->device_variant ? "by the texture matrix over t1 (infinite viewer: the device-only variant)"
                 : s->matrix_rule  ? "by the texture matrix (infinite viewer)"
                                   : "on the CPU per vertex", split_note);
    *out = s;
    return HT_OK;
}

/* ---- per mesh, per frame ---- */

/* The texture matrix reads the tangent as it is: make it unit once, here,
   so T.L and T.H are cosines (model.c's rule: shorter than
   sqrt(HT_MODEL_MIN_LENGTH2), or not finite, is no direction: zero, and
   ht_fixed_coords_colors makes such a vertex black). */
static void normalize_tangents(ht_vertex *v, size_t n) {
    for (size_t i = 0; i < n; i++) {
        double t[3];
        ht_vec3_from_float(t, v[i].tangent);
        ht_vec3_direction(t, t);
        ht_vec3_store(v[i].tangent, t);
    }
}

/* Copies data into a buffer object the draws read, once per change (not
   once per pass); nothing where the device has no VBOs (the draws point
   client arrays at the data). A refused upload drops the buffer (client
   arrays until the next upload) and is one line naming GL's error and
   what follows (then), or none when then is NULL (the caller's). */
static GLenum upload(fixed_state *s, GLuint *buffer, const void *data, size_t bytes, GLenum usage, const char *then) {
    const ht_gl *gl = s->gl;
    if (!s->caps->has_vbo || !gl->GenBuffers) return GL_NO_ERROR;
    if (!*buffer) gl->GenBuffers(1, buffer);
    gl->BindBuffer(GL_ARRAY_BUFFER, *buffer);
    gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)bytes, data, usage);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    GLenum e = gl->GetError();
    if (e == GL_NO_ERROR) return e;
    if (then) ht_log_linef(s->log, s->log_user, "hairtier: fixed: glBufferData: %s: %s", ht_gl_error_name(e), then);
    gl->DeleteBuffers(1, buffer);
    *buffer = 0;
    return e;
}

/* Vertices range[0] .. + range[1] of an array of `width` floats a vertex
   onto its buffer (sized in set_mesh): only what the frame made; the whole
   array where the buffer is gone (a refused upload). */
static void upload_range(fixed_state *s, GLuint *buffer, const float *data, int width, const char *then) {
    const ht_gl *gl = s->gl;
    const size_t vertex = (size_t)width * sizeof(float);
    if (!*buffer) {
        upload(s, buffer, data, (size_t)s->vertex_count * vertex, GL_DYNAMIC_DRAW, then);
        return;
    }
    gl->BindBuffer(GL_ARRAY_BUFFER, *buffer);
    gl->BufferSubData(GL_ARRAY_BUFFER, (GLintptr)(s->range[0] * vertex), (GLsizeiptr)(s->range[1] * vertex),
                      data + (size_t)s->range[0] * (size_t)width);
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    GLenum e = gl->GetError();
    if (e == GL_NO_ERROR) return;
    ht_log_linef(s->log, s->log_user, "hairtier: fixed: glBufferSubData: %s: %s", ht_gl_error_name(e), then);
    gl->DeleteBuffers(1, buffer);
    *buffer = 0;
}

/* Until the first frame: unlit, inside the LUT. */
static void unlit(float *coords, float *colors, size_t n) {
    for (size_t i = 0; coords && i < 3 * n; i++) coords[i] = 0.5f;
    for (size_t i = 0; i < 4 * n; i++) colors[i] = (i % 4 == 3) ? 1.0f : 0.0f;
}

static ht_result set_mesh(void *state, const ht_mesh *mesh) {
    fixed_state *s = state;
    size_t n = mesh->vertex_count;
    ht_vertex *v = malloc(n ? n * sizeof *v : 1);
    const int width = s->matrix_rule ? 5 : 2;
    float *statics = malloc(n ? n * (size_t)width * sizeof(float) : 1);
    float *coords[HT_MAX_LIGHTS] = { NULL }, *colors[HT_MAX_LIGHTS] = { NULL };
    bool ok = v != NULL && statics != NULL;
    for (int k = 0; ok && k < s->slot_count; k++) {
        coords[k] = s->matrix_rule ? NULL : malloc(n ? n * 3 * sizeof(float) : 1);
        colors[k] = malloc(n ? n * 4 * sizeof(float) : 1);
        ok = (s->matrix_rule || coords[k]) && colors[k];
    }
    ht_fixed_soa soa = { 0 };
    if (ok && n) memcpy(v, mesh->vertices, n * sizeof *v);
    if (ok && s->device_variant) ht_fixed_device_vectors(&s->program, v, n);
    if (ok && s->matrix_rule) normalize_tangents(v, n);
    if (ok && !s->matrix_rule) ok = ht_fixed_soa_make(&s->program, mesh->vertices, n, &soa) == HT_OK;
    if (!ok) {
        free(v);
        free(statics);
        for (int k = 0; k < s->slot_count; k++) {
            free(coords[k]);
            free(colors[k]);
        }
        return HT_ERR_OUT_OF_MEMORY;
    }
    ht_fixed_soa_free(&s->soa);
    s->soa = soa;
    for (size_t i = 0; i < n; i++) {
        float *out = statics + i * (size_t)width;
        if (s->matrix_rule) memcpy(out, v[i].tangent, 3 * sizeof(float));
        memcpy(out + width - 2, v[i].uv, 2 * sizeof(float));
    }
    free(s->vertices);
    s->vertices = v;
    free(s->statics);
    s->statics = statics;
    s->static_width = width;
    s->vertex_count = mesh->vertex_count;
    for (int k = 0; k < s->slot_count; k++) {
        light_slot *slot = &s->slots[k];
        free(slot->coords);
        free(slot->colors);
        slot->coords = coords[k];
        slot->colors = colors[k];
        slot->coords_valid = slot->colors_valid = false;
        unlit(coords[k], colors[k], n);
    }
    /* On the device from here: the tangents and uv for good, the others
       until a frame changes them (every buffer the size of this mesh). */
    if (s->caps->has_vbo)
        while (s->gl->GetError() != GL_NO_ERROR) {}
    /* refused: the renderer drops the mesh with its one line (as fixed4) */
    GLenum e = upload(s, &s->vertex_buffer, statics, n * (size_t)width * sizeof(float), GL_STATIC_DRAW, NULL);
    for (int k = 0; e == GL_NO_ERROR && k < s->slot_count; k++) {
        light_slot *slot = &s->slots[k];
        e = upload(s, &slot->color_buffer, slot->colors, n * 4 * sizeof(float), GL_DYNAMIC_DRAW, NULL);
        if (e == GL_NO_ERROR && slot->coords)
            e = upload(s, &slot->coord_buffer, slot->coords, n * 3 * sizeof(float), GL_DYNAMIC_DRAW, NULL);
    }
    if (e != GL_NO_ERROR) return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
    return HT_OK;
}

static void active_unit(const fixed_state *s, int unit) {
    if (s->gl->ActiveTexture) s->gl->ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
}

/* Loads unit's GL_TEXTURE matrix (identity when m is NULL), keeping the
   caller's matrix mode. */
static void load_texture_matrix(const fixed_state *s, int unit, const float *m) {
    const ht_gl *gl = s->gl;
    GLint mode = GL_MODELVIEW;
    gl->GetIntegerv(GL_MATRIX_MODE, &mode);
    active_unit(s, unit);
    gl->MatrixMode(GL_TEXTURE);
    if (m) gl->LoadMatrixf(m);
    else gl->LoadIdentity();
    gl->MatrixMode((GLenum)mode);
}

static const ht_light *slot_light(const light_slot *slot, const ht_tier_frame *f) {
    return slot->light < f->light_count ? &f->lights[slot->light] : NULL;
}

/* "cpu-dots": a slot's LUT coordinates, only when the eye or its light
   moved (float, structure of arrays: fixed_soa.h). */
static void update_coords(fixed_state *s, light_slot *slot, const ht_tier_frame *f) {
    const ht_light *light = slot_light(slot, f);
    const float key[8] = { f->eye[0], f->eye[1], f->eye[2], light ? light->vector[0] : 0.0f,
                           light ? light->vector[1] : 0.0f, light ? light->vector[2] : 0.0f, light ? 1.0f : 0.0f,
                           light && light->type == HT_LIGHT_POINT ? 1.0f : 0.0f };
    if (slot->coords_valid && memcmp(key, slot->coords_key, sizeof key) == 0 &&
        memcmp(s->range, slot->coords_range, sizeof s->range) == 0)
        return;
    const ht_fixed_soa range = ht_fixed_soa_range(&s->soa, s->range[0], s->range[1]);
    ht_fixed_soa_coords(&s->program, &range, light, f->eye, slot->coords + 3 * (size_t)s->range[0]);
    memcpy(slot->coords_key, key, sizeof key);
    memcpy(slot->coords_range, s->range, sizeof s->range);
    slot->coords_valid = true;
    s->cpu_vertices += s->range[1];
    upload_range(s, &slot->coord_buffer, slot->coords, 3, "client arrays instead");
}

/* A slot's primary colours: per vertex, but only when what they depend on
   (is the light there, its colour) changed. */
static void update_colors(fixed_state *s, light_slot *slot, const ht_tier_frame *f) {
    const ht_light *light = slot_light(slot, f);
    const float key[4] = { light ? 1.0f : 0.0f, light ? light->color[0] : 0.0f, light ? light->color[1] : 0.0f,
                           light ? light->color[2] : 0.0f };
    if (slot->colors_valid && memcmp(key, slot->color_key, sizeof key) == 0 &&
        memcmp(s->range, slot->colors_range, sizeof s->range) == 0)
        return;
    char err[256];
    if (ht_fixed_coords_colors_of(&s->program, slot->light, s->vertices + s->range[0], s->range[1], f->lights,
                                  f->light_count, slot->colors + 4 * (size_t)s->range[0], err, sizeof err) != HT_OK) {
        ht_log_linef(s->log, s->log_user, "hairtier: fixed: %s", err);
        return;
    }
    memcpy(slot->color_key, key, sizeof key);
    memcpy(slot->colors_range, s->range, sizeof s->range);
    slot->colors_valid = true;
    s->cpu_vertices += s->range[1];
    upload_range(s, &slot->color_buffer, slot->colors, 4, "client arrays instead");
}

/* The "texture-matrix" rule for one slot: its matrix, or (a point light)
   CPU coordinates, made on first need. */
static void begin_matrix_slot(fixed_state *s, light_slot *slot, const ht_tier_frame *f) {
    char err[256];
    /* the view matrix's third row is the unit direction from the target to the eye */
    const float view_dir[3] = { f->view[2], f->view[6], f->view[10] };
    ht_result r = ht_fixed_coords_texture_matrix_of(&s->program, slot->light, f->lights, f->light_count, view_dir,
                                                    slot->matrix, err, sizeof err);
    if (r == HT_OK) {
        slot->frame_matrix = true;
        update_colors(s, slot, f);
        return;
    }
    if (!s->point_light_logged)
        ht_log_linef(s->log, s->log_user, "hairtier: fixed: %s: CPU coordinates for such frames", err);
    s->point_light_logged = true;
    if (!slot->coords) slot->coords = malloc(s->vertex_count ? (size_t)s->vertex_count * 3 * sizeof(float) : 1);
    if (!slot->coords ||
        (!s->soa.px && ht_fixed_soa_make(&s->program, s->vertices, s->vertex_count, &s->soa) != HT_OK)) {
        ht_log_linef(s->log, s->log_user, "hairtier: fixed: out of memory for CPU coordinates: light %d not drawn",
                     slot->light + 1);
        free(slot->coords);
        slot->coords = NULL;
        return;
    }
    update_colors(s, slot, f);
    update_coords(s, slot, f);
}

static void begin_frame(void *state, const ht_tier_frame *f) {
    fixed_state *s = state;
    s->opacity_cut = f->opacity_cut;
    if (!s->vertices) return;
    s->range[0] = f->first_vertex < s->vertex_count ? f->first_vertex : 0;
    s->range[1] = f->vertex_count <= s->vertex_count - s->range[0] ? f->vertex_count : s->vertex_count - s->range[0];
    for (int k = 0; k < s->slot_count; k++) {
        light_slot *slot = &s->slots[k];
        slot->frame_matrix = false;
        slot->lit = slot->light < f->light_count;
        if (s->matrix_rule) {
            begin_matrix_slot(s, slot, f);
        } else {
            update_colors(s, slot, f);
            update_coords(s, slot, f);
        }
    }
}

/* One stage's texture environment, exactly as the program states it. */
static void apply_env(const ht_gl *gl, const ht_combiner_stage *st) {
    static const GLenum src_rgb[3] = { GL_SOURCE0_RGB, GL_SOURCE1_RGB, GL_SOURCE2_RGB };
    static const GLenum op_rgb[3] = { GL_OPERAND0_RGB, GL_OPERAND1_RGB, GL_OPERAND2_RGB };
    static const GLenum src_alpha[3] = { GL_SOURCE0_ALPHA, GL_SOURCE1_ALPHA, GL_SOURCE2_ALPHA };
    static const GLenum op_alpha[3] = { GL_OPERAND0_ALPHA, GL_OPERAND1_ALPHA, GL_OPERAND2_ALPHA };
    gl->TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_RGB, (GLint)st->combine_rgb);
    gl->TexEnvi(GL_TEXTURE_ENV, GL_COMBINE_ALPHA, (GLint)st->combine_alpha);
    for (int a = 0; a < 3; a++) {
        gl->TexEnvi(GL_TEXTURE_ENV, src_rgb[a], (GLint)st->source_rgb[a]);
        gl->TexEnvi(GL_TEXTURE_ENV, op_rgb[a], (GLint)st->operand_rgb[a]);
        gl->TexEnvi(GL_TEXTURE_ENV, src_alpha[a], (GLint)st->source_alpha[a]);
        gl->TexEnvi(GL_TEXTURE_ENV, op_alpha[a], (GLint)st->operand_alpha[a]);
    }
    gl->TexEnvf(GL_TEXTURE_ENV, GL_RGB_SCALE, (GLfloat)st->rgb_scale);
    gl->TexEnvf(GL_TEXTURE_ENV, GL_ALPHA_SCALE, (GLfloat)st->alpha_scale);
    gl->TexEnvfv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_COLOR, st->constant);
}

static void disable_targets(const fixed_state *s) {
    s->gl->Disable(GL_TEXTURE_2D);
    if (s->caps->has_3d_textures) s->gl->Disable(GL_TEXTURE_3D);
}

static int sub_passes(void *state, ht_pass pass) {
    const fixed_state *s = state;
    return pass == HT_PASS_PRIME_Z ? 1 : s->slot_count;
}

/* A light after the key's, added over the fragments sub-pass 0 drew
   (combiner.h): the pass's own cull and alpha test, no depth or alpha
   writes, depth EQUAL where the pass wrote depth or tests EQUAL already,
   the pass's LESS in the back pass (which writes none, so both sub-passes
   pass the same fragments). */
static void additive_state(const ht_gl *gl, ht_pass pass) {
    gl->Enable(GL_BLEND);
    gl->BlendFunc(pass == HT_PASS_OPAQUE ? GL_ONE : GL_SRC_ALPHA, GL_ONE);
    gl->DepthMask(GL_FALSE);
    if (pass != HT_PASS_BACK) gl->DepthFunc(GL_EQUAL);
    gl->ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
}

static void bind_pass(void *state, ht_pass pass, int sub_pass) {
    fixed_state *s = state;
    const ht_gl *gl = s->gl;
    if (sub_pass > 0) additive_state(gl, pass);
    const int first = pass == HT_PASS_PRIME_Z ? s->prime_first : 0;
    for (int i = 0; sub_pass == 0 && i < s->program.stage_count; i++) {
        const ht_combiner_stage *st = &s->program.stages[i];
        active_unit(s, st->unit);
        disable_targets(s);
        if (i < first) continue;
        gl->BindTexture(st->target, s->textures[i]);
        gl->Enable(st->target);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_COMBINE);
        ht_combiner_stage scaled;
        if (i + 1 == s->program.stage_count && s->opacity_cut > 0.0f) {
            if (ht_combiner_stage_scale_alpha(st, 1.0f - s->opacity_cut, &scaled)) st = &scaled;
            else if (!s->opacity_refused) {
                s->opacity_refused = true;
                ht_log_linef(s->log, s->log_user, "hairtier: fixed: the last stage's alpha takes no width-rule opacity");
            }
        }
        apply_env(gl, st);
        if (i == s->split_unit) {
            float m[16];
            ht_fixed_split_matrix(m);
            load_texture_matrix(s, st->unit, m);
        }
    }
    const light_slot *slot = sub_pass < s->slot_count ? &s->slots[sub_pass] : NULL;
    if (slot && slot->frame_matrix) {
        load_texture_matrix(s, s->lut_unit, slot->matrix);
        s->matrix_loaded = true;
    }
    active_unit(s, 0);
}

/* Binds where an array is read from and answers the pointer GL takes: an
   offset into buffer, or (buffer 0: no VBOs, or its upload was refused)
   the client memory, read with no array buffer bound. */
static const void *array_source(const ht_gl *gl, GLuint buffer, const void *client, size_t offset) {
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, buffer);
    return buffer ? (const void *)(uintptr_t)offset : (const void *)((const char *)client + offset);
}

/* Points each stage's texture coordinates and the colour array at the
   sub-pass's light's buffers; the renderer then draws its own index range
   and gets its array buffer binding back. */
static bool point_stage_arrays(void *state, ht_pass pass, int sub_pass) {
    (void)pass;
    fixed_state *s = state;
    const ht_gl *gl = s->gl;
    if (!s->vertices) return true; /* no mesh of its own: the renderer's arrays */
    if (sub_pass < 0 || sub_pass >= s->slot_count) return false;
    const light_slot *slot = &s->slots[sub_pass];
    /* a light the frame does not have adds nothing: no draw */
    if (sub_pass > 0 && !slot->lit) return false;
    /* a point-light frame of a texture-matrix program without memory for its
       coordinates (logged in begin_frame): draw nothing rather than garbage */
    if (!slot->frame_matrix && !slot->coords) return false;
    const GLuint bound = ht_gl_array_buffer_binding(gl);
    const GLsizei stride = (GLsizei)((size_t)s->static_width * sizeof(float));
    const size_t uv_offset = (size_t)(s->static_width - 2) * sizeof(float);
    for (int i = 0; i < s->program.stage_count; i++) {
        const ht_combiner_stage *st = &s->program.stages[i];
        if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)st->unit);
        gl->EnableClientState(GL_TEXTURE_COORD_ARRAY);
        if (st->coords == HT_COORDS_TEXTURE_MATRIX && slot->frame_matrix)
            gl->TexCoordPointer(3, GL_FLOAT, stride,
                                array_source(gl, s->vertex_buffer, s->statics, 0));
        else if (st->coords != HT_COORDS_UV)
            gl->TexCoordPointer(3, GL_FLOAT, 0, array_source(gl, slot->coord_buffer, slot->coords, 0));
        else
            gl->TexCoordPointer(2, GL_FLOAT, stride,
                                array_source(gl, s->vertex_buffer, s->statics, uv_offset));
    }
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
    gl->EnableClientState(GL_COLOR_ARRAY);
    gl->ColorPointer(4, GL_FLOAT, 0, array_source(gl, slot->color_buffer, slot->colors, 0));
    /* no GL lighting here: the renderer's normals would be fetched for nothing */
    gl->DisableClientState(GL_NORMAL_ARRAY);
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, bound);
    return true;
}

static void end_frame(void *state) {
    fixed_state *s = state;
    const ht_gl *gl = s->gl;
    ht_combiner_stage initial;
    for (int i = s->program.stage_count - 1; i >= 0; i--) {
        const ht_combiner_stage *st = &s->program.stages[i];
        ht_combiner_stage_defaults(&initial, st->unit);
        active_unit(s, st->unit);
        apply_env(gl, &initial);
        gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        gl->BindTexture(st->target, 0);
        disable_targets(s);
        if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0 + (GLenum)st->unit);
        gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    }
    if (s->matrix_loaded) load_texture_matrix(s, s->lut_unit, NULL);
    if (s->split_unit >= 0) load_texture_matrix(s, s->split_unit, NULL);
    s->matrix_loaded = false;
    for (int k = 0; k < s->slot_count; k++) s->slots[k].frame_matrix = false;
    active_unit(s, 0);
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
    gl->DisableClientState(GL_COLOR_ARRAY);
    /* The colour array leaves the current colour undefined: back to GL's initial white. */
    gl->Color4f(1, 1, 1, 1);
}

static uint64_t cpu_vertices(void *state) { return ((const fixed_state *)state)->cpu_vertices; }
static bool device_variant(void *state) { return ((const fixed_state *)state)->device_variant; }

const ht_tier_backend ht_tier_fixed_backend = {
    .tier = HT_TIER_FIXED,
    .create = create,
    .set_mesh = set_mesh,
    .begin_frame = begin_frame,
    .sub_passes = sub_passes,
    .bind_pass = bind_pass,
    .set_arrays = point_stage_arrays,
    .end_frame = end_frame,
    .destroy = destroy,
    .cpu_vertices = cpu_vertices,
    .device_variant = device_variant,
};

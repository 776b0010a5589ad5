/* gl11.c — the `gl11` tier's backend (gl11_program.h has the model and
   the why). GL 1.1 only: one texture unit, GL_MODULATE, vertex arrays; no
   multitexture, combiner or shader call anywhere, and a buffer object
   only where the device has them (a GL 1.1 driver with
   ARB_vertex_buffer_object, or a newer one run at this tier).

   Create: the program (gl11.json) and the albedo, its rgb uploaded x
   albedo_scale (a 1x1 white texel, scale 1, when the bundle has none).
   Per mesh (set_mesh): the structure-of-arrays inputs and the colour array
   (4 floats per vertex), and its buffer object where the device has VBOs.
   Per frame (begin_frame): the colours of the draw range's vertices
   recomputed on the CPU only when the eye, a light's type, vector or
   colour, the light count or the range changed since they were made (the
   cache key); counted in ht_gl11_cpu_vertices; then, where the device has
   VBOs, that range written into the buffer (glBufferSubData; a steady
   frame uploads nothing: NVIDIA copies client arrays across the bus at
   every draw), else left in client memory.
   Per pass: every pass points the colour array at the same data; the
   prime-Z pass draws the albedo's alpha with a constant white colour (no
   array), the others albedo x colour.
   The width rule per vertex (tier.h's width_rule), on the CPU as the
   colours are: each vertex of the range widened about its row's centre to
   the least drawn width at its own clip w, its colour's alpha x 1 / f, into
   a position array of the tier's own that every pass draws (the Z-prime
   pass then with the colour array too, so a scaled fragment fails its
   alpha test as it does the opaque pass's); remade with the colours, and
   when the eye's clip w row changes. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "errfmt.h"
#include "gl11.h"
#include "gl11_program.h"
#include "lod_internal.h"
#include "gl_error.h"
#include "tier_program.h"
#include "gl_texture.h"
#include <hairtier/image.h>

static _Atomic uint64_t cpu_vertices_total;

uint64_t ht_gl11_cpu_vertices(void) { return atomic_load_explicit(&cpu_vertices_total, memory_order_relaxed); }

/* What the colours were made for: compared bytewise (padding zeroed). */
typedef struct shade_key {
    float eye[3];
    int light_count;
    struct {
        int type;
        float vector[3], color[3];
    } lights[HT_MAX_LIGHTS];
    float opacity; /* the width rule's (tier.h): every colour's alpha */
    uint32_t first_vertex, vertex_count; /* the draw range's vertices (tier.h): only those are shaded */
    float width_rule;    /* tier.h's; 0: off, and clip_w unused (zero) */
    float clip_w[4];     /* projection x view's last row: a vertex's clip w */
} shade_key;

typedef struct gl11_state {
    const ht_gl *gl;
    bool has_vbo;
    ht_gl11_program program;
    double albedo_scale;      /* the program's; 1 with the white texel */
    GLuint albedo;
    ht_gl11_soa soa;
    float *colors;            /* 4 x soa.padded */
    GLuint color_buffer;      /* the colours on the device (0: client memory) */
    float (*sides)[3];        /* each vertex's offset from its row's centre (ht_lod_sides) */
    float (*wide)[3];         /* the width rule's positions (NULL until it is first on) */
    GLuint wide_buffer;       /* them on the device (0: client memory) */
    bool wide_refused;        /* the device refused that buffer once: client memory from then on */
    bool wide_valid;          /* this frame draws them */
    bool have_mesh;
    bool colors_valid;
    shade_key key;
    ht_log_fn log;
    void *log_user;
    uint64_t cpu_vertices;     /* this renderer's share, for ht_renderer_get_stats */
} gl11_state;

static void destroy(void *state) {
    gl11_state *s = state;
    if (!s) return;
    if (s->albedo) s->gl->DeleteTextures(1, &s->albedo);
    if (s->color_buffer) s->gl->DeleteBuffers(1, &s->color_buffer);
    if (s->wide_buffer) s->gl->DeleteBuffers(1, &s->wide_buffer);
    free(s->sides);
    free(s->wide);
    ht_gl11_soa_free(&s->soa);
    free(s->colors);
    free(s);
}

static ht_result load_program(gl11_state *s, const ht_tier_context *ctx, char *err, size_t err_size) {
    char path[HT_LIMIT_BUNDLE_FILE_PATH];
    ht_result r;
    char *text = ht_tier_program_read(ctx, path, sizeof path, &r, err, err_size);
    if (!text) return r;
    r = ht_gl11_parse(text, path, &s->program, err, err_size);
    free(text);
    return r;
}

/* The albedo with its rgb x albedo_scale (the colours are / albedo_scale),
   alpha untouched; texels the scale would push past 1 saturate. */
static ht_result load_albedo(gl11_state *s, const ht_tier_context *ctx, char *err, size_t err_size) {
    const ht_manifest *b = ctx->bundle;
    const ht_manifest_texture *t = ht_manifest_find_texture(b, ctx->tier, "albedo");
    ht_image img = { 0 };
    char path[HT_LIMIT_BUNDLE_FILE_PATH] = "white albedo";
    static const unsigned char white[4] = { 255, 255, 255, 255 };
    if (t) {
        ht_result r = ht_manifest_read_texture(b, t, &img, path, sizeof path, err, err_size);
        if (r != HT_OK) return r;
        s->albedo_scale = s->program.albedo_scale;
        const int rgb = img.channels >= 3 ? 3 : (img.channels == 2 ? 1 : img.channels);
        const size_t n = (size_t)img.width * (size_t)img.height;
        for (size_t i = 0; s->albedo_scale != 1.0 && i < n; i++)
            for (int c = 0; c < rgb; c++) {
                uint8_t *px = &img.pixels[i * (size_t)img.channels + (size_t)c];
                double v = (double)*px * s->albedo_scale;
                *px = v >= 255.0 ? 255 : (uint8_t)lround(v);
            }
    } else {
        img = (ht_image){ .width = 1, .height = 1, .channels = 4, .pixels = (uint8_t *)white };
        s->albedo_scale = 1.0;
    }
    ht_result r = ht_gl_texture_upload(s->gl, &(ht_gl_texture_desc){ .target = GL_TEXTURE_2D, .image = &img,
                                                                     .filter = GL_LINEAR, .wrap = GL_REPEAT,
                                                                     .name = path },
                                       &s->albedo, err, err_size);
    if (t) ht_image_free(&img);
    return r;
}

static ht_result create(const ht_tier_context *ctx, void **out, char *err, size_t err_size) {
    *out = NULL;
    gl11_state *s = calloc(1, sizeof *s);
    if (!s) return HT_ERR_OUT_OF_MEMORY;
    s->gl = ctx->gl;
    s->has_vbo = ctx->caps->has_vbo && ctx->gl->GenBuffers;
    s->log = ctx->log;
    s->log_user = ctx->log_user;
    ht_result r = load_program(s, ctx, err, err_size);
    if (r == HT_OK) r = load_albedo(s, ctx, err, err_size);
    if (r != HT_OK) {
        destroy(s);
        return r;
    }
    /* the program's albedo_scale is for the albedo it was made with */
    s->program.albedo_scale = s->albedo_scale;
    ht_log_linef(s->log, s->log_user, "hairtier: gl11: 1 unit (albedo x %.3g, GL_MODULATE), %s per vertex on the "
                 "CPU for %d light%s, local viewer", s->albedo_scale,
                 s->program.shading.model == HT_MODEL_KAJIYA_KAY ? "kajiya-kay" : "scheuermann", s->program.lights,
                 s->program.lights == 1 ? "" : "s");
    *out = s;
    return HT_OK;
}

/* A refused upload is one line naming GL's error, and the buffer is
   dropped: client arrays from then on. */
static void check_upload(gl11_state *s, const char *call) {
    const ht_gl *gl = s->gl;
    gl->BindBuffer(GL_ARRAY_BUFFER, 0);
    GLenum e = gl->GetError();
    if (e == GL_NO_ERROR) return;
    ht_log_linef(s->log, s->log_user, "hairtier: gl11: %s: %s: client arrays instead", call, ht_gl_error_name(e));
    gl->DeleteBuffers(1, &s->color_buffer);
    s->color_buffer = 0;
}

static ht_result set_mesh(void *state, const ht_mesh *mesh) {
    gl11_state *s = state;
    ht_gl11_soa soa;
    if (ht_gl11_soa_make(&s->program, mesh->vertices, mesh->vertex_count, &soa) != HT_OK)
        return HT_ERR_OUT_OF_MEMORY;
    float *colors = calloc(4 * soa.padded, sizeof(float));
    float(*sides)[3] = malloc(mesh->vertex_count ? mesh->vertex_count * sizeof *sides : 1);
    if (!colors || !sides) {
        free(colors);
        free(sides);
        ht_gl11_soa_free(&soa);
        return HT_ERR_OUT_OF_MEMORY;
    }
    ht_lod_sides(mesh, sides);
    ht_gl11_soa_free(&s->soa);
    free(s->colors);
    free(s->sides);
    free(s->wide);
    s->wide = NULL;
    if (s->wide_buffer) s->gl->DeleteBuffers(1, &s->wide_buffer);
    s->wide_buffer = 0;
    s->soa = soa;
    s->colors = colors;
    s->sides = sides;
    s->have_mesh = true;
    s->colors_valid = false;
    /* the buffer sized once per mesh; frames write their range into it */
    if (s->has_vbo) {
        const ht_gl *gl = s->gl;
        while (gl->GetError() != GL_NO_ERROR) {}
        if (!s->color_buffer) gl->GenBuffers(1, &s->color_buffer);
        gl->BindBuffer(GL_ARRAY_BUFFER, s->color_buffer);
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(4 * s->soa.count * sizeof(float)), s->colors, GL_DYNAMIC_DRAW);
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
        /* refused: the renderer drops the mesh with its one line (as fixed) */
        const GLenum e = gl->GetError();
        if (e != GL_NO_ERROR) {
            s->have_mesh = false;
            return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
        }
    }
    return HT_OK;
}

/* The colours just made for vertices [first, first + count), onto the
   device where it has a buffer for them. */
static void upload_colors(gl11_state *s, size_t first, size_t count) {
    const ht_gl *gl = s->gl;
    if (!s->color_buffer || !count) return;
    gl->BindBuffer(GL_ARRAY_BUFFER, s->color_buffer);
    gl->BufferSubData(GL_ARRAY_BUFFER, (GLintptr)(4 * first * sizeof(float)), (GLsizeiptr)(4 * count * sizeof(float)),
                      s->colors + 4 * first);
    check_upload(s, "glBufferSubData");
}

/* The width rule per vertex for vertices [first, first + n): the widened
   positions and each colour's alpha x 1 / f (shader_interface.h's rule,
   here on the CPU); onto the device where it has buffers (sized for the
   whole mesh at the first use). false when memory is short: per draw. */
static bool widen_range(gl11_state *s, const shade_key *key, size_t first, size_t n) {
    if (!s->wide && !(s->wide = malloc(s->soa.count ? s->soa.count * sizeof *s->wide : 1))) return false;
    if (first + n > s->soa.count) n = first < s->soa.count ? s->soa.count - first : 0;
    const float *px = s->soa.a[HT_GL11_PX], *py = s->soa.a[HT_GL11_PX + 1], *pz = s->soa.a[HT_GL11_PX + 2];
    for (size_t i = first; i < first + n; i++) {
        const float *side = s->sides[i];
        const float half = sqrtf(side[0] * side[0] + side[1] * side[1] + side[2] * side[2]);
        const float w = key->clip_w[0] * px[i] + key->clip_w[1] * py[i] + key->clip_w[2] * pz[i] + key->clip_w[3];
        float f = half > 0.0f ? w * key->width_rule / (2.0f * half) : 1.0f;
        f = f > 1.0f ? (f < 1024.0f ? f : 1024.0f) : 1.0f;
        s->wide[i][0] = px[i] + side[0] * (f - 1.0f);
        s->wide[i][1] = py[i] + side[1] * (f - 1.0f);
        s->wide[i][2] = pz[i] + side[2] * (f - 1.0f);
        s->colors[4 * i + 3] /= f;
    }
    if (s->has_vbo && !s->wide_refused && n) {
        const ht_gl *gl = s->gl;
        const bool fresh = !s->wide_buffer;
        if (fresh) gl->GenBuffers(1, &s->wide_buffer);
        gl->BindBuffer(GL_ARRAY_BUFFER, s->wide_buffer);
        if (fresh)
            gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(s->soa.count * sizeof *s->wide), NULL, GL_DYNAMIC_DRAW);
        gl->BufferSubData(GL_ARRAY_BUFFER, (GLintptr)(first * sizeof *s->wide), (GLsizeiptr)(n * sizeof *s->wide),
                          s->wide + first);
        gl->BindBuffer(GL_ARRAY_BUFFER, 0);
        const GLenum e = gl->GetError();
        if (e != GL_NO_ERROR) {
            ht_log_linef(s->log, s->log_user, "hairtier: gl11: the width rule's positions: %s: client arrays instead",
                         ht_gl_error_name(e));
            gl->DeleteBuffers(1, &s->wide_buffer);
            s->wide_buffer = 0;
            s->wide_refused = true;
        }
    }
    return true;
}

static void begin_frame(void *state, const ht_tier_frame *f) {
    gl11_state *s = state;
    if (!s->have_mesh) return;
    shade_key key;
    memset(&key, 0, sizeof key);
    memcpy(key.eye, f->eye, sizeof key.eye);
    key.light_count = f->light_count < s->program.lights ? f->light_count : s->program.lights;
    for (int l = 0; l < key.light_count; l++) {
        key.lights[l].type = (int)f->lights[l].type;
        memcpy(key.lights[l].vector, f->lights[l].vector, sizeof key.lights[l].vector);
        memcpy(key.lights[l].color, f->lights[l].color, sizeof key.lights[l].color);
    }
    key.opacity = 1.0f - f->opacity_cut;
    key.first_vertex = f->first_vertex < s->soa.count ? f->first_vertex : 0;
    key.vertex_count = f->vertex_count <= s->soa.count - key.first_vertex ? f->vertex_count
                                                                           : (uint32_t)(s->soa.count - key.first_vertex);
    if (f->width_rule > 0.0f) {
        key.width_rule = f->width_rule;
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 4; k++) key.clip_w[c] += f->projection[k * 4 + 3] * f->view[c * 4 + k];
    }
    if (s->colors_valid && memcmp(&key, &s->key, sizeof key) == 0) return;
    const size_t n = ht_gl11_shade_range(&s->program, &s->soa, key.first_vertex, key.vertex_count, f->lights,
                                         key.light_count, f->eye, s->colors);
    /* the vertices shaded: the range widened to whole blocks */
    const size_t first = key.first_vertex / HT_GL11_BLOCK * HT_GL11_BLOCK;
    /* Desktop GL clamps array colours before interpolating them; llvmpipe's
       ES 1.1 interpolates them unclamped: clamped here, every driver draws
       the same (the colours are >= 0; alpha is 1). */
    float *c = s->colors + 4 * first;
    for (size_t i = 0; i < 4 * n; i++)
        if (c[i] > 1.0f) c[i] = 1.0f;
    /* GL_MODULATE: the drawn alpha is the albedo's x the colour's */
    for (size_t i = 0; key.opacity != 1.0f && i < n; i++) c[4 * i + 3] = key.opacity;
    s->wide_valid = key.width_rule > 0.0f && widen_range(s, &key, first, n);
    atomic_fetch_add_explicit(&cpu_vertices_total, (uint64_t)n, memory_order_relaxed);
    s->cpu_vertices += n;
    s->key = key;
    s->colors_valid = true;
    upload_colors(s, first, n);
}

static void bind_pass(void *state, ht_pass pass, int sub_pass) {
    (void)pass;
    (void)sub_pass;
    gl11_state *s = state;
    const ht_gl *gl = s->gl;
    /* unit 0 is the active one (the baseline leaves it so; GL 1.1 has no other) */
    gl->BindTexture(GL_TEXTURE_2D, s->albedo);
    gl->Enable(GL_TEXTURE_2D);
    gl->TexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
}

static bool set_arrays(void *state, ht_pass pass, int sub_pass) {
    (void)sub_pass;
    gl11_state *s = state;
    const ht_gl *gl = s->gl;
    if (!s->have_mesh || !s->colors_valid) return false;
    if (s->wide_valid) {
        const GLuint bound = ht_gl_array_buffer_binding(gl);
        ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, s->wide_buffer);
        gl->VertexPointer(3, GL_FLOAT, 0, s->wide_buffer ? NULL : s->wide);
        ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, bound);
    }
    if (pass == HT_PASS_PRIME_Z && !s->wide_valid) {
        /* alpha only: white x the albedo's alpha (x the width rule's) */
        gl->DisableClientState(GL_COLOR_ARRAY);
        gl->Color4f(1, 1, 1, s->key.opacity);
        return true;
    }
    /* the buffer, or (none: no VBOs, or its upload was refused) client
       memory with no array buffer bound; the renderer's binding back after */
    const GLuint bound = ht_gl_array_buffer_binding(gl);
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, s->color_buffer);
    gl->EnableClientState(GL_COLOR_ARRAY);
    gl->ColorPointer(4, GL_FLOAT, 0, s->color_buffer ? NULL : s->colors);
    ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, bound);
    return true;
}

static void end_frame(void *state) {
    gl11_state *s = state;
    const ht_gl *gl = s->gl;
    gl->BindTexture(GL_TEXTURE_2D, 0);
    gl->Disable(GL_TEXTURE_2D);
    gl->DisableClientState(GL_COLOR_ARRAY);
    gl->Color4f(1, 1, 1, 1);
}

/* The rule per vertex needs only the mesh's positions and sides: always. */
static bool vertex_width_rule(void *state) { return ((const gl11_state *)state)->have_mesh; }

static uint64_t cpu_vertices(void *state) { return ((const gl11_state *)state)->cpu_vertices; }

const ht_tier_backend ht_tier_gl11_backend = {
    .tier = HT_TIER_GL11,
    .create = create,
    .set_mesh = set_mesh,
    .begin_frame = begin_frame,
    .bind_pass = bind_pass,
    .set_arrays = set_arrays,
    .end_frame = end_frame,
    .destroy = destroy,
    .cpu_vertices = cpu_vertices,
    .vertex_width_rule = vertex_width_rule,
};

/* test_render_glsl_compile.c — the emitted desktop programs on a real Mesa
   driver (OSMesa compatibility context): every program compiles and links,
   exposes the uniforms the runtime binds, and shades what runtime/shading/model.c
   computes. Shading cases are drawn as single points, so each pixel sees
   exactly its vertex's attributes and can be checked against the oracle. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "emit.h"
#include "fixed4_stages.h"
#include "gl_api.h"
#include "rng.h"
#include "shader_interface.h"
#include "support_osmesa.h"

#define W 64
#define H 4
#define VERTEX_TOLERANCE 3

/* <GL/gl.h> declares GL 1.3 itself, so glext.h leaves this out. */
typedef void (APIENTRYP multitexcoord2f_fn)(GLenum, GLfloat, GLfloat);

typedef struct gl2 {
    PFNGLCREATESHADERPROC CreateShader;
    PFNGLSHADERSOURCEPROC ShaderSource;
    PFNGLCOMPILESHADERPROC CompileShader;
    PFNGLGETSHADERIVPROC GetShaderiv;
    PFNGLGETSHADERINFOLOGPROC GetShaderInfoLog;
    PFNGLDELETESHADERPROC DeleteShader;
    PFNGLCREATEPROGRAMPROC CreateProgram;
    PFNGLATTACHSHADERPROC AttachShader;
    PFNGLBINDATTRIBLOCATIONPROC BindAttribLocation;
    PFNGLLINKPROGRAMPROC LinkProgram;
    PFNGLGETPROGRAMIVPROC GetProgramiv;
    PFNGLGETPROGRAMINFOLOGPROC GetProgramInfoLog;
    PFNGLUSEPROGRAMPROC UseProgram;
    PFNGLDELETEPROGRAMPROC DeleteProgram;
    PFNGLGETUNIFORMLOCATIONPROC GetUniformLocation;
    PFNGLUNIFORM1IPROC Uniform1i;
    PFNGLUNIFORM1FPROC Uniform1f;
    PFNGLUNIFORM3FVPROC Uniform3fv;
    PFNGLUNIFORM4FVPROC Uniform4fv;
    PFNGLACTIVETEXTUREPROC ActiveTexture;
    PFNGLVERTEXATTRIB1FPROC VertexAttrib1f;
    PFNGLVERTEXATTRIB3FPROC VertexAttrib3f;
    multitexcoord2f_fn MultiTexCoord2f;
} gl2;

typedef struct fixture {
    ht_test_gl context;
    gl2 gl;
    GLuint albedo_tex, detail_tex, white_tex;
} fixture;

#define LOAD(f, name)                                               \
    do {                                                            \
        *(void **)&(f)->gl.name = ht_test_getproc("gl" #name);      \
        if (!(f)->gl.name) return -1;                               \
    } while (0)

/* The 1x1 textures every case samples: base and alpha, shift and sparkle. */
static const uint8_t albedo_texel[4] = { 200, 180, 150, 255 };
static const uint8_t detail_texel[4] = { 179, 153, 0, 255 };

static GLuint texture_1x1(const uint8_t texel[4]) {
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, texel);
    return t;
}

static int setup(void **state) {
    fixture *f = calloc(1, sizeof *f);
    char err[256];
    if (!f) return -1;
    if (!ht_test_gl_create(&f->context, W, H, NULL, err, sizeof err)) {
        print_error("%s\n", err);
        free(f);
        return -1;
    }
    *state = f;
    LOAD(f, CreateShader);
    LOAD(f, ShaderSource);
    LOAD(f, CompileShader);
    LOAD(f, GetShaderiv);
    LOAD(f, GetShaderInfoLog);
    LOAD(f, DeleteShader);
    LOAD(f, CreateProgram);
    LOAD(f, AttachShader);
    LOAD(f, BindAttribLocation);
    LOAD(f, LinkProgram);
    LOAD(f, GetProgramiv);
    LOAD(f, GetProgramInfoLog);
    LOAD(f, UseProgram);
    LOAD(f, DeleteProgram);
    LOAD(f, GetUniformLocation);
    LOAD(f, Uniform1i);
    LOAD(f, Uniform1f);
    LOAD(f, Uniform3fv);
    LOAD(f, Uniform4fv);
    LOAD(f, ActiveTexture);
    LOAD(f, VertexAttrib1f);
    LOAD(f, VertexAttrib3f);
    LOAD(f, MultiTexCoord2f);
    f->albedo_tex = texture_1x1(albedo_texel);
    f->detail_tex = texture_1x1(detail_texel);
    f->white_tex = texture_1x1((const uint8_t[4]){ 255, 255, 255, 255 });
    glViewport(0, 0, W, H);
    return 0;
}

static int teardown(void **state) {
    fixture *f = *state;
    if (!f) return 0;
    ht_test_gl_destroy(&f->context);
    free(f);
    return 0;
}

static GLuint compile(const gl2 *gl, GLenum type, const char *file, const char *src) {
    GLuint s = gl->CreateShader(type);
    gl->ShaderSource(s, 1, &src, NULL);
    gl->CompileShader(s);
    GLint ok = 0;
    gl->GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = "";
        gl->GetShaderInfoLog(s, sizeof log, NULL, log);
        fail_msg("%s does not compile on %s: %s\n%s", file, (const char *)glGetString(GL_RENDERER), log, src);
    }
    return s;
}

/* Links a vertex shader with a fragment shader, or with the fixed-function
   fragment stage when fs is NULL (the vertex tier), with tangent and ao at
   the locations the runtime binds (shader_interface.h). */
static GLuint link_program(const gl2 *gl, const ht_out_text *vs, const ht_out_text *fs) {
    GLuint p = gl->CreateProgram();
    GLuint v = compile(gl, GL_VERTEX_SHADER, vs->file, vs->text);
    gl->AttachShader(p, v);
    GLuint fr = 0;
    if (fs) {
        fr = compile(gl, GL_FRAGMENT_SHADER, fs->file, fs->text);
        gl->AttachShader(p, fr);
    }
    gl->BindAttribLocation(p, HT_ATTR_TANGENT_LOCATION, HT_ATTR_TANGENT);
    gl->BindAttribLocation(p, HT_ATTR_AO_LOCATION, HT_ATTR_AO);
    gl->LinkProgram(p);
    gl->DeleteShader(v);
    if (fr) gl->DeleteShader(fr);
    GLint ok = 0;
    gl->GetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[2048] = "";
        gl->GetProgramInfoLog(p, sizeof log, NULL, log);
        fail_msg("%s + %s do not link: %s", vs->file, fs ? fs->file : "fixed-function", log);
    }
    return p;
}

static const ht_out_text *text_of(const ht_tier_output *o, const char *file) {
    for (int i = 0; i < o->text_count; i++)
        if (strcmp(o->texts[i].file, file) == 0) return &o->texts[i];
    fail_msg("no %s", file);
    return NULL;
}

static ht_material hand_material(ht_model_kind model, unsigned textures) {
    ht_material m;
    memset(&m, 0, sizeof m);
    m.shading = (ht_shading){
        .model = model,
        .diffuse_color = { 0.23, 0.14, 0.08 },
        .wrap = 0.25,
        .primary = { .color = { 1.0, 0.95, 0.9 }, .exponent = 80.0, .shift = -0.1 },
        .secondary = { .color = { 0.55, 0.40, 0.28 }, .exponent = 24.0, .shift = 0.15 },
    };
    for (int i = 0; i < HT_TEX_COUNT; i++)
        m.textures[i].origin = (textures >> i) & 1u ? HT_TEXTURE_PROCEDURAL : HT_TEXTURE_ABSENT;
    m.opaque_cutoff = 0.98;
    return m;
}

static ht_plan plan_for(const ht_material *m, int lights, unsigned point_mask) {
    ht_scene s;
    memset(&s, 0, sizeof s);
    s.light_count = lights;
    for (int i = 0; i < lights; i++) s.lights[i].type = (point_mask >> i) & 1u ? HT_LIGHT_POINT : HT_LIGHT_DIRECTIONAL;
    ht_plan p;
    ht_plan_make(m, &s, &p);
    return p;
}

static void emit(const ht_plan *p, ht_tier_output *full, ht_tier_output *vertex) {
    char err[4096];
    if (ht_emit_full(p, full, err, sizeof err) != HT_OK) fail_msg("%s", err);
    if (ht_emit_vertex(p, vertex, err, sizeof err) != HT_OK) fail_msg("%s", err);
}

static void test_every_desktop_program_links_and_exposes_the_runtime_uniforms(void **state) {
    fixture *f = *state;
    const gl2 *gl = &f->gl;
    const unsigned subsets[] = { 0x0, 0xf, 0x3, 0x4, 0x8, 0x2 };
    const struct { int n; unsigned points; } mixes[] = { { 1, 0x0 }, { 1, 0x1 }, { 4, 0x5 } };
    for (int model = 0; model < 2; model++)
        for (size_t si = 0; si < sizeof subsets / sizeof subsets[0]; si++)
            for (size_t li = 0; li < sizeof mixes / sizeof mixes[0]; li++) {
                ht_material m = hand_material((ht_model_kind)model, subsets[si]);
                ht_plan p = plan_for(&m, mixes[li].n, mixes[li].points);
                ht_tier_output full, vertex;
                emit(&p, &full, &vertex);

                GLuint main_program = link_program(gl, text_of(&full, "full.vert"), text_of(&full, "full.frag"));
                assert_true(gl->GetUniformLocation(main_program, HT_U_EYE) >= 0);
                char name[64];
                for (int i = 0; i < p.light_count; i++) {
                    snprintf(name, sizeof name, "%s[%d]", HT_U_LIGHT_VECTOR, i);
                    assert_true(gl->GetUniformLocation(main_program, name) >= 0);
                    snprintf(name, sizeof name, "%s[%d]", HT_U_LIGHT_COLOR, i);
                    assert_true(gl->GetUniformLocation(main_program, name) >= 0);
                }
                for (int i = 0; i < full.sampler_count; i++)
                    assert_true(gl->GetUniformLocation(main_program, full.samplers[i].sampler) >= 0);
                gl->DeleteProgram(main_program);

                GLuint prime = link_program(gl, text_of(&full, "full-prime.vert"), text_of(&full, "full-prime.frag"));
                assert_int_equal(gl->GetUniformLocation(prime, HT_U_ALBEDO) >= 0, p.alpha);
                gl->DeleteProgram(prime);

                GLuint lit = link_program(gl, text_of(&vertex, "vertex.vert"), NULL);
                assert_true(gl->GetUniformLocation(lit, HT_U_EYE) >= 0);
                snprintf(name, sizeof name, "%s[0]", HT_U_LIGHT_VECTOR);
                assert_true(gl->GetUniformLocation(lit, name) >= 0);
                /* Kajiya-Kay's first two lights are wholly in the LUTs: colour
                   and scale matter to the shader only through lights after
                   them (a driver may keep or drop them otherwise). */
                const bool per_vertex_colour = model == HT_MODEL_SCHEUERMANN || p.light_count > 2;
                if (per_vertex_colour) {
                    assert_true(gl->GetUniformLocation(lit, HT_U_LIGHT_COLOR) >= 0);
                    assert_true(gl->GetUniformLocation(lit, HT_U_LUT_SCALE) >= 0);
                }
                gl->DeleteProgram(lit);
                gl->DeleteProgram(link_program(gl, text_of(&vertex, "vertex-prime.vert"), NULL));
                assert_int_equal(glGetError(), GL_NO_ERROR);
                ht_tier_output_free(&full);
                ht_tier_output_free(&vertex);
            }
}

/* ---- parity with runtime/shading/model.c ---- */

typedef struct shading_case {
    double T[3], N[3], ao;
    ht_light lights[HT_MAX_LIGHTS];
} shading_case;

static const float eye[3] = { 0.3f, 0.2f, 2.0f };

static void random_vector(ht_rng *r, double v[3], double scale) {
    for (int i = 0; i < 3; i++) v[i] = ht_rng_range(r, -scale, scale);
}

/* Mostly random; a few at the model's undefined points. */
static void make_case(ht_rng *r, int index, const ht_plan *p, const float position[3], shading_case *c) {
    memset(c, 0, sizeof *c);
    random_vector(r, c->T, 1.0);
    random_vector(r, c->N, 1.0);
    c->ao = ht_rng_range(r, 0.3, 1.0);
    for (int i = 0; i < p->light_count; i++) {
        double v[3];
        random_vector(r, v, p->light_types[i] == HT_LIGHT_POINT ? 3.0 : 1.0);
        for (int k = 0; k < 3; k++) {
            c->lights[i].vector[k] = (float)v[k];
            c->lights[i].color[k] = (float)ht_rng_range(r, 0.2, 0.5);
        }
        c->lights[i].type = p->light_types[i];
    }
    if (index == 1) memset(c->T, 0, sizeof c->T);     /* no strand direction */
    if (index == 2) memset(c->N, 0, sizeof c->N);     /* no normal: diffuse = wrap */
    if (index == 3 && p->light_types[0] == HT_LIGHT_DIRECTIONAL)
        for (int k = 0; k < 3; k++) c->lights[0].vector[k] = position[k] - eye[k]; /* L = -V: no H */
    if (index == 4) /* T = -shift * N exactly: t1 has no direction */
        for (int k = 0; k < 3; k++) c->T[k] = -p->shading.primary.shift * c->N[k];
}

static void expected_rgb(const ht_plan *p, const shading_case *c, const float position[3], bool per_pixel_textures,
                         uint8_t out[3]) {
    ht_surface s;
    memset(&s, 0, sizeof s);
    for (int k = 0; k < 3; k++) {
        s.T[k] = (float)c->T[k];
        s.N[k] = (float)c->N[k];
        s.V[k] = (double)eye[k] - position[k];
        s.base[k] = p->base ? albedo_texel[k] / 255.0 : 1.0;
    }
    s.shift_tex = p->shift && per_pixel_textures ? detail_texel[0] / 255.0 : 0.5;
    s.sparkle = p->sparkle && per_pixel_textures ? detail_texel[1] / 255.0 : 1.0;
    s.ao = (float)c->ao;
    ht_light_ray rays[HT_MAX_LIGHTS];
    for (int i = 0; i < p->light_count; i++)
        for (int k = 0; k < 3; k++) {
            rays[i].L[k] = c->lights[i].vector[k] - (c->lights[i].type == HT_LIGHT_POINT ? position[k] : 0.0f);
            rays[i].color[k] = c->lights[i].color[k];
        }
    double rgb[3];
    ht_model_shade_d(&p->shading, &s, rays, p->light_count, rgb);
    for (int k = 0; k < 3; k++) {
        assert_true(isfinite(rgb[k]));
        double v = rgb[k] < 0 ? 0 : rgb[k] > 1 ? 1 : rgb[k];
        out[k] = (uint8_t)lround(v * 255.0);
    }
}

static void set_light_uniforms(const gl2 *gl, GLuint program, const ht_plan *p, const shading_case *c) {
    gl->Uniform3fv(gl->GetUniformLocation(program, HT_U_EYE), 1, eye);
    for (int i = 0; i < p->light_count; i++) {
        char name[64];
        float v[4] = { c->lights[i].vector[0], c->lights[i].vector[1], c->lights[i].vector[2],
                       c->lights[i].type == HT_LIGHT_POINT ? 1.0f : 0.0f };
        snprintf(name, sizeof name, "%s[%d]", HT_U_LIGHT_VECTOR, i);
        gl->Uniform4fv(gl->GetUniformLocation(program, name), 1, v);
        snprintf(name, sizeof name, "%s[%d]", HT_U_LIGHT_COLOR, i);
        gl->Uniform3fv(gl->GetUniformLocation(program, name), 1, c->lights[i].color);
    }
}

/* Draws one point per case with the tier's program and compares each pixel
   with the model; tolerance covers 8-bit rounding on both sides. */
static void check_parity(fixture *f, const ht_plan *p, bool full_tier) {
    const gl2 *gl = &f->gl;
    ht_tier_output full, vertex;
    emit(p, &full, &vertex);
    GLuint program = full_tier ? link_program(gl, text_of(&full, "full.vert"), text_of(&full, "full.frag"))
                               : link_program(gl, text_of(&vertex, "vertex.vert"), NULL);
    gl->UseProgram(program);
    const ht_tier_output *tier = full_tier ? &full : &vertex;
    for (int i = 0; i < tier->sampler_count; i++) {
        gl->ActiveTexture(GL_TEXTURE0 + (GLenum)tier->samplers[i].unit);
        glBindTexture(GL_TEXTURE_2D, strcmp(tier->samplers[i].name, "albedo") == 0 ? f->albedo_tex : f->detail_tex);
        gl->Uniform1i(gl->GetUniformLocation(program, tier->samplers[i].sampler), tier->samplers[i].unit);
    }
    gl->ActiveTexture(GL_TEXTURE0);
    /* The vertex tier's fragment stages are the runtime's own
       (fallback/fixed4_stages.h) over the bundle's LUT program, with the
       test's albedo (or a white texel) on the albedo and final units. */
    ht_gl htgl;
    ht_fixed4_program luts;
    ht_fixed4_stages stages;
    memset(&stages, 0, sizeof stages);
    if (!full_tier) {
        char err[512];
        if (ht_gl_load(&htgl, ht_test_getproc, err, sizeof err) != HT_OK) fail_msg("ht_gl_load: %s", err);
        if (ht_fixed4_parse(text_of(&vertex, "vertex-luts.json")->text, "vertex-luts.json", &luts, err,
                            sizeof err) != HT_OK)
            fail_msg("%s", err);
        ht_fixed4_stages_init(&stages, &htgl, &luts, "vertex");
        stages.albedo = tier->sampler_count ? f->albedo_tex : f->white_tex;
    }
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);

    ht_rng r = ht_rng_seed(0x5eed + (uint64_t)p->light_count);
    shading_case cases[W];
    float positions[W][3];
    for (int i = 0; i < W; i++) {
        positions[i][0] = (2.0f * ((float)i + 0.5f) / W) - 1.0f;
        positions[i][1] = (2.0f * (1.5f) / H) - 1.0f;
        positions[i][2] = 0.0f;
        make_case(&r, i, p, positions[i], &cases[i]);
        set_light_uniforms(gl, program, p, &cases[i]);
        if (!full_tier) {
            /* LUTs and scale for this case's light colours, as begin_frame does. */
            float colors[HT_MAX_LIGHTS][3] = { { 0 } };
            for (int l = 0; l < p->light_count; l++) memcpy(colors[l], cases[i].lights[l].color, sizeof colors[l]);
            int scale = ht_fixed4_scale_lights(&luts, (const float(*)[3])colors, p->light_count);
            char err[256];
            if (ht_fixed4_stages_bake(&stages, (const float(*)[3])colors, scale, err, sizeof err) != HT_OK)
                fail_msg("%s", err);
            ht_fixed4_stages_bind(&stages, false);
            gl->Uniform1f(gl->GetUniformLocation(program, HT_U_LUT_SCALE), (float)scale);
        }
        glBegin(GL_POINTS);
        glNormal3f((float)cases[i].N[0], (float)cases[i].N[1], (float)cases[i].N[2]);
        gl->MultiTexCoord2f(GL_TEXTURE0, 0.5f, 0.5f);
        gl->VertexAttrib3f(HT_ATTR_TANGENT_LOCATION, (float)cases[i].T[0], (float)cases[i].T[1],
                           (float)cases[i].T[2]);
        gl->VertexAttrib1f(HT_ATTR_AO_LOCATION, (float)cases[i].ao);
        glVertex3fv(positions[i]);
        glEnd();
    }
    uint8_t pixels[W * H * 4];
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    /* The vertex tier reads 8-bit LUTs (up to 0.5/255 x scale each, and
       bilinear between texels) and rounds its primary colour. */
    const int tolerance = full_tier ? 2 : VERTEX_TOLERANCE;
    int worst = 0;
    for (int i = 0; i < W; i++) {
        uint8_t want[3];
        expected_rgb(p, &cases[i], positions[i], full_tier, want);
        const uint8_t *got = &pixels[(1 * W + i) * 4];
        for (int k = 0; k < 3; k++) {
            if (abs((int)got[k] - (int)want[k]) > worst) worst = abs((int)got[k] - (int)want[k]);
            if (abs((int)got[k] - (int)want[k]) > tolerance)
                fail_msg("%s tier, case %d, channel %d: got %d, model %d", full_tier ? "full" : "vertex", i, k,
                         got[k], want[k]);
        }
        if (full_tier) assert_int_equal(got[3], p->alpha ? albedo_texel[3] : 255);
    }
    printf("%s tier, %d light%s: worst %d/255 (bound %d)\n", full_tier ? "full" : "vertex", p->light_count,
           p->light_count == 1 ? "" : "s", worst, tolerance);
    if (!full_tier) {
        ht_fixed4_stages_unbind(&stages);
        stages.albedo = 0; /* the fixture's */
        ht_fixed4_stages_release(&stages);
    }
    gl->UseProgram(0);
    gl->DeleteProgram(program);
    ht_tier_output_free(&full);
    ht_tier_output_free(&vertex);
}

static void test_full_tier_shades_what_the_model_computes(void **state) {
    for (int model = 0; model < 2; model++) {
        ht_material m = hand_material((ht_model_kind)model, 0xf);
        ht_plan p = plan_for(&m, 2, 0x2);
        check_parity(*state, &p, true);
        p = plan_for(&m, 1, 0x0);
        check_parity(*state, &p, true);
    }
}

static void test_full_tier_matches_the_model_at_extremes(void **state) {
    const double exponents[][2] = { { 0.0, 0.0 }, { 10000.0, 0.5 }, { 1.0, 0.0 } };
    for (size_t i = 0; i < 3; i++) {
        ht_material m = hand_material(HT_MODEL_SCHEUERMANN, i == 1 ? 0x0 : 0xf);
        m.shading.primary.exponent = exponents[i][0];
        m.shading.secondary.exponent = exponents[i][1];
        m.shading.primary.shift = i == 1 ? 100.0 : -0.1;
        m.shading.secondary.shift = i == 1 ? -100.0 : 0.15;
        ht_plan p = plan_for(&m, 1, 0x0);
        check_parity(*state, &p, true);
        m.shading.model = HT_MODEL_KAJIYA_KAY;
        p = plan_for(&m, 1, 0x0);
        check_parity(*state, &p, true);
    }
}

static void test_vertex_tier_shades_what_the_model_computes_without_detail(void **state) {
    for (int model = 0; model < 2; model++) {
        ht_material m = hand_material((ht_model_kind)model, 0xf);
        ht_plan p = plan_for(&m, 2, 0x1);
        check_parity(*state, &p, false);
        m = hand_material((ht_model_kind)model, 0x0);
        p = plan_for(&m, 1, 0x0);
        check_parity(*state, &p, false);
    }
}

/* A narrow highlight that falls between two vertices: one quad across the
   viewport whose tangent turns from t.H = -0.6 on the left edge to +0.6
   on the right, exponent 400. At the vertices the highlight is black, so
   colours computed per vertex (the old vertex tier) interpolate to the
   diffuse alone; the vertex tier interpolates the LUT coordinates and
   looks the highlight up per pixel, so the middle of the quad lights up as
   the model says. */
static void test_vertex_tier_keeps_a_highlight_that_falls_between_vertices(void **state) {
    fixture *f = *state;
    const gl2 *gl = &f->gl;
    ht_material m = hand_material(HT_MODEL_SCHEUERMANN, 0x0);
    m.shading.diffuse_color[0] = m.shading.diffuse_color[1] = m.shading.diffuse_color[2] = 0.05;
    m.shading.wrap = 0.0;
    m.shading.primary = (ht_lobe){ .color = { 0.8, 0.8, 0.8 }, .exponent = 400.0, .shift = 0.0 };
    m.shading.secondary = (ht_lobe){ .color = { 0, 0, 0 }, .exponent = 1.0, .shift = 0.0 };
    ht_plan p = plan_for(&m, 1, 0x0);
    ht_tier_output full, vertex;
    emit(&p, &full, &vertex);
    GLuint program = link_program(gl, text_of(&vertex, "vertex.vert"), NULL);
    gl->UseProgram(program);

    /* H at the quad's centre; tangents either side of the plane t.H = 0. */
    shading_case c;
    memset(&c, 0, sizeof c);
    c.N[2] = 1.0;
    c.ao = 1.0;
    c.lights[0] = (ht_light){ .type = HT_LIGHT_DIRECTIONAL, .vector = { 0, 0, 1 }, .color = { 1, 1, 1 } };
    double hv[3] = { eye[0], eye[1], eye[2] + sqrt(eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2]) };
    double h = sqrt(hv[0] * hv[0] + hv[1] * hv[1] + hv[2] * hv[2]);
    for (int k = 0; k < 3; k++) hv[k] /= h;
    double u[3] = { hv[2], 0.0, -hv[0] }; /* H x (0, 1, 0), perpendicular to H */
    double ul = sqrt(u[0] * u[0] + u[2] * u[2]);
    float tangent[2][3];
    for (int side = 0; side < 2; side++)
        for (int k = 0; k < 3; k++) tangent[side][k] = (float)(u[k] / ul + (side ? 0.6 : -0.6) * hv[k]);
    set_light_uniforms(gl, program, &p, &c);

    char err[512];
    ht_gl htgl;
    ht_fixed4_program luts;
    ht_fixed4_stages stages;
    if (ht_gl_load(&htgl, ht_test_getproc, err, sizeof err) != HT_OK) fail_msg("ht_gl_load: %s", err);
    if (ht_fixed4_parse(text_of(&vertex, "vertex-luts.json")->text, "vertex-luts.json", &luts, err, sizeof err) !=
        HT_OK)
        fail_msg("%s", err);
    ht_fixed4_stages_init(&stages, &htgl, &luts, "vertex");
    stages.albedo = f->white_tex;
    const float colors[1][3] = { { 1, 1, 1 } };
    int scale = ht_fixed4_scale(&luts, colors);
    if (ht_fixed4_stages_bake(&stages, colors, scale, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_fixed4_stages_bind(&stages, false);
    gl->Uniform1f(gl->GetUniformLocation(program, HT_U_LUT_SCALE), (float)scale);

    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    const float corners[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    glBegin(GL_QUADS);
    for (int i = 0; i < 4; i++) {
        const float *t = tangent[corners[i][0] > 0];
        glNormal3f(0, 0, 1);
        gl->MultiTexCoord2f(GL_TEXTURE0, 0.5f, 0.5f);
        gl->VertexAttrib3f(HT_ATTR_TANGENT_LOCATION, t[0], t[1], t[2]);
        gl->VertexAttrib1f(HT_ATTR_AO_LOCATION, 1.0f);
        glVertex3f(corners[i][0], corners[i][1], 0.0f);
    }
    glEnd();
    uint8_t pixels[W * H * 4];
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    assert_int_equal(glGetError(), GL_NO_ERROR);

    /* The model at the vertices (what per-vertex colours interpolate) and
       at the middle pixel (the tangent interpolated there). */
    int at_vertices = 0;
    for (int i = 0; i < 4; i++) {
        const float pos[3] = { corners[i][0], corners[i][1], 0.0f };
        for (int k = 0; k < 3; k++) c.T[k] = tangent[corners[i][0] > 0][k];
        uint8_t want[3];
        expected_rgb(&p, &c, pos, false, want);
        for (int k = 0; k < 3; k++) at_vertices = want[k] > at_vertices ? want[k] : at_vertices;
    }
    const int x = W / 2, y = 1;
    const float pos[3] = { 2.0f * ((float)x + 0.5f) / W - 1.0f, 2.0f * ((float)y + 0.5f) / H - 1.0f, 0.0f };
    const double a = (pos[0] + 1.0) / 2.0;
    for (int k = 0; k < 3; k++) c.T[k] = (1.0 - a) * tangent[0][k] + a * tangent[1][k];
    uint8_t want[3];
    expected_rgb(&p, &c, pos, false, want);
    const uint8_t *got = &pixels[(y * W + x) * 4];
    printf("highlight between vertices: vertex tier %d, model %d, brightest vertex %d\n", got[0], want[0],
           at_vertices);
    assert_true(at_vertices < 40);    /* per-vertex colours could reach no more */
    assert_true(want[0] > 150);       /* the highlight the model has there */
    for (int k = 0; k < 3; k++) assert_true(abs((int)got[k] - (int)want[k]) <= 12);

    ht_fixed4_stages_unbind(&stages);
    stages.albedo = 0; /* the fixture's */
    ht_fixed4_stages_release(&stages);
    gl->UseProgram(0);
    gl->DeleteProgram(program);
    ht_tier_output_free(&full);
    ht_tier_output_free(&vertex);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_desktop_program_links_and_exposes_the_runtime_uniforms),
        cmocka_unit_test(test_full_tier_shades_what_the_model_computes),
        cmocka_unit_test(test_full_tier_matches_the_model_at_extremes),
        cmocka_unit_test(test_vertex_tier_shades_what_the_model_computes_without_detail),
        cmocka_unit_test(test_vertex_tier_keeps_a_highlight_that_falls_between_vertices),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

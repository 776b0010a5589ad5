/* test_render_app_state — ht_renderer_draw inside an application's GL
   context: fixed-function state the application left behind (lighting and
   an extra light, fog, colour material, texgen and texture matrices,
   textures enabled on units a tier does not use, its own program, its own
   client arrays, flat shading, line polygons, a logic op) changes no tier's
   image, the head's included; after the draw the application finds that
   state as it left it; a full attribute stack is refused with one line and
   nothing drawn. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include <hairtier/hairtier.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"

#define SIZE 96
#define UNITS 4   /* the units the application dirties and the checks read */

static ht_test_furball fx;
static ht_mesh head;

/* <GL/gl.h> declares GL 1.3 itself, so glext.h leaves this one out. */
typedef void (APIENTRYP unit_fn)(GLenum unit);

/* What the test calls beyond GL 1.1, through getproc as the library does. */
static struct {
    unit_fn ActiveTexture;
    unit_fn ClientActiveTexture;
    PFNGLCREATESHADERPROC CreateShader;
    PFNGLSHADERSOURCEPROC ShaderSource;
    PFNGLCOMPILESHADERPROC CompileShader;
    PFNGLCREATEPROGRAMPROC CreateProgram;
    PFNGLATTACHSHADERPROC AttachShader;
    PFNGLLINKPROGRAMPROC LinkProgram;
    PFNGLGETPROGRAMIVPROC GetProgramiv;
    PFNGLDELETESHADERPROC DeleteShader;
    PFNGLDELETEPROGRAMPROC DeleteProgram;
    PFNGLUSEPROGRAMPROC UseProgram;
    PFNGLVERTEXATTRIBPOINTERPROC VertexAttribPointer;
    PFNGLENABLEVERTEXATTRIBARRAYPROC EnableVertexAttribArray;
    PFNGLGETVERTEXATTRIBIVPROC GetVertexAttribiv;
    PFNGLGENBUFFERSPROC GenBuffers;
    PFNGLDELETEBUFFERSPROC DeleteBuffers;
    PFNGLBINDBUFFERPROC BindBuffer;
} gl;

#define LOAD(name)                                              \
    do {                                                        \
        void *p_ = ht_test_getproc("gl" #name);                 \
        if (!p_) return -1;                                     \
        memcpy(&gl.name, &p_, sizeof p_);                       \
    } while (0)

/* The application's own objects. */
static GLuint app_program, app_buffers[2], black_2d, black_1d, black_cube;
static float *junk;        /* client arrays the application left enabled */

static GLuint black_texture(GLenum target) {
    static const uint8_t black[4] = { 0, 0, 0, 255 };
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(target, t);
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    if (target == GL_TEXTURE_1D) {
        glTexImage1D(GL_TEXTURE_1D, 0, GL_RGBA8, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, black);
    } else if (target == GL_TEXTURE_2D) {
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, black);
    } else {
        for (int face = 0; face < 6; face++)
            glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + (GLenum)face, 0, GL_RGBA8, 1, 1, 0, GL_RGBA,
                         GL_UNSIGNED_BYTE, black);
    }
    glBindTexture(target, 0);
    return t;
}

/* Magenta everywhere: what the head or the fixed tier would show if they
   drew with the application's program. */
static GLuint magenta_program(void) {
    static const char *vs = "#version 110\nvoid main() { gl_Position = ftransform(); }\n";
    static const char *fs = "#version 110\nvoid main() { gl_FragColor = vec4(1.0, 0.0, 1.0, 1.0); }\n";
    GLuint p = gl.CreateProgram(), v = gl.CreateShader(GL_VERTEX_SHADER), f = gl.CreateShader(GL_FRAGMENT_SHADER);
    gl.ShaderSource(v, 1, &vs, NULL);
    gl.ShaderSource(f, 1, &fs, NULL);
    gl.CompileShader(v);
    gl.CompileShader(f);
    gl.AttachShader(p, v);
    gl.AttachShader(p, f);
    gl.LinkProgram(p);
    gl.DeleteShader(v);
    gl.DeleteShader(f);
    GLint ok = GL_FALSE;
    gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
    return ok == GL_TRUE ? p : 0;
}

static int setup(void **state) {
    (void)state;
    if (!ht_test_furball_setup(&fx, "app-state", SIZE)) return -1;
    ht_mesh strips;
    if (ht_mesh_build_patches(&(ht_patches_desc){ .head_radius = 0.3f, .layers = 1, .strips = 8, .segments = 2 },
                              &strips, &head) != HT_OK)
        return -1;
    ht_mesh_free(&strips);
    LOAD(ActiveTexture);
    LOAD(ClientActiveTexture);
    LOAD(CreateShader);
    LOAD(ShaderSource);
    LOAD(CompileShader);
    LOAD(CreateProgram);
    LOAD(AttachShader);
    LOAD(LinkProgram);
    LOAD(GetProgramiv);
    LOAD(DeleteShader);
    LOAD(DeleteProgram);
    LOAD(UseProgram);
    LOAD(VertexAttribPointer);
    LOAD(EnableVertexAttribArray);
    LOAD(GetVertexAttribiv);
    LOAD(GenBuffers);
    LOAD(DeleteBuffers);
    LOAD(BindBuffer);
    if (!(app_program = magenta_program())) return -1;
    gl.GenBuffers(2, app_buffers);
    black_2d = black_texture(GL_TEXTURE_2D);
    black_1d = black_texture(GL_TEXTURE_1D);
    black_cube = black_texture(GL_TEXTURE_CUBE_MAP);
    uint32_t n = fx.mesh.vertex_count > head.vertex_count ? fx.mesh.vertex_count : head.vertex_count;
    junk = malloc(sizeof *junk * 4 * n);
    if (!junk) return -1;
    for (uint32_t i = 0; i < 4 * n; i++) junk[i] = 0.5f;
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    free(junk);
    ht_mesh_free(&head);
    if (gl.DeleteProgram && app_program) {
        gl.DeleteProgram(app_program);
        gl.DeleteBuffers(2, app_buffers);
        GLuint textures[3] = { black_2d, black_1d, black_cube };
        glDeleteTextures(3, textures);
    }
    return ht_test_furball_teardown(&fx);
}

static ht_frame_desc frame(void) {
    ht_frame_desc f = ht_test_furball_frame(2.4f);
    f.opaque = &head;
    return f;
}

/* ---- the application's state ---- */

/* Everything the application sets below, as GL reports it. */
typedef struct gl_snapshot {
    GLboolean enabled[14];
    GLboolean unit_enabled[UNITS][8];
    GLint unit_binding[UNITS][3];
    GLint env_mode[UNITS];
    GLfloat texture_matrix[UNITS][16];
    GLboolean texcoord_array[UNITS];
    GLfloat projection[16], modelview[16];
    GLint matrix_mode, active_texture, client_active_texture, program;
    GLint blend_src, blend_dst, alpha_func, depth_func, cull_face, shade_model, polygon_mode[2], logic_op;
    GLfloat alpha_ref, current_color[4], light5_diffuse[4], fog_color[4], emission[4];
    GLboolean depth_mask, color_mask[4];
    GLboolean vertex_array, normal_array, color_array;
    GLint attrib0_array, array_buffer, element_buffer, unpack_alignment;
} gl_snapshot;

static const GLenum snapshot_caps[14] = {
    GL_LIGHTING, GL_LIGHT0, GL_LIGHT5, GL_FOG, GL_COLOR_MATERIAL, GL_NORMALIZE, GL_DEPTH_TEST,
    GL_BLEND, GL_ALPHA_TEST, GL_CULL_FACE, GL_POLYGON_OFFSET_FILL, GL_COLOR_LOGIC_OP, GL_POLYGON_STIPPLE,
    GL_SCISSOR_TEST,
};

static const GLenum unit_caps[8] = {
    GL_TEXTURE_1D, GL_TEXTURE_2D, GL_TEXTURE_3D, GL_TEXTURE_CUBE_MAP,
    GL_TEXTURE_GEN_S, GL_TEXTURE_GEN_T, GL_TEXTURE_GEN_R, GL_TEXTURE_GEN_Q,
};

static void snapshot(gl_snapshot *s) {
    memset(s, 0, sizeof *s);
    GLint active = 0, client = 0, mode = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    glGetIntegerv(GL_CLIENT_ACTIVE_TEXTURE, &client);
    glGetIntegerv(GL_MATRIX_MODE, &mode);
    s->active_texture = active;
    s->client_active_texture = client;
    s->matrix_mode = mode;
    for (int i = 0; i < 14; i++) s->enabled[i] = glIsEnabled(snapshot_caps[i]);
    for (int u = 0; u < UNITS; u++) {
        gl.ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        for (int k = 0; k < 8; k++) s->unit_enabled[u][k] = glIsEnabled(unit_caps[k]);
        glGetIntegerv(GL_TEXTURE_BINDING_1D, &s->unit_binding[u][0]);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &s->unit_binding[u][1]);
        glGetIntegerv(GL_TEXTURE_BINDING_CUBE_MAP, &s->unit_binding[u][2]);
        glGetTexEnviv(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, &s->env_mode[u]);
        glGetFloatv(GL_TEXTURE_MATRIX, s->texture_matrix[u]);
        gl.ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        s->texcoord_array[u] = glIsEnabled(GL_TEXTURE_COORD_ARRAY);
    }
    gl.ActiveTexture((GLenum)active);
    gl.ClientActiveTexture((GLenum)client);
    glGetFloatv(GL_PROJECTION_MATRIX, s->projection);
    glGetFloatv(GL_MODELVIEW_MATRIX, s->modelview);
    glGetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    glGetIntegerv(GL_BLEND_SRC, &s->blend_src);
    glGetIntegerv(GL_BLEND_DST, &s->blend_dst);
    glGetIntegerv(GL_ALPHA_TEST_FUNC, &s->alpha_func);
    glGetFloatv(GL_ALPHA_TEST_REF, &s->alpha_ref);
    glGetIntegerv(GL_DEPTH_FUNC, &s->depth_func);
    glGetIntegerv(GL_CULL_FACE_MODE, &s->cull_face);
    glGetIntegerv(GL_SHADE_MODEL, &s->shade_model);
    glGetIntegerv(GL_POLYGON_MODE, s->polygon_mode);
    glGetIntegerv(GL_LOGIC_OP_MODE, &s->logic_op);
    glGetFloatv(GL_CURRENT_COLOR, s->current_color);
    glGetLightfv(GL_LIGHT5, GL_DIFFUSE, s->light5_diffuse);
    glGetFloatv(GL_FOG_COLOR, s->fog_color);
    glGetMaterialfv(GL_FRONT, GL_EMISSION, s->emission);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s->depth_mask);
    glGetBooleanv(GL_COLOR_WRITEMASK, s->color_mask);
    s->vertex_array = glIsEnabled(GL_VERTEX_ARRAY);
    s->normal_array = glIsEnabled(GL_NORMAL_ARRAY);
    s->color_array = glIsEnabled(GL_COLOR_ARRAY);
    gl.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &s->attrib0_array);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &s->array_buffer);
    glGetIntegerv(GL_ELEMENT_ARRAY_BUFFER_BINDING, &s->element_buffer);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &s->unpack_alignment);
}

/* Fails naming the first member that differs. */
static void check_same_state(const gl_snapshot *before, const gl_snapshot *after, const char *what) {
#define SAME(member)                                                                                  \
    if (memcmp(&before->member, &after->member, sizeof before->member) != 0)                          \
        fail_msg("%s: %s changed across ht_renderer_draw", what, #member);
    for (int i = 0; i < 14; i++)
        if (before->enabled[i] != after->enabled[i])
            fail_msg("%s: glIsEnabled(0x%04x) changed from %d to %d", what, snapshot_caps[i], before->enabled[i],
                     after->enabled[i]);
    for (int u = 0; u < UNITS; u++)
        for (int k = 0; k < 8; k++)
            if (before->unit_enabled[u][k] != after->unit_enabled[u][k])
                fail_msg("%s: unit %d: glIsEnabled(0x%04x) changed from %d to %d", what, u, unit_caps[k],
                         before->unit_enabled[u][k], after->unit_enabled[u][k]);
    SAME(unit_binding) SAME(env_mode) SAME(texture_matrix) SAME(texcoord_array)
    SAME(projection) SAME(modelview) SAME(matrix_mode) SAME(active_texture) SAME(client_active_texture)
    SAME(program) SAME(blend_src) SAME(blend_dst) SAME(alpha_func) SAME(alpha_ref) SAME(depth_func)
    SAME(cull_face) SAME(shade_model) SAME(polygon_mode) SAME(logic_op) SAME(current_color)
    SAME(light5_diffuse) SAME(fog_color) SAME(emission) SAME(depth_mask) SAME(color_mask)
    SAME(vertex_array) SAME(normal_array) SAME(color_array) SAME(attrib0_array) SAME(array_buffer)
    SAME(element_buffer) SAME(unpack_alignment)
#undef SAME
}

/* What an application might leave set when it hands over for the hair;
   none of it is GL's initial state. */
static void dirty_state(void) {
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT5);
    glLightfv(GL_LIGHT5, GL_DIFFUSE, (const GLfloat[4]){ 1, 0, 0, 1 });
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    glMaterialfv(GL_FRONT_AND_BACK, GL_EMISSION, (const GLfloat[4]){ 0.4f, 0, 0, 1 });
    glEnable(GL_COLOR_MATERIAL);
    glEnable(GL_FOG);
    glFogi(GL_FOG_MODE, GL_LINEAR);
    glFogf(GL_FOG_START, 0.0f);
    glFogf(GL_FOG_END, 1.0f);
    glFogfv(GL_FOG_COLOR, (const GLfloat[4]){ 0, 1, 0, 1 });
    glEnable(GL_NORMALIZE);
    glColor4f(1, 0, 0, 0.5f);
    glShadeModel(GL_FLAT);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glEnable(GL_COLOR_LOGIC_OP);
    glLogicOp(GL_XOR);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(0, 5000);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_TRUE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glEnable(GL_ALPHA_TEST);
    glAlphaFunc(GL_NEVER, 0.25f);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT_AND_BACK);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int u = 0; u < UNITS; u++) {
        gl.ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glTexGeni(GL_S, GL_TEXTURE_GEN_MODE, GL_OBJECT_LINEAR);
        glTexGeni(GL_T, GL_TEXTURE_GEN_MODE, GL_OBJECT_LINEAR);
        glEnable(GL_TEXTURE_GEN_S);
        glEnable(GL_TEXTURE_GEN_T);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_ADD);
        glMatrixMode(GL_TEXTURE);
        glLoadIdentity();
        glTranslatef(0.25f, 0.5f, 0);
        glScalef(3, 3, 3);
    }
    /* Black textures on the units: 2D where the tiers put theirs, a cube
       map (which outranks 2D) and 1D beside them. */
    gl.ActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, black_2d);
    glEnable(GL_TEXTURE_2D);
    gl.ActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_CUBE_MAP, black_cube);
    glEnable(GL_TEXTURE_CUBE_MAP);
    gl.ActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, black_2d);
    glEnable(GL_TEXTURE_2D);
    gl.ActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_1D, black_1d);
    glEnable(GL_TEXTURE_1D);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(-2, 3, -1, 4, -5, 6);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glTranslatef(0.5f, -0.25f, 0.125f);
    glMatrixMode(GL_TEXTURE); /* with unit 3 active */
    gl.UseProgram(app_program);
    /* Arrays of its own, in client memory, then its buffers bound. */
    glEnableClientState(GL_COLOR_ARRAY);
    glColorPointer(4, GL_FLOAT, 0, junk);
    for (int u = 1; u < UNITS; u++) {
        gl.ClientActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glTexCoordPointer(2, GL_FLOAT, 0, junk);
    }
    gl.ClientActiveTexture(GL_TEXTURE2);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, junk);
    gl.EnableVertexAttribArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, app_buffers[0]);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, app_buffers[1]);
    assert_int_equal(glGetError(), GL_NO_ERROR);
}

/* Runs body with the application's state dirty, then puts GL's initial
   state back for the next case (the attribute stacks hold all of it but
   the program and the matrices). */
static void begin_dirty(void) {
    glPushAttrib(GL_ALL_ATTRIB_BITS);
    glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS);
    dirty_state();
}

static void end_dirty(void) {
    gl.UseProgram(0);
    for (int u = UNITS - 1; u >= 0; u--) {
        gl.ActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glMatrixMode(GL_TEXTURE);
        glLoadIdentity();
    }
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glPopClientAttrib();
    glPopAttrib();
    assert_int_equal(glGetError(), GL_NO_ERROR);
}

/* Clears, draws, reads back; the clear is the test's, under its own state. */
static void draw_frame(ht_renderer *r, ht_image *img) {
    GLboolean mask[4];
    glGetBooleanv(GL_COLOR_WRITEMASK, mask);
    GLboolean depth_mask;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glColorMask(mask[0], mask[1], mask[2], mask[3]);
    glDepthMask(depth_mask);
    ht_frame_desc f = frame();
    ht_result res = ht_renderer_draw(r, &f);
    if (res != HT_OK) fail_msg("ht_renderer_draw: %s; log:\n%s", ht_result_string(res), ht_test_log_text);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    assert_int_equal(ht_test_gl_read(&fx.gl, img), HT_OK);
}

typedef struct tier_case {
    const char *name;
    ht_renderer_desc desc;
} tier_case;

static const tier_case every_tier[4] = {
    { "full", { .tier = HT_TIER_FULL, .strict = true } },
    { "vertex", { .tier = HT_TIER_VERTEX, .strict = true } },
    { "fixed", { .tier = HT_TIER_FIXED, .strict = true } },
    { "flat", { .flat = true } },
};

static ht_renderer *create(const tier_case *c) {
    ht_renderer *r = ht_test_renderer_create(c->desc, fx.bundle_dir, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    return r;
}

/* ---- tests ---- */

static void test_state_the_application_left_changes_no_tiers_image(void **state) {
    (void)state;
    char failed[512] = "";
    for (int t = 0; t < 4; t++) {
        ht_renderer *r = create(&every_tier[t]);
        ht_image clean, dirty;
        draw_frame(r, &clean);
        ht_test_pixel_stats s = ht_test_pixel_stats_of(&clean, ht_test_background);
        assert_true(s.changed > SIZE * SIZE / 10);
        assert_int_equal(s.magenta, 0);
        begin_dirty();
        draw_frame(r, &dirty);
        end_dirty();
        size_t differ = 0;
        for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++) differ += clean.pixels[i] != dirty.pixels[i];
        if (differ)
            snprintf(failed + strlen(failed), sizeof failed - strlen(failed), " %s (%zu channels)",
                     every_tier[t].name, differ);
        ht_image_free(&clean);
        ht_image_free(&dirty);
        ht_renderer_destroy(r);
    }
    if (failed[0]) fail_msg("the application's state changed the image of:%s", failed);
}

static void test_draw_gives_the_application_its_state_back(void **state) {
    (void)state;
    gl_snapshot before, after;
    for (int t = 0; t < 4; t++) {
        ht_renderer *r = create(&every_tier[t]);
        ht_image img;
        /* GL's initial state, then an application's. */
        snapshot(&before);
        draw_frame(r, &img);
        ht_image_free(&img);
        snapshot(&after);
        check_same_state(&before, &after, every_tier[t].name);
        begin_dirty();
        snapshot(&before);
        draw_frame(r, &img);
        ht_image_free(&img);
        snapshot(&after);
        check_same_state(&before, &after, every_tier[t].name);
        end_dirty();
        ht_renderer_destroy(r);
    }
}

/* A draw with no room to save the application's state draws nothing and
   leaves both stacks as they were. */
static void test_full_attribute_stacks_are_refused_with_one_line(void **state) {
    (void)state;
    ht_renderer *r = create(&every_tier[0]);
    const ht_frame_desc f = frame();
    ht_image img;
    draw_frame(r, &img); /* the frame's one-time warnings (a light's type) out of the way */
    ht_image_free(&img);
    const struct { GLenum max, depth; const char *call; } stacks[2] = {
        { GL_MAX_ATTRIB_STACK_DEPTH, GL_ATTRIB_STACK_DEPTH, "glPushAttrib" },
        { GL_MAX_CLIENT_ATTRIB_STACK_DEPTH, GL_CLIENT_ATTRIB_STACK_DEPTH, "glPushClientAttrib" },
    };
    for (int i = 0; i < 2; i++) {
        GLint max = 0, depth = 0, other = 0;
        glGetIntegerv(stacks[i].max, &max);
        assert_true(max >= 16);
        for (int k = 0; k < max; k++) {
            if (i == 0) glPushAttrib(GL_ENABLE_BIT);
            else glPushClientAttrib(GL_CLIENT_PIXEL_STORE_BIT);
        }
        assert_int_equal(glGetError(), GL_NO_ERROR);
        glClearColor(ht_test_background[0], ht_test_background[1], ht_test_background[2], 1);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        ht_test_log_clear();
        assert_int_equal(ht_renderer_draw(r, &f), HT_ERR_GL);
        char want[128];
        snprintf(want, sizeof want, "hairtier: ht_renderer_draw: %s: GL_STACK_OVERFLOW", stacks[i].call);
        assert_true(ht_test_logged(want));
        assert_int_equal(strchr(ht_test_log_text, '\n') - ht_test_log_text + 1, (long)strlen(ht_test_log_text));
        assert_int_equal(glGetError(), GL_NO_ERROR);
        glGetIntegerv(stacks[i].depth, &depth);
        glGetIntegerv(stacks[1 - i].depth, &other);
        assert_int_equal(depth, max);
        assert_int_equal(other, 0);
        assert_int_equal(ht_test_gl_read(&fx.gl, &img), HT_OK);
        assert_int_equal(ht_test_pixel_stats_of(&img, ht_test_background).changed, 0);
        ht_image_free(&img);
        for (int k = 0; k < max; k++) {
            if (i == 0) glPopAttrib();
            else glPopClientAttrib();
        }
    }
    /* With room again, it draws. */
    draw_frame(r, &img);
    assert_true(ht_test_pixel_stats_of(&img, ht_test_background).changed > SIZE * SIZE / 10);
    ht_image_free(&img);
    ht_renderer_destroy(r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state_the_application_left_changes_no_tiers_image),
        cmocka_unit_test(test_draw_gives_the_application_its_state_back),
        cmocka_unit_test(test_full_attribute_stacks_are_refused_with_one_line),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

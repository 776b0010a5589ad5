/* test_render_probe — the full tier's pixels against the double-precision
   oracle (runtime/model.c), on whichever Mesa driver runs it (make test
   runs it on llvmpipe and on softpipe).

   The probe is a grid of flat cells in the plane z = 0, facing a camera on
   the z axis. Every vertex of a cell carries the same T, N, uv and ao, so
   every pixel of the cell has known inputs; V and L come from the pixel's
   position, which the test reconstructs exactly by casting the pixel
   centre's ray onto the plane. Each pixel is compared with
   ht_model_shade_d, clamped to [0,1] and rounded to 8 bits: within
   TOLERANCE per channel. Cells and bundles cover the model's extremes:
   L = -V (the centre pixel of a 129-pixel view, where V is exactly +z),
   T parallel and antiparallel to H, T parallel to N after the shift
   (shifts of +-100), T = -N with a shift of 1 (shifted tangent of zero
   length), a zero tangent, exponents 0 and 10000, Kajiya-Kay, point and
   directional lights, and the base/shift/sparkle textures sampled at texel
   centres. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GL/gl.h>

#include "hairgen.h"
#include "hairtier.h"
#include "image.h"
#include "model.h"
#include "rng.h"
#include "support_osmesa.h"

#define SIZE 129          /* odd: the centre pixel's ray is exactly the z axis */
#define GRID 9            /* odd: a cell sits centred on the origin */
#define TOLERANCE 2       /* per channel, in 1/255 */
#define EYE_Z 4.0
#define FOV_Y 30.0
#define TEXTURE_SIZE 16

static char work[64];
static ht_test_gl gl;

typedef struct cell {
    double T[3], N[3];
    double uv[2];
    double ao;
} cell;

static cell cells[GRID * GRID];

/* ---- bundles ---- */

typedef struct probe_material {
    const char *name;
    const char *model;
    double e1, s1, e2, s2;
    bool textured;
} probe_material;

static void write_material(const probe_material *p, const char *path) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    bool kk = strcmp(p->model, "kajiya-kay") == 0;
    fprintf(f, "{ \"format\": \"hairtier-material/1\", \"name\": \"%s\", \"model\": \"%s\",\n"
               "  \"diffuse\": {\"color\": [0.35, 0.22, 0.12]%s},\n",
            p->name, p->model, kk ? "" : ", \"wrap\": 0.25");
    if (kk)
        fprintf(f, "  \"primary\": {\"color\": [0.7, 0.65, 0.6], \"exponent\": %g}", p->e1);
    else
        fprintf(f, "  \"primary\": {\"color\": [0.7, 0.65, 0.6], \"exponent\": %g, \"shift\": %g},\n"
                   "  \"secondary\": {\"color\": [0.4, 0.3, 0.2], \"exponent\": %g, \"shift\": %g}",
                p->e1, p->s1, p->e2, p->s2);
    if (p->textured)
        fprintf(f, ",\n  \"textures\": {\n"
                   "    \"base\": {\"procedural\": \"stretched-noise\", \"size\": %d, \"seed\": 5},\n"
                   "    \"shift\": {\"procedural\": \"noise\", \"size\": %d, \"seed\": 6},\n"
                   "    \"sparkle\": {\"procedural\": \"sparkle\", \"size\": %d, \"seed\": 7} }",
                TEXTURE_SIZE, TEXTURE_SIZE, TEXTURE_SIZE);
    fprintf(f, " }\n");
    fclose(f);
}

static void write_scene(const char *path, const char *light_type) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "{ \"format\": \"hairtier-scene/1\", \"resolution\": [%d, %d],\n"
               "  \"camera\": {\"eye\": [0, 0, %g], \"target\": [0, 0, 0], \"fov_y\": %g},\n"
               "  \"lights\": [{\"type\": \"%s\", \"%s\": [0, 0, 1]}],\n"
               "  \"geometry\": {\"type\": \"furball\"} }\n",
            SIZE, SIZE, EYE_Z, FOV_Y, light_type,
            strcmp(light_type, "point") == 0 ? "position" : "direction");
    fclose(f);
}

static void make_bundle(const probe_material *p, const char *light_type, char *dir, size_t dir_size) {
    char material[256], scene[256], err[2048];
    snprintf(material, sizeof material, "%s/%s.json", work, p->name);
    snprintf(scene, sizeof scene, "%s/scene-%s.json", work, light_type);
    snprintf(dir, dir_size, "%s/bundle-%s-%s", work, p->name, light_type);
    write_material(p, material);
    write_scene(scene, light_type);
    if (ht_bundle_generate(material, scene, dir, NULL, err, sizeof err) != HT_OK)
        fail_msg("hairgen %s: %s", p->name, err);
}

/* ---- the probe mesh ---- */

static void unit(double v[3]) {
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0)
        for (int i = 0; i < 3; i++) v[i] /= len;
}

static void set3(double v[3], double x, double y, double z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

/* Cells 0..: special cases first, the rest random (T perpendicular to N as
   on real ribbons, some not). H is computed for the first frame's light. */
static void make_cells(const double light_dir[3]) {
    ht_rng rng = ht_rng_seed(42);
    double H[3] = { light_dir[0], light_dir[1], light_dir[2] + 1.0 };
    unit(H);
    for (int i = 0; i < GRID * GRID; i++) {
        cell *c = &cells[i];
        double a[3] = { ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1) };
        double b[3] = { ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1) };
        unit(a);
        double along = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        if (i % 3 != 0)
            for (int k = 0; k < 3; k++) b[k] -= along * a[k];
        unit(b);
        memcpy(c->T, a, sizeof a);
        memcpy(c->N, b, sizeof b);
        c->ao = ht_rng_range(&rng, 0.3, 1.0);
        int texel = (int)(ht_rng_unit(&rng) * TEXTURE_SIZE * TEXTURE_SIZE);
        c->uv[0] = (texel % TEXTURE_SIZE + 0.5) / TEXTURE_SIZE;
        c->uv[1] = (texel / TEXTURE_SIZE + 0.5) / TEXTURE_SIZE;
    }
    memcpy(cells[0].T, H, sizeof H);                              /* T parallel to H */
    set3(cells[0].N, H[1], -H[0], 0), unit(cells[0].N);
    for (int k = 0; k < 3; k++) cells[1].T[k] = -H[k];            /* antiparallel */
    memcpy(cells[1].N, cells[0].N, sizeof cells[0].N);
    set3(cells[2].T, 0, 0, 0);                                    /* zero tangent */
    set3(cells[3].N, 0, 1, 0), set3(cells[3].T, 0, -1, 0);        /* T = -N: zero at shift 1 */
    set3(cells[4].T, 1, 0, 0), set3(cells[4].N, 0, 1, 0);         /* T perpendicular to H */
    set3(cells[5].N, 0, 0, 0);                                    /* zero normal */
    int centre = (GRID / 2) * GRID + GRID / 2;                    /* L = -V in frame 1 */
    set3(cells[centre].T, 0, 1, 0), set3(cells[centre].N, 0, 0, 1);
}

static double half_extent(void) { return EYE_Z * tan(FOV_Y * M_PI / 360.0); }

static void build_mesh(ht_mesh *mesh) {
    int n = GRID * GRID;
    mesh->vertices = calloc((size_t)n * 4, sizeof *mesh->vertices);
    mesh->indices = calloc((size_t)n * 6, sizeof *mesh->indices);
    mesh->components = calloc((size_t)n, sizeof *mesh->components);
    assert_non_null(mesh->vertices);
    mesh->vertex_count = (uint32_t)n * 4;
    mesh->index_count = (uint32_t)n * 6;
    mesh->component_count = (uint32_t)n;
    double pitch = 2 * half_extent() / GRID, size = pitch * 0.8;
    for (int i = 0; i < n; i++) {
        double cx = -half_extent() + pitch * (i % GRID + 0.5), cy = -half_extent() + pitch * (i / GRID + 0.5);
        for (int v = 0; v < 4; v++) {
            ht_vertex *out = &mesh->vertices[i * 4 + v];
            out->position[0] = (float)(cx + size * ((v & 1) ? 0.5 : -0.5));
            out->position[1] = (float)(cy + size * ((v & 2) ? 0.5 : -0.5));
            for (int k = 0; k < 3; k++) {
                out->normal[k] = (float)cells[i].N[k];
                out->tangent[k] = (float)cells[i].T[k];
            }
            out->uv[0] = (float)cells[i].uv[0];
            out->uv[1] = (float)cells[i].uv[1];
            out->ao = (float)cells[i].ao;
        }
        static const uint32_t quad[6] = { 0, 1, 3, 0, 3, 2 };
        for (int k = 0; k < 6; k++) mesh->indices[i * 6 + k] = (uint32_t)i * 4 + quad[k];
        mesh->components[i] = (ht_component){ (uint32_t)i * 6, 6, 0 };
    }
}

static int setup(void **state) {
    (void)state;
    unsetenv("HAIRTIER_TIER");
    strcpy(work, "/tmp/hairtier-test-probe-XXXXXX");
    if (!mkdtemp(work)) return -1;
    char err[512];
    if (!ht_test_gl_create(&gl, SIZE, SIZE, NULL, err, sizeof err)) {
        fprintf(stderr, "setup: %s\n", err);
        return -1;
    }
    return 0;
}

static int teardown(void **state) {
    (void)state;
    ht_test_gl_destroy(&gl);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", work);
    return system(cmd) == 0 ? 0 : -1;
}

/* ---- the oracle, per pixel ---- */

typedef struct textures { ht_image albedo, detail; } textures;

static void texel(const ht_image *img, const double uv[2], int channel_count, double out[]) {
    int x = (int)(uv[0] * img->width), y = (int)(uv[1] * img->height);
    const uint8_t *p = img->pixels + ((size_t)y * img->width + x) * img->channels;
    for (int c = 0; c < channel_count; c++) out[c] = p[c] / 255.0;
}

/* Which cell a pixel's centre falls in, at least one pixel inside its edge. */
static int cell_at(double px, double py, double world[3]) {
    double ndc_x = (px + 0.5) * 2.0 / SIZE - 1.0, ndc_y = (py + 0.5) * 2.0 / SIZE - 1.0;
    world[0] = ndc_x * half_extent();
    world[1] = ndc_y * half_extent();
    world[2] = 0;
    double pitch = 2 * half_extent() / GRID, margin = 2 * half_extent() / SIZE * 1.01;
    int gx = (int)floor((world[0] + half_extent()) / pitch), gy = (int)floor((world[1] + half_extent()) / pitch);
    if (gx < 0 || gy < 0 || gx >= GRID || gy >= GRID) return -1;
    double lx = world[0] + half_extent() - pitch * (gx + 0.5), ly = world[1] + half_extent() - pitch * (gy + 0.5);
    double inner = pitch * 0.4 - margin;
    if (fabs(lx) > inner || fabs(ly) > inner) return -1;
    return gy * GRID + gx;
}

typedef struct probe_result { int pixels, worst, worst_cell; double worst_expected, worst_got; } probe_result;

static probe_result compare(const ht_image *img, const ht_shading *shading, const ht_light *light,
                            const textures *tex) {
    probe_result res = { 0, 0, -1, 0, 0 };
    for (int row = 0; row < SIZE; row++) {
        for (int x = 0; x < SIZE; x++) {
            double P[3];
            int ci = cell_at(x, SIZE - 1 - row, P);
            if (ci < 0) continue;
            const cell *c = &cells[ci];
            ht_surface s = { .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = c->ao };
            memcpy(s.T, c->T, sizeof s.T);
            memcpy(s.N, c->N, sizeof s.N);
            set3(s.V, -P[0], -P[1], EYE_Z - P[2]);
            if (tex->albedo.pixels) texel(&tex->albedo, c->uv, 3, s.base);
            if (tex->detail.pixels) {
                double d[2];
                texel(&tex->detail, c->uv, 2, d);
                s.shift_tex = d[0];
                s.sparkle = d[1];
            }
            ht_light_ray ray = { .L = { light->vector[0], light->vector[1], light->vector[2] },
                                 .color = { light->color[0], light->color[1], light->color[2] } };
            if (light->type == HT_LIGHT_POINT)
                for (int k = 0; k < 3; k++) ray.L[k] -= P[k];
            double rgb[3];
            ht_model_shade_d(shading, &s, &ray, 1, rgb);
            const uint8_t *got = img->pixels + ((size_t)row * SIZE + x) * 4;
            for (int k = 0; k < 3; k++) {
                double clamped = fmin(1.0, fmax(0.0, rgb[k]));
                int expected = (int)lround(clamped * 255.0);
                int diff = abs(expected - got[k]);
                if (diff > res.worst) {
                    res.worst = diff;
                    res.worst_cell = ci;
                    res.worst_expected = expected;
                    res.worst_got = got[k];
                }
            }
            res.pixels++;
        }
    }
    return res;
}

/* The renderer's log, shown only when a probe fails. */
static char log_text[8192];

static void log_line(void *user, const char *line) {
    (void)user;
    size_t used = strlen(log_text);
    snprintf(log_text + used, sizeof log_text - used, "%s\n", line);
}

/* Renders the probe with one bundle's full tier under one light and
   compares every covered pixel with the oracle. */
static void probe(const probe_material *p, ht_light light) {
    char dir[256], material_path[300], err[2048];
    const char *type = light.type == HT_LIGHT_POINT ? "point" : "directional";
    make_bundle(p, type, dir, sizeof dir);
    snprintf(material_path, sizeof material_path, "%s/%s.json", work, p->name);
    ht_material m;
    assert_int_equal(ht_material_load(material_path, &m, err, sizeof err), HT_OK);

    textures tex = { 0 };
    char path[400];
    if (p->textured) {
        snprintf(path, sizeof path, "%s/albedo.png", dir);
        assert_int_equal(ht_image_read_png(path, &tex.albedo, err, sizeof err), HT_OK);
        snprintf(path, sizeof path, "%s/detail.png", dir);
        assert_int_equal(ht_image_read_png(path, &tex.detail, err, sizeof err), HT_OK);
    }

    ht_mesh mesh = { 0 };
    build_mesh(&mesh);
    ht_renderer *r = NULL;
    log_text[0] = '\0';
    assert_int_equal(ht_renderer_create(&(ht_renderer_desc){ .getproc = ht_test_getproc, .bundle_dir = dir,
                                                             .tier = HT_TIER_FULL, .strict = true,
                                                             .log = log_line }, &r), HT_OK);
    assert_int_equal(ht_renderer_tier(r), HT_TIER_FULL);
    assert_int_equal(ht_renderer_set_mesh(r, &mesh), HT_OK);
    glViewport(0, 0, SIZE, SIZE);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ht_frame_desc frame = { .camera = { .eye = { 0, 0, (float)EYE_Z }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 },
                                        .fov_y = (float)FOV_Y },
                            .lights = &light, .light_count = 1 };
    assert_int_equal(ht_renderer_draw(r, &frame), HT_OK);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    ht_image img;
    assert_int_equal(ht_test_gl_read(&gl, &img), HT_OK);

    probe_result res = compare(&img, &m.shading, &light, &tex);
    printf("probe %-14s %-11s light (%5.2f %5.2f %5.2f): %d pixels, worst %d/255", p->name, type,
           (double)light.vector[0], (double)light.vector[1], (double)light.vector[2], res.pixels, res.worst);
    if (res.worst_cell >= 0) printf(" (cell %d)", res.worst_cell);
    printf("\n");
    assert_true(res.pixels > GRID * GRID * 20); /* the cells were drawn and found */
    if (res.worst > TOLERANCE)
        fail_msg("%s: cell %d: expected %g/255, got %g/255\n%s", p->name, res.worst_cell, res.worst_expected,
                 res.worst_got, log_text);

    ht_image_free(&img);
    ht_image_free(&tex.albedo);
    ht_image_free(&tex.detail);
    ht_renderer_destroy(r);
    ht_mesh_free(&mesh);
}

static ht_light directional(double x, double y, double z) {
    double d[3] = { x, y, z };
    unit(d);
    return (ht_light){ HT_LIGHT_DIRECTIONAL, { (float)d[0], (float)d[1], (float)d[2] }, { 0.95f, 0.9f, 1.0f } };
}

static const double first_light[3] = { 0.3, 0.5, 0.8 };

static const probe_material plain = { "plain", "scheuermann", 80, 1.0, 24, 0.0, false };

static void test_full_tier_matches_oracle_on_generic_cells(void **state) {
    (void)state;
    probe(&plain, directional(first_light[0], first_light[1], first_light[2]));
}

static void test_full_tier_matches_oracle_when_light_is_behind_the_strand(void **state) {
    (void)state;
    probe(&plain, directional(0, 0, -1)); /* L = -V exactly at the centre pixel */
    probe(&plain, directional(0, 0, 1));  /* L = V */
    probe(&plain, directional(1, 0, 0));  /* grazing */
}

static void test_full_tier_matches_oracle_at_exponent_extremes(void **state) {
    (void)state;
    const probe_material zero = { "exponent-0", "scheuermann", 0, 0.0, 0, 0.0, false };
    const probe_material huge = { "exponent-10000", "scheuermann", 10000, 0.0, 10000, 0.0, false };
    probe(&zero, directional(first_light[0], first_light[1], first_light[2]));
    probe(&huge, directional(first_light[0], first_light[1], first_light[2]));
}

static void test_full_tier_matches_oracle_with_wide_shifts(void **state) {
    (void)state;
    const probe_material wide = { "shift-100", "scheuermann", 80, 100.0, 24, -100.0, false };
    probe(&wide, directional(first_light[0], first_light[1], first_light[2]));
}

static void test_full_tier_matches_oracle_for_kajiya_kay(void **state) {
    (void)state;
    const probe_material kk = { "kajiya-kay", "kajiya-kay", 60, 0, 0, 0, false };
    probe(&kk, directional(first_light[0], first_light[1], first_light[2]));
}

static void test_full_tier_matches_oracle_with_a_point_light(void **state) {
    (void)state;
    probe(&plain, (ht_light){ HT_LIGHT_POINT, { 0.8f, 1.1f, 1.5f }, { 1.0f, 0.9f, 0.8f } });
}

static void test_full_tier_matches_oracle_with_textures_at_texel_centres(void **state) {
    (void)state;
    const probe_material textured = { "textured", "scheuermann", 80, -0.1, 24, 0.15, true };
    probe(&textured, directional(first_light[0], first_light[1], first_light[2]));
}

int main(void) {
    double l[3] = { first_light[0], first_light[1], first_light[2] };
    unit(l);
    make_cells(l);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_tier_matches_oracle_on_generic_cells),
        cmocka_unit_test(test_full_tier_matches_oracle_when_light_is_behind_the_strand),
        cmocka_unit_test(test_full_tier_matches_oracle_at_exponent_extremes),
        cmocka_unit_test(test_full_tier_matches_oracle_with_wide_shifts),
        cmocka_unit_test(test_full_tier_matches_oracle_for_kajiya_kay),
        cmocka_unit_test(test_full_tier_matches_oracle_with_a_point_light),
        cmocka_unit_test(test_full_tier_matches_oracle_with_textures_at_texel_centres),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

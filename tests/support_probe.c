/* support_probe.c — see support_probe.h. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/hairgen.h>
#include "rng.h"
#include "support_probe.h"

#define SIZE HT_PROBE_SIZE
#define GRID HT_PROBE_GRID
#define EYE_Z HT_PROBE_EYE_Z
#define FOV_Y HT_PROBE_FOV_Y
#define TEXTURE_SIZE HT_PROBE_TEXTURE_SIZE

ht_probe_cell ht_probe_cells[HT_PROBE_CELLS];

const double ht_probe_first_light[3] = { 0.3, 0.5, 0.8 };

const ht_probe_material ht_probe_plain = { "plain", "scheuermann", 80, 1.0, 24, 0.0, false };

void ht_probe_unit(double v[3]) {
    double len = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (len > 0)
        for (int i = 0; i < 3; i++) v[i] /= len;
}

void ht_probe_set3(double v[3], double x, double y, double z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

/* H is computed for the first light. */
void ht_probe_make_cells(void) {
    ht_probe_cell *cells = ht_probe_cells;
    double light_dir[3] = { ht_probe_first_light[0], ht_probe_first_light[1], ht_probe_first_light[2] };
    ht_probe_unit(light_dir);
    ht_rng rng = ht_rng_seed(42);
    double H[3] = { light_dir[0], light_dir[1], light_dir[2] + 1.0 };
    ht_probe_unit(H);
    for (int i = 0; i < GRID * GRID; i++) {
        ht_probe_cell *c = &cells[i];
        double a[3] = { ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1) };
        double b[3] = { ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1), ht_rng_range(&rng, -1, 1) };
        ht_probe_unit(a);
        double along = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        if (i % 3 != 0)
            for (int k = 0; k < 3; k++) b[k] -= along * a[k];
        ht_probe_unit(b);
        memcpy(c->T, a, sizeof a);
        memcpy(c->N, b, sizeof b);
        c->ao = ht_rng_range(&rng, 0.3, 1.0);
        int texel = (int)(ht_rng_unit(&rng) * TEXTURE_SIZE * TEXTURE_SIZE);
        c->uv[0] = (texel % TEXTURE_SIZE + 0.5) / TEXTURE_SIZE;
        c->uv[1] = (texel / TEXTURE_SIZE + 0.5) / TEXTURE_SIZE;
    }
    memcpy(cells[0].T, H, sizeof H);                                        /* T parallel to H */
    ht_probe_set3(cells[0].N, H[1], -H[0], 0), ht_probe_unit(cells[0].N);
    for (int k = 0; k < 3; k++) cells[1].T[k] = -H[k];                      /* antiparallel */
    memcpy(cells[1].N, cells[0].N, sizeof cells[0].N);
    ht_probe_set3(cells[2].T, 0, 0, 0);                                     /* zero tangent */
    ht_probe_set3(cells[3].N, 0, 1, 0), ht_probe_set3(cells[3].T, 0, -1, 0); /* T = -N: zero at shift 1 */
    ht_probe_set3(cells[4].T, 1, 0, 0), ht_probe_set3(cells[4].N, 0, 1, 0);  /* T perpendicular to H */
    ht_probe_set3(cells[5].N, 0, 0, 0);                                     /* zero normal */
    int centre = (GRID / 2) * GRID + GRID / 2;                              /* L = -V for a light along -z */
    ht_probe_set3(cells[centre].T, 0, 1, 0), ht_probe_set3(cells[centre].N, 0, 0, 1);
}

static double half_extent(void) { return EYE_Z * tan(FOV_Y * M_PI / 360.0); }

void ht_probe_build_mesh(ht_mesh *mesh) {
    const ht_probe_cell *cells = ht_probe_cells;
    int n = GRID * GRID;
    memset(mesh, 0, sizeof *mesh);
    mesh->vertices = calloc((size_t)n * 4, sizeof *mesh->vertices);
    mesh->indices = calloc((size_t)n * 6, sizeof *mesh->indices);
    mesh->components = calloc((size_t)n, sizeof *mesh->components);
    assert_non_null(mesh->vertices);
    assert_non_null(mesh->indices);
    assert_non_null(mesh->components);
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

int ht_probe_cell_at(double px, double py, double world[3]) {
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

ht_light ht_probe_directional(double x, double y, double z) {
    double d[3] = { x, y, z };
    ht_probe_unit(d);
    return (ht_light){ HT_LIGHT_DIRECTIONAL, { (float)d[0], (float)d[1], (float)d[2] }, { 0.95f, 0.9f, 1.0f } };
}

const char *ht_probe_light_type(const ht_light *light) {
    return light->type == HT_LIGHT_POINT ? "point" : "directional";
}

ht_frame_desc ht_probe_frame(const ht_light *light) {
    return (ht_frame_desc){ .camera = { .eye = { 0, 0, (float)EYE_Z }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 },
                                        .fov_y = (float)FOV_Y },
                            .lights = light, .light_count = 1 };
}

/* ---- bundles ---- */

static void write_material(const ht_probe_material *p, const char *path) {
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

/* The probe lights' types and colours (the fixed tier's LUT carries the
   scene's light colours above 1). */
static void write_scene(const char *path, const ht_light *lights, int count) {
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "{ \"format\": \"hairtier-scene/1\", \"resolution\": [%d, %d],\n"
               "  \"camera\": {\"eye\": [0, 0, %g], \"target\": [0, 0, 0], \"fov_y\": %g},\n  \"lights\": [",
            SIZE, SIZE, EYE_Z, FOV_Y);
    for (int i = 0; i < count; i++) {
        const bool point = lights[i].type == HT_LIGHT_POINT;
        fprintf(f, "%s{\"type\": \"%s\", \"%s\": [0, 0, 1], \"color\": [%.9g, %.9g, %.9g]}", i ? ", " : "",
                point ? "point" : "directional", point ? "position" : "direction", (double)lights[i].color[0],
                (double)lights[i].color[1], (double)lights[i].color[2]);
    }
    fprintf(f, "],\n  \"geometry\": {\"type\": \"furball\"} }\n");
    fclose(f);
}

void ht_probe_make_bundle(const char *work, const ht_probe_material *p, const ht_light *light, char *dir,
                          size_t dir_size, ht_material *material) {
    char material_path[256];
    snprintf(material_path, sizeof material_path, "%s/%s.json", work, p->name);
    write_material(p, material_path);
    ht_probe_make_bundle_from_file(work, p->name, material_path, light, dir, dir_size, material);
}

void ht_probe_make_bundle_from_file(const char *work, const char *name, const char *material_path,
                                    const ht_light *light, char *dir, size_t dir_size, ht_material *material) {
    ht_probe_make_bundle_lights(work, name, material_path, light, 1, dir, dir_size, material);
}

void ht_probe_make_bundle_lights(const char *work, const char *name, const char *material_path,
                                 const ht_light *lights, int count, char *dir, size_t dir_size,
                                 ht_material *material) {
    char types[64] = "", scene[256], err[2048];
    for (int i = 0; i < count; i++)
        snprintf(types + strlen(types), sizeof types - strlen(types), "%s%s", i ? "-" : "",
                 ht_probe_light_type(&lights[i]));
    snprintf(scene, sizeof scene, "%s/scene-%s.json", work, types);
    snprintf(dir, dir_size, "%s/probe-%s-%s", work, name, types);
    write_scene(scene, lights, count);
    if (ht_generate_bundle(material_path, scene, dir, NULL, err, sizeof err) != HT_OK)
        fail_msg("hairgen %s: %s", name, err);
    assert_int_equal(ht_material_load(material_path, material, err, sizeof err), HT_OK);
}

/* ---- the oracle ---- */

void ht_probe_texel(const ht_image *img, const double uv[2], int channel_count, double out[]) {
    int x = (int)(uv[0] * img->width), y = (int)(uv[1] * img->height);
    const uint8_t *p = img->pixels + ((size_t)y * img->width + x) * img->channels;
    for (int c = 0; c < channel_count; c++) out[c] = p[c] / 255.0;
}

ht_surface ht_probe_surface(const ht_probe_cell *c, const double P[3]) {
    ht_surface s = { .base = { 1, 1, 1 }, .shift_tex = 0.5, .sparkle = 1, .ao = c->ao };
    memcpy(s.T, c->T, sizeof s.T);
    memcpy(s.N, c->N, sizeof s.N);
    ht_probe_set3(s.V, -P[0], -P[1], EYE_Z - P[2]);
    return s;
}

int ht_probe_to_byte(double v) { return (int)lround(fmin(1.0, fmax(0.0, v)) * 255.0); }

void ht_probe_oracle(const ht_shading *m, const ht_surface *s, const ht_light *light, const double P[3],
                     int expected[3]) {
    ht_probe_oracle_lights(m, s, light, 1, P, expected);
}

void ht_probe_oracle_lights(const ht_shading *m, const ht_surface *s, const ht_light *lights, int count,
                            const double P[3], int expected[3]) {
    ht_light_ray rays[HT_MAX_LIGHTS];
    assert_true(count >= 1 && count <= HT_MAX_LIGHTS);
    for (int i = 0; i < count; i++) {
        rays[i] = (ht_light_ray){ .L = { lights[i].vector[0], lights[i].vector[1], lights[i].vector[2] },
                                  .color = { lights[i].color[0], lights[i].color[1], lights[i].color[2] } };
        if (lights[i].type == HT_LIGHT_POINT)
            for (int k = 0; k < 3; k++) rays[i].L[k] -= P[k];
    }
    double rgb[3];
    ht_model_shade_d(m, s, rays, count, rgb);
    for (int k = 0; k < 3; k++) expected[k] = ht_probe_to_byte(rgb[k]);
}

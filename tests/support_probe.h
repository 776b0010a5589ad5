/* support_probe.h — the shading probe of test_render_probe.c (full tier
   against the oracle) and test_render_fixed.c (fixed tier against its
   emulator and the oracle).

   The probe is a grid of flat cells in the plane z = 0, facing a camera on
   the z axis. Every vertex of a cell carries the same T, N, uv and ao, so
   every pixel of the cell has known inputs; V and L come from the pixel's
   position, which ht_probe_cell_at reconstructs exactly by casting the
   pixel centre's ray onto the plane. The cells cover the model's extremes
   (ht_probe_make_cells); the materials are written as JSON and turned into
   a bundle by ht_generate_bundle.

   Helpers that check fail the running cmocka test. */
#ifndef HT_SUPPORT_PROBE_H
#define HT_SUPPORT_PROBE_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include <hairtier/model.h>

#define HT_PROBE_SIZE 129          /* pixels per side of the view; odd: the centre pixel's ray is the z axis */
#define HT_PROBE_GRID 9            /* cells per side; odd: a cell sits centred on the origin */
#define HT_PROBE_CELLS (HT_PROBE_GRID * HT_PROBE_GRID)
#define HT_PROBE_EYE_Z 4.0
#define HT_PROBE_FOV_Y 30.0
#define HT_PROBE_TEXTURE_SIZE 16   /* texels per side of a textured probe material's textures */

typedef struct ht_probe_cell {
    double T[3], N[3];
    double uv[2];   /* a texel centre */
    double ao;
} ht_probe_cell;

/* Filled by ht_probe_make_cells. */
extern ht_probe_cell ht_probe_cells[HT_PROBE_CELLS];

typedef struct ht_probe_material {
    const char *name;
    const char *model;       /* "scheuermann" or "kajiya-kay" */
    double e1, s1, e2, s2;   /* primary and secondary exponent and shift */
    bool textured;           /* procedural base, shift and sparkle textures */
} ht_probe_material;

/* The light the special cells are made for (not unit length). */
extern const double ht_probe_first_light[3];
/* A Scheuermann material with no textures. */
extern const ht_probe_material ht_probe_plain;

void ht_probe_unit(double v[3]);
void ht_probe_set3(double v[3], double x, double y, double z);

/* Cells 0..5 and the centre one are special cases for ht_probe_first_light:
   T parallel and antiparallel to H, a zero tangent, T = -N (a shifted
   tangent of zero length at shift 1), T perpendicular to H, a zero normal,
   and at the centre (where a light along -z is L = -V) a T along y on a
   normal facing the camera. The rest are random (seeded): T perpendicular
   to N as on real ribbons, every third not. */
void ht_probe_make_cells(void);

/* Cell i is vertices 4i..4i+3 at (-,-), (+,-), (-,+), (+,+); triangles
   (0,1,3) and (0,3,2); each cell 0.8 of the grid pitch wide. */
void ht_probe_build_mesh(ht_mesh *mesh);

/* Which cell pixel (px, py) (rows bottom to top) falls in, at least one
   pixel inside its edge, or -1; world receives the point of the plane z = 0
   the pixel centre sees. */
int ht_probe_cell_at(double px, double py, double world[3]);

/* A unit directional light of colour (0.95, 0.9, 1). */
ht_light ht_probe_directional(double x, double y, double z);
/* "point" or "directional". */
const char *ht_probe_light_type(const ht_light *light);
/* The probe's camera and light. */
ht_frame_desc ht_probe_frame(const ht_light *light);

/* Writes p to work/NAME.json and a scene with one light of light's type,
   generates the bundle into dir (work/probe-NAME-TYPE) and loads p back
   into material. */
void ht_probe_make_bundle(const char *work, const ht_probe_material *p, const ht_light *light, char *dir,
                          size_t dir_size, ht_material *material);

/* The same for a material file of any model (a Marschner one). */
void ht_probe_make_bundle_from_file(const char *work, const char *name, const char *material_path,
                                    const ht_light *light, char *dir, size_t dir_size, ht_material *material);
/* The same with a scene of count lights of lights' types, in order (the
   runtime shades lights[i] as the bundle's light i), into
   work/probe-NAME-TYPE-TYPE... */
void ht_probe_make_bundle_lights(const char *work, const char *name, const char *material_path,
                                 const ht_light *lights, int count, char *dir, size_t dir_size,
                                 ht_material *material);

/* The first channel_count channels of img's texel at uv, in [0,1]. */
void ht_probe_texel(const ht_image *img, const double uv[2], int channel_count, double out[]);
/* The oracle's surface for cell c at world point P: base 1, shift texture
   0.5 and sparkle 1 until the caller fills in what its tier samples. */
ht_surface ht_probe_surface(const ht_probe_cell *c, const double P[3]);
/* ht_model_shade_d of s under light at P, clamped to [0,1] and rounded to
   8 bits per channel: what the framebuffer should hold. */
void ht_probe_oracle(const ht_shading *m, const ht_surface *s, const ht_light *light, const double P[3],
                     int expected[3]);
/* The same under count lights, summed before the clamp. */
void ht_probe_oracle_lights(const ht_shading *m, const ht_surface *s, const ht_light *lights, int count,
                            const double P[3], int expected[3]);
/* v clamped to [0,1], rounded to 8 bits. */
int ht_probe_to_byte(double v);

#endif

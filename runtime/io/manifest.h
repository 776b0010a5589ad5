/* manifest.h — a hairgen bundle's manifest.json read into plain structs (the
   format is docs/bundle.md), from a directory or a bundle in memory; the
   readers of the bundle's other files. Internal to libhairtier.

   Usage:
       ht_manifest b;
       char err[512];
       if (ht_manifest_load("out/bundle", &b, err, sizeof err) != HT_OK) puts(err);
       const ht_manifest_tier *full = ht_manifest_find_tier(&b, HT_TIER_FULL);
       char *frag = ht_manifest_read_text(&b, ht_manifest_tier_file(full, "fragment"), err, sizeof err);

   Every error is one line "DIR/manifest.json: FIELD: what is wrong"
   (FIELD like tiers[1].requires.glsl). File names in a manifest must be plain
   names inside the bundle directory. */
#ifndef HT_MANIFEST_H
#define HT_MANIFEST_H

#include <stdbool.h>
#include <stddef.h>

#include <hairtier/hairtier.h>
#include <hairtier/lod.h>
#include "bundle_source.h"
#include <hairtier/image.h>
#include <hairtier/ht_limits.h>

/* The schema's one home: shadergen/generate.c writes what this reader
   accepts and checks these limits before writing, so hairgen never makes a
   bundle the runtime refuses (tests/test_manifest.c holds the two together). */
#define HT_MANIFEST_FORMAT "hairtier-bundle/1"
/* The generator version a bundle records: hairgen writes it, the runtime
   refuses any other ("regenerate with ..."), input_hash covers it. Bump it
   with any change to what a bundle holds. */
#define HT_MANIFEST_GENERATOR "hairgen 8"
#define HT_MANIFEST_FILE "manifest.json"
/* Texture sizes the runtime reads: per side, 3D depth (slices), and texels
   in all (the PNG reader's cap, so a listed texture is never one it refuses).
   The values live in ht_limits.h, the one table generator and runtime share. */
#define HT_MANIFEST_MAX_TEXTURE_SIZE HT_LIMIT_TEXTURE_SIDE
#define HT_MANIFEST_MAX_TEXTURE_DEPTH HT_LIMIT_TEXTURE_DEPTH
#define HT_MANIFEST_MAX_TEXTURE_PIXELS HT_LIMIT_TEXTURE_PIXELS
_Static_assert(HT_LIMIT_TEXTURE_PIXELS == HT_IMAGE_MAX_PIXELS, "the PNG reader reads every bundle texture");

/* Every key of the manifest, written by shadergen/generate.c and read by
   runtime/io/manifest_read.c (docs/bundle.md describes them). */
#define HT_MANIFEST_KEY_FORMAT "format"
#define HT_MANIFEST_KEY_GENERATOR "generator"
#define HT_MANIFEST_KEY_INPUT_HASH "input_hash"
#define HT_MANIFEST_KEY_MATERIAL "material"
#define HT_MANIFEST_KEY_MODEL "model"
#define HT_MANIFEST_KEY_LIGHTS "lights"
#define HT_MANIFEST_KEY_OPAQUE_CUTOFF "opaque_cutoff"
#define HT_MANIFEST_KEY_TEXTURES "textures"      /* root and tier: name -> texture */
#define HT_MANIFEST_KEY_NOTES "notes"
#define HT_MANIFEST_KEY_TIERS "tiers"
/* a texture */
#define HT_MANIFEST_KEY_FILE "file"
#define HT_MANIFEST_KEY_WIDTH "width"
#define HT_MANIFEST_KEY_HEIGHT "height"
#define HT_MANIFEST_KEY_DEPTH "depth"
#define HT_MANIFEST_KEY_CONTENTS "contents"
/* a tier */
#define HT_MANIFEST_KEY_NAME "name"
#define HT_MANIFEST_KEY_REQUIRES "requires"
#define HT_MANIFEST_KEY_API "api"              /* requires: "gl"; an "es" entry: "gles" */
#define HT_MANIFEST_KEY_GL "gl"
#define HT_MANIFEST_KEY_GLSL "glsl"
#define HT_MANIFEST_KEY_EXTENSIONS "extensions"
#define HT_MANIFEST_KEY_TEXTURE_UNITS "texture_units"
#define HT_MANIFEST_KEY_FILES "files"            /* role -> file name */
#define HT_MANIFEST_KEY_SAMPLERS "samplers"
#define HT_MANIFEST_KEY_UNIFORM "uniform"
#define HT_MANIFEST_KEY_TEXTURE "texture"
#define HT_MANIFEST_KEY_UNIT "unit"
#define HT_MANIFEST_KEY_FEATURES "features"
#define HT_MANIFEST_KEY_DROPPED "dropped"
/* a GLSL tier's optional "es" list: its GL ES targets, best first */
#define HT_MANIFEST_KEY_ES "es"
#define HT_MANIFEST_KEY_ES_VERSION "version"      /* the lowest ES version, "2.0" or "3.0" */
#define HT_MANIFEST_KEY_ESSL "essl"               /* "1.00" or "3.00" */
#define HT_MANIFEST_KEY_PRECISION "fragment_precision" /* "highp" or "mediump" */
#define HT_MANIFEST_KEY_VERTEX "vertex"
#define HT_MANIFEST_KEY_FRAGMENT "fragment"
#define HT_MANIFEST_API_GL "gl"
#define HT_MANIFEST_API_GLES "gles"
#define HT_MANIFEST_PRECISION_HIGHP "highp"
#define HT_MANIFEST_PRECISION_MEDIUMP "mediump"
/* a tier's optional "measured" object: how the tier compares with full on
   one scene, measured offline (hairgen --measure; shadergen/metrics.h has the
   definitions). psnr_db null means identical (infinite). */
#define HT_MANIFEST_KEY_MEASURED "measured"
/* the same for the tier's device-only variant (fixed4, fixed: no per-vertex
   CPU work while the eye or a light moves; hairtier.h ht_variant), present
   when the backend has one for this bundle */
#define HT_MANIFEST_KEY_MEASURED_DEVICE "measured_device"
#define HT_MANIFEST_KEY_PSNR_DB "psnr_db"
#define HT_MANIFEST_KEY_SSIM "ssim"
#define HT_MANIFEST_KEY_DELTA_E00_MEAN "delta_e00_mean"
#define HT_MANIFEST_KEY_DELTA_E00_P95 "delta_e00_p95"
#define HT_MANIFEST_KEY_COST_RATIO "cost_ratio"
/* LDR-FLIP at 67 pixels per degree (shadergen/flip.h): optional, as a
   pair, so bundles measured before FLIP still load. */
#define HT_MANIFEST_KEY_FLIP_MEAN "flip_mean"
#define HT_MANIFEST_KEY_FLIP_P95 "flip_p95"
#define HT_MANIFEST_KEY_SCENE "scene"
#define HT_MANIFEST_KEY_DRIVER "driver"
/* the optional top-level "lods" object (hairgen --measure-lods): the
   reference tier drawn at every geometry LOD (include/hairtier/lod.h) at
   a few projected sizes, each cell against LOD 0 at the same size, and
   the pop (PSNR against the level before). docs/lod.md. */
#define HT_MANIFEST_KEY_LODS "lods"
#define HT_MANIFEST_KEY_LOD_TIER "tier"
#define HT_MANIFEST_KEY_CELLS "cells"
#define HT_MANIFEST_KEY_SAMPLES "samples"     /* optional: the LOD frames' multisampling */
#define HT_MANIFEST_MAX_LOD_SAMPLES 32
/* optional: what the cells are against. "samples" (the default): LOD 0 of
   the first tier drawn as the cells are; "supersample": LOD 0 of the first
   tier at 4 x 4 the pixels, box-filtered (the 16x truth), every cell drawn
   with the width rule (hairgen --lod-reference) */
#define HT_MANIFEST_KEY_LOD_REFERENCE "reference"
#define HT_MANIFEST_KEY_LEVEL "level"
#define HT_MANIFEST_KEY_STRANDS "strands"
#define HT_MANIFEST_KEY_SIZE "size"
#define HT_MANIFEST_KEY_POP_PSNR_DB "pop_psnr_db"
#define HT_MANIFEST_KEY_LOD_KIND "kind"
#define HT_MANIFEST_KEY_LOD_FILE "lod_file" /* a bundle storing levels: "lods.bin" (the runtime does not read it) */
/* optional: the level drawn soft (lod.h's ht_lod_cell.soften), (1, 16]; a strand level >= 1 only */
#define HT_MANIFEST_KEY_SOFTEN "soften"
#define HT_MANIFEST_MAX_LOD_CELLS HT_LOD_MAX_CELLS
/* Limits of a measured object's numbers. */
#define HT_MANIFEST_MAX_PSNR_DB 1000.0
#define HT_MANIFEST_MAX_DELTA_E 1000.0
#define HT_MANIFEST_MAX_COST_RATIO 1.0e6

#define HT_MANIFEST_MAX_TIERS HT_LIMIT_TIERS
#define HT_MANIFEST_MAX_FILES HT_LIMIT_TIER_FILES
#define HT_MANIFEST_MAX_SAMPLERS HT_LIMIT_SAMPLERS
#define HT_MANIFEST_MAX_TEXTURES HT_LIMIT_TEXTURES
#define HT_MANIFEST_MAX_EXTENSIONS HT_LIMIT_EXTENSIONS
#define HT_MANIFEST_NAME (HT_LIMIT_BUNDLE_NAME + 1)

typedef struct ht_manifest_texture {
    char name[24];                 /* key: "albedo", "detail", "fixed-lut" */
    char file[HT_MANIFEST_NAME];
    int width, height, depth;      /* depth 1 for 2D */
} ht_manifest_texture;

typedef struct ht_manifest_file {
    char role[24];                 /* "vertex", "fragment", "prime_vertex", "program", ... */
    char file[HT_MANIFEST_NAME];
} ht_manifest_file;

typedef struct ht_manifest_sampler {
    char uniform[32];
    char texture[24];              /* a key of the tier's or the bundle's textures */
    int unit;
} ht_manifest_sampler;

/* A tier's "measured" object (all its numbers are required when it is
   present; scene and driver are optional labels). */
typedef struct ht_manifest_measured {
    bool present;                  /* false when the tier has no "measured" */
    double psnr_db;                /* [0, 1000], INFINITY for null (identical to full) */
    double ssim;                   /* [-1, 1] */
    double delta_e00_mean, delta_e00_p95; /* [0, 1000] */
    double cost_ratio;             /* (0, 1e6]: frame time / full's */
    double flip_mean, flip_p95;    /* [0, 1]; NAN when absent (measured before FLIP) */
    char scene[64];                /* "" when absent */
    char driver[128];              /* "" when absent */
} ht_manifest_measured;

/* One GL ES target of a GLSL tier ("es" entry). */
typedef struct ht_manifest_es {
    int es_major, es_minor;        /* version: the lowest ES version it runs on */
    int essl_major, essl_minor;    /* essl: 1.00 or 3.00 ({1, 0}, {3, 0}) */
    bool mediump;                  /* fragment_precision "mediump": runs without fragment highp */
    char vertex[HT_MANIFEST_NAME], fragment[HT_MANIFEST_NAME];
} ht_manifest_es;

#define HT_MANIFEST_MAX_ES 4

typedef struct ht_manifest_tier {
    char name[16];
    ht_tier tier;                  /* HT_TIER_COUNT: a tier this runtime does not know */
    int gl_major, gl_minor;        /* requires.gl */
    int glsl_major, glsl_minor;    /* requires.glsl; 0.0 when the tier has no GLSL */
    char extensions[HT_MANIFEST_MAX_EXTENSIONS][48];
    int extension_count;
    int texture_units;             /* requires.texture_units; 0 when absent */
    ht_manifest_file files[HT_MANIFEST_MAX_FILES];
    int file_count;
    ht_manifest_sampler samplers[HT_MANIFEST_MAX_SAMPLERS];
    int sampler_count;
    ht_manifest_texture textures[HT_MANIFEST_MAX_TEXTURES]; /* the tier's own ("fixed-lut") */
    int texture_count;
    ht_manifest_es es[HT_MANIFEST_MAX_ES]; /* optional: GL ES targets, best first */
    int es_count;
    ht_manifest_measured measured;   /* optional */
    ht_manifest_measured measured_device; /* optional: the device-only variant's */
} ht_manifest_tier;

/* The "lods" reference (HT_MANIFEST_KEY_LOD_REFERENCE), in its names' order. */
typedef enum ht_lod_reference { HT_LOD_REFERENCE_SAMPLES, HT_LOD_REFERENCE_SUPERSAMPLE } ht_lod_reference;
#define HT_LOD_REFERENCE_NAMES { "samples", "supersample", NULL }

/* One cell of "lods": psnr_db and pop_psnr_db INFINITY for null (level 0,
   identical to itself; no level before). */
typedef struct ht_manifest_lod_cell {
    int level;                     /* 0..HT_LOD_FILE_MAX_LEVELS - 1: a stored level's index */
    int cards;                     /* "kind": "cards" (a cards level); absent or "strands": 0 */
    float soften;                  /* "soften": the level drawn soft; absent: 0 (plain) */
    char tier[16];                 /* the tier drawn; a cell without "tier": the lods' */
    uint32_t strands;
    double size;                   /* (0, 4]: projected size / the scene's */
    double psnr_db, ssim, delta_e00_mean, cost_ratio, pop_psnr_db;
} ht_manifest_lod_cell;

typedef struct ht_manifest_lods {
    char tier[16];                 /* "" when the manifest has no "lods" */
    int samples;                   /* 0: one sample a pixel; else the frames' (hairgen --lod-samples) */
    ht_lod_reference reference;    /* "reference": what the cells are against */
    ht_manifest_lod_cell cells[HT_MANIFEST_MAX_LOD_CELLS];
    int cell_count;
} ht_manifest_lods;

/* The "lods" object of a parsed manifest's root (manifest_lods.c); an
   absent one leaves out empty. */
struct cJSON;
struct ht_jctx;
ht_result ht_manifest_parse_lods(const struct ht_jctx *c, const struct cJSON *root, ht_manifest_lods *out);

typedef struct ht_manifest {
    char dir[HT_LIMIT_DIR_PATH + 1]; /* a longer path is refused, never cut; a memory bundle's name */
    const ht_bundle_memory *memory;  /* NULL: the files are in dir; else the caller's memory bundle */
    char material[64];
    char model[32];
    ht_light_type lights[HT_MAX_LIGHTS];
    int light_count;
    float opaque_cutoff;           /* (0, 1] */
    ht_manifest_texture textures[HT_MANIFEST_MAX_TEXTURES];
    int texture_count;
    ht_manifest_tier tiers[HT_MANIFEST_MAX_TIERS]; /* best first, as listed */
    int tier_count;
    ht_manifest_lods lods;         /* optional */
} ht_manifest;

ht_result ht_manifest_load(const char *dir, ht_manifest *out, char *err, size_t err_size);
/* The same from a bundle in memory (checked with ht_bundle_memory_check
   first); every message names NAME/FILE where a directory's names DIR/FILE. */
ht_result ht_manifest_load_memory(const ht_bundle_memory *m, ht_manifest *out, char *err, size_t err_size);
/* Parses manifest text; file_name only labels errors. */
ht_result ht_manifest_parse(const char *json_text, const char *dir, const char *file_name,
                          ht_manifest *out, char *err, size_t err_size);

const ht_manifest_tier *ht_manifest_find_tier(const ht_manifest *b, ht_tier tier);
/* The file of a role, NULL when the tier lists none. */
const char *ht_manifest_tier_file(const ht_manifest_tier *t, const char *role);
/* A texture by key: the tier's own first, then the bundle's; NULL if neither. */
const ht_manifest_texture *ht_manifest_find_texture(const ht_manifest *b, const ht_manifest_tier *t,
                                                const char *name);
/* Where the bundle's files come from (bundle_source.h). */
ht_bundle_source ht_manifest_source(const ht_manifest *b);
/* DIR/file into out (what messages name); false when it does not fit. */
bool ht_manifest_path(const ht_manifest *b, const char *file, char *out, size_t out_size);
/* Reads a JSON file of the bundle (malloc'd, NUL-terminated) or NULL with
   "DIR/FILE: why" in err; file NULL (a role the tier lacks) is an error too. */
char *ht_manifest_read_text(const ht_manifest *b, const char *file, char *err, size_t err_size);
/* The same for a GLSL source (its own size cap). */
char *ht_manifest_read_shader(const ht_manifest *b, const char *file, char *err, size_t err_size);
/* Reads a 2D texture of the bundle held to its manifest entry: the size the
   PNG header declares is checked before decoding (a hostile header must
   not make us allocate what it claims), then the decoded size. path
   receives DIR/FILE for the caller's own messages. Errors are one line
   naming the file: "DIR/FILE: 8x8, manifest says 256x256". */
ht_result ht_manifest_read_texture(const ht_manifest *b, const ht_manifest_texture *t, ht_image *img, char *path,
                                   size_t path_size, char *err, size_t err_size);

#endif

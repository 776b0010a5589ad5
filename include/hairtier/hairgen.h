/* hairgen.h — the offline generator as a library (libhairgen.a): a material
   and a scene in, every tier's shader texts, the combiner program, the
   lookup textures and the manifest out, in memory (ht_generate) or written
   as a bundle directory (ht_generate_bundle, what `hairgen` runs). No GL
   context in the generator (only measure.h, `hairgen --measure`, renders
   a finished bundle); the output is a pure function of the input: same
   input, byte-identical output.

   Usage (in memory):
       ht_material m;
       char err[1024];
       if (ht_material_load("materials/blond.json", &m, err, sizeof err) != HT_OK) puts(err);
       ht_scene scene;
       ht_scene_default(&scene);
       ht_generated g;
       if (ht_generate(&(ht_generate_desc){ .material = &m, .scene = &scene }, &g,
                       err, sizeof err) != HT_OK) puts(err);
       const ht_generated_file *frag = ht_generated_find(&g, "full.frag");
       puts(frag->text);
       puts(g.manifest);
       ht_generated_free(&g);

   Usage (files, what hairgen does):
       char err[1024];
       if (ht_generate_bundle("materials/blond.json", "scenes/furball.json", "out/bundle",
                              stdout, err, sizeof err) != HT_OK)
           puts(err);

   Usage (many materials, what `hairgen -o DIR A.json B.json` does):
       const char *files[] = { "materials/blond.json", "materials/dark-brown.json" };
       char err[1024];
       ht_batch_result res;
       ht_generate_batch(&(ht_batch_desc){ .materials = files, .material_count = 2,
                                           .scene = "scenes/furball.json", .out_dir = "out",
                                           .progress = stdout }, &res, err, sizeof err);
       // out/blond/, out/dark-brown/; a re-run skips both (res.skipped == 2)

   Errors are one line "FILE: FIELD: what is wrong" written to err.
   Internal interfaces (plan, emitters, texture baking) are in
   hairgen_internal.h. Installed (make install) with the public headers it
   includes, hairtier.h, model.h, scene.h and image.h, under
   include/hairtier/; `pkg-config --cflags --libs --static hairgen`. */
#ifndef HT_HAIRGEN_H
#define HT_HAIRGEN_H

#include "export.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hairtier.h"
#include "model.h"
#include "scene.h"
#include "image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- material (materials/NAME.json, format "hairtier-material/1") ---- */

typedef enum ht_texture_slot {
    HT_TEX_BASE = 0,   /* rgb */
    HT_TEX_ALPHA,      /* coverage */
    HT_TEX_SHIFT,      /* tangent shift jitter, 0.5 = none */
    HT_TEX_SPARKLE,    /* secondary highlight mask */
    HT_TEX_COUNT
} ht_texture_slot;

HT_API const char *ht_texture_slot_name(ht_texture_slot s); /* "base", ... */

typedef enum ht_texture_origin {
    HT_TEXTURE_ABSENT = 0,     /* not modelled anywhere */
    HT_TEXTURE_PROCEDURAL,
    HT_TEXTURE_FILE,
} ht_texture_origin;

typedef struct ht_texture_source {
    ht_texture_origin origin;
    char procedural[32];   /* "stretched-noise", "strand-alpha", "noise", "sparkle" */
    int size;              /* procedural: power of two 16..2048 */
    uint32_t seed;
    char path[1024];       /* file: resolved against the material file's folder */
} ht_texture_source;

typedef struct ht_material {
    char name[64];
    ht_shading shading;
    ht_texture_source textures[HT_TEX_COUNT];
    double opaque_cutoff;  /* alpha at or above this is opaque; (0,1], default 0.98 */
    char file[1024];       /* the file it was read from, naming it in errors;
                              "" for a material built in memory */
} ht_material;

/* Errors are one line "FILE: FIELD: what is wrong" written to err. */
HT_API ht_result ht_material_load(const char *path, ht_material *out, char *err, size_t err_size);
HT_API ht_result ht_material_parse(const char *json_text, const char *file_name,
                            ht_material *out, char *err, size_t err_size);
/* Checks a material built in memory against the rules the file reader
   enforces (docs/materials.md): finite colours in [0,1], exponents in
   [0, 10000], finite shifts, wrap in [0,1], opaque_cutoff 0 (default) or in
   (0,1], known texture generators and power-of-two sizes 16..2048. FILE is
   m->file, or "<material>" when empty; FIELD is the JSON path
   ("primary.exponent"). */
HT_API ht_result ht_material_check(const ht_material *m, char *err, size_t err_size);

/* ---- generator (shadergen/generate.c) ---- */

typedef struct ht_generate_desc {
    const ht_material *material; /* required; checked with ht_material_check */
    const ht_scene *scene;       /* NULL: ht_scene_default() */
    uint64_t input_hash;         /* 0: FNV-1a 64 over the generator version, the
                                    material's and scene's values the plan reads
                                    and the bytes of the material's texture files;
                                    ht_generate_bundle passes the hash of its input
                                    files' bytes instead */
} ht_generate_desc;

#define HT_GENERATED_MAX_FILES 40

/* One file of a bundle: a text (shader, combiner program, manifest) or an
   image (written as PNG). */
typedef struct ht_generated_file {
    char name[48];      /* file name in the bundle: "full.vert", "fixed-lut.png", "manifest.json" */
    ht_tier tier;       /* the tier it belongs to; HT_TIER_AUTO for the bundle's own
                           files (albedo.png, detail.png, manifest.json) */
    char role[24];      /* its manifest key: "vertex", "fragment", "program", "fixed-lut",
                           "albedo", "detail"; "manifest" for manifest.json */
    char *text;         /* NUL-terminated; NULL for an image */
    ht_image image;     /* pixels NULL for a text; a 3D texture's slices stacked vertically */
    int depth;          /* image depth in slices (1 for 2D); 0 for a text */
    unsigned char *png; /* an image's bytes in a bundle directory (its PNG file); NULL for a text */
    size_t png_size;
} ht_generated_file;

typedef struct ht_generated {
    ht_generated_file files[HT_GENERATED_MAX_FILES]; /* in the order ht_generate_bundle
                                                         writes them; manifest.json last */
    int file_count;
    const char *manifest;  /* manifest.json's text (files[file_count - 1].text) */
    uint64_t input_hash;   /* the hash written to the manifest */
    char *summary;         /* the tier table hairgen prints, one tier per line */
} ht_generated;

/* Generates every tier for desc->material and desc->scene into *out; writes
   no file. On failure *out is empty (safe to ht_generated_free) and err
   holds one line. */
HT_API ht_result ht_generate(const ht_generate_desc *desc, ht_generated *out, char *err, size_t err_size);
/* Frees what ht_generate allocated and zeroes *g; NULL and zeroed are fine. */
HT_API void ht_generated_free(ht_generated *g);
/* The file named `name`, or NULL. */
HT_API const ht_generated_file *ht_generated_find(const ht_generated *g, const char *name);

/* Loads the material (and scene; scene_path may be NULL: ht_scene_default)
   and runs ht_generate keyed by the files' bytes: in memory, the bundle
   ht_generate_bundle writes. material, when not NULL, receives the material
   read. On failure *out is empty and err holds one line. */
HT_API ht_result ht_generate_files(const char *material_path, const char *scene_path, ht_material *material,
                            ht_generated *out, char *err, size_t err_size);

/* The bytes `f` has in a bundle directory (a text as it is, an image as its
   PNG file: f->png, or the generator's encoding of f->image when that is
   NULL), malloc'd into *data (free()). */
HT_API ht_result ht_generated_file_bytes(const ht_generated_file *f, unsigned char **data, size_t *size, char *err,
                                  size_t err_size);

/* Loads the material (and scene; scene_path may be NULL: ht_scene_default),
   runs ht_generate and writes DIR atomically (a temporary sibling renamed
   into place; an existing DIR is replaced only after the new one is
   complete, and only when it is empty or a bundle). summary, when not NULL,
   receives the human-readable table. */
HT_API ht_result ht_generate_bundle(const char *material_path, const char *scene_path,
                             const char *out_dir, FILE *summary, char *err, size_t err_size);

/* A step over the finished bundle before it is published: dir is the
   temporary directory holding every file, scene the scene the bundle was
   planned for (the default one when no scene file was given). It may
   rewrite files in dir. A failure (err: one line) removes the temporary
   directory and leaves out_dir as it was. */
typedef ht_result (*ht_bundle_step_fn)(void *user, const char *dir, const ht_scene *scene, char *err,
                                       size_t err_size);
/* ht_generate_bundle with step (NULL: none, exactly ht_generate_bundle) run
   between writing and publishing; `hairgen --measure` passes
   ht_measure_step (shadergen/measure.h). */
HT_API ht_result ht_generate_bundle_then(const char *material_path, const char *scene_path, const char *out_dir,
                                  FILE *summary, ht_bundle_step_fn step, void *step_user, char *err,
                                  size_t err_size);

/* ---- the bundle as one C header (shadergen/emit_header.c) ---- */

/* The longest header symbol: room for the suffixes of its arrays within the
   63 significant characters C99 promises. */
#define HT_HEADER_SYMBOL_MAX 48

/* Writes g as one C header at path (a temporary sibling renamed into
   place): every file's bytes as a static const array and one entry,
   `static const ht_bundle_memory SYMBOL`, for ht_renderer_desc.bundle_memory.
   symbol NULL: from the material name (ht_header_symbol_default). The text
   depends only on g and symbol (same bundle, same bytes) and compiles
   warning-free as C99 and C++ with -Wall -Wextra -pedantic. */
HT_API ht_result ht_bundle_header_write(const ht_generated *g, const char *material_name, const char *symbol,
                                 const char *path, char *err, size_t err_size);
/* The same text in memory, malloc'd into *text (free()). */
HT_API ht_result ht_bundle_header_text(const ht_generated *g, const char *material_name, const char *symbol,
                                char **text, char *err, size_t err_size);
/* "dark-brown" → "dark_brown_bundle": letters, digits and _ kept, any other
   byte _, "_bundle" appended, cut to fit HT_HEADER_SYMBOL_MAX; "hair"
   before a name starting with a digit or _, "hair_" before one starting
   with ht_ (so the default always passes ht_header_symbol_check). */
HT_API void ht_header_symbol_default(const char *material_name, char out[HT_HEADER_SYMBOL_MAX + 1]);
/* A usable symbol: a C identifier of 1..HT_HEADER_SYMBOL_MAX bytes, not
   starting with _ (reserved), not a C or C++ keyword, and shaped so that
   it and the names derived from it cannot collide with what the header
   includes: not starting with ht_/HT_ (hairtier's), with a lower-case
   letter (the standard headers' macros are capitals: NULL), not ending in
   _t (size_t, uint8_t), not offsetof or std; else one line. */
HT_API ht_result ht_header_symbol_check(const char *symbol, char *err, size_t err_size);
/* What hairgen --emit-header runs: ht_generate_files, then the header at
   path; summary, when not NULL, receives hairgen's table. */
HT_API ht_result ht_generate_header(const char *material_path, const char *scene_path, const char *path,
                             const char *symbol, FILE *summary, char *err, size_t err_size);

/* ---- batches (shadergen/batch.c, what `hairgen` runs) ---- */

typedef struct ht_batch_desc {
    const char *const *materials; /* material files; required */
    int material_count;           /* at least 1 */
    const char *scene;            /* one scene file for every material; NULL: ht_scene_default() */
    const char *out_dir;          /* required */
    bool in_place;                /* false (default): each bundle in out_dir/<material file name
                                     without .json>/, out_dir created if missing; true: one
                                     material, out_dir is its bundle */
    int jobs;                     /* threads; 0: one per online core */
    bool force;                   /* false (default): a material whose bundle's input_hash is
                                     its inputs' hash is skipped; true: always regenerate */
    const char *depfile;          /* NULL: none; else make/ninja rules
                                     "BUNDLE/manifest.json: MATERIAL SCENE TEXTURES..." for
                                     every bundle made or up to date, written atomically */
    bool depfile_per_bundle;      /* -MD: a depfile beside each bundle, "BUNDLE.d" (depfile
                                     above ignored) */
    FILE *progress;               /* NULL: quiet; else one line per material, with time and ETA */
    FILE *summary;                /* NULL: none; else each bundle's tier table */
    FILE *errors;                 /* one line per material that failed; NULL: stderr */
    bool store_lods;              /* true: with a scene file, each bundle stores the scene's
                                     strand levels in lods.bin (what hairgen does unless
                                     --no-lods; docs/bundle.md); false: none */
} ht_batch_desc;

typedef struct ht_batch_result {
    int generated, skipped, failed;
} ht_batch_result;

/* Makes every material's bundle on desc->jobs threads. Each bundle is
   all-or-nothing (ht_generate_bundle's atomic write): a material that
   fails leaves its bundle directory as it was, its one-line error goes to
   desc->errors, and the other materials still run. Returns HT_OK when
   every material succeeded; the first failure's code otherwise (err then
   says how many failed), or a code before anything ran (no material, two
   materials with the same file name, an unreadable scene). Output bytes do
   not depend on jobs. */
HT_API ht_result ht_generate_batch(const ht_batch_desc *desc, ht_batch_result *result, char *err, size_t err_size);

#ifdef __cplusplus
}
#endif

#endif

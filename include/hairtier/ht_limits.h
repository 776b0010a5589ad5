/* ht_limits.h — the one table of limits shared by hairgen and libhairtier:
   file sizes, path lengths, counts, texture sizes, scene memory. The
   generator checks a bundle against these before writing it and the runtime
   refuses what exceeds them, so the two never disagree (docs/robustness.md
   lists every refusal with its message). Internal to libhairtier and hairgen.

   Usage:
       const char *dir = "out/bundle";
       if (strlen(dir) > HT_LIMIT_DIR_PATH) return;   // refused: "DIR: ... at most 1023"
       int width = 4096, height = 4096;
       if (width > HT_LIMIT_TEXTURE_SIDE || (unsigned)(width * height) > HT_LIMIT_TEXTURE_PIXELS) return;
       // a scene: ht_scene_memory_estimate (scene.h) against HT_LIMIT_SCENE_BYTES

   Configuration: none; change a value here and both sides follow. */
#ifndef HT_HT_LIMITS_H
#define HT_HT_LIMITS_H

#include "export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- shading constants (a material and every tier program alike) ---- */
#define HT_LIMIT_EXPONENT 10000.0   /* a highlight's exponent: 0 .. this */
#define HT_LIMIT_SHIFT    100.0     /* a highlight's tangent shift: -this .. this */
/* A transmission lobe's colour, each channel 0 .. this: Marschner's TT
   peaks near 2 per unit of light (brown, M_TT N_TT), above a highlight's 1. */
#define HT_LIMIT_TRANSMISSION 4.0

/* ---- files: the most bytes read from one file of each kind (file_open.h) ---- */
#define HT_LIMIT_FILE_JSON    (16u << 20)   /* materials, scenes, manifests, combiner programs */
#define HT_LIMIT_FILE_SHADER  (1u << 20)    /* one GLSL source */
#define HT_LIMIT_FILE_PNG     (512u << 20)  /* a PNG: 64 Mi RGBA pixels stored, with room for poor compression */
/* A strand file (.tfx, .hair): the most points below take at most 4 + 4 + 4
   + 4 + 12 bytes each in a .hair file (points, thickness, transparency,
   colours) or 16 + 8 + 16 in a .tfx (positions, uvs, colours). */
#define HT_LIMIT_FILE_STRANDS (256u << 20)

/* ---- paths ---- */
/* A bundle directory path, in bytes (without the NUL): the manifest keeps
   it in a char[HT_LIMIT_DIR_PATH + 1]; hairgen refuses a longer -o. */
#define HT_LIMIT_DIR_PATH 1023
/* A file name inside a bundle (manifest "file" fields), without the NUL. */
#define HT_LIMIT_BUNDLE_NAME 63
/* DIR/NAME: every bundle file path fits in this many bytes with its NUL. */
#define HT_LIMIT_BUNDLE_FILE_PATH (HT_LIMIT_DIR_PATH + 1 + HT_LIMIT_BUNDLE_NAME + 1)
/* A material's texture path (resolved against the material's folder). */
#define HT_LIMIT_TEXTURE_PATH 1023
/* A scene's strand file path (resolved against the scene's folder). */
#define HT_LIMIT_STRANDS_PATH 1023

/* ---- textures (the PNG reader's cap is the texel cap) ---- */
#define HT_LIMIT_TEXTURE_SIDE 16384               /* per side */
#define HT_LIMIT_TEXTURE_DEPTH 4096               /* 3D slices */
#define HT_LIMIT_TEXTURE_PIXELS (64u * 1024u * 1024u) /* texels in all */

/* ---- counts in a bundle ---- */
#define HT_LIMIT_TIERS 8
#define HT_LIMIT_TIER_FILES 8
#define HT_LIMIT_SAMPLERS 4
#define HT_LIMIT_TEXTURES 4
#define HT_LIMIT_EXTENSIONS 8
#define HT_LIMIT_JSON_DEPTH 1000                  /* nesting of any JSON file */

/* ---- scenes ---- */
/* The memory one scene's hair may need, all copies together (the mesh, the
   renderer's copy, the driver's buffer, the fixed tier's per-vertex arrays):
   ht_scene_memory_estimate() is checked against it when a scene is read, so
   a 2-core 24 GB machine renders every scene the reader accepts. */
#define HT_LIMIT_SCENE_BYTES (4ull << 30)
/* Bytes per vertex and per index counted by the estimate: 3 copies of a
   48-byte ht_vertex plus the fixed tier's vertex, coordinate and colour
   arrays (48 + 12 + 16); 3 copies of a 4-byte index. */
#define HT_LIMIT_SCENE_BYTES_PER_VERTEX (3u * 48u + 76u)
#define HT_LIMIT_SCENE_BYTES_PER_INDEX (3u * 4u)

/* ---- strand files (strands.h) ---- */
/* Strands, and points in all the strands of one file: 4 Mi points make 8 Mi
   ribbon vertices, about 2 GB by the estimate above, so every strand file
   the readers accept fits HT_LIMIT_SCENE_BYTES (scene_budget.c asserts it).
   A strand has 2..HT_LIMIT_STRAND_POINTS points (a .hair segment count is a
   uint16: at most 65 536 points). */
#define HT_LIMIT_STRANDS (1u << 20)
#define HT_LIMIT_STRANDS_POINTS (4u << 20)
#define HT_LIMIT_STRAND_POINTS 65536u
/* |coordinate| and thickness in a strand file, in the file's units: beyond,
   the ribbon builder's float arithmetic loses the hair's width. */
#define HT_LIMIT_STRANDS_COORD 1e7

#ifdef __cplusplus
}
#endif

#endif

/* ht_limits.h — the one table of limits shared by hairgen and libhairtier:
   file sizes, path lengths, counts, texture sizes, scene memory. The
   generator checks a bundle against these before writing it and the runtime
   refuses what exceeds them, so the two never disagree (docs/robustness.md
   lists every refusal with its message). Internal to libhairtier and hairgen.

   Usage:
       if (strlen(dir) > HT_LIMIT_DIR_PATH) refuse("DIR: ... at most 1023");
       if (ht_scene_memory_estimate(&scene) > HT_LIMIT_SCENE_BYTES) refuse(...);

   Configuration: none; change a value here and both sides follow. */
#ifndef HT_HT_LIMITS_H
#define HT_HT_LIMITS_H

/* ---- files: the most bytes read from one file of each kind (file_open.h) ---- */
#define HT_LIMIT_FILE_JSON    (16u << 20)   /* materials, scenes, manifests, combiner programs */
#define HT_LIMIT_FILE_SHADER  (1u << 20)    /* one GLSL source */
#define HT_LIMIT_FILE_PNG     (512u << 20)  /* a PNG: 64 Mi RGBA pixels stored, with room for poor compression */

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

#endif

/* lod.h — geometry levels of detail of a hair mesh: fewer strands, fewer
   segments, chosen at run time from the hair's projected size (docs/lod.md).

   A LOD is made from the full mesh a scene builds (fur ball, patches or a
   strand file: every builder writes ribbons as rows of two vertices, one
   component per strand), so it is the same geometry with less of it:
     strands   the first ceil(n / stride) strands of one stratified order of
               the roots (a Z-order curve over the root positions, read in
               bit-reversed order), so every LOD's strands are a prefix of
               one permutation (LOD n + 1 is a subset of LOD n) and every
               prefix is spread evenly over the scalp;
     width     every kept ribbon is widened about its centre line by
               (area of all ribbons) / (area of the kept ones), about the
               stride, opacity kept: the summed ribbon area, and so the
               covered area and mean opacity where ribbons do not pile up,
               is the full mesh's (tests/test_lod.c measures the coverage
               kept per level);
     segments  a row (joint) is dropped while the centre line turns by less
               than max_turn_deg since the last kept row (root and tip
               always kept); the kept rows' tangents are recomputed from the
               kept centre line, unit and root to tip.
   The LOD keeps the full mesh's inside-out order (the order of its
   components) and is drawn by the same four passes as any mesh.

   Usage:
       ht_mesh full, lod;
       if (ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 4000 }, &full) != HT_OK) return;
       ht_mesh_sort_inside_out(&full);
       ht_lod_desc level;
       ht_lod_level(2, &level);                 // a quarter of the strands, 4x as wide
       if (ht_mesh_build_lod(&full, &level, &lod) == HT_OK) {
           // ht_renderer_set_mesh(r, &lod) when the hair is small on screen
           ht_mesh_free(&lod);
       }
       double px = ht_projected_width_px(ht_mesh_mean_width(&full), 3.0, 40.0, 512);
       int n = ht_lod_pick_best(px, 0, ht_lod_max_level(&full));   // keeps 0 while a strand is >= 1 px
       (void)n;
       ht_mesh_free(&full);

   Usage, the (level, tier) pair per frame (a bundle measured by
   hairgen --measure-lods):
       ht_renderer *r;
       if (ht_renderer_create(&(ht_renderer_desc){ .getproc = my_getproc, .bundle_dir = "out/furball" }, &r) != HT_OK)
           return;
       ht_mesh full;
       ht_lod_chain chain;
       if (ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 4000 }, &full) != HT_OK) return;
       ht_mesh_sort_inside_out(&full);
       if (ht_lod_chain_build(&full, &chain) != HT_OK) return;
       static ht_lod_cell cells[HT_LOD_MAX_CELLS];   // plain and soft (ht_lod_cell.soften) pairs
       ht_lod_rule rule = { .kind = HT_POLICY_ERROR, .value = 30, .cells = cells,
                            .cell_count = ht_renderer_lod_cells(r, cells, HT_LOD_MAX_CELLS),
                            .size1_px = ht_projected_width_px(chain.width, 3.0, 40.0, 512) };
       ht_camera cam = { .eye = { 0, 0, 3 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_y = 40 };
       ht_result res;
       for (int frame = 0; frame < 100; frame++) {
           cam.eye[2] = 3.0f + 0.5f * (float)frame;     // dollying out
           int level = ht_lod_chain_select_pair(&chain, r, &cam, 512, &rule, &res);
           if (level < 0) break;                          // res says why
           // chain.tier is the pair's tier, chain.soften > 1 a soft pair; draw with ht_renderer_draw as always
       }
       ht_lod_chain_free(&chain);
       ht_renderer_destroy(r);
       ht_mesh_free(&full);
*/
#ifndef HAIRTIER_LOD_H
#define HAIRTIER_LOD_H

#include "export.h"
#include "hairtier.h"
#include "image.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ht_lod_desc {
    uint32_t strand_stride; /* 0 or 1: every strand; k: the first ceil(n / k) of the order */
    float max_turn_deg;     /* 0: every row; else rows turning less than this go, [0, 90] */
    float soften;           /* 0 or 1: none; s in (1, HT_LOD_MAX_SOFTEN]: every ribbon s times wider
                               again after the area rule, drawn at opacity ht_lod_opacity (a soft level) */
} ht_lod_desc;

/* The shipped ladder, level 0 (full) to HT_LOD_LEVELS - 1: stride 2^level,
   max_turn_deg 0, 4, 4, 4, 4. Levels outside are clamped. */
#define HT_LOD_LEVELS 5
/* The most levels a stored ladder (lods.bin) or a chain holds: the
   strand levels and the cards. */
#define HT_LOD_FILE_MAX_LEVELS 8
HT_API void ht_lod_level(int level, ht_lod_desc *out);

/* Soft levels (docs/lod.md, "Why the levels lose"): a level's error
   against full detail is mostly each kept strand's own pixel-scale
   pattern, which full detail does not share; the same ribbons HT_LOD_SOFTEN
   times wider at 1 / HT_LOD_SOFTEN the opacity keep the ink (width x
   opacity) and draw the local mean instead. ht_lod_soft_level is
   ht_lod_level with soften HT_LOD_SOFTEN from level 1 on (level 0 stays
   full detail). A soft level is drawn as the width rule's strands are:
   sorted back to front (ht_mesh_sort_back_to_front) and with
   ht_renderer_set_opacity_scale(r, ht_lod_opacity(&desc)). */
#define HT_LOD_SOFTEN 3.0f
/* The factors hairgen measures soft cells at by default (--lod-soften): a
   dense groom's long strands reach 30 dB at 6-8 where 3 does not, short
   fur pays their fragments (docs/lod.md); the measured cells choose. */
#define HT_LOD_DEFAULT_SOFTENS { HT_LOD_SOFTEN, 6.0f, 8.0f }
#define HT_LOD_MAX_SOFTEN 16.0f
HT_API void ht_lod_soft_level(int level, ht_lod_desc *out);
/* The opacity scale a level is drawn with: 1 / soften, 1 for a level that
   is not soft (or a NULL desc). */
HT_API float ht_lod_opacity(const ht_lod_desc *desc);

/* The coarsest level worth building for a mesh: the ladder stops before
   fewer than HT_LOD_MIN_STRANDS strands would remain (a few very wide
   ribbons stop looking like hair; patches' 144 strips end at level 2). */
#define HT_LOD_MIN_STRANDS 32
HT_API int ht_lod_max_level(const ht_mesh *mesh);

/* Builds the LOD of a mesh made by one of the builders (or any mesh whose
   components each index a run of rows of two vertices as they do).
   A soft desc's ribbons come out soften times wider than the area rule's
   (their drawn area soften times the mesh's). HT_ERR_INVALID_ARGUMENT for
   a mesh of another layout or a desc out of range (soften NaN, negative,
   in (0, 1) or above HT_LOD_MAX_SOFTEN), HT_ERR_OUT_OF_MEMORY; on failure
   *out is zeroed. */
HT_API ht_result ht_mesh_build_lod(const ht_mesh *full, const ht_lod_desc *desc, ht_mesh *out);

/* rank[c] = the position of component c in the stratified order (0 first):
   a LOD of stride k keeps the components of rank < ceil(n / k). */
HT_API ht_result ht_mesh_strand_order(const ht_mesh *mesh, uint32_t *rank);

/* The mean ribbon width of a mesh (scene units): the mean distance between
   the two vertices of a row. 0 for an empty mesh. */
HT_API double ht_mesh_mean_width(const ht_mesh *mesh);

/* A width at `distance` from a perspective camera of vertical field
   `fov_y_deg`, in pixels of a viewport `viewport_h` pixels high. */
HT_API double ht_projected_width_px(double width, double distance, double fov_y_deg, int viewport_h);
/* A mesh's mean ribbon width (ht_mesh_mean_width) projected at the
   camera's eye-to-target distance: a scene's strand in pixels. */
HT_API double ht_mesh_projected_width_px(const ht_mesh *mesh, const ht_camera *camera, int viewport_h);

/* The `best` rule with hysteresis: full detail while a strand is at least
   a pixel wide; narrower, the level whose widened strand is a pixel wide
   again (level ceil(log2(1 / px)), clamped to max_level). `current` (-1:
   none yet) is kept while the ideal level is within HT_LOD_HYSTERESIS
   (in levels, log2 of the width) of its band, so a size sitting on a
   boundary does not flicker. */
#define HT_LOD_HYSTERESIS 0.25
HT_API int ht_lod_pick_best(double strand_px, int current, int max_level);

/* The width rule (docs/lod.md): a strand narrower than a pixel is drawn
   about a pixel wide, its opacity scaled by (projected width / drawn
   width), so its coverage is kept instead of aliasing. Per draw: the
   factor for a mesh whose mean strand is strand_px wide, rounded up to a
   quarter octave (2^(k/4), so a widened mesh serves a range of sizes);
   1 at a pixel or wider. The mesh drawn is ht_mesh_widen(mesh, f), the
   opacity ht_renderer_set_opacity_scale(r, 1 / f): width x opacity, the
   coverage, stays the strand's. */
HT_API double ht_width_rule_widen(double strand_px);

/* Every ribbon of a mesh (a builder's layout, as ht_mesh_build_lod takes)
   `factor` times as wide about its centre line, [1, 1024] (refitted so the
   drawn area is factor times the mesh's: twisted quads grow faster than
   their width); every strand and row kept, the order kept. HT_ERR_INVALID_ARGUMENT, HT_ERR_OUT_OF_MEMORY;
   on failure *out is zeroed. */
#define HT_LOD_MAX_WIDEN 1024.0
HT_API ht_result ht_mesh_widen(const ht_mesh *mesh, double factor, ht_mesh *out);

/* The width rule's strands are translucent (opacity 1 / f): their
   coverage composes only when they are blended far to near, so the
   widened mesh is drawn in this order instead of inside out: segments
   (a builder's 6 indices between two rows; a component of another count
   whole) by their centroid's distance from eye, farthest first. Each
   becomes a component (sort_key = minus that distance): a strand's
   segments lie at different depths among other strands'. Once per camera
   position; the opaque cutoff sends every scaled fragment to the blended
   passes (ht_renderer_set_opacity_scale). */
HT_API void ht_mesh_sort_back_to_front(ht_mesh *mesh, const float eye[3]);
/* ht_mesh_widen by factor, then ht_mesh_sort_back_to_front from eye: the
   mesh the width rule and a soft level draw (at opacity 1 / factor). */
HT_API ht_result ht_mesh_widen_back_to_front(const ht_mesh *mesh, double factor, const float eye[3], ht_mesh *out);

/* The width rule on one mesh for one eye, in a framebuffer of `samples`
   samples a pixel: *factor = ht_width_rule_widen(strand_px) where
   ht_width_rule_applies(strand_px, samples), else 1; above 1, *out is
   ht_mesh_widen(mesh, factor) sorted back to front from eye, to be drawn
   at opacity 1 / factor; at 1, *out is zeroed (draw mesh itself at
   opacity 1). HT_ERR_INVALID_ARGUMENT, HT_ERR_OUT_OF_MEMORY (then *out
   zeroed). */
HT_API ht_result ht_mesh_width_rule(const ht_mesh *mesh, double strand_px, int samples, const float eye[3],
                                    ht_mesh *out, double *factor);

/* Scales the hair's drawn alpha by scale in every pass of every tier (a
   uniform in the GLSL texts, the last combiner stage's constant in fixed4,
   the vertex tier and fixed, the colour array in gl11); (0, 1], 1 (the
   default) draws alpha as the material has it. Below 1 the passes' alpha
   reference is 1: the Z-prime and opaque passes (alpha >= ref) take no
   scaled fragment and the back and front passes (alpha < ref) blend every
   one, so none is dropped and none is drawn opaque, which would undo the
   scale (a material's lower cutoff would otherwise keep some opaque).
   HT_ERR_INVALID_ARGUMENT outside (0, 1]. */
typedef struct ht_renderer ht_renderer;
HT_API ht_result ht_renderer_set_opacity_scale(ht_renderer *r, float scale);

/* The width rule per vertex (docs/lod.md): on, each vertex of the tiers
   that can (the programs of full and marschner and the vertex tier's GL
   ES texts; gl11 on the CPU with its per-vertex colours) widens its ribbon about the centre line to a pixel at its own distance
   and scales its alpha by (its width / its drawn width): tapered tips and
   near and far strands each get their own factor, no widened mesh and no
   upload per size. Takes effect at the next ht_renderer_set_mesh, which
   then uploads each vertex's offset from its row's centre (12 bytes a
   vertex; a mesh split into 16-bit chunks, split alike). Drawn in the
   frames whose mesh is back to front (ht_renderer_set_back_to_front, or
   an opacity scale), so a caller turns it on and off per frame by the
   order it draws (ht_width_rule_applies); inside out the strands are
   drawn as they are. Off by default. */
HT_API void ht_renderer_set_width_rule(ht_renderer *r, bool per_vertex);
/* On: the mesh drawn is ordered back to front from the frame's eye
   (ht_mesh_sort_back_to_front), so the blended passes draw both faces in
   one pass in its order, as under an opacity scale below 1 (which implies
   it). For the width rule per vertex while it applies
   (ht_width_rule_applies); off (the default) they are split by facing,
   inside out. */
HT_API void ht_renderer_set_back_to_front(ht_renderer *r, bool on);
/* The width a vertex is drawn at least (pixels): a ribbon a pixel wide
   still misses pixel centres; 1.5 was the closest to the supersampled
   fur ball at 1/8 to 1/2 of its size (docs/lod.md). */
#define HT_WIDTH_RULE_VERTEX_PX 1.5
/* Whether the width rule applies to a mesh whose mean strand is strand_px
   wide, drawn with `samples` samples a pixel (0 or 1: one): while
   strand_px x samples^(1/4) is under HT_WIDTH_RULE_VERTEX_PX (4 samples:
   1.06 px). Multisampling resolves such strands; there the rule's widened,
   translucent strands blurred what the samples resolve (the fur ball at 4
   samples, strands 1.1-1.5 px: 4-5 dB further from the truth than without
   it), while a dense groom's levels at 0.7-0.8 px still gain from it
   (docs/lod.md, "The width rule under multisampling"). Where it applies:
   per draw the factor is ht_width_rule_widen's; per vertex the mesh is
   drawn back to front (ht_mesh_sort_back_to_front,
   ht_renderer_set_back_to_front), translucent strands blending right only
   far to near; where it does not, per vertex the mesh is drawn as it is,
   inside out. */
HT_API bool ht_width_rule_applies(double strand_px, int samples);
/* The samples a pixel of the framebuffer bound for drawing (GL_SAMPLES;
   1 without multisampling, or where the GL has no GL_SAMPLES: GL 1.1,
   1.2), what ht_width_rule_applies reads. */
HT_API int ht_renderer_samples(const ht_renderer *r);
/* The passes' alpha reference while it is on: the material's cutoff, at
   least this. Most strands are not scaled and keep their opaque pass
   (reference 1 sent every fragment under it to the blended passes, whose
   order misplaces near, long strands: 0.4 dB lost on a close fur ball); a
   scaled fragment still drawn opaque was scaled by at least this, within
   2 % of its coverage. */
#define HT_WIDTH_RULE_VERTEX_REF 0.98f
/* Whether the next frame applies it per vertex: asked for, the tier drawing
   now can, and the mesh was set with it. false: the caller applies the
   rule per draw (ht_width_rule_widen, ht_mesh_widen, the opacity scale),
   as the fixed-function tiers need. */
HT_API bool ht_renderer_width_rule_per_vertex(const ht_renderer *r);

/* A stored level's geometry (lods.bin, a measured cell): strands or cards;
   SCENE: level 0 not stored, the scene's own mesh (a plain bundle's). */
typedef enum ht_lod_kind { HT_LOD_KIND_STRANDS = 0, HT_LOD_KIND_CARDS = 1, HT_LOD_KIND_SCENE = 2 } ht_lod_kind;

/* One measured (LOD, tier) pair at a projected size (hairgen --measure's
   cells): PSNR against (LOD 0, top tier) at that size and the frame cost
   as a ratio of it. */
typedef struct ht_lod_cell {
    int lod;       /* the level; a bundle's stored cards: their index in lods.bin */
    ht_tier tier;
    double size;   /* projected size / the scene's, e.g. 1, 0.5, 0.25 */
    double psnr;   /* dB; INFINITY for the reference itself */
    double cost;   /* frame time / the reference's */
    float soften;  /* 0: the plain level; s in (1, HT_LOD_MAX_SOFTEN]: the strand level lod >= 1 soft,
                      ht_mesh_widen_back_to_front of it by s, drawn at opacity 1 / s (a pair of its own) */
} ht_lod_cell;
/* Whether two cells hold one pair: level, tier and softness (plain, or the same soften). */
HT_API bool ht_lod_cell_same_pair(const ht_lod_cell *a, const ht_lod_cell *b);
/* The most soften factors a bundle's soft cells are measured at (hairgen --lod-soften). */
#define HT_LOD_MAX_SOFTENS 3
/* The most cells a bundle measures: 3 sizes x (8 stored levels + 7 soft at each factor) x 6 tiers. */
#define HT_LOD_MAX_CELLS (3 * (8 + 7 * HT_LOD_MAX_SOFTENS) * 6)

/* The `error:DB` rule: among the cells measured at the size nearest `size`
   (in log2), the cheapest whose PSNR is at least db; none: the most
   accurate. With hysteresis: the current pair (index into cells, -1: none)
   stays while it still meets db at that size and no other pair meeting
   db + HT_LOD_ERROR_HYSTERESIS_DB costs less. Returns an index into cells,
   -1 when count is 0. */
#define HT_LOD_ERROR_HYSTERESIS_DB 1.0
HT_API int ht_lod_pick_error(const ht_lod_cell *cells, int count, double size, double db, int current);

/* The `frame:MS` rule on the same cells: at the measured size nearest
   `size`, the most accurate pair whose frame, cost x reference_ms (the
   (LOD 0, top tier) frame at this size, timed on this device), is within
   budget_ms; none within: the cheapest. With hysteresis: the current pair
   stays while its frame is within budget_ms x (1 + HT_LOD_FRAME_HYSTERESIS)
   and no pair within budget_ms is HT_LOD_ERROR_HYSTERESIS_DB more
   accurate. Returns an index into cells, -1 when count is 0 or
   reference_ms is not positive. */
#define HT_LOD_FRAME_HYSTERESIS 0.1
HT_API int ht_lod_pick_frame(const ht_lod_cell *cells, int count, double size, double budget_ms, double reference_ms,
                             int current);

/* Every level of one mesh, switched per frame by the best rule: level 0
   is the caller's mesh (borrowed: it must outlive the chain), the others
   are built here, and all of them are concatenated into one mesh (`all`,
   level l the indices [first[l], first[l] + count[l])). The first
   ht_lod_chain_select on a renderer uploads `all` once
   (ht_renderer_set_mesh); from then on it picks the level for this
   frame's camera (the strand width projected at the distance from the eye
   to the mesh's centre, ht_lod_pick_best with its hysteresis) and, when
   it changes, only moves the renderer's draw range
   (ht_renderer_set_draw_range: no upload). It returns the level drawn, or
   -1 with *result set when the upload fails (the renderer keeps the mesh
   it had). A renderer whose mesh the application replaced: set `uploaded`
   and `wide_renderer` to NULL so the next select uploads again.
   width_rule (false unless the caller sets it, after build): the width
   rule per draw on the level drawn, every frame: where its strands
   (its mean ribbon width at the eye's distance to the centre) are under
   a pixel and the rule applies (ht_width_rule_applies, with
   ht_renderer_samples), f = ht_width_rule_widen of it, the level widened by f
   (ht_mesh_widen), sorted back to front from this frame's eye and
   uploaded alone (ht_renderer_set_mesh: that level's vertices), the
   opacity 1 / f (ht_renderer_set_opacity_scale); while level and f (a
   quarter octave) stay, nothing more: the order is the one of the eye
   that made it; a pixel or wider again: `all` is uploaded again and the
   opacity is 1. Where the renderer does the rule per vertex
   (ht_renderer_set_width_rule, a tier that can) nothing is widened or
   copied: while the rule applies to the level's strands
   (ht_width_rule_applies, the renderer's samples) its
   range of `all` is sorted back to front and `all`'s indices uploaded
   alone (ht_renderer_set_mesh_order, ht_renderer_set_back_to_front; the
   order restored the same way when the level leaves it); else `all`'s
   range as built. While the level and f stay, the order is sorted
   again only past HT_LOD_RESORT_DEG / HT_LOD_RESORT_DISTANCE (below).
   ht_lod_chain_from_file takes the levels a bundle stores instead (its
   lods.bin, hairgen --cards: the strand levels, then the cards, whose
   best-rule level is one past the last strand level's);
   ht_lod_chain_from_scene_file those of a plain hairgen --scene bundle,
   whose level 0 is the scene's mesh, not stored. */
typedef struct ht_renderer ht_renderer;
typedef struct ht_lod_chain {
    const ht_mesh *full;
    ht_mesh levels[HT_LOD_FILE_MAX_LEVELS]; /* built here; [0] only from a file */
    int count;                     /* levels built, 1 + ht_lod_max_level(full) */
    int current;                   /* -1 until the first select */
    double width;                  /* full's mean ribbon width */
    ht_mesh all;                   /* every level, one after the other */
    uint32_t first[HT_LOD_FILE_MAX_LEVELS], index_count[HT_LOD_FILE_MAX_LEVELS]; /* level l's range in all */
    uint32_t first_vertex[HT_LOD_FILE_MAX_LEVELS], vertex_count[HT_LOD_FILE_MAX_LEVELS]; /* the vertices it uses */
    const ht_renderer *uploaded;   /* the renderer holding `all`, NULL: none yet */
    ht_tier tier;                  /* the pair's tier (ht_lod_chain_select_pair); HT_TIER_COUNT: none yet */
    unsigned refused_tiers;        /* bit t: the renderer could not draw tier t; its cells are skipped */
    double size;                   /* the measured size the pair was read at, 0: none yet */
    double level_width[HT_LOD_FILE_MAX_LEVELS]; /* each level's mean ribbon width */
    float soften;                  /* the pair's: 0 plain, else its soft cell's soften (select_pair) */
    ht_lod_cell *usable;           /* select_pair's scratch: the rule's cells it can draw */
    int usable_capacity;
    /* The width rule per draw, when the caller sets width_rule (below). */
    bool width_rule;
    /* A level drawn alone (a soft pair, the width rule): widened, back to front. */
    ht_mesh wide;                  /* the level drawn, widened by wide_factor, back to front */
    const ht_renderer *wide_renderer; /* the renderer holding `wide`, NULL: none */
    int wide_level;
    double wide_factor;            /* wide_soften x the width rule's f; the opacity is its inverse */
    double wide_soften;            /* the soft pair's soften, 1: plain */
    float wide_eye[3];             /* the eye wide's order is of */
    /* The width rule per vertex: `all` uploaded with this level's range
       sorted back to front (ht_renderer_set_mesh_order), -1: as built. */
    int ordered_level;
    float ordered_eye[3];          /* the eye that order is of */
    /* Asynchronous (false unless the caller sets it, after build): below. */
    bool async;
    struct ht_lod_job *job;        /* the sort or copy in flight, or done and not yet uploaded; NULL: none */
    bool waiting;                  /* the last select drew something else than it was asked for */
} ht_lod_chain;
/* A level drawn alone is sorted again (its indices uploaded alone:
   ht_renderer_set_mesh_order) only when the eye's direction from the mesh's centre has
   turned by more than HT_LOD_RESORT_DEG since its order was made, or its
   distance changed by more than HT_LOD_RESORT_DISTANCE times (docs/lod.md). */
#define HT_LOD_RESORT_DEG 5.0
#define HT_LOD_RESORT_DISTANCE 2.0
HT_API ht_result ht_lod_chain_build(const ht_mesh *full, ht_lod_chain *out);
typedef struct ht_lod_file ht_lod_file;
HT_API ht_result ht_lod_chain_from_file(const ht_lod_file *file, ht_lod_chain *out);
/* The same for a file whose level 0 is the scene's mesh (SCENE, a plain
   bundle's): full (borrowed, as ht_lod_chain_build's) is level 0, the
   file's levels follow it; HT_ERR_INVALID_ARGUMENT unless
   ht_lod_file_matches(file, full). A file storing its level 0 is
   ht_lod_chain_from_file's (full unused). */
HT_API ht_result ht_lod_chain_from_scene_file(const ht_lod_file *file, const ht_mesh *full, ht_lod_chain *out);
HT_API int ht_lod_chain_select(ht_lod_chain *chain, ht_renderer *r, const ht_camera *camera, int viewport_h,
                               ht_result *result);
HT_API const ht_mesh *ht_lod_chain_mesh(const ht_lod_chain *chain, int level);

/* The (level, tier) pair per frame: the rule applied to this frame's
   projected size with its hysteresis (best: ht_lod_chain_select, the tier
   left as it is; error:DB: ht_lod_pick_error; frame:MS:
   ht_lod_pick_frame), over the cells whose level the chain has. The size
   is the strand's projected width at the eye's distance to the mesh's
   centre over size1_px; the rule reads the cells at the measured size
   nearest it, the one in use kept while it is within HT_LOD_HYSTERESIS
   octaves of being the nearest (a size jittering across the midpoint of
   two measured ones switches once). A level change moves the draw range as
   ht_lod_chain_select does; a tier change is ht_renderer_set_tier on the
   one uploaded `all`: the tier's backend is made at its first use (its
   programs, textures, and for the fixed-function tiers their per-vertex
   data of `all`), nothing is uploaded or made at later switches. A tier
   the renderer cannot make is refused once (refused_tiers, logged) and the
   rule picks again without it. A soft cell (soften s > 1, a strand level
   >= 1: hairgen --measure-lods measures them) is a pair of its own: its
   level is derived when picked, ht_mesh_widen_back_to_front of the plain
   level by s x f (f: the width rule's on the soft strand, level width x
   s, 1 without width_rule), from this frame's eye, uploaded alone as the
   width rule's level is, with ht_renderer_set_opacity_scale(1 / (s x f));
   it is sorted again only past HT_LOD_RESORT_DEG / _DISTANCE; a switch
   to a plain pair uploads `all` again and sets the opacity back to 1
   (chain->soften: the pair's, 0 plain). Hysteresis as for plain pairs:
   soft and plain of one (level, tier) are two pairs. Returns the level (chain->tier the tier),
   or -1 with *result set: HT_ERR_INVALID_ARGUMENT for a rule without
   cells (error, frame), size1_px or, for frame, reference_ms not > 0;
   an upload's error; HT_ERR_OUT_OF_MEMORY when the chain's copy of the
   usable cells (chain->usable, grown to the rule's count) cannot grow;
   HT_ERR_NO_TIER when no cell's tier can be drawn. */
/* frame:MS's reference frame at one measured size (ht_lod_rule). */
typedef struct ht_lod_reference_frame {
    double size; /* a cells' size, e.g. 1, 0.5, 0.25 */
    double ms;   /* the (level 0, reference tier) frame with the hair at that size, on this device */
} ht_lod_reference_frame;

typedef struct ht_lod_rule {
    ht_policy_kind kind;      /* HT_POLICY_BEST, HT_POLICY_ERROR (value dB) or HT_POLICY_FRAME (value ms) */
    double value;
    const ht_lod_cell *cells; /* ht_renderer_lod_cells's */
    int cell_count;
    double size1_px;          /* a level-0 strand's projected width at the cells' size 1 (the scene's view) */
    double reference_ms;      /* frame: the (level 0, reference tier) frame on this device, taken for
                                 every size not in reference_frames (the cells' costs are ratios of it) */
    const ht_lod_reference_frame *reference_frames; /* frame, optional: that frame timed at each measured
                                 size, as each size's cells' costs are ratios of their own size's reference */
    int reference_frame_count;
} ht_lod_rule;
/* The reference frame the frame rule uses at a measured size: the rule's
   reference_frames entry of that size, else reference_ms. */
HT_API double ht_lod_rule_reference_ms(const ht_lod_rule *rule, double size);
HT_API int ht_lod_chain_select_pair(ht_lod_chain *chain, ht_renderer *r, const ht_camera *camera, int viewport_h,
                                    const ht_lod_rule *rule, ht_result *result);
/* Joins a job still running (chain.async) and frees it with the levels. */
HT_API void ht_lod_chain_free(ht_lod_chain *chain);
/* chain.async: a select whose level (or its order, or its widened copy)
   needs CPU work (a level's first sort and re-sorts past
   HT_LOD_RESORT_DEG / _DISTANCE, per vertex; a soft or per-draw level's
   ht_mesh_widen_back_to_front and its re-sorts) gives that work to a
   thread of its own (a job) and draws, meanwhile, what the renderer
   holds: the level, order, widened copy, opacity and tier of the frame
   before (chain.current, ordered_level, wide_*, soften say which), or,
   where the renderer holds nothing of the chain yet, `all`'s range of the
   level as built. select returns that level, the one drawn. A later
   select that finds the job done uploads its result on the caller's
   thread (ht_renderer_set_mesh_order, _set_mesh: the GL calls never
   leave it) when it still serves what that frame asks for: the order of
   the level asked for, the widened level of the soften asked for (at the
   factor it was made for, if the factor has moved on since: a new job
   follows), or the widened level held sorted again; else it is dropped.
   A result whose eye is past the order's reach of this frame's is
   uploaded (nearer than what is drawn) and a new sort starts. One job at
   a time: one asked for no more runs to its end before the next starts.
   An error of the job (HT_ERR_OUT_OF_MEMORY) is the select's result (-1)
   that finds it done, when it still serves; nothing changes on r. Work
   of no CPU cost (a level as built, a level already sorted or widened)
   is done in the select as without async. */
/* Whether the last select drew something else than it was asked for
   while a job makes it. */
HT_API bool ht_lod_chain_pending(const ht_lod_chain *chain);
/* Blocks until the job in flight, if any, is done (the next select
   uploads it; a superseded one starts its successor there). */
HT_API void ht_lod_chain_wait(ht_lod_chain *chain);

/* Cards (lod_cards.c, docs/lod.md): clumps of strands replaced by one
   textured ribbon each, the coarsest geometry. Clumps are k-means
   clusters of the strands' centres at root, middle and tip, seeded with
   runs of strands_per_card neighbours on the Z-order curve of their key
   points (the curve the LOD order strides over). A card follows the
   clump's mean centre line (each strand resampled root 0 to tip 1), lies
   across the principal direction of the strands' spread about it and is
   as wide as the farthest strand's edge on each row; tangents along it,
   unit, root to tip; the normal is the strands' mean normal made
   perpendicular to the tangent. A card is rows of two vertices like a
   strand's ribbon (the same four passes, the same inside-out sort), its uv
   the card's cell of the atlas, its vertex ao 1 (the ao is in the atlas).
   The atlas is baked from the strands the card replaces, rasterised into
   the card's (u across, v root to tip) space with 4 x 4 samples a texel,
   each strand sampling the material's own textures at its own uv (box-
   filtered across u over the texels one strand's width covers):
     albedo  rgb = the strands' base x their ao (alpha-weighted mean),
             a = coverage 1 - prod(1 - alpha) over the strands at a sample;
     detail  r = 0.5 + tangent shift: the strand's tangent against the
             card's frame (t.N / t.T) plus the material's shift there,
             g = sparkle;
   so every tier, which samples albedo and detail at uv, draws cards as
   it draws strands (docs/lod.md says what each tier keeps of them). */
#define HT_CARDS_DEFAULT_STRANDS 32
typedef struct ht_cards_desc {
    uint32_t strands_per_card;       /* 0: HT_CARDS_DEFAULT_STRANDS */
    int atlas_width, atlas_height;   /* 0: strand_albedo's size, else 256 */
    const ht_image *strand_albedo;   /* NULL: base 1, alpha 1; else RGBA: base.rgb, alpha.a */
    const ht_image *strand_detail;   /* NULL: shift 0.5, sparkle 1; else shift in r, sparkle in g */
    int reserve_rows;                /* rows at the atlas's top left free of cells (hairgen --cards
                                        puts the material's own textures there); their texels
                                        are the bake's: the caller fills them */
} ht_cards_desc;

typedef struct ht_cards {
    ht_mesh mesh;        /* one component per card, sorted inside out */
    ht_image albedo;     /* RGBA atlas, strand_albedo's layout */
    ht_image detail;     /* RGBA atlas, strand_detail's layout */
    ht_image ao;         /* 1 channel: the baked ao albedo.rgb is multiplied by */
    int columns, rows;   /* the atlas's grid of cells, one a card, row-major */
    int first_row;       /* the grid's top row: desc.reserve_rows */
} ht_cards;

/* HT_ERR_INVALID_ARGUMENT for a mesh not made of ribbons (as
   ht_mesh_build_lod), an image that is not RGBA, or more cards than the
   atlas has cells of at least 2 x 4 texels; HT_ERR_OUT_OF_MEMORY. On
   failure *out is zeroed. */
HT_API ht_result ht_mesh_build_cards(const ht_mesh *full, const ht_cards_desc *desc, ht_cards *out);
HT_API void ht_cards_free(ht_cards *cards);

/* A stored ladder (docs/bundle.md, "lods.bin"; hairgen --scene S writes
   the scene's strand levels, hairgen --cards the strand levels and cards): levels over one vertex and index buffer, each a
   range of it, read with every count, range, index and box checked, so
   a hostile file is refused with one line "NAME: FIELD: what is wrong"
   and nothing allocated. The levels follow each other in every buffer
   (level l's vertices, indices and components after level l - 1's).
   Little-endian:
     "HTLODS3\n" (an older HTLODS is refused: "regenerate with hairgen N"),
     u32 levels (1..HT_LOD_FILE_MAX_LEVELS), u32 vertices, u32 indices,
     u32 stored indices, u32 components, f32 center[3], the scene's mesh
     the levels were made from: u32 vertices, indices, components, u64 hash
     (ht_lod_file_set_scene); the position box and the (u, v, ao) box,
     each f32 min[3], f32 extent[3] (finite, extent > 0);
     per level: u32 kind (0 strands, 1 cards, 2 the scene's mesh: level 0
     only, not stored, param 1 and every count 0), u32 param (the strand
     stride, or strands per card), u32 strips (1: its indices are not
     stored: each component is a ribbon of index_count / 6 + 1 rows of two
     vertices, the next ones, drawn as the builders draw them; 0: stored),
     u32 vertex_count, index_count, component_count;
     vertices, 22 bytes each: u64 holding the position's three 21-bit
     steps of the position box (x in bits 0..20), the normal and the
     tangent as octahedral u16 pairs, u, v, ao as u16 steps of their box;
     the stored indices (u32, each from its level's first vertex);
     components (u32 first_index, u32 index_count, f32 sort_key); nothing
     after.
   Read back, a vertex is within HT_LOD_FILE_POSITION_ERROR x the box's
   extent on each axis (u, v and ao: HT_LOD_FILE_ATTRIBUTE_ERROR x theirs)
   and its normal and tangent are unit vectors within
   HT_LOD_FILE_DIRECTION_ERROR radians of the written ones (float rounding
   on top); indices, components and ranges are exact. */
#define HT_LOD_FILE_NAME "lods.bin"
#define HT_LOD_FILE_MAX_VERTICES (64u << 20)
#define HT_LOD_FILE_POSITION_BITS 21
#define HT_LOD_FILE_POSITION_ERROR (0.5 / ((1u << HT_LOD_FILE_POSITION_BITS) - 1)) /* half a step */
#define HT_LOD_FILE_ATTRIBUTE_ERROR (0.5 / 65535)
/* half an octahedral step (1 / 65535) through the map's largest stretch,
   sqrt(18) at a face's centre */
#define HT_LOD_FILE_DIRECTION_ERROR 6.5e-5
typedef struct ht_lod_range {
    ht_lod_kind kind;
    uint32_t param;
    uint32_t first_index, index_count;          /* ht_renderer_set_draw_range's */
    uint32_t first_component, component_count; /* its components in mesh */
} ht_lod_range;
typedef struct ht_lod_file {
    ht_mesh mesh;                               /* every stored level, one after the other */
    ht_lod_range levels[HT_LOD_FILE_MAX_LEVELS];
    int level_count;
    uint32_t scene_vertices, scene_indices, scene_components; /* the mesh the levels were made from */
    uint64_t scene_hash;                        /* FNV-1a 64 of its positions and indices */
} ht_lod_file;
HT_API ht_result ht_lod_file_parse(const void *data, size_t size, const char *name, ht_lod_file *out, char *err,
                                   size_t err_size);
HT_API ht_result ht_lod_file_read(const char *path, ht_lod_file *out, char *err, size_t err_size);
/* The file's bytes (malloc'd), HT_ERR_INVALID_ARGUMENT for a ladder the
   parser would refuse or the layout cannot hold (levels not one after
   the other in the buffers, a box not finite). */
HT_API ht_result ht_lod_file_encode(const ht_lod_file *f, unsigned char **data, size_t *size);
/* Level `level` as a mesh of its own (copies; for a renderer of its own);
   HT_ERR_INVALID_ARGUMENT for a SCENE level (the caller's mesh is it). */
HT_API ht_result ht_lod_file_level_mesh(const ht_lod_file *f, int level, ht_mesh *out);
HT_API void ht_lod_file_free(ht_lod_file *f);
/* Whether the levels were made from `full` (a scene's mesh as
   ht_scene_build_meshes leaves it): the same counts and the same hash of
   its vertex positions and indices, so they are that scene's (uv may
   differ: a cards bundle maps them into its atlas). set_scene records
   full's in f, for the writer. */
HT_API bool ht_lod_file_matches(const ht_lod_file *f, const ht_mesh *full);
HT_API void ht_lod_file_set_scene(ht_lod_file *f, const ht_mesh *full);

/* The bundle's measured cells (hairgen --measure-lods: every tier at every
   LOD and size, against (LOD 0, the bundle's first tier)), at most max
   into out; how many. 0 when the bundle has none. */
HT_API int ht_renderer_lod_cells(const ht_renderer *r, ht_lod_cell *out, int max);
/* True when the bundle's cells were measured with the width rule per
   draw (hairgen --lod-reference supersample: against the 16x truth, every
   cell drawn so): a pair they pick means its error only drawn that way
   (chain.width_rule; ht_mesh_width_rule on a still mesh). */
HT_API bool ht_renderer_lod_cells_width_rule(const ht_renderer *r);

#ifdef __cplusplus
}
#endif

#endif

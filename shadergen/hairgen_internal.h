/* hairgen_internal.h — the generator's internal interfaces (libhairgen and
   its tests): texture baking, the plan of what to model. The public API is
   hairgen.h; the emitters are emit.h. */
#ifndef HT_HAIRGEN_INTERNAL_H
#define HT_HAIRGEN_INTERNAL_H

#include <hairtier/hairgen.h>

/* ---- textures ---- */

/* Makes one texture of the material: procedural ones generated, file ones
   read (PNG) and reduced to the channels the slot needs (base: 3, others: 1). */
ht_result ht_texture_make(const ht_texture_source *src, ht_texture_slot slot,
                          ht_image *out, char *err, size_t err_size);

/* The bytes of img as a bundle's PNG file (png_encode.c), malloc'd into
   *data (free()): HT_ERR_INVALID_ARGUMENT for an image no PNG can hold,
   HT_ERR_OUT_OF_MEMORY. The same image gives the same bytes. */
ht_result ht_png_encode(const ht_image *img, unsigned char **data, size_t *size);

/* ---- plan: what the scene needs modelled ---- */

#define HT_MAX_NOTES 16
#define HT_MAX_UNITS 4

typedef struct ht_plan_texture {
    char name[16];          /* "albedo", "detail", "lut" */
    char sampler[24];       /* uniform name in GLSL tiers */
    char contents[64];      /* "base.rgb alpha.a" */
    int unit;
} ht_plan_texture;

typedef struct ht_plan {
    ht_shading shading;
    int light_count;
    ht_light_type light_types[HT_MAX_LIGHTS];
    double light_colors[HT_MAX_LIGHTS][3];  /* the scene's, [0,4] each */
    bool base, alpha, shift, sparkle, secondary, ao;  /* modelled features */
    double opaque_cutoff;
    /* Mean of the sparkle texture (1 until generate.c measures it): the
       tiers that cannot sample the mask scale the secondary highlight by it
       instead of leaving it unmasked. */
    double sparkle_mean;
    /* The angle (radians) the hair's bounding sphere subtends from the
       scene's eye, and whether the tiers that could take the viewer at
       infinity should not: true when that spread moves the narrowest
       highlight by more than a quarter of its width (1/sqrt(e)). */
    double viewer_spread;
    bool local_viewer;
    /* The key light (light 0) is directional and shines from behind the
       hair as the scene's camera sees it (L . (eye - target) < 0): it
       lights little of what the camera sees, so a fill light's diffuse
       matters more than where an infinite viewer puts its highlight
       (emit_fixed.c choose_add_lights). */
    bool key_behind;
    /* Brightest rgb channel of the packed albedo in [0, 1] (1 until
       generate.c measures it): the gl11 tier's headroom (gl11_program.h). */
    double albedo_max;
    ht_plan_texture textures[HT_MAX_UNITS];  /* GLSL tiers' texture units */
    int texture_count;
    char notes[HT_MAX_NOTES][160];           /* what was dropped and why */
    int note_count;
} ht_plan;

void ht_plan_make(const ht_material *m, const ht_scene *scene, ht_plan *out);
/* The shading a tier without the sparkle mask evaluates: the secondary
   colour scaled by plan->sparkle_mean (unchanged when sparkle is absent). */
ht_shading ht_plan_unmasked_shading(const ht_plan *plan);

/* ---- one bundle from files (generate.c): ht_generate_bundle's steps,
   shared with batches (batch.c) ---- */

typedef struct ht_bundle_request {
    const char *material_path;   /* required */
    const char *scene_path;      /* NULL: ht_scene_default(), no scene bytes hashed */
    const ht_scene *scene;       /* scene_path loaded already (a batch loads it once);
                                    NULL: loaded here */
    const void *scene_bytes;     /* scene_path's bytes, read once by a batch; NULL: read here */
    size_t scene_size;
    const char *out_dir;         /* the bundle directory */
    bool skip_unchanged;         /* leave out_dir alone when its manifest's input_hash
                                    is the inputs' hash (false: always regenerate) */
    FILE *summary;               /* NULL: none; else "hairgen: NAME -> DIR" and the tier table */
    ht_bundle_step_fn step;      /* NULL: none; else run on the written, unpublished bundle
                                    (ht_generate_bundle_then) */
    void *step_user;
    const char *header_path;     /* NULL: none; else the same bundle as one C header too
                                    (emit_header.c), from this one generation, its manifest
                                    as the step left it; written after out_dir is published */
    const char *header_symbol;   /* NULL: from the material name */
    int threads;                 /* threads one bundle's build may use (build.h); 0: every
                                    online core */
    bool store_lods;             /* a scene file's strand levels into lods.bin (lods_store.h),
                                    written before the step; not with header_path */
    struct ht_lods_cache *lods_cache; /* NULL: made for this bundle; else a batch's, shared */
    bool depfile_names;          /* a depfile will list the inputs: refuse, before any
                                    work, a name make and ninja cannot both read (depfile.h) */
} ht_bundle_request;

/* The files a bundle was made from: the material, the scene (when given),
   a strands scene's strand file and each texture file the material names,
   in that order. */
#define HT_BUNDLE_MAX_INPUTS (3 + HT_TEX_COUNT)

typedef struct ht_bundle_report {
    bool skipped;                                /* up to date: nothing written */
    char material_name[64];
    char inputs[HT_BUNDLE_MAX_INPUTS][1024];
    int input_count;
} ht_bundle_report;

/* A strands scene's strand file read whole by the runtime's reader
   (scene_check.c): HT_OK for any other scene; else the reader's one line
   after "SCENE: geometry.file: ". */
ht_result ht_scene_check_strands(const ht_scene *scene, const char *scene_path, char *err, size_t err_size);

/* Loads, hashes, (unless skipped) generates and publishes one bundle
   atomically. Thread-safe: a batch runs it on several threads at once for
   different out_dirs. */
ht_result ht_bundle_make(const ht_bundle_request *rq, ht_bundle_report *report, char *err, size_t err_size);

#endif

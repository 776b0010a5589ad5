/* hairtier.h — draw anisotropic hair from a hairgen bundle on any GL context,
   with the best shader tier the device can run.

   The API of libhairtier (the other installed headers serve hairgen.h and
   scene files). A bundle is a directory written
   offline by `hairgen` (manifest.json, the shaders of every tier, the
   fixed-function combiner program and its textures), or the same files
   compiled in (`hairgen --emit-header`); this library probes
   the GL context it is handed, picks a tier, logs why it skipped the
   others, and draws hair in Scheuermann's four passes over a mesh whose
   strands are sorted inside to outside once, at load time.

   Usage (any GL 1.1+ compatibility context, or GL ES 1.1 / 2.0+ context, current; my_getproc hands out
   its entry points, my_log gets each log line):
       ht_mesh mesh;   // built once, sorted inside out once
       if (ht_mesh_build_furball(&(ht_furball_desc){ .hairs = 10000 }, &mesh) != HT_OK) return;
       ht_mesh_sort_inside_out(&mesh);
       ht_renderer *r;
       if (ht_renderer_create(&(ht_renderer_desc){ .getproc = my_getproc, .bundle_dir = "out/bundle",
                                                   .log = my_log },
                              &r) != HT_OK) {
           ht_mesh_free(&mesh);   // the log said why
           return;
       }
       // or .bundle_memory = &dark_brown_bundle, from the header that
       // `hairgen --emit-header bundle.h` writes, instead of .bundle_dir
       ht_renderer_set_mesh(r, &mesh);
       ht_camera cam = { .eye = { 0, 0, 3 }, .target = { 0, 0, 0 }, .up = { 0, 1, 0 }, .fov_y = 40 };
       ht_light key = { .type = HT_LIGHT_DIRECTIONAL, .vector = { 0.6f, 0.8f, 0.7f }, .color = { 1, 1, 1 } };
       ht_renderer_draw(r, &(ht_frame_desc){ .camera = cam, .lights = &key, .light_count = 1 });   // every frame
       ht_renderer_destroy(r);
       ht_mesh_free(&mesh);

   Environment: HAIRTIER_TIER=marschner|full|vertex|fixed4|fixed|gl11 forces a tier
   like ht_renderer_desc.tier does (the desc wins when both are set); gl11,
   the last resort, runs on any GL 1.1 context with one texture unit.
   HAIRTIER_POLICY=best|fastest|error:DB|error:flip:E|frame:MS picks among the tiers the
   device runs like ht_renderer_desc.policy (the desc wins; a forced tier
   wins over both).
   HAIRTIER_VARIANT=exact|device picks the variant of fixed4 and fixed like
   ht_renderer_desc.variant (ht_variant below; the desc wins).
   HAIRTIER_DEVICE_PROFILE=gl11|gl13|gl20|videocore4|mali400|videocore6
   caps the device like
   ht_renderer_desc.profile (ht_device_profile_parse; a non-zero desc
   profile wins).

   Policies, the speed-for-accuracy dial (every choice is logged with its
   reason and numbers, e.g. "tier fixed (error:30: 31.2 dB >= 30 dB, cost
   0.4x full)"):
       best        the best tier the device runs (the default)
       fastest     the cheapest tier the device runs: the least measured
                   cost_ratio when every such tier has one, else the last
                   in the bundle's order
       error:DB    the cheapest tier the device runs whose measured PSNR
                   against full is at least DB; needs the bundle's per-tier
                   "measured" numbers (hairgen --measure), HT_ERR_INVALID_ARGUMENT
                   without them; when none reaches DB, the most accurate one
       error:flip:E  the same by FLIP: the cheapest tier the device runs
                   whose measured LDR-FLIP mean against full (at 67 pixels
                   per degree) is at most E, in [0, 1]; when none is within
                   E, the one of least FLIP mean
       frame:MS    the best tier whose frame time on this device is within
                   MS. Timing needs a mesh and a frame, which come after
                   create: create picks the best tier (or times with
                   desc.time_tier when set), and the app calls
                       ht_renderer_set_mesh(r, &mesh);
                       ht_renderer_choose_by_frame_time(r, &mesh, &frame, 0);
                   which draws each tier the device runs for a few frames,
                   logs every timing, and keeps the chosen tier's backend.

   Errors: functions return ht_result; the log callback (or the message
   buffer a function takes) says what failed and where. Nothing here exits. */
#ifndef HAIRTIER_H
#define HAIRTIER_H

#include "export.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum ht_result {
    HT_OK = 0,
    HT_ERR_INVALID_ARGUMENT,
    HT_ERR_IO,            /* a file could not be read or written */
    HT_ERR_PARSE,         /* malformed or out-of-range input */
    HT_ERR_UNSUPPORTED,   /* the device cannot run what was asked */
    HT_ERR_COMPILE,       /* a shader failed to compile, link or validate */
    HT_ERR_GL,            /* GL reported an error */
    HT_ERR_NO_TIER,       /* no tier of the bundle runs here */
    HT_ERR_OUT_OF_MEMORY,
} ht_result;

HT_API const char *ht_result_string(ht_result r);

typedef enum ht_tier {
    HT_TIER_AUTO = 0,  /* best the device runs */
    HT_TIER_MARSCHNER, /* per-pixel GLSL, Marschner's fibre from lookup textures (model "marschner") */
    HT_TIER_FULL,      /* per-pixel GLSL */
    HT_TIER_VERTEX,    /* per-vertex GLSL lighting, fixed-function fragment */
    HT_TIER_FIXED,     /* GL 1.3 texture combiners + lookup textures, 2 units */
    HT_TIER_FIXED4,    /* GL 1.3 combiners on 4 units, every coordinate made by the device */
    HT_TIER_GL11,      /* GL 1.1, one unit: the model per vertex on the CPU x the albedo */
    HT_TIER_COUNT
} ht_tier;

HT_API const char *ht_tier_name(ht_tier t);          /* "auto", "full", ... */
HT_API ht_tier ht_tier_from_name(const char *name);  /* HT_TIER_COUNT when unknown */

/* ---- lights, camera, hair geometry (a whole scene: scene.h) ---- */

#define HT_MAX_LIGHTS 4

typedef enum ht_light_type { HT_LIGHT_DIRECTIONAL = 0, HT_LIGHT_POINT = 1 } ht_light_type;

typedef struct ht_light {
    ht_light_type type;
    float vector[3]; /* directional: towards the light; point: position */
    float color[3];  /* [0,4] each */
} ht_light;

typedef struct ht_camera {
    float eye[3], target[3], up[3];
    float fov_y;      /* degrees, (0,180) */
    float z_near;     /* 0 → 0.05 */
    float z_far;      /* 0 → 100 */
} ht_camera;

typedef struct ht_furball_desc {
    int hairs;          /* 0 → 2000 */
    int joints;         /* 0 → 16; quads per hair = joints - 1 */
    float length;       /* 0 → 0.08, segment length */
    float gravity[3];   /* added to the direction at every joint */
    float inertia[3];   /* added too: the ball's motion bending hair back */
    float width;        /* 0 → 0.01, ribbon width */
    uint32_t seed;
} ht_furball_desc;

typedef struct ht_patches_desc {
    float head_radius;  /* 0 → 1 */
    int layers;         /* 0 → 3, shells of strips around the head */
    int strips;         /* 0 → 64, strips per layer */
    int segments;       /* 0 → 12, quads along a strip */
    uint32_t seed;
} ht_patches_desc;

/* ---- hair meshes ---- */

/* One vertex of a hair ribbon: what every tier reads. */
typedef struct ht_vertex {
    float position[3];
    float normal[3];    /* ribbon normal, unit */
    float tangent[3];   /* root to tip, unit */
    float uv[2];        /* u across the ribbon, v root (0) to tip (1) */
    float ao;           /* ambient occlusion, [0,1] */
} ht_vertex;

/* A connected component (one hair, one strip): a run of the index buffer. */
typedef struct ht_component {
    uint32_t first_index;
    uint32_t index_count;
    float sort_key;      /* what the sort orders by; the builders write the distance
                            of the component's vertex centroid from ht_mesh.center */
} ht_component;

typedef struct ht_mesh {
    ht_vertex *vertices;
    uint32_t vertex_count;
    uint32_t *indices;           /* triangles */
    uint32_t index_count;
    ht_component *components;
    uint32_t component_count;
    float center[3];             /* the point the builders measured sort_key from
                                    (written by them; the sort reads only sort_key) */
} ht_mesh;

HT_API ht_result ht_mesh_build_furball(const ht_furball_desc *desc, ht_mesh *out);
/* hair strips around a head; `head` (may be NULL) receives the head sphere,
   an opaque mesh drawn before the hair. */
HT_API ht_result ht_mesh_build_patches(const ht_patches_desc *desc, ht_mesh *out, ht_mesh *head);
/* Reorders components (and the index buffer) by ascending sort_key; ties
   keep build order. Done once at load time. */
HT_API void ht_mesh_sort_inside_out(ht_mesh *mesh);
HT_API void ht_mesh_free(ht_mesh *mesh);

/* ---- device capabilities ---- */

typedef void *(*ht_getproc_fn)(const char *name);
typedef void (*ht_log_fn)(void *user, const char *line);

typedef struct ht_caps {
    int gl_major, gl_minor;       /* on GL ES: the ES version ("OpenGL ES 3.2 Mesa ..." → 3.2) */
    int glsl_major, glsl_minor;   /* 0.0 when there are no shaders; on ES the ESSL version (1.00 → {1, 0}) */
    int texture_units;            /* fixed-function units; on ES 2.0+ the fragment stage's (GL_MAX_TEXTURE_IMAGE_UNITS) */
    bool es;                      /* an OpenGL ES context ("OpenGL ES ..." version string) */
    bool fragment_highp;          /* fragment highp float: always on desktop GL; on ES what
                                     glGetShaderPrecisionFormat(GL_FRAGMENT_SHADER, GL_HIGH_FLOAT) says */
    char renderer[128];
    char version[128];
    bool has_shaders;             /* entry points loaded and GL >= 2.0 */
    bool has_vbo;
    bool has_combine;             /* GL 1.3 or ARB_texture_env_combine */
    bool has_crossbar;            /* GL 1.4 or ARB_texture_env_crossbar */
    bool has_3d_textures;         /* GL 1.2 */
    bool has_multitexture;        /* GL 1.3 or ARB_multitexture, entry points loaded */
    bool has_vertex_shaders;      /* GLSL vertex stage (has_shaders, unless a profile hides it) */
    bool has_fragment_shaders;    /* GLSL fragment stage */
    int max_3d_texture_size;      /* GL_MAX_3D_TEXTURE_SIZE; 0 without 3D textures */
    uint32_t known_extensions;    /* one bit per extension libhairtier asks about by name (its own
                                     table, internal); the device's whole list is glGetString's */
} ht_caps;

/* A device profile caps what the runtime may use, so tests (and cautious
   apps) stand in for low-end hardware on a capable driver. Zero fields cap
   nothing. Pair it with Mesa's MESA_GL_VERSION_OVERRIDE=1.3 and
   MESA_EXTENSION_OVERRIDE="-GL_ARB_texture_env_combine ..." (set before the
   context is created) to make the driver itself refuse what the profile
   hides. Lowering the GL version also drops what that version brought
   (shaders below 2.0, VBOs below 1.5, combine/multitexture below 1.3 unless
   the extension remains, 3D textures below 1.2). */
typedef struct ht_device_profile {
    int gl_major, gl_minor;       /* 0.0 → no cap */
    int glsl_major, glsl_minor;   /* 0.0 → no cap; GLSL 1.10 is {1, 10} */
    int texture_units;            /* 0 → no cap */
    int max_3d_texture_size;      /* 0 → no cap; GL 1.2 promises only 16 */
    const char *hide_extensions;  /* NULL → none; space-separated names the runtime must not use */
    bool no_fragment_shaders;     /* false; true models a vertex-shader-only device */
    bool no_shaders;              /* false */
    bool no_vbo;                  /* false */
    int es_major, es_minor;       /* 0.0 → a desktop profile; else a GL ES device of that version
                                     (the context must be ES: the renderer refuses it on desktop GL) */
    bool no_fragment_highp;       /* false; true models a fragment stage without highp (Mali-400) */
} ht_device_profile;

/* Probes the current context: versions, the flags above, units. */
HT_API ht_result ht_caps_probe(ht_getproc_fn getproc, ht_caps *out);
/* Lowers caps to what the profile allows (NULL or all-zero: unchanged). */
HT_API void ht_caps_apply_profile(ht_caps *caps, const ht_device_profile *profile);
/* A named profile: "gl11" (GL 1.1, one unit, no multitexture, combine,
   VBOs, shaders or 3D textures: the gl11 tier), "gl13" (GL 1.3, the
   driver's units and extensions: what MESA_GL_VERSION_OVERRIDE=1.3 leaves),
   "gl20" (GL 2.0, GLSL 1.10); the GL ES devices "videocore4" (Raspberry
   Pi 1-3, Mesa vc4: ES 2.0, 8 units), "mali400" (Mesa lima: ES 2.0, no
   fragment highp, 8 units) and "videocore6" (Pi 4, Mesa v3d: ES 3.1, 16
   units), whose sources docs/materials.md cites; NULL, "" or "none" → the
   zero profile. Other
   text: HT_ERR_INVALID_ARGUMENT with one line in err. This is what
   HAIRTIER_DEVICE_PROFILE names; it stands in for old hardware on any
   driver, NVIDIA's too, where Mesa's overrides do not exist. */
HT_API ht_result ht_device_profile_parse(const char *text, ht_device_profile *out, char *err, size_t err_size);
HT_API bool ht_device_profile_is_zero(const ht_device_profile *profile);

/* ---- the renderer ---- */

/* One record of what a pass set and drew: tests compare traces across tiers. */
typedef enum ht_pass {
    HT_PASS_PRIME_Z = 0,
    HT_PASS_OPAQUE,
    HT_PASS_BACK,
    HT_PASS_FRONT,
    HT_PASS_COUNT
} ht_pass;

typedef struct ht_trace_entry {
    ht_pass pass;
    int sub_pass;              /* 0 unless a tier splits a pass */
    bool cull;                 /* culling enabled */
    unsigned cull_face;        /* GL_FRONT / GL_BACK */
    unsigned depth_func;       /* GL_LESS / GL_EQUAL */
    bool depth_write;
    bool color_write;
    bool blend;
    bool alpha_test;
    unsigned alpha_func;       /* GL_GEQUAL / GL_LESS */
    float alpha_ref;
    float opacity_scale;       /* the hair's alpha scale the pass drew with (ht_renderer_set_opacity_scale) */
    uint32_t first_index, index_count;
    unsigned gl_error;         /* glGetError() after the draw */
} ht_trace_entry;

#define HT_TRACE_MAX 64

typedef struct ht_trace {
    ht_trace_entry entries[HT_TRACE_MAX];
    int count;
} ht_trace;

/* ---- policies (the header comment above says what each does) ---- */

typedef enum ht_policy_kind {
    HT_POLICY_BEST = 0,
    HT_POLICY_FASTEST,
    HT_POLICY_ERROR,       /* value: the least PSNR in dB */
    HT_POLICY_FRAME,       /* value: the frame budget in ms */
    HT_POLICY_ERROR_FLIP,  /* value: the largest FLIP mean, in [0, 1] */
} ht_policy_kind;

typedef struct ht_policy {
    ht_policy_kind kind;
    double value;
} ht_policy;

/* A tier's variant. fixed4 and fixed make some LUT coordinates per vertex
   on the CPU whenever the eye or a light moves (the local viewer; fixed:
   three dot products of three vectors). Their device-only variant makes
   every coordinate on the device (texture matrices over static vectors,
   infinite viewer) at an error hairgen --measure records per bundle
   ("measured_device"). AUTO: HAIRTIER_VARIANT ("exact", "device"), else
   the policy's rule (ht_select_variant in select.h): the device variant
   when its measured PSNR is within HT_VARIANT_DEVICE_DB of the exact
   one's (error:DB: when it meets DB; fastest: when it costs less). A
   tier without a device variant ignores the request. */
typedef enum ht_variant {
    HT_VARIANT_AUTO = 0,
    HT_VARIANT_EXACT,      /* CPU coordinates where only the CPU is exact */
    HT_VARIANT_DEVICE,     /* no per-vertex CPU work while anything moves */
} ht_variant;
#define HT_VARIANT_DEVICE_DB 0.5

/* "best", "fastest", "error:<dB>" (a finite number >= 0), "error:flip:<E>"
   (E in [0, 1]), "frame:<ms>" (> 0)
   into a policy; HT_ERR_INVALID_ARGUMENT with one line in err otherwise. */
HT_API ht_result ht_policy_parse(const char *text, ht_policy *out, char *err, size_t err_size);

/* ---- a bundle held in memory (hairgen --emit-header writes one) ---- */

/* One file of a bundle: its name in the bundle directory and its bytes,
   exactly what hairgen writes to disk (PNG files stay PNG). */
typedef struct ht_bundle_file {
    const char *name;            /* "manifest.json", "full.frag", "albedo.png": a plain file name */
    const unsigned char *data;   /* size bytes; may be NULL only when size is 0 */
    size_t size;
} ht_bundle_file;

/* A whole bundle in memory, read with the same checks and the same one-line
   messages as a directory, NAME standing where the directory path would
   ("NAME/full.frag: cannot read: No such file or directory"). Nothing is
   copied: the files must outlive the renderer (the arrays hairgen
   --emit-header writes are static). */
typedef struct ht_bundle_memory {
    const char *name;            /* labels messages; NULL or "" → "memory" */
    const ht_bundle_file *files;
    int file_count;              /* 1..HT_BUNDLE_MEMORY_MAX_FILES; names unique */
} ht_bundle_memory;

#define HT_BUNDLE_MEMORY_MAX_FILES 64

/* Mean milliseconds a frame of `tier` takes; tests and apps with their own
   timer provide it (frame:MS policy). A value <= 0 or not finite: not timed. */
typedef double (*ht_time_tier_fn)(void *user, ht_tier tier);

typedef struct ht_renderer_desc {
    ht_getproc_fn getproc;   /* required */
    const char *bundle_dir;  /* a directory written by hairgen; this or bundle_memory is required */
    const ht_bundle_memory *bundle_memory; /* NULL; else the bundle, in memory, instead of bundle_dir */
    ht_tier tier;            /* HT_TIER_AUTO → best supported (or HAIRTIER_TIER) */
    bool strict;             /* false: a forced tier that fails drops to the next */
    ht_log_fn log;           /* NULL → stderr */
    void *log_user;
    bool record_trace;       /* false */
    float flat_color[3];     /* used only when flat is set; {0,0,0} → 0.5 grey */
    bool flat;               /* false; true → geometry floor: same passes, flat colour, no textures */
    ht_device_profile profile; /* zero → HAIRTIER_DEVICE_PROFILE, else everything the context offers */
    const char *policy;      /* NULL → HAIRTIER_POLICY, else "best"; "fastest", "error:30", "frame:16.7" */
    ht_time_tier_fn time_tier; /* NULL → frame:MS times by drawing (ht_renderer_choose_by_frame_time);
                                  set → create and choose_by_frame_time ask it instead of drawing */
    void *time_tier_user;
    ht_variant variant;      /* AUTO → HAIRTIER_VARIANT, else the policy and the manifest's measured numbers */
} ht_renderer_desc;

typedef struct ht_renderer ht_renderer;

typedef struct ht_frame_desc {
    ht_camera camera;
    float aspect;                 /* 0 → viewport width / height */
    const ht_light *lights;
    int light_count;
    const ht_mesh *opaque;        /* NULL, or drawn lit before the hair (the head) */
} ht_frame_desc;

HT_API ht_result ht_renderer_create(const ht_renderer_desc *desc, ht_renderer **out);
HT_API ht_tier ht_renderer_tier(const ht_renderer *r);
/* Why this tier: "best supported", "forced by HAIRTIER_TIER", ... */
HT_API const char *ht_renderer_reason(const ht_renderer *r);
/* HT_VARIANT_DEVICE when the tier runs its device-only variant, else
   HT_VARIANT_EXACT (every tier without one). */
HT_API ht_variant ht_renderer_variant(const ht_renderer *r);
/* Uploads the hair mesh (VBOs where the GL has them). Non-finite vertex
   data, indices out of range or a partial triangle are refused with
   HT_ERR_INVALID_ARGUMENT and one log line naming the element; the
   previously set mesh stays in place. */
HT_API ht_result ht_renderer_set_mesh(ht_renderer *r, const ht_mesh *mesh);
/* The mesh set last in a new order: mesh has its vertices and counts, its
   triangles reordered (ht_mesh_sort_back_to_front again as the eye
   moves). Uploads the indices alone: the vertices, their per-vertex data
   and a tier's own arrays stay. The draw range becomes the whole mesh. A
   mesh split into 16-bit runs (GL ES 2.0 without 32-bit indices) goes up
   whole (ht_renderer_set_mesh). HT_ERR_INVALID_ARGUMENT with one log line
   when no mesh is set, a count differs or an index is out of range; the
   order set before stays. */
HT_API ht_result ht_renderer_set_mesh_order(ht_renderer *r, const ht_mesh *mesh);
/* Draws indices [first_index, first_index + index_count) of the mesh set
   last instead of all of them (ht_renderer_set_mesh resets it to all): one
   buffer holding several meshes, e.g. every geometry LOD (lod.h's
   ht_lod_chain), switched without an upload. HT_ERR_INVALID_ARGUMENT with
   one log line for a range past the mesh or not of whole triangles (the
   range in use stays). The fixed-function tiers' per-frame CPU work
   covers the range's vertices (within a block of 768 indices at each end),
   not the whole mesh's. */
HT_API ht_result ht_renderer_set_draw_range(ht_renderer *r, uint32_t first_index, uint32_t index_count);
/* ht_renderer_set_draw_range with the range's vertices named: every index
   in it lies in [first_vertex, first_vertex + vertex_count) (a chain's
   level: its own vertices). The tiers that work per vertex on the CPU
   (gl11's lighting, the fixed tiers' coordinates) then touch only those,
   not what the renderer's blocks of indices bound (a block straddling the
   range's ends reaches into its neighbours' vertices). The next
   ht_renderer_set_draw_range, set_mesh or set_mesh_order forgets them, and
   a mesh in 16-bit chunks (its vertices reordered) ignores them.
   HT_ERR_INVALID_ARGUMENT: not within the mesh's vertices (logged). */
HT_API ht_result ht_renderer_set_draw_range_vertices(ht_renderer *r, uint32_t first_index, uint32_t index_count,
                                                     uint32_t first_vertex, uint32_t vertex_count);
/* Draws `tier` of the bundle from the next frame on, with the mesh and
   draw range in place (no upload of the renderer's buffers): the tier's
   backend (programs, textures, lookup tables) is made at its first use and
   kept until ht_renderer_destroy, so switching back and forth costs nothing
   after that. A tier with per-vertex data of its own (fixed4, fixed, gl11)
   makes it from `mesh`, which must be the mesh set last, at its first use
   after each ht_renderer_set_mesh (NULL is enough otherwise). The tier is
   forced: no selection or fallback. HT_ERR_INVALID_ARGUMENT (a flat
   renderer, a tier not in the bundle, another mesh), HT_ERR_UNSUPPORTED
   (the device lacks what the tier needs), or the backend's own error, each
   with one log line; the renderer keeps drawing the tier it had. lod.h's
   ht_lod_chain_select_pair switches (level, tier) pairs with it. */
HT_API ht_result ht_renderer_set_tier(ht_renderer *r, ht_tier tier, const ht_mesh *mesh);
/* Draws the opaque mesh, then the hair in the four passes. The frame is
   checked first (finite camera with eye != target and up not parallel to
   the view, fov_y in (0,180), finite lights with colours in [0,4]); a bad
   frame is HT_ERR_INVALID_ARGUMENT with one log line and no draw call.
   Lights beyond the count the bundle was planned for are ignored, and a
   light whose type differs from the plan is shaded as planned; each is
   logged once per renderer.
   GL state: the draw saves the application's (glPushAttrib(GL_ALL_ATTRIB_BITS),
   glPushClientAttrib(GL_CLIENT_ALL_ATTRIB_BITS), the current program, the
   projection, modelview and every unit's texture matrix), draws from a
   baseline of its own (lighting, fog, colour material, texgen, logic op,
   polygon offset and stipple off; every texture target off, GL_MODULATE
   and an identity texture matrix on every unit; smooth shading, filled
   polygons; no program; no client array or generic attribute array but
   its own), and restores all of it. What it leaves changed: the colour and
   depth buffers it drew into, and glGetError, which it clears first (an
   error the application left pending is consumed). Taken from the
   application as they are: viewport, scissor and stencil tests, clip
   planes, depth range, blend equation and colour, the framebuffer and draw
   buffer. With no room on either attribute stack the draw draws nothing
   and returns HT_ERR_GL with one log line.
   On GL ES 2.0 and later (no attribute stacks) the draw reads back and
   restores what it changes: depth test, function and mask, blend enable
   and functions, culling and its face, front face, polygon offset, colour
   mask, the program, the active unit and every unit's 2D texture, both
   buffer bindings, the vertex array object (ES 3: it draws with object 0)
   and on that object every attribute's enable and attributes 0-7's
   arrays. On GL ES 1.1 it reads back and restores the same fixed-function
   state as its own: those enables and functions, the alpha test, lighting,
   colour material, normalize, rescale normal, fog and logic op enables, shade model,
   current colour, light model, lights 0-7 and the material, the matrix
   mode and the projection, modelview and texture matrices, per unit the 2D
   enable and texture and the whole texture environment, the vertex,
   normal, colour and texture coordinate arrays, the active and
   client-active units and both buffer bindings.
   ht_renderer_create and ht_renderer_set_mesh are not wrapped that way:
   they leave the current program 0, the active unit's 2D (and 3D) texture
   binding 0, GL_UNPACK_ALIGNMENT 4 and GL_ARRAY_BUFFER and
   GL_ELEMENT_ARRAY_BUFFER bound to 0, and clear glGetError. */
HT_API ht_result ht_renderer_draw(ht_renderer *r, const ht_frame_desc *frame);
HT_API const ht_trace *ht_renderer_trace(const ht_renderer *r);
/* How long to draw before timing frames on a GL whose GL_RENDERER is
   `renderer`: a GPU lowers its clock while the CPU works between timings
   and raises it only after a while busy (NVIDIA: every frame of a short
   timing 1.1-1.5x its steady time after one warm-up frame, docs/lod.md
   "Warm-up by time"), HT_TIMING_WARMUP_MS; a software rasterizer (a
   GL_RENDERER naming llvmpipe, softpipe, Software Rasterizer, Mesa
   OffScreen or SwiftShader; NULL too) has no clock: 0, one warm-up frame.
   An application timing frame:MS's reference frames (ht_lod_rule) warms
   up so too. */
#define HT_TIMING_WARMUP_MS 250.0
HT_API double ht_timing_warmup_ms(const char *renderer);
#define HT_FRAME_TIMING_FRAMES 5
/* The frame:MS policy's step after set_mesh: draws every tier the device
   runs for HT_FRAME_TIMING_FRAMES frames of `mesh` and `frame` after a
   warm-up (one frame, more until ht_timing_warmup_ms of the caps'
   renderer: on a GPU about 250 ms more a tier), timed with glFinish and
   the monotonic clock (or asks
   desc.time_tier), logs each timing, and keeps the best tier whose mean is
   within budget_ms (0 → the policy's budget; HT_ERR_INVALID_ARGUMENT when
   neither is set), else the fastest. The mesh is uploaded again for each
   tier and stays set. A tier whose backend fails to create is skipped with
   its reason. */
HT_API ht_result ht_renderer_choose_by_frame_time(ht_renderer *r, const ht_mesh *mesh, const ht_frame_desc *frame,
                                           double budget_ms);
/* What the renderer saw of the device, after the desc's profile. */
HT_API const ht_caps *ht_renderer_caps(const ht_renderer *r);

/* What the renderer has done so far: frames drawn, and the CPU work per
   vertex it did for them (a tier whose coordinates or colours the CPU
   computes counts every vertex each time it recomputes them; a device
   rule such as fixed4's texture matrices counts none). Tests and the
   benchmark read it to prove a frame costs the CPU nothing per vertex. */
typedef struct ht_renderer_stats {
    uint64_t frames;
    uint64_t cpu_vertices;
} ht_renderer_stats;

HT_API ht_renderer_stats ht_renderer_get_stats(const ht_renderer *r);
HT_API void ht_renderer_destroy(ht_renderer *r);

#ifdef __cplusplus
}
#endif
#endif

/* shader_interface.h — the contract between the GLSL the generator emits and
   the runtime that binds it. Change both sides together. */
#ifndef HT_SHADER_INTERFACE_H
#define HT_SHADER_INTERFACE_H

/* Desktop GLSL (1.10 / 1.20) reads position, normal and uv from the
   fixed-function vertex arrays, so every tier draws from the same buffers and
   ftransform() keeps depth invariant:
     gl_Vertex          position (world space: the model matrix is identity)
     gl_Normal          ribbon normal
     gl_MultiTexCoord0  uv
   Tangent and ao are generic attributes at fixed locations (bound before
   linking), not texture coordinates: a device with one or two texture units
   has only that many coordinate sets. 6 and 7 alias no conventional
   attribute on drivers that alias (0 is gl_Vertex, 2 gl_Normal, 3 gl_Color,
   8.. the texture coordinates). ESSL 1.00 uses the same two names. */
#define HT_ATTR_TANGENT          "a_tangent"   /* vec3 */
#define HT_ATTR_AO               "a_ao"        /* float */
#define HT_ATTR_TANGENT_LOCATION 6
#define HT_ATTR_AO_LOCATION      7
/* The width rule per vertex (docs/lod.md): the vertex's offset from its
   ribbon's centre line (half the row's width vector, mesh_gpu.c makes it
   from the row's two vertices; zero for a mesh not of ribbons). 5 aliases
   only the fog coordinate, which no hair pass reads. */
#define HT_ATTR_SIDE             "a_side"      /* vec3 */
#define HT_ATTR_SIDE_LOCATION    5

/* ESSL 1.00 has no built-in attributes; its variants read these too. */
#define HT_ES_ATTR_POSITION "a_position"
#define HT_ES_ATTR_NORMAL   "a_normal"
#define HT_ES_ATTR_UV       "a_uv"
#define HT_ES_U_MVP         "u_mvp"        /* mat4, ES only */
/* ESSL 3.00 has no gl_FragColor: its fragment texts write this output. */
#define HT_ES3_FRAG_COLOR   "ht_frag_color"
/* Where the runtime binds the ES attributes before linking (tangent and ao
   keep their desktop locations; ES 2.0 guarantees 8 attributes). */
#define HT_ES_ATTR_POSITION_LOCATION 0
#define HT_ES_ATTR_NORMAL_LOCATION   1
#define HT_ES_ATTR_UV_LOCATION       2
/* The vertex tier's ES fragment stage samples its LUTs through these
   ("u_lut0", "u_lut1"); its albedo is HT_U_ALBEDO on the unit after them. */
#define HT_ES_U_LUT_PREFIX  "u_lut"

/* Uniforms, world space. Arrays sized by the planned light count. */
#define HT_U_EYE            "u_eye"          /* vec3 */
#define HT_U_LIGHT_VECTOR   "u_light_vector" /* vec4[n]: w=0 direction towards the light, w=1 position */
#define HT_U_LIGHT_COLOR    "u_light_color"  /* vec3[n] */
/* The vertex tier's: the final combiner stage's GL_RGB_SCALE (1, 2 or 4),
   which its primary colour is divided by. */
#define HT_U_LUT_SCALE      "u_lut_scale"    /* float */

/* The width rule (docs/lod.md): a strand drawn wider than it is has its
   alpha scaled by (1 - this); 0, GLSL's initial value, draws it as it is.
   Every fragment text (and the GLSL Z-prime) multiplies its alpha by it. */
#define HT_U_OPACITY_CUT    "u_opacity_cut"  /* float */
/* The width rule per vertex: the world length the least drawn width
   (lod.h's HT_WIDTH_RULE_VERTEX_PX pixels) spans at clip w = 1,
   px x 2 / (projection[1][1] x viewport height); 0, GLSL's initial value,
   is off. On, each vertex whose ribbon is narrower than that at its own
   clip w moves off its centre line by f = w u / (2 |a_side|) (clamped to
   [1, 1024]) and hands 1 / f to the fragment stage in this varying, which
   every fragment text multiplies its alpha by, as by 1 - u_opacity_cut. */
#define HT_U_WIDTH_RULE     "u_width_rule"   /* float, vertex stages */
#define HT_V_WIDTH_ALPHA    "v_width_alpha"  /* varying float */

/* Samplers: names the manifest lists with their unit. */
#define HT_U_ALBEDO         "u_albedo"       /* rgb = base, a = alpha */
#define HT_U_DETAIL         "u_detail"       /* r = shift, g = sparkle */

/* Alpha testing: desktop tiers use fixed-function glAlphaFunc (it applies to
   shader output in compatibility contexts); ES has none, so its fragment
   shaders discard against these. */
#define HT_ES_U_ALPHA_REF   "u_alpha_ref"    /* float */
#define HT_ES_U_ALPHA_PASS_OPAQUE "u_alpha_pass_opaque" /* float: 1 keeps a >= ref, 0 keeps a < ref */

#endif

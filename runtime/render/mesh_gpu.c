/* mesh_gpu.c — the hair mesh on the GL side: uploaded once (VBOs where
   the GL has them, else a private copy) and pointed at as vertex arrays
   for each draw. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "gl_error.h"
#include "errfmt.h"
#include "caps.h"
#include "index_chunks.h"
#include "lod_internal.h"
#include "renderer_internal.h"
#include "shader_interface.h"

void ht_renderer_release_mesh(ht_renderer *r) {
    if (r->vbo) r->gl.DeleteBuffers(1, &r->vbo);
    if (r->ibo) r->gl.DeleteBuffers(1, &r->ibo);
    if (r->side_vbo) r->gl.DeleteBuffers(1, &r->side_vbo);
    r->vbo = r->ibo = r->side_vbo = 0;
    free(r->sides);
    r->sides = NULL;
    r->has_sides = false;
    free(r->vertices);
    free(r->indices);
    free(r->chunks);
    free(r->span);
    r->span = NULL;
    r->span_count = 0;
    r->vertices = NULL;
    r->indices = NULL;
    r->chunks = NULL;
    r->chunk_count = 0;
    r->has_mesh = false;
}

/* Each block's least and largest vertex; NULL when memory is short (the
   draws then report every vertex). */
static uint32_t *make_span(const ht_mesh *m, uint32_t *count) {
    *count = (m->index_count + HT_SPAN_INDICES - 1) / HT_SPAN_INDICES;
    uint32_t *span = malloc(*count ? 2 * (size_t)*count * sizeof *span : 1);
    for (uint32_t b = 0; span && b < *count; b++) {
        uint32_t lo = UINT32_MAX, hi = 0;
        const uint32_t end = (b + 1) * HT_SPAN_INDICES < m->index_count ? (b + 1) * HT_SPAN_INDICES : m->index_count;
        for (uint32_t i = b * HT_SPAN_INDICES; i < end; i++) {
            lo = m->indices[i] < lo ? m->indices[i] : lo;
            hi = m->indices[i] > hi ? m->indices[i] : hi;
        }
        span[2 * b] = lo;
        span[2 * b + 1] = hi;
    }
    return span;
}

void ht_renderer_draw_vertices(const ht_renderer *r, uint32_t *first_vertex, uint32_t *vertex_count) {
    *first_vertex = 0;
    *vertex_count = r->vertex_count;
    if (r->draw_vertex_count) {
        *first_vertex = r->draw_vertex_first;
        *vertex_count = r->draw_vertex_count;
        return;
    }
    if (!r->span || !r->draw_count) return;
    uint32_t lo = UINT32_MAX, hi = 0;
    const uint32_t last = (r->draw_first + r->draw_count - 1) / HT_SPAN_INDICES;
    for (uint32_t b = r->draw_first / HT_SPAN_INDICES; b <= last && b < r->span_count; b++) {
        lo = r->span[2 * b] < lo ? r->span[2 * b] : lo;
        hi = r->span[2 * b + 1] > hi ? r->span[2 * b + 1] : hi;
    }
    if (lo > hi) return;
    *first_vertex = lo;
    *vertex_count = hi - lo + 1;
}

bool ht_renderer_short_indices(const ht_renderer *r) {
    return r->caps.es && !ht_extension_list_has(r->extensions, "GL_OES_element_index_uint");
}

void ht_renderer_draw_client_elements(ht_renderer *r, const ht_mesh *m) {
    uint16_t *indices16 = NULL;
    if (ht_renderer_short_indices(r) &&
        (m->vertex_count > 65536u || !(indices16 = ht_renderer_indices16(m->indices, m->index_count))))
        return;
    r->gl.DrawElements(GL_TRIANGLES, (GLsizei)m->index_count, indices16 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT,
                       indices16 ? (const void *)indices16 : (const void *)m->indices);
    free(indices16);
}

uint16_t *ht_renderer_indices16(const uint32_t *indices, uint32_t count) {
    uint16_t *out = malloc(count ? (size_t)count * sizeof *out : 1);
    for (uint32_t i = 0; out && i < count; i++) out[i] = (uint16_t)indices[i];
    return out;
}

bool ht_renderer_width_rule_active(const ht_renderer *r) {
    return r->width_vertex && r->has_sides && r->backend && r->backend->vertex_width_rule &&
           r->backend->vertex_width_rule(r->backend_state);
}

bool ht_renderer_width_rule_drawn(const ht_renderer *r) {
    return ht_renderer_width_rule_active(r) && (r->back_to_front || r->opacity_cut > 0.0f);
}

/* The width rule per vertex's a_side array (ht_lod_sides), in the order
   the vertices went up (source: a split mesh's, index_chunks.h; NULL: the
   mesh's own). A buffer where the GL has them; false when memory or the
   GL refuses (logged; the mesh is drawn without). */
static bool upload_sides(ht_renderer *r, const ht_mesh *mesh, const uint32_t *source, uint32_t count) {
    float(*sides)[3] = malloc(mesh->vertex_count ? (size_t)mesh->vertex_count * sizeof *sides : 1);
    float(*split)[3] = source ? malloc(count ? (size_t)count * sizeof *split : 1) : NULL;
    if (!sides || (source && !split)) {
        free(sides);
        free(split);
        ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: the width rule per vertex: out of memory "
                     "for %u vertices; per draw", count);
        return false;
    }
    ht_lod_sides(mesh, sides);
    if (source) {
        for (uint32_t i = 0; i < count; i++) memcpy(split[i], sides[source[i]], sizeof split[i]);
        free(sides);
        sides = split;
    }
    if (!r->caps.has_vbo) {
        r->sides = sides;
        return true;
    }
    while (r->gl.GetError() != GL_NO_ERROR) {}
    r->gl.GenBuffers(1, &r->side_vbo);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, r->side_vbo);
    r->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)count * sizeof *sides), sides, GL_STATIC_DRAW);
    r->gl.BindBuffer(GL_ARRAY_BUFFER, 0);
    free(sides);
    const GLenum e = r->gl.GetError();
    if (e == GL_NO_ERROR) return true;
    ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: the width rule per vertex: glBufferData: %s; "
                 "per draw", ht_gl_error_name(e));
    r->gl.DeleteBuffers(1, &r->side_vbo);
    r->side_vbo = 0;
    return false;
}

ht_result ht_renderer_set_mesh(ht_renderer *r, const ht_mesh *mesh) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!mesh) return ht_renderer_reject(r, "ht_renderer_set_mesh", "mesh", "NULL");
    /* A rejected mesh leaves the previous one in place. */
    ht_result checked = ht_renderer_check_mesh(r, "ht_renderer_set_mesh: mesh", mesh);
    if (checked != HT_OK) return checked;
    /* ES 2.0 without GL_OES_element_index_uint indexes 65536 vertices
       (Mesa's vc4 truncates 32-bit indices, docs/materials.md): a larger
       mesh goes up split into runs of its own vertices (index_chunks.h),
       drawn one after another. A tier with per-vertex arrays of its own
       (set_mesh) would need them split too: refused instead. */
    const bool short_indices = ht_renderer_short_indices(r);
    const bool split = short_indices && mesh->vertex_count > HT_CHUNK_VERTICES;
    if (split && r->backend && r->backend->set_mesh) {
        ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: mesh: %u vertices, this device indexes "
                     "65536 (16-bit indices: no GL_OES_element_index_uint) and the %s tier's own vertex arrays "
                     "are not split", mesh->vertex_count, ht_tier_name(r->tier));
        return HT_ERR_UNSUPPORTED;
    }
    ht_renderer_release_mesh(r);
    ht_index_chunks chunks = { 0 };
    uint16_t *indices16 = NULL;
    const ht_vertex *vertex_data = mesh->vertices;
    uint32_t vertex_count = mesh->vertex_count;
    if (split) {
        if (ht_index_chunks_split(mesh, &chunks)) {
            indices16 = chunks.indices;
            vertex_data = chunks.vertices;
            vertex_count = chunks.vertex_count;
            r->chunks = chunks.chunks;
            r->chunk_count = chunks.chunk_count;
        }
    } else if (short_indices) {
        indices16 = ht_renderer_indices16(mesh->indices, mesh->index_count);
    }
    if (short_indices && !indices16) {
        ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: mesh: out of memory for %u indices",
                     mesh->index_count);
        return HT_ERR_OUT_OF_MEMORY;
    }
    size_t vbytes = (size_t)vertex_count * sizeof(ht_vertex);
    size_t ibytes = (size_t)mesh->index_count * (short_indices ? sizeof(uint16_t) : sizeof(uint32_t));
    const void *index_data = short_indices ? (const void *)indices16 : (const void *)mesh->indices;
    r->index_type = short_indices ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    if (r->caps.has_vbo) {
        while (r->gl.GetError() != GL_NO_ERROR) {}
        r->gl.GenBuffers(1, &r->vbo);
        r->gl.GenBuffers(1, &r->ibo);
        r->gl.BindBuffer(GL_ARRAY_BUFFER, r->vbo);
        r->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)vbytes, vertex_data, GL_STATIC_DRAW);
        r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
        r->gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)ibytes, index_data, GL_STATIC_DRAW);
        free(indices16);
        free(chunks.vertices);
        r->gl.BindBuffer(GL_ARRAY_BUFFER, 0);
        r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        GLenum e = r->gl.GetError();
        if (e != GL_NO_ERROR) {
            ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: glBufferData: %s", ht_gl_error_name(e));
            ht_renderer_release_mesh(r);
            free(chunks.source);
            return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
        }
    } else {
        r->vertices = malloc(vbytes ? vbytes : 1);
        r->indices = malloc(ibytes ? ibytes : 1);
        if (!r->vertices || !r->indices) {
            free(indices16);
            free(chunks.vertices);
            free(chunks.source);
            ht_renderer_release_mesh(r);
            ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: mesh: out of memory for %u vertices",
                         mesh->vertex_count);
            return HT_ERR_OUT_OF_MEMORY;
        }
        if (vbytes) memcpy(r->vertices, vertex_data, vbytes);
        if (ibytes) memcpy(r->indices, index_data, ibytes);
        free(indices16);
        free(chunks.vertices);
    }
    r->vertex_count = vertex_count;
    r->index_count = mesh->index_count;
    r->draw_first = 0;
    r->draw_count = mesh->index_count;
    r->draw_vertex_count = 0;
    r->has_mesh = true;
    r->span = make_span(mesh, &r->span_count);
    /* a_side feeds programs; without them (gl11) a tier widens from its own copy */
    if (r->width_vertex)
        r->has_sides = !r->gl.has_shaders || upload_sides(r, mesh, r->chunk_count ? chunks.source : NULL, vertex_count);
    free(chunks.source);
    r->mesh_serial++;
    if (r->backend && r->backend->set_mesh) {
        ht_result res = r->backend->set_mesh(r->backend_state, mesh);
        if (res != HT_OK) {
            ht_log_linef(r->log, r->log_user, "hairtier: ht_renderer_set_mesh: %s tier: %s", ht_tier_name(r->tier),
                         ht_result_string(res));
            ht_renderer_release_mesh(r);
            return res;
        }
    }
    /* the other tiers made so far get theirs at their next ht_renderer_set_tier */
    if (r->backend) r->made[r->backend_index].mesh_serial = r->mesh_serial;
    return HT_OK;
}

ht_result ht_renderer_set_mesh_order(ht_renderer *r, const ht_mesh *mesh) {
    static const char what[] = "ht_renderer_set_mesh_order";
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!mesh) return ht_renderer_reject(r, what, "mesh", "NULL");
    if (!r->has_mesh) return ht_renderer_reject(r, what, "mesh", "none set (ht_renderer_set_mesh first)");
    if (r->chunk_count) return ht_renderer_set_mesh(r, mesh);
    if (mesh->vertex_count != r->vertex_count || mesh->index_count != r->index_count)
        return ht_renderer_reject(r, what, "mesh", "%u vertices and %u indices, the mesh set has %u and %u",
                                  mesh->vertex_count, mesh->index_count, r->vertex_count, r->index_count);
    if (mesh->index_count && !mesh->indices)
        return ht_renderer_reject(r, what, "indices", "NULL with index_count %u", mesh->index_count);
    for (uint32_t i = 0; i < mesh->index_count; i++)
        if (mesh->indices[i] >= mesh->vertex_count) {
            char field[64];
            snprintf(field, sizeof field, "indices[%u]", i);
            return ht_renderer_reject(r, what, field, "%u, only %u vertices", mesh->indices[i], mesh->vertex_count);
        }
    const bool short_indices = r->index_type == GL_UNSIGNED_SHORT;
    uint16_t *indices16 = short_indices ? ht_renderer_indices16(mesh->indices, mesh->index_count) : NULL;
    uint32_t span_count = 0;
    uint32_t *span = make_span(mesh, &span_count);
    if ((short_indices && !indices16) || !span) {
        free(indices16);
        free(span);
        ht_log_linef(r->log, r->log_user, "hairtier: %s: out of memory for %u indices", what, mesh->index_count);
        return HT_ERR_OUT_OF_MEMORY;
    }
    const void *data = short_indices ? (const void *)indices16 : (const void *)mesh->indices;
    const size_t bytes = (size_t)mesh->index_count * (short_indices ? sizeof(uint16_t) : sizeof(uint32_t));
    if (r->caps.has_vbo) {
        while (r->gl.GetError() != GL_NO_ERROR) {}
        r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
        r->gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, data);
        r->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
        const GLenum e = r->gl.GetError();
        if (e != GL_NO_ERROR) {
            free(indices16);
            free(span);
            ht_log_linef(r->log, r->log_user, "hairtier: %s: glBufferSubData: %s", what, ht_gl_error_name(e));
            ht_renderer_release_mesh(r);
            return e == GL_OUT_OF_MEMORY ? HT_ERR_OUT_OF_MEMORY : HT_ERR_GL;
        }
    } else if (bytes) {
        memcpy(r->indices, data, bytes);
    }
    free(indices16);
    free(r->span);
    r->span = span;
    r->span_count = span_count;
    r->draw_first = 0;
    r->draw_count = mesh->index_count;
    r->draw_vertex_count = 0;
    return HT_OK;
}

ht_result ht_renderer_set_draw_range(ht_renderer *r, uint32_t first_index, uint32_t index_count) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (!r->has_mesh) return ht_renderer_reject(r, "ht_renderer_set_draw_range", "mesh", "none set");
    if (first_index % 3 || index_count % 3 || first_index > r->index_count || index_count > r->index_count - first_index) {
        ht_log_linef(r->log, r->log_user,
                     "hairtier: ht_renderer_set_draw_range: [%u, +%u): not whole triangles within the mesh's %u indices",
                     first_index, index_count, r->index_count);
        return HT_ERR_INVALID_ARGUMENT;
    }
    r->draw_first = first_index;
    r->draw_count = index_count;
    r->draw_vertex_count = 0;
    return HT_OK;
}

ht_result ht_renderer_set_draw_range_vertices(ht_renderer *r, uint32_t first_index, uint32_t index_count,
                                              uint32_t first_vertex, uint32_t vertex_count) {
    if (!r) return HT_ERR_INVALID_ARGUMENT;
    if (r->has_mesh && !r->chunk_count &&
        (vertex_count == 0 || first_vertex > r->vertex_count || vertex_count > r->vertex_count - first_vertex)) {
        ht_log_linef(r->log, r->log_user,
                     "hairtier: ht_renderer_set_draw_range_vertices: vertices [%u, +%u): not within the mesh's %u",
                     first_vertex, vertex_count, r->vertex_count);
        return HT_ERR_INVALID_ARGUMENT;
    }
    ht_result res = ht_renderer_set_draw_range(r, first_index, index_count);
    /* a mesh in 16-bit chunks has its vertices reordered: the blocks bound them */
    if (res != HT_OK || r->chunk_count) return res;
    r->draw_vertex_first = first_vertex;
    r->draw_vertex_count = vertex_count;
    return HT_OK;
}

/* A member of vertex first of ht_vertex arrays: an offset into the bound
   VBO when base is NULL (GL takes offsets as pointers), else its address
   in base. */
static const void *array_at(const ht_vertex *base, uint32_t first, size_t offset) {
    offset += (size_t)first * sizeof(ht_vertex);
    return base ? (const void *)((const char *)base + offset) : (const void *)(uintptr_t)offset;
}

/* The width rule per vertex's offsets from vertex first on, at their
   generic location (set only while it is active: otherwise the programs
   read the attribute's current value and u_width_rule is 0). */
static void set_side_array(ht_renderer *r, uint32_t first) {
    if (!ht_renderer_width_rule_active(r)) return;
    const ht_gl *gl = &r->gl;
    const size_t offset = (size_t)first * sizeof *r->sides;
    if (r->side_vbo) ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, r->side_vbo);
    gl->VertexAttribPointer(HT_ATTR_SIDE_LOCATION, 3, GL_FLOAT, GL_FALSE, 0,
                            r->side_vbo ? (const void *)(uintptr_t)offset : (const void *)(r->sides + first));
    gl->EnableVertexAttribArray(HT_ATTR_SIDE_LOCATION);
    if (r->side_vbo) ht_gl_bind_buffer(gl, GL_ARRAY_BUFFER, r->vbo);
}

/* Arrays of ht_vertex: base is NULL with a bound VBO, else the data. The
   hair gets uv as texture coordinate set 0 and, for a backend that asks
   (generic_attributes), tangent and ao as generic attributes
   (shader_interface.h); a backend points any other array itself (tier.h:
   set_arrays). */
/* GL ES: every array is a generic attribute at shader_interface.h's
   locations, which the ES texts and the head's program bind. */
static void set_es_arrays(ht_renderer *r, const ht_vertex *base, uint32_t first, bool hair_attributes) {
    const ht_gl *gl = &r->gl;
    const GLsizei stride = (GLsizei)sizeof(ht_vertex);
    static const struct { GLuint location; GLint size; size_t offset; bool hair; } arrays[] = {
        { HT_ES_ATTR_POSITION_LOCATION, 3, offsetof(ht_vertex, position), false },
        { HT_ES_ATTR_NORMAL_LOCATION, 3, offsetof(ht_vertex, normal), false },
        { HT_ES_ATTR_UV_LOCATION, 2, offsetof(ht_vertex, uv), true },
        { HT_ATTR_TANGENT_LOCATION, 3, offsetof(ht_vertex, tangent), true },
        { HT_ATTR_AO_LOCATION, 1, offsetof(ht_vertex, ao), true },
    };
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++) {
        if (arrays[i].hair && !hair_attributes) continue;
        gl->VertexAttribPointer(arrays[i].location, arrays[i].size, GL_FLOAT, GL_FALSE, stride,
                                array_at(base, first, arrays[i].offset));
        gl->EnableVertexAttribArray(arrays[i].location);
    }
    if (hair_attributes) set_side_array(r, first);
}

void ht_renderer_set_arrays(ht_renderer *r, const ht_vertex *base, bool hair_attributes) {
    ht_renderer_set_arrays_from(r, base, 0, hair_attributes);
}

void ht_renderer_set_arrays_from(ht_renderer *r, const ht_vertex *base, uint32_t first, bool hair_attributes) {
    const ht_gl *gl = &r->gl;
    const GLsizei stride = (GLsizei)sizeof(ht_vertex);
    if (ht_caps_es_programs(&r->caps)) {
        set_es_arrays(r, base, first, hair_attributes);
        return;
    }
    gl->EnableClientState(GL_VERTEX_ARRAY);
    gl->VertexPointer(3, GL_FLOAT, stride, array_at(base, first, offsetof(ht_vertex, position)));
    gl->EnableClientState(GL_NORMAL_ARRAY);
    gl->NormalPointer(GL_FLOAT, stride, array_at(base, first, offsetof(ht_vertex, normal)));
    if (!hair_attributes) return;
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
    gl->EnableClientState(GL_TEXTURE_COORD_ARRAY);
    gl->TexCoordPointer(2, GL_FLOAT, stride, array_at(base, first, offsetof(ht_vertex, uv)));
    if (r->backend && r->backend->generic_attributes) {
        gl->VertexAttribPointer(HT_ATTR_TANGENT_LOCATION, 3, GL_FLOAT, GL_FALSE, stride,
                                array_at(base, first, offsetof(ht_vertex, tangent)));
        gl->EnableVertexAttribArray(HT_ATTR_TANGENT_LOCATION);
        gl->VertexAttribPointer(HT_ATTR_AO_LOCATION, 1, GL_FLOAT, GL_FALSE, stride,
                                array_at(base, first, offsetof(ht_vertex, ao)));
        gl->EnableVertexAttribArray(HT_ATTR_AO_LOCATION);
        set_side_array(r, first);
    }
}

/* Off again before the next draw of the frame (the head's arrays are not
   the hair's), whatever the app's arrays were: those come back with the
   client attributes at the end of the frame. */
void ht_renderer_clear_arrays(ht_renderer *r) {
    const ht_gl *gl = &r->gl;
    if (ht_caps_es_programs(&r->caps)) {
        static const GLuint locations[] = { HT_ES_ATTR_POSITION_LOCATION, HT_ES_ATTR_NORMAL_LOCATION,
                                            HT_ES_ATTR_UV_LOCATION, HT_ATTR_TANGENT_LOCATION, HT_ATTR_AO_LOCATION,
                                            HT_ATTR_SIDE_LOCATION };
        for (size_t i = 0; i < sizeof locations / sizeof locations[0]; i++) gl->DisableVertexAttribArray(locations[i]);
        return;
    }
    if (r->backend && r->backend->generic_attributes) {
        gl->DisableVertexAttribArray(HT_ATTR_SIDE_LOCATION);
        gl->DisableVertexAttribArray(HT_ATTR_AO_LOCATION);
        gl->DisableVertexAttribArray(HT_ATTR_TANGENT_LOCATION);
    }
    if (gl->ClientActiveTexture) gl->ClientActiveTexture(GL_TEXTURE0);
    gl->DisableClientState(GL_TEXTURE_COORD_ARRAY);
    gl->DisableClientState(GL_NORMAL_ARRAY);
    gl->DisableClientState(GL_VERTEX_ARRAY);
}

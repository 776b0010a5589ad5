/* scene_budget.c — how much memory a scene's hair needs, checked when a
   scene is read (ht_limits.h: HT_LIMIT_SCENE_BYTES), so a scene the reader
   accepts is one a small machine renders (defect G: 1e6 hairs x 64 joints
   needed more than 9 GB, then failed in glBufferData naming nothing). */
#include <stdio.h>

#include "errfmt.h"
#include <hairtier/ht_limits.h>
#include <hairtier/scene.h>

/* Every strand file the readers accept fits: two vertices per point, at
   most six indices per point. */
_Static_assert((uint64_t)HT_LIMIT_STRANDS_POINTS * 2 * HT_LIMIT_SCENE_BYTES_PER_VERTEX +
                       (uint64_t)HT_LIMIT_STRANDS_POINTS * 6 * HT_LIMIT_SCENE_BYTES_PER_INDEX <=
                   HT_LIMIT_SCENE_BYTES,
               "a strand file at HT_LIMIT_STRANDS_POINTS must fit HT_LIMIT_SCENE_BYTES");

static void counts(const ht_scene *s, uint64_t *vertices, uint64_t *indices) {
    if (s->geometry == HT_GEOMETRY_STRANDS) {
        *vertices = (uint64_t)HT_LIMIT_STRANDS_POINTS * 2;
        *indices = (uint64_t)HT_LIMIT_STRANDS_POINTS * 6;
    } else if (s->geometry == HT_GEOMETRY_PATCHES) {
        const uint64_t strips = (uint64_t)s->patches.layers * (uint64_t)s->patches.strips;
        *vertices = strips * ((uint64_t)s->patches.segments + 1) * 2;
        *indices = strips * (uint64_t)s->patches.segments * 6;
    } else {
        const uint64_t hairs = (uint64_t)s->furball.hairs, joints = (uint64_t)s->furball.joints;
        *vertices = hairs * joints * 2;
        *indices = hairs * (joints > 0 ? joints - 1 : 0) * 6;
    }
}

uint64_t ht_scene_memory_estimate(const ht_scene *s) {
    uint64_t v, i;
    counts(s, &v, &i);
    return v * HT_LIMIT_SCENE_BYTES_PER_VERTEX + i * HT_LIMIT_SCENE_BYTES_PER_INDEX;
}

ht_result ht_scene_check_budget(const ht_scene *s, const char *file_name, char *err, size_t err_size) {
    uint64_t need = ht_scene_memory_estimate(s);
    if (need <= HT_LIMIT_SCENE_BYTES) return HT_OK;
    const double gb = 1024.0 * 1024.0 * 1024.0;
    const char *file = file_name ? file_name : "<input>";
    if (s->geometry == HT_GEOMETRY_PATCHES)
        return ht_fail(err, err_size, HT_ERR_UNSUPPORTED,
                       "%s: geometry.strips: needs about %.1f GB (%d layers x %d strips x %d segments), more "
                       "than the %.0f GB a scene may use", file, (double)need / gb, s->patches.layers,
                       s->patches.strips, s->patches.segments, (double)HT_LIMIT_SCENE_BYTES / gb);
    /* The most hairs that fit at this many joints. */
    const uint64_t joints = (uint64_t)s->furball.joints;
    const uint64_t per_hair = joints * 2 * HT_LIMIT_SCENE_BYTES_PER_VERTEX + (joints - 1) * 6 * HT_LIMIT_SCENE_BYTES_PER_INDEX;
    return ht_fail(err, err_size, HT_ERR_UNSUPPORTED,
                   "%s: geometry.hairs: needs about %.1f GB (%d hairs x %d joints), more than the %.0f GB a "
                   "scene may use; at most %llu hairs at %d joints", file, (double)need / gb, s->furball.hairs,
                   s->furball.joints, (double)HT_LIMIT_SCENE_BYTES / gb,
                   (unsigned long long)(HT_LIMIT_SCENE_BYTES / per_hair), s->furball.joints);
}

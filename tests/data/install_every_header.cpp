/* install_every_header.cpp — a C++ application of the installed libraries:
   it includes every public header and calls a function declared in each,
   so a header without extern "C" or a symbol the shared libraries do not
   export fails to link. Built by tests/install_test.sh through pkg-config
   and through find_package(hairtier), shared and static. Exits 0 when each
   call answers what it should. */
#include <cmath>
#include <cstdio>
#include <cstring>

#include <hairtier/export.h>
#include <hairtier/hairtier.h>
#include <hairtier/hairgen.h>
#include <hairtier/ht_limits.h>
#include <hairtier/image.h>
#include <hairtier/lod.h>
#include <hairtier/model.h>
#include <hairtier/model_marschner.h>
#include <hairtier/scene.h>
#include <hairtier/strands.h>

static int check(bool ok, const char *what) {
    if (!ok) std::fprintf(stderr, "install_every_header: %s\n", what);
    return ok ? 0 : 1;
}

int main() {
    int failed = 0;
    failed += check(std::strcmp(ht_tier_name(HT_TIER_FULL), "full") == 0, "hairtier.h: ht_tier_name");
    char symbol[HT_HEADER_SYMBOL_MAX + 1];
    ht_header_symbol_default("dark-brown", symbol);
    failed += check(std::strcmp(symbol, "dark_brown_bundle") == 0, "hairgen.h: ht_header_symbol_default");
    ht_image img;
    failed += check(ht_image_alloc(&img, 4, 4, 3) == HT_OK && img.pixels, "image.h: ht_image_alloc");
    ht_image_free(&img);
    ht_scene scene;
    ht_scene_default(&scene);
    failed += check(scene.width > 0 && scene.light_count > 0, "scene.h: ht_scene_default");
    ht_strands strands;
    std::memset(&strands, 0, sizeof strands);
    ht_strands_free(&strands);
    double f = ht_marschner_fresnel(1.55, 1.0, 0.0);
    failed += check(f > 0.03 && f < 0.06, "model_marschner.h: ht_marschner_fresnel at normal incidence");
    ht_shading shading;
    std::memset(&shading, 0, sizeof shading);
    failed += check(std::isfinite(ht_model_dot_terms_max(&shading)), "model.h: ht_model_dot_terms_max");
    failed += check(HT_LIMIT_FILE_JSON > 0, "ht_limits.h");
    failed += check(ht_lod_pick_best(0.3, -1, 4) == 2, "lod.h: ht_lod_pick_best");
    if (!failed) std::puts("install_every_header: every public header included, one call each: ok");
    return failed ? 1 : 0;
}

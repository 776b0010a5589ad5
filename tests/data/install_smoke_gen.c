/* install_smoke_gen.c — an application of libhairgen as installed: built by
   tests/install_test.sh with only `pkg-config --cflags --libs --static
   hairgen`. It generates every tier of a material in memory and exits 0
   only when the full tier's fragment shader and the manifest came out.

   usage: install_smoke_gen MATERIAL.json */
#include <stdio.h>
#include <string.h>

#include <hairtier/hairgen.h>

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: install_smoke_gen MATERIAL.json\n");
        return 2;
    }
    char err[1024];
    ht_material m;
    if (ht_material_load(argv[1], &m, err, sizeof err) != HT_OK) {
        fprintf(stderr, "install_smoke_gen: %s\n", err);
        return 1;
    }
    ht_generated g;
    if (ht_generate(&(ht_generate_desc){ .material = &m }, &g, err, sizeof err) != HT_OK) {
        fprintf(stderr, "install_smoke_gen: %s\n", err);
        return 1;
    }
    const ht_generated_file *frag = ht_generated_find(&g, "full.frag");
    int ok = frag && frag->text && strstr(frag->text, "void main") && g.manifest &&
             strstr(g.manifest, "\"hairtier-bundle/1\"");
    printf("install_smoke_gen: %s: %d files, full.frag %zu bytes\n", m.name, g.file_count,
           frag && frag->text ? strlen(frag->text) : (size_t)0);
    ht_generated_free(&g);
    return ok ? 0 : 1;
}

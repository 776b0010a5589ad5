/* bench_mesh — what building and sorting a hair mesh of about a million
   triangles costs at load time: a fur ball of 33,334 hairs × 16 joints and
   patches of 8 layers × 2048 strips × 32 segments. Prints one line per mesh:
   triangles, build ms and sort ms, each the median of RUNS runs.
   Run: make bench. */
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"
#include <hairtier/hairtier.h>
#include "timing.h"

#define RUNS 5

typedef struct mesh_case {
    const char *name;
    ht_furball_desc furball;
    ht_patches_desc patches;
    int is_patches;
} mesh_case;

static int run(const mesh_case *c) {
    double build[RUNS], sort[RUNS];
    uint32_t triangles = 0;
    for (int i = 0; i < RUNS; i++) {
        ht_mesh mesh;
        double t0 = now_ms();
        ht_result r = c->is_patches ? ht_mesh_build_patches(&c->patches, &mesh, NULL)
                                    : ht_mesh_build_furball(&c->furball, &mesh);
        double t1 = now_ms();
        if (r != HT_OK) {
            fprintf(stderr, "bench_mesh: %s: build failed: %s\n", c->name, ht_result_string(r));
            return 1;
        }
        ht_mesh_sort_inside_out(&mesh);
        double t2 = now_ms();
        build[i] = t1 - t0;
        sort[i] = t2 - t1;
        triangles = mesh.index_count / 3;
        ht_mesh_free(&mesh);
    }
    printf("%-8s %8u triangles  build %8.2f ms  sort %7.2f ms  (median of %d)\n", c->name, triangles,
           median(build, RUNS), median(sort, RUNS), RUNS);
    return 0;
}

static const cli_program program = {
    .name = "bench_mesh",
    .synopsis = "usage: bench_mesh\n",
    .help = "Builds and sorts a fur ball of 33,334 hairs x 16 joints and patches of 8 layers x 2048 strips\n"
            "x 32 segments; prints triangles, build ms and sort ms per mesh, each the median of "
            CLI_STR(RUNS) " runs.\n",
};

int main(int argc, char **argv) {
    int rc = cli_parse(&program, argc, argv, cli_take_nothing, NULL);
    if (rc != CLI_RUN) return rc;
    const mesh_case cases[] = {
        { .name = "furball",
          .furball = { .hairs = 33334, .joints = 16, .gravity = { 0, -0.15f, 0 },
                       .inertia = { 0.05f, 0, 0 }, .seed = 1 } },
        { .name = "patches", .patches = { .layers = 8, .strips = 2048, .segments = 32, .seed = 1 },
          .is_patches = 1 },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        if (run(&cases[i]) != 0) return 1;
    return 0;
}

/* hairgen — the offline generator's command line: one material (and the
   scene it is for) in, a bundle directory with every tier out. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "hairgen.h"
#include "measure.h"

static void usage(FILE *out) {
    fputs("usage: hairgen MATERIAL.json [--scene SCENE.json] [--measure] -o DIR\n"
          "       hairgen MATERIAL.json [--scene SCENE.json] [-o DIR] --emit-header OUT.h\n"
          "               [--header-symbol NAME]\n"
          "\n"
          "Generates every shader tier of one hair material for one scene and writes\n"
          "DIR (manifest.json, GLSL files, the fixed-function combiner program, PNG\n"
          "textures). Every GLSL file is validated with glslang; on any error nothing\n"
          "is written and the exit status is 1 (2 for a usage error). DIR is replaced\n"
          "whole if it is a bundle already; any other existing directory is refused.\n"
          "Without --scene the material is planned for one white directional light.\n"
          "--measure renders the scene (or, without --scene, the built-in one) with\n"
          "every tier on OSMesa before DIR is published, and writes each tier's\n"
          "\"measured\" numbers against full into the manifest (PSNR, SSIM, CIEDE2000\n"
          "over the whole frame; frame-time ratio to full on this driver); if\n"
          "measuring fails, nothing is written and the exit status is 1.\n"
          "--emit-header writes the same bundle as one C header instead of (or beside)\n"
          "DIR: every file's bytes as static const arrays and one entry,\n"
          "`static const ht_bundle_memory NAME` (default: the material's name +\n"
          "_bundle) for ht_renderer_desc.bundle_memory.\n"
          "See docs/bundle.md.\n", out);
}

int main(int argc, char **argv) {
    const char *material = NULL, *scene = NULL, *out_dir = NULL, *header = NULL, *symbol = NULL;
    bool measure = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return 0;
        } else if (strcmp(argv[i], "--measure") == 0) {
            measure = true;
        } else if ((strcmp(argv[i], "--scene") == 0 || strcmp(argv[i], "-o") == 0) && i + 1 < argc) {
            const char **slot = argv[i][1] == 'o' ? &out_dir : &scene;
            if (*slot) {
                fprintf(stderr, "hairgen: %s: given twice (see --help)\n", argv[i]);
                return 2;
            }
            *slot = argv[++i];
        } else if ((strcmp(argv[i], "--emit-header") == 0 || strcmp(argv[i], "--header-symbol") == 0) &&
                   i + 1 < argc) {
            const char **slot = argv[i][2] == 'e' ? &header : &symbol;
            if (*slot) {
                fprintf(stderr, "hairgen: %s: given twice (see --help)\n", argv[i]);
                return 2;
            }
            *slot = argv[++i];
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "hairgen: %s: unknown option or missing value (see --help)\n", argv[i]);
            return 2;
        } else if (!material) {
            material = argv[i];
        } else {
            fprintf(stderr, "hairgen: %s: only one material per run\n", argv[i]);
            return 2;
        }
    }
    if (!material || (out_dir && !out_dir[0]) || (header && !header[0]) || (!out_dir && !header) ||
        (symbol && !header) || (measure && !out_dir)) {
        usage(stderr);
        return 2;
    }
    char err[2048] = "";
    /* A bad symbol is refused before DIR is written. */
    ht_result r = symbol ? ht_header_symbol_check(symbol, err, sizeof err) : HT_OK;
    ht_measure_job job = { .scene_path = scene, .out_dir = out_dir };
    if (r == HT_OK && out_dir)
        r = ht_generate_bundle_then(material, scene, out_dir, stdout, measure ? ht_measure_step : NULL, &job, err,
                                    sizeof err);
    /* The header's generation repeats the directory's (same input, same
       bytes): the two outputs stay independent steps. */
    if (r == HT_OK && header) r = ht_generate_header(material, scene, header, symbol, stdout, err, sizeof err);
    if (r != HT_OK) {
        fprintf(stderr, "hairgen: %s\n", err[0] ? err : ht_result_string(r));
        return 1;
    }
    if (measure) ht_measure_print(stdout, &job.result);
    return 0;
}

/* hairgen — the offline generator's command line: one material (and the
   scene it is for) in, a bundle directory with every tier out; or many
   materials in one run, a bundle each, on every core (ht_generate_batch). */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cards_bundle.h"
#include "cli.h"
#include "errfmt.h"
#include <hairtier/hairgen.h>
#include <hairtier/lod.h>
#include "hairgen_internal.h"
#include "huge_heap.h"
#include "manifest.h"
#include "measure.h"
#include "trace.h"

/* The address space hairgen's heap reserves on huge pages (beyond it the
   heap grows in small pages), and how much of it one material backs at
   once: one material touches about 6 MiB (dark-brown, furball), a cold
   batch of the 100 bench variants on two threads 26 MiB. */
#define HUGE_HEAP_RESERVE_MIB 256
#define HUGE_HEAP_POPULATE_MIB 8

static const char synopsis[] =
    "usage: hairgen MATERIAL.json [--scene SCENE.json [--no-lods]] -o DIR [-MD | -MF FILE] [-q]\n"
    "       hairgen MATERIAL.json [--scene SCENE.json] [--measure | --measure-lods] -o DIR\n"
    "       hairgen MATERIAL.json [--scene SCENE.json] [-o DIR] --emit-header OUT.h\n"
    "               [--header-symbol NAME]\n"
    "       hairgen -o OUTDIR MATERIAL.json... [--scene SCENE.json] [-j N] [--force]\n"
    "               [-MD | -MF FILE] [-q]\n"
    "       hairgen --cards BUNDLE --scene SCENE.json [--strands-per-card N] [--measure-lods] -o DIR\n";

static const char help[] =
    "\n"
    "Generates every shader tier of a hair material for one scene and writes\n"
    "a bundle directory (manifest.json, GLSL files, the fixed-function combiner\n"
    "program, PNG textures). Every GLSL file is validated with glslang; on any\n"
    "error nothing is written and the exit status is 1 (2 for a usage error).\n"
    "A bundle directory is replaced whole if it is a bundle already; any other\n"
    "existing directory is refused. Without --scene the material is planned for\n"
    "one white directional light. See docs/bundle.md.\n"
    "\n"
    "One material: the bundle is DIR, always regenerated, and its tier table\n"
    "printed. Two or more materials, or --batch: each bundle is OUTDIR/NAME\n"
    "(NAME: the material's file name without .json), materials run on N threads\n"
    "(default: every core), each distinct shader text is validated once, and a\n"
    "material whose inputs (material, scene and texture bytes, generator\n"
    "version) hash to its bundle's input_hash, and whose bundle files all have\n"
    "the sizes and checksums its manifest lists, is skipped (--force regenerates).\n"
    "A material that fails leaves its bundle (and depfile) as it was; the others\n"
    "still run. A depfile lists the inputs and hairgen itself; a file name make\n"
    "and ninja cannot both read is refused. See docs/robustness.md.\n"
    "\n"
    "  --scene FILE          the scene every material is planned for; its strand levels are\n"
    "                        stored in each bundle's lods.bin (docs/lod.md)\n"
    "  --no-lods             no lods.bin: the runtime builds the levels from the scene\n"
    "  -o DIR                the bundle (one material) or the folder of bundles (a batch)\n"
    "  --batch               bundles in DIR/NAME even for one material (for globs)\n"
    "  -j N                  threads (default: every online core)\n"
    "  --force               regenerate bundles that are up to date\n"
    "  -MD                   write a make/ninja depfile beside each bundle, BUNDLE.d\n"
    "  -MF FILE              write the depfile (every bundle's rule) to FILE\n"
    "  -q                    quiet: no tier table, no progress; errors only\n"
    "  --measure             render every tier of the new bundle on the scene (OSMesa, else\n"
    "                        EGL), compare each with the reference tier and write the\n"
    "                        numbers into its manifest (HAIRGEN_OSMESA, HAIRGEN_EGL name\n"
    "                        other libraries; HAIRTIER_CONTEXT=osmesa|egl forces one)\n"
    "  --measure-lods        --measure, then every tier at every geometry LOD of the scene (the\n"
    "                        bundle's stored ones: lods.bin, a --cards bundle's cards too)\n"
    "                        at 1, 1/2 and 1/4 of its size against (LOD 0, first tier):\n"
    "                        cost, error, the pop between levels, into the manifest's\n"
    "                        \"lods\" (docs/lod.md)\n"
    "  --lod-samples N       --measure-lods with every LOD frame drawn with N samples (2..32),\n"
    "                        as hairview --samples N draws\n"
    "  --lod-reference R     --measure-lods against: samples (level 0 drawn as the cells are,\n"
    "                        the default) or supersample (level 0 at 4x4 the pixels, box-\n"
    "                        filtered: the truth; every cell drawn with the width rule)\n"
    "  --lod-soften F[,F..]  --measure-lods with the soft cells F times wider at 1/F the opacity,\n"
    "                        up to 3 factors, each its own cells (above 1, at most 16; default\n"
    "                        3,6,8; hairview --soft=F draws one)\n"
    "  --cards BUNDLE        write DIR: BUNDLE with every geometry level of the scene stored in\n"
    "                        DIR/lods.bin, the strand levels and cards (clumps of N strands,\n"
    "                        default 32, as textured ribbons), its textures one atlas of the\n"
    "                        material's and the cards' (hairview --cards, --lod N; docs/lod.md);\n"
    "                        with --measure-lods, every stored level, cards too, measured\n"
    "  --emit-header OUT.h   write the bundle as one C header (beside DIR, or instead of it)\n"
    "  --header-symbol NAME  the header's C name (default: from the material's name)\n"
    "  --help, --version     this text; the version and the bundle generator version\n";

typedef struct options {
    const char *scene, *out_dir, *depfile, *jobs, *header, *symbol, *cards, *strands_per_card;
    ht_measure_lods_desc lod;
    int batch, force, quiet, depfile_per_bundle, measure, measure_lods, no_lods;
    const char **materials;
    int material_count;
} options;

enum { KEY_SCENE = CLI_LONG_ONLY, KEY_EMIT_HEADER, KEY_HEADER_SYMBOL, KEY_MEASURE, KEY_MEASURE_LODS, KEY_BATCH, KEY_FORCE, KEY_MD,
       KEY_MF, KEY_LOD_SAMPLES, KEY_LOD_REFERENCE, KEY_LOD_SOFTEN, KEY_CARDS, KEY_STRANDS_PER_CARD, KEY_NO_LODS };
static const struct option long_options[] = {
    { "scene", required_argument, NULL, KEY_SCENE },
    { "emit-header", required_argument, NULL, KEY_EMIT_HEADER },
    { "header-symbol", required_argument, NULL, KEY_HEADER_SYMBOL },
    { "measure", no_argument, NULL, KEY_MEASURE },
    { "measure-lods", no_argument, NULL, KEY_MEASURE_LODS },
    { "lod-samples", required_argument, NULL, KEY_LOD_SAMPLES },
    { "lod-reference", required_argument, NULL, KEY_LOD_REFERENCE },
    { "lod-soften", required_argument, NULL, KEY_LOD_SOFTEN },
    { "batch", no_argument, NULL, KEY_BATCH },
    { "force", no_argument, NULL, KEY_FORCE },
    { "MD", no_argument, NULL, KEY_MD },
    { "MF", required_argument, NULL, KEY_MF },
    { "cards", required_argument, NULL, KEY_CARDS },
    { "strands-per-card", required_argument, NULL, KEY_STRANDS_PER_CARD },
    { "no-lods", no_argument, NULL, KEY_NO_LODS },
    { 0 },
};

static const cli_program program = {
    .name = "hairgen",
    .synopsis = synopsis,
    .help = help,
    .version_note = "bundles: generator version " HT_MANIFEST_GENERATOR,
    .short_options = "o:j:q",
    .long_options = long_options,
    .long_only = true,   /* -MD, -MF as compilers spell them */
};

/* A value option given twice is refused: which one was meant? */
static const char *once(const char **slot, const char *value, const char *name) {
    static char message[64];
    if (*slot) {
        snprintf(message, sizeof message, "%s: given twice", name);
        return message;
    }
    *slot = value;
    return NULL;
}

static const char *take(void *user, int key, const char *value) {
    options *o = user;
    switch (key) {
    case CLI_OPERAND: o->materials[o->material_count++] = value; return NULL;
    case KEY_SCENE: return once(&o->scene, value, "--scene");
    case 'o': return once(&o->out_dir, value, "-o");
    case KEY_MF: return once(&o->depfile, value, "-MF");
    case 'j': return once(&o->jobs, value, "-j");
    case KEY_EMIT_HEADER: return once(&o->header, value, "--emit-header");
    case KEY_HEADER_SYMBOL: return once(&o->symbol, value, "--header-symbol");
    case KEY_MEASURE: o->measure = 1; return NULL;
    case KEY_MEASURE_LODS: o->measure = o->measure_lods = 1; return NULL;
    case KEY_LOD_SAMPLES: {
        char *end;
        const long n = strtol(value, &end, 10);
        if (end == value || *end || n < 2 || n > HT_MANIFEST_MAX_LOD_SAMPLES)
            return "--lod-samples: expected a sample count in 2..32";
        o->measure = o->measure_lods = 1;
        o->lod.samples = (int)n;
        return NULL;
    }
    case KEY_LOD_REFERENCE:
        if (strcmp(value, "samples") && strcmp(value, "supersample"))
            return "--lod-reference: expected samples or supersample";
        o->measure = o->measure_lods = 1;
        o->lod.reference = strcmp(value, "supersample") ? HT_LOD_REFERENCE_SAMPLES : HT_LOD_REFERENCE_SUPERSAMPLE;
        return NULL;
    case KEY_LOD_SOFTEN: {
        _Static_assert(HT_LOD_MAX_SOFTENS == 3, "--lod-soften's message and help");
        const char *p = value;
        memset(o->lod.soften, 0, sizeof o->lod.soften);
        static const char *const why =
            "--lod-soften: expected up to 3 factors, comma-separated, each above 1, at most 16, none twice";
        for (int k = 0;; k++) {
            char *end;
            const double f = strtod(p, &end);
            /* 0 would end the list early: refused here, the rest by the check below */
            if (k == HT_LOD_MAX_SOFTENS || end == p || (*end && *end != ',') || !(f > 1.0)) return why;
            o->lod.soften[k] = (float)f;
            if (!*end) break;
            p = end + 1;
        }
        if (!ht_measure_lods_softens_valid(&o->lod)) return why;
        o->measure = o->measure_lods = 1;
        return NULL;
    }
    case KEY_BATCH: o->batch = 1; return NULL;
    case KEY_FORCE: o->force = 1; return NULL;
    case 'q': o->quiet = 1; return NULL;
    case KEY_MD: o->depfile_per_bundle = 1; return NULL;
    case KEY_NO_LODS: o->no_lods = 1; return NULL;
    case KEY_CARDS: return once(&o->cards, value, "--cards");
    case KEY_STRANDS_PER_CARD: return once(&o->strands_per_card, value, "--strands-per-card");
    default: return cli_unexpected(value);
    }
}

static int parse_jobs(const char *text, int *jobs) {
    *jobs = 0;
    if (!text) return 0;
    char *end;
    long n = strtol(text, &end, 10);
    if (end == text || *end || n < 1 || n > 256) {
        char why[96];
        snprintf(why, sizeof why, "-j: %.40s: expected a thread count in 1..256", text);
        return cli_usage_error(&program, why);
    }
    *jobs = (int)n;
    return 0;
}

/* The one-material outputs beside the bundle: --measure (a step on the
   unpublished bundle) and --emit-header (the bundle as one C header). With
   -o and --emit-header both come from one generation: the header holds the
   directory's files, the measured manifest included. */
static int run_measure_or_header(const options *o, const char *material) {
    char err[2048] = "";
    /* A bad symbol is refused before DIR is written. */
    ht_result r = o->symbol ? ht_header_symbol_check(o->symbol, err, sizeof err) : HT_OK;
    ht_measure_job job = { .scene_path = o->scene, .out_dir = o->out_dir, .lods = o->measure_lods,
                           .lod = o->lod };
    FILE *summary = o->quiet ? NULL : stdout;
    if (r == HT_OK && o->out_dir) {
        ht_bundle_report report;
        r = ht_bundle_make(&(ht_bundle_request){ .material_path = material, .scene_path = o->scene,
                                                 .out_dir = o->out_dir, .summary = summary,
                                                 .store_lods = !o->no_lods,
                                                 .step = o->measure ? ht_measure_step : NULL, .step_user = &job,
                                                 .header_path = o->header, .header_symbol = o->symbol },
                           &report, err, sizeof err);
    } else if (r == HT_OK && o->header) {
        r = ht_generate_header(material, o->scene, o->header, o->symbol, summary, err, sizeof err);
    }
    if (r != HT_OK) {
        fprintf(stderr, "hairgen: %s\n", err[0] ? err : ht_result_string(r));
        return 1;
    }
    if (o->measure && !o->quiet) ht_measure_print(stdout, &job.result);
    if (o->measure_lods && !o->quiet) ht_measure_lods_print(stdout, &job.lods_result);
    return 0;
}

/* --cards: a bundle's cards atlas (cards_bundle.h). 1024 square: 245
   cards of the fur ball get cells of 33 x 128 texels. */
#define HT_CARDS_ATLAS_SIZE 1024
static int run_cards(const options *o) {
    long n = HT_CARDS_DEFAULT_STRANDS;
    if (o->strands_per_card) {
        char *end;
        n = strtol(o->strands_per_card, &end, 10);
        if (end == o->strands_per_card || *end || n < 1 || n > 65536)
            return cli_usage_error(&program, "--strands-per-card: expected 1..65536");
    }
    if (!o->scene || !o->out_dir || o->material_count || (o->measure && !o->measure_lods) || o->header || o->batch)
        return cli_usage_error(&program, "--cards: needs --scene and -o, and no material, --measure or --emit-header");
    char err[2048] = "";
    ht_result r = ht_cards_bundle_write(o->cards, o->scene, (uint32_t)n, HT_CARDS_ATLAS_SIZE, o->out_dir,
                                        o->quiet ? NULL : stdout, err, sizeof err);
    /* --measure-lods: the stored levels, cards included, into DIR's manifest. */
    ht_measure_lods *lods = r == HT_OK && o->measure_lods ? malloc(sizeof *lods) : NULL;
    if (r == HT_OK && o->measure_lods) {
        ht_scene scene;
        r = lods ? ht_scene_load(o->scene, &scene, err, sizeof err) : HT_ERR_OUT_OF_MEMORY;
        if (r == HT_OK) r = ht_measure_lods_run(o->out_dir, &scene, o->scene, &o->lod, lods, err, sizeof err);
        if (r == HT_OK) r = ht_measure_lods_write(o->out_dir, lods, err, sizeof err);
        if (r == HT_OK && !o->quiet) ht_measure_lods_print(stdout, lods);
    }
    free(lods);
    if (r != HT_OK) {
        fprintf(stderr, "hairgen: %s\n", err[0] ? err : ht_result_string(r));
        return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    ht_gen_trace("main");
    options o = { 0 };
    const char **materials = calloc((size_t)argc, sizeof *materials);
    if (!materials) {
        fputs("hairgen: out of memory\n", stderr);
        return 1;
    }
    o.materials = materials;
    int status = cli_parse(&program, argc, argv, take, &o);
    if (status != CLI_RUN) {
        free(materials);
        return status;
    }
    if (status == CLI_RUN && (o.cards || o.strands_per_card)) {
        status = o.cards ? run_cards(&o) : cli_usage_error(&program, "--strands-per-card: only with --cards");
        free(materials);
        return status;
    }
    const int material_count = o.material_count;
    int jobs = 0;
    status = parse_jobs(o.jobs, &jobs);
    /* Past the usage checks, before any bundle: the heap hairgen builds in.
       One material is always generated (never skipped): its heap is backed
       now. A batch may find every bundle up to date: it is not. (Building
       glslang's tables on a third thread from here was tried: on 2 cores it
       took a core from the textures and gained nothing.) */
    const bool always_generates = material_count == 1 && !o.batch;
    if (status == 0) ht_huge_heap(HUGE_HEAP_RESERVE_MIB, always_generates ? HUGE_HEAP_POPULATE_MIB : 0);
    ht_gen_trace("heap");
    if (status == 0 && (o.measure || o.header || o.symbol)) {
        bool usable = material_count == 1 && !o.batch && !o.depfile && !o.depfile_per_bundle &&
                      (o.out_dir || o.header) && (!o.out_dir || o.out_dir[0]) && (!o.header || o.header[0]) &&
                      (!o.symbol || o.header) && (!o.measure || o.out_dir) && !o.jobs && !o.force;
        status = usable ? run_measure_or_header(&o, materials[0])
                        : cli_usage_error(&program, "--measure, --emit-header: one material, no --batch, -j, "
                                                    "--force, -MD or -MF; --measure needs -o, --header-symbol "
                                                    "--emit-header");
        free(materials);
        return status;
    }
    if (status == 0 && material_count == 0) status = cli_usage_error(&program, "no material given");
    if (status == 0 && (!o.out_dir || !o.out_dir[0])) status = cli_usage_error(&program, "-o: required");
    if (status == 0 && o.depfile && o.depfile_per_bundle)
        status = cli_usage_error(&program, "-MD and -MF: give one");
    if (status != 0) {
        free(materials);
        return status;
    }

    /* One material without --batch is the original form: the bundle is
       DIR itself, always regenerated, the tier table printed. */
    const bool single = material_count == 1 && !o.batch;
    char depfile[4200];
    if (single && o.depfile_per_bundle) {
        size_t len = strlen(o.out_dir);
        while (len > 1 && o.out_dir[len - 1] == '/') len--;
        snprintf(depfile, sizeof depfile, "%.*s.d", (int)len, o.out_dir);
        o.depfile = depfile;
    }
    ht_batch_desc desc = {
        .materials = materials,
        .material_count = material_count,
        .scene = o.scene,
        .out_dir = o.out_dir,
        .in_place = single,
        .jobs = jobs,
        .force = single || o.force,
        .depfile = o.depfile,
        .depfile_per_bundle = o.depfile_per_bundle && !single,
        .progress = single || o.quiet ? NULL : stdout,
        .summary = single && !o.quiet ? stdout : NULL,
        .errors = stderr,
        .store_lods = !o.no_lods,
    };
    char err[2048] = "";
    ht_batch_result result;
    ht_result r = ht_generate_batch(&desc, &result, err, sizeof err);
    /* Each failed material has printed its own line; a batch says how many. */
    if (r != HT_OK && (result.failed == 0 || !single))
        fprintf(stderr, "hairgen: %s\n", err[0] ? err : ht_result_string(r));
    else if (r == HT_OK && !single && !o.quiet)
        ht_print_line(stdout, "hairgen: %d generated, %d up to date, in %s", result.generated, result.skipped, o.out_dir);
    free(materials);
    ht_gen_trace("exit");
    return r == HT_OK ? 0 : 1;
}

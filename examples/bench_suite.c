/* bench_suite — `make bench`: every benchmark in one run, its results in
   files a person opens.

   build/bench_suite [-o DIR] [--quick]

   Runs, each as a child process so a driver is chosen per run
   (GALLIUM_DRIVER, read once per process by Mesa):
   1. build/bench_hairgen (the generator's figures) and build/bench_mesh;
   2. build/bench_frame for every scene × driver (the matrix): every tier's
      median frame ms with the camera still and (llvmpipe) with the eye
      orbiting a little every frame, its ratios to the geometry floor and
      to full taken in that same run, and its error against full's image;
   3. build/bench_frame on the fur ball at 1k, 5k, 20k and 40k hairs on
      llvmpipe (the scaling series; the matrix's 10k run is its fifth point);
   4. build/bench_frame --api gles2 and gles3 (series "gles2", "gles3"):
      the GLSL tiers on a GL ES context beside desktop full, every scene on
      llvmpipe, the patches on softpipe (its fur ball would add ~4 min a
      run), camera still; ES 2.0 is Mesa's ES lowered by
      MESA_GLES_VERSION_OVERRIDE=2.0, so the ESSL 1.00 texts run.
   5. build/bench_frame --lods --samples 4 on the 8 000-hair fur ball at
      half and a quarter of the size on llvmpipe: (LOD, tier) pairs beside
      full detail (series "lods", in results.csv; docs/lod.md); and (not
      with --quick) on the 100 000-strand groom at a quarter size with
      --width-rule --truth, every PSNR against the 16x truth, full detail
      with the width rule beside (series "lods-dense"), and at half size
      with levels 1 and 2 soft by 8 (series "dense-soft8", the pairs
      that reach 30 dB there).
   Their own tables print as they run; after each step a progress line with
   the time taken and an ETA (from the steps so far against a predicted
   weight per step). Then writes, atomically, DIR/results.csv (every row),
   DIR/results.md (the tables), DIR/results.svg (error against cost, a panel
   per scene × driver) and DIR/scaling.svg (ms against hairs, a line per
   tier); DIR defaults to bench/. Nothing is written if a step fails (exit 1).
   --quick: tiny sizes and frame counts, to try the pipeline (the preamble
   of results.md says so). */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "file_atomic.h"
#include "bench/support_figures.h"
#include "bench/support_progress.h"
#include "bench/support_results.h"
#include "bench/support_results_md.h"
#include "bench/support_results_svg.h"
#include "tempdir.h"
#include "timing.h"

/* The matrix: every scene here runs on every driver below (one line adds a scene). */
static const char *const scenes[] = { "scenes/furball.json", "scenes/patches.json" };

/* Both drivers draw the same fur ball (10k hairs, 512²), the size the
   low-end tiers' targets name; softpipe interprets every fragment, so it
   takes fewer frames (a frame of full there is about 21 s). frame_s
   predicts, for the ETA only, the seconds of one contender's frame of the
   fur ball at 10k hairs, 512²: fitted, like the other steps' weights, to
   the `make bench` run of 2026-12-02 04:50 UTC on the 2-core development
   machine (docs/DESIGN.md "Benchmark"). */
typedef struct driver {
    const char *name;
    int size, frames, furball_hairs;
    double frame_s;
} driver;
static const driver drivers[] = { { "llvmpipe", 512, 9, 10000, 0.35 }, { "softpipe", 512, 3, 10000, 7.2 } };

/* The scaling series: the fur ball on the first driver; its 10k point is the matrix run's. */
static const int scaling_hairs[] = { 1000, 5000, 20000, 40000 };
enum { SCALING_FRAMES = 5 };

#define MAX_STEPS 32
#define CONTENDERS 8   /* the floor, five tiers and the device variants of fixed4 and fixed */
#define ES_CONTENDERS 4 /* the floor, desktop full, full and vertex on GL ES */
#define WARM_UP 1

typedef enum step_kind { FIGURES, PRINT_ONLY, FRAME } step_kind;

typedef struct step {
    step_kind kind;
    const char *program;     /* in the suite's own directory */
    const char *driver;      /* GALLIUM_DRIVER for the child; NULL: none needed */
    const char *scene;
    int hairs;               /* 0: the scene's (not a fur ball) */
    int size, frames;
    bool orbit;
    bool lods;               /* bench_frame --lods --samples 4: (LOD, tier) pairs */
    bool truth;              /* with lods: --width-rule --truth */
    int soft;                /* with lods: 0, else --soft=N */
    bool generated;          /* scene: a file make wrote in the build directory (the suite's own) */
    const char *series;
    const char *api;         /* bench_frame --api; NULL: desktop GL */
    double weight;           /* predicted seconds; only their proportions matter */
} step;

/* A frame step's predicted seconds: frames × contenders × a frame's cost,
   which grows with pixels and, on the fur ball, with hairs (the same run's
   fit: a 1k-hair frame costs 0.35 of a 10k one); the patches scene costs
   0.13 of the 10k fur ball. */
static double frame_weight(const driver *d, bool furball, int hairs, int size, int frames, bool orbit,
                           int contenders) {
    double pixels = (double)size * size / (512.0 * 512.0);
    double per_frame = d->frame_s * pixels * (furball ? 0.27 + 0.73 * hairs / 10000.0 : 0.13);
    return contenders * (frames + WARM_UP) * (orbit ? 2 : 1) * per_frame;
}

static int plan(step *s, bool quick) {
    int n = 0;
    s[n++] = (step){ .kind = FIGURES, .program = "bench_hairgen", .series = "generator", .weight = 35 };
    s[n++] = (step){ .kind = PRINT_ONLY, .program = "bench_mesh", .weight = 3 };
    for (size_t d = 0; d < sizeof drivers / sizeof drivers[0]; d++)
        for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
            const driver *dr = &drivers[d];
            bool furball = strstr(scenes[k], "furball") != NULL;
            int size = quick ? 96 : dr->size, frames = quick ? 2 : dr->frames;
            int hairs = furball ? (quick ? dr->furball_hairs / 10 : dr->furball_hairs) : 0;
            /* Orbiting frames (timed, beside the still ones) on the first driver only: the CPU's
               per-vertex work is the driver's business not at all, and softpipe's frames are long. */
            bool orbit = d == 0;
            s[n++] = (step){ .kind = FRAME, .program = "bench_frame", .driver = dr->name, .scene = scenes[k],
                             .hairs = hairs, .size = size, .frames = frames, .orbit = orbit, .series = "matrix",
                             .weight = frame_weight(dr, furball, hairs, size, frames, orbit, CONTENDERS) };
        }
    for (size_t i = 0; i < sizeof scaling_hairs / sizeof scaling_hairs[0]; i++) {
        const driver *dr = &drivers[0];
        int size = quick ? 96 : dr->size, frames = quick ? 2 : SCALING_FRAMES;
        int hairs = quick ? scaling_hairs[i] / 10 : scaling_hairs[i];
        s[n++] = (step){ .kind = FRAME, .program = "bench_frame", .driver = dr->name, .scene = "scenes/furball.json",
                         .hairs = hairs, .size = size, .frames = frames, .orbit = false, .series = "scaling",
                         .weight = frame_weight(dr, true, hairs, size, frames, false, CONTENDERS) };
    }
    static const char *const apis[] = { "gles2", "gles3" };
    for (size_t a = 0; a < sizeof apis / sizeof apis[0]; a++)
        for (size_t d = 0; d < sizeof drivers / sizeof drivers[0]; d++)
            for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
                const driver *dr = &drivers[d];
                bool furball = strstr(scenes[k], "furball") != NULL;
                if (d > 0 && furball) continue;
                int size = quick ? 96 : dr->size, frames = quick ? 2 : dr->frames;
                int hairs = furball ? (quick ? dr->furball_hairs / 10 : dr->furball_hairs) : 0;
                s[n++] = (step){ .kind = FRAME, .program = "bench_frame", .driver = dr->name, .scene = scenes[k],
                                 .hairs = hairs, .size = size, .frames = frames, .orbit = false,
                                 .series = apis[a], .api = apis[a],
                                 .weight = frame_weight(dr, furball, hairs, size, frames, false, ES_CONTENDERS) };
            }
    /* (LOD, tier) pairs beside full detail at half and a quarter size, 4
       samples (docs/lod.md): rows of series "lods" in results.csv. */
    for (int half = 1; half <= 2; half++) {
        const driver *dr = &drivers[0];
        int size = (quick ? 96 : dr->size) >> half, frames = quick ? 2 : SCALING_FRAMES;
        if (size < 16) size = 16;
        s[n++] = (step){ .kind = FRAME, .program = "bench_frame", .driver = dr->name, .scene = "scenes/furball.json",
                         .hairs = quick ? 800 : 8000, .size = size, .frames = frames, .orbit = false, .lods = true,
                         .series = "lods",
                         .weight = frame_weight(dr, true, quick ? 800 : 8000, size, frames, false, CONTENDERS) };
    }
    /* The dense groom against the truth at a quarter size (build/gen/dense.json,
       which make writes): about 4 s a contender's frame on llvmpipe. */
    if (!quick)
        s[n++] = (step){ .kind = FRAME, .program = "bench_frame", .driver = drivers[0].name,
                         .scene = "gen/dense.json", .generated = true, .size = drivers[0].size >> 2, .frames = 3, .orbit = false,
                         .lods = true, .truth = true, .series = "lods-dense", .weight = 9 * 4 * 4.5 };
    if (!quick)
        s[n++] = (step){ .kind = FRAME, .program = "bench_frame", .driver = drivers[0].name,
                         .scene = "gen/dense.json", .generated = true, .size = drivers[0].size >> 1, .frames = 3, .orbit = false,
                         .lods = true, .truth = true, .soft = 8, .series = "dense-soft8", .weight = 9 * 4 * 5.5 };
    return n;
}

/* ---- running a step ---- */

#define MAX_ARGS 20

typedef struct argv_buf {
    char text[MAX_ARGS][1024];
    char *argv[MAX_ARGS + 1];
    int argc;
} argv_buf;

static void arg(argv_buf *a, const char *fmt, const char *value) {
    if (a->argc == MAX_ARGS) abort(); /* the plan above outgrew MAX_ARGS: a programming error */
    snprintf(a->text[a->argc], sizeof a->text[0], fmt, value);
    a->argv[a->argc] = a->text[a->argc];
    a->argv[++a->argc] = NULL;
}

static void arg_int(argv_buf *a, int value) {
    char v[32];
    snprintf(v, sizeof v, "%d", value);
    arg(a, "%s", v);
}

static void command_line(const step *s, const char *bindir, const char *csv, argv_buf *a) {
    a->argc = 0;
    char program[600];
    snprintf(program, sizeof program, "%s/%s", bindir, s->program);
    arg(a, "%s", program);
    if (s->kind != FRAME) return;
    char scene[900];
    snprintf(scene, sizeof scene, "%s%s%s", s->generated ? bindir : "", s->generated ? "/" : "", s->scene);
    arg(a, "%s", "--scene"), arg(a, "%s", scene);
    if (s->hairs) arg(a, "%s", "--hairs"), arg_int(a, s->hairs);
    arg(a, "%s", "--size"), arg_int(a, s->size);
    arg(a, "%s", "--frames"), arg_int(a, s->frames);
    if (!s->orbit) arg(a, "%s", "--no-orbit");
    if (s->lods) arg(a, "%s", "--lods"), arg(a, "%s", "--samples"), arg(a, "%s", "4");
    if (s->truth) arg(a, "%s", "--width-rule"), arg(a, "%s", "--truth");
    char soft[32];
    snprintf(soft, sizeof soft, "--soft=%d", s->soft);
    if (s->soft) arg(a, "%s", soft);
    arg(a, "%s", "--series"), arg(a, "%s", s->series);
    if (s->api) arg(a, "%s", "--api"), arg(a, "%s", s->api);
    arg(a, "%s", "--csv"), arg(a, "%s", csv);
}

/* Runs argv with GALLIUM_DRIVER=driver (when given), and for --api gles2
   Mesa's GL ES lowered to 2.0; with capture, its stdout comes through a
   pipe, each line echoed and handed to on_line. 0 when it exits 0. */
static int run_child(char *const argv[], const char *driver, const char *api, bool capture, bench_rows *rows,
                     const char *series) {
    int fds[2] = { -1, -1 };
    if (capture && pipe(fds) != 0) return -1;
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        if (driver) setenv("GALLIUM_DRIVER", driver, 1);
        if (api && strcmp(api, "gles2") == 0) setenv("MESA_GLES_VERSION_OVERRIDE", "2.0", 1);
        if (capture) {
            dup2(fds[1], STDOUT_FILENO);
            close(fds[0]);
            close(fds[1]);
        }
        execv(argv[0], argv);
        fprintf(stderr, "bench_suite: cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    int failed = 0;
    if (capture) {
        close(fds[1]);
        FILE *in = fdopen(fds[0], "r");
        char line[1024];
        while (in && fgets(line, sizeof line, in)) {
            fputs(line, stdout);
            line[strcspn(line, "\n")] = '\0';
            bench_row row;
            if (bench_parse_figure(line, series, &row)) {
                bench_row *r = bench_rows_add(rows);
                if (r) *r = row;
                else failed = 1;
            }
        }
        if (in) fclose(in);
        else close(fds[0]);
    }
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) return -1;
    return failed || !WIFEXITED(status) || WEXITSTATUS(status) != 0 ? -1 : 0;
}

static void print_command(const step *s, char *const argv[]) {
    if (s->driver) printf("GALLIUM_DRIVER=%s ", s->driver);
    for (int i = 0; argv[i]; i++) printf("%s%s", i ? " " : "", argv[i]);
}

/* ---- the report ---- */

typedef struct machine {
    const char *command;     /* how the suite was started */
    char cpu[128];
    long cores;
    double load_start, load_end;
    double minutes;
    char date[32];
    bool quick;
} machine;

static void cpu_model(char *out, size_t size) {
    snprintf(out, size, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[256];
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) != 0 || !strchr(line, ':')) continue;
        const char *v = strchr(line, ':') + 1;
        while (*v == ' ') v++;
        snprintf(out, size, "%.*s", (int)strcspn(v, "\n"), v);
        break;
    }
    if (f) fclose(f);
}

static double load_average(void) {
    double load[1];
    return getloadavg(load, 1) == 1 ? load[0] : -1;
}

static void preamble(const machine *m, char *out, size_t size) {
    bool busy = m->load_start > m->cores || m->load_end > m->cores;
    snprintf(out, size,
             "Made by `make bench` (`%s`) on %s: %s, %ld cores, "
             "%.1f minutes in all. Load average %.1f at the start, %.1f at the end%s. "
             "Frame times are wall-clock medians; each ratio comes from one run whose tiers took their frames "
             "round-robin, so a change in load falls on every tier alike, but the absolute milliseconds "
             "move with the machine's load%s.%s",
             m->command, m->date, m->cpu, m->cores, m->minutes, m->load_start, m->load_end,
             busy ? " (above the core count: other processes ran during the measurements)" : "",
             busy ? ", and here they were measured on a busy machine" : "",
             m->quick ? " A --quick run: tiny sizes to try the pipeline, not numbers to quote." : "");
}

typedef struct report_ctx {
    const bench_rows *rows;
    const char *preamble;
} report_ctx;

/* ht_file_writer_fn's: each writer fails only as its stream does, with
   no reason of its own. */
static bool write_csv(FILE *f, void *c, char *why, size_t why_size) {
    (void)why, (void)why_size;
    return bench_rows_write_csv(f, ((report_ctx *)c)->rows);
}
static bool write_md(FILE *f, void *c, char *why, size_t why_size) {
    (void)why, (void)why_size;
    const report_ctx *r = c;
    return bench_write_markdown(f, r->rows, &(bench_markdown){ .preamble = r->preamble, .cost_svg = "results.svg",
                                                                .scaling_svg = "scaling.svg" });
}
static bool write_cost(FILE *f, void *c, char *why, size_t why_size) {
    (void)why, (void)why_size;
    return bench_write_cost_svg(f, ((report_ctx *)c)->rows);
}
static bool write_scaling(FILE *f, void *c, char *why, size_t why_size) {
    (void)why, (void)why_size;
    return bench_write_scaling_svg(f, ((report_ctx *)c)->rows);
}

/* The results directory, made before any measurement so a bad -o fails at once. */
static bool make_out_dir(const char *dir) {
    struct stat st;
    const char *why = NULL;
    if (mkdir(dir, 0755) != 0 && errno != EEXIST) why = strerror(errno);
    else if (stat(dir, &st) != 0) why = strerror(errno);
    else if (!S_ISDIR(st.st_mode)) why = "not a directory";
    else if (access(dir, W_OK) != 0) why = strerror(errno);
    if (why) fprintf(stderr, "bench_suite: %s: cannot make or write the results directory: %s\n", dir, why);
    return why == NULL;
}

static int write_report(const char *dir, const bench_rows *rows, const machine *m) {
    char text[2048];
    preamble(m, text, sizeof text);
    report_ctx ctx = { rows, text };
    static const struct {
        const char *name;
        ht_file_writer_fn fn;
    } files[] = { { "results.csv", write_csv }, { "results.md", write_md }, { "results.svg", write_cost },
                  { "scaling.svg", write_scaling } };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char path[1024], err[1200];
        snprintf(path, sizeof path, "%s/%s", dir, files[i].name);
        if (ht_file_write_atomic(path, files[i].fn, &ctx, err, sizeof err) != HT_OK) {
            fprintf(stderr, "bench_suite: %s\n", err);
            return 1;
        }
        printf("bench_suite: wrote %s\n", path);
    }
    return 0;
}

/* ---- main ---- */

static int run(const char *bindir, const char *work, const char *out_dir, bool quick, const char *command) {
    step steps[MAX_STEPS];
    int n = plan(steps, quick);
    double total = 0, done = 0;
    for (int i = 0; i < n; i++) total += steps[i].weight;
    machine m = { .command = command, .cores = sysconf(_SC_NPROCESSORS_ONLN), .load_start = load_average(), .quick = quick };
    cpu_model(m.cpu, sizeof m.cpu);
    time_t now = time(NULL);
    strftime(m.date, sizeof m.date, "%Y-%m-%d %H:%M UTC", gmtime(&now));

    bench_rows rows = { 0 };
    const double start = now_ms();
    int status = 0;
    for (int i = 0; i < n && status == 0; i++) {
        const step *s = &steps[i];
        char csv[512];
        snprintf(csv, sizeof csv, "%s/step-%02d.csv", work, i);
        argv_buf a;
        command_line(s, bindir, csv, &a);
        printf("== [%d/%d] ", i + 1, n);
        print_command(s, a.argv);
        printf("\n");
        double t0 = now_ms();
        if (run_child(a.argv, s->driver, s->api, s->kind == FIGURES, &rows, s->series) != 0) {
            fprintf(stderr, "bench_suite: step %d failed: %s\n", i + 1, a.argv[0]);
            status = 1;
            break;
        }
        char err[1024];
        if (s->kind == FRAME && !bench_rows_read_csv(csv, &rows, err, sizeof err)) {
            fprintf(stderr, "bench_suite: %s\n", err);
            status = 1;
            break;
        }
        done += s->weight;
        double elapsed = (now_ms() - start) / 1e3;
        char took[32], so_far[32], eta[32];
        printf("-- [%d/%d] %s took %s; elapsed %s, ETA %s\n", i + 1, n, s->program,
               bench_format_duration((now_ms() - t0) / 1e3, took, sizeof took),
               bench_format_duration(elapsed, so_far, sizeof so_far),
               bench_format_duration(bench_eta_seconds(elapsed, done, total - done), eta, sizeof eta));
    }
    if (status == 0) {
        m.load_end = load_average();
        m.minutes = (now_ms() - start) / 60e3;
        status = write_report(out_dir, &rows, &m);
    }
    bench_rows_free(&rows);
    return status;
}

enum { KEY_QUICK = CLI_LONG_ONLY };
static const struct option long_options[] = { { "quick", no_argument, NULL, KEY_QUICK }, { 0 } };

static const cli_program program = {
    .name = "bench_suite",
    .synopsis = "usage: bench_suite [-o DIR] [--quick]\n",
    .help = "Runs every benchmark (bench_hairgen, bench_mesh, bench_frame per scene and driver, the\n"
            "fur-ball scaling series), each as a child, and writes DIR/results.csv, results.md,\n"
            "results.svg and scaling.svg atomically (DIR defaults to bench/); nothing is written if a\n"
            "step fails (exit 1). --quick: tiny sizes and frame counts, to try the pipeline.\n",
    .short_options = "o:",
    .long_options = long_options,
};

typedef struct options {
    const char *out_dir;
    bool quick;
} options;

static const char *take(void *user, int key, const char *value) {
    options *o = user;
    if (key == 'o') o->out_dir = value;
    else if (key == KEY_QUICK) o->quick = true;
    else return cli_unexpected(value);
    return NULL;
}

int main(int argc, char **argv) {
    options o = { .out_dir = "bench" };
    int rc = cli_parse(&program, argc, argv, take, &o);
    if (rc != CLI_RUN) return rc;
    const char *out_dir = o.out_dir;
    const bool quick = o.quick;
    /* The other benchmarks sit beside this program (build/). */
    char bindir[512];
    snprintf(bindir, sizeof bindir, "%s", argv[0]);
    char *slash = strrchr(bindir, '/');
    if (slash) *slash = '\0';
    else snprintf(bindir, sizeof bindir, ".");

    if (!make_out_dir(out_dir)) return 1;
    char work[] = "/tmp/hairtier-bench-suite-XXXXXX";
    if (!mkdtemp(work)) {
        perror("mkdtemp");
        return 1;
    }
    char command[700];
    snprintf(command, sizeof command, "%s -o %s%s", argv[0], out_dir, quick ? " --quick" : "");
    int status = run(bindir, work, out_dir, quick, command);
    if (tempdir_remove(work) != 0) {
        fprintf(stderr, "bench_suite: cannot remove %s\n", work);
        status = 1;
    }
    return status;
}

/* batch.c — many materials in one run (ht_generate_batch, hairgen.h): a
   pool of threads takes materials in turn, each one bundle made with
   ht_bundle_make (load, hash, skip when up to date, generate, publish
   atomically), then the make/ninja depfiles. The scene is read once; glslang
   is initialised once and each distinct shader text validated once
   (glsl_validate.c), whatever the thread. */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "depfile.h"
#include "errfmt.h"
#include "file_atomic.h"
#include "file_open.h"
#include "hairgen_internal.h"
#include "lods_store.h"

#define MAX_JOBS 256

typedef struct material_job {
    char dir[4096];               /* its bundle directory */
    ht_result result;
    ht_bundle_report report;
} material_job;

typedef struct batch_run {
    const ht_batch_desc *desc;
    const ht_scene *scene;
    const char *scene_bytes;
    size_t scene_size;
    material_job *jobs;
    pthread_mutex_t lock;         /* next, done, the counts and every line printed */
    int next, done;
    ht_batch_result counts;
    double start_ms;
    int bundle_threads;           /* what each material's build may use (build.h) */
    ht_lods_cache lods;           /* the scene's lods.bin, made once (desc->store_lods) */
} batch_run;

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e3 + t.tv_nsec / 1e6;
}

/* "dir/name.json" -> "name": the bundle's directory name in a batch. */
static void bundle_name(const char *material, char *out, size_t size) {
    const char *slash = strrchr(material, '/');
    const char *base = slash ? slash + 1 : material;
    size_t len = strlen(base);
    if (len > 5 && strcmp(base + len - 5, ".json") == 0) len -= 5;
    snprintf(out, size, "%.*s", (int)len, base);
}

/* One line after each material: what happened, its time, and when the
   batch should end at the pace so far. Called with the lock held. */
static void report_progress(batch_run *b, int i, double ms) {
    const ht_batch_desc *d = b->desc;
    const material_job *j = &b->jobs[i];
    if (!d->progress || j->result != HT_OK) return;
    double elapsed_s = (now_ms() - b->start_ms) / 1e3;
    double eta_s = elapsed_s / b->done * (d->material_count - b->done);
    if (j->report.skipped)
        ht_print_line(d->progress, "hairgen: [%d/%d] %s: up to date, skipped (--force regenerates)", b->done,
                d->material_count, j->dir);
    else
        ht_print_line(d->progress, "hairgen: [%d/%d] %s -> %s: %.0f ms, ETA %.1f s", b->done, d->material_count,
                d->materials[i], j->dir, ms, eta_s);
    fflush(d->progress);
}

static void *worker(void *arg) {
    batch_run *b = arg;
    const ht_batch_desc *d = b->desc;
    for (;;) {
        pthread_mutex_lock(&b->lock);
        int i = b->next < d->material_count ? b->next++ : -1;
        pthread_mutex_unlock(&b->lock);
        if (i < 0) return NULL;

        material_job *j = &b->jobs[i];
        char err[2048] = "";
        /* The tier table is printed whole, so it goes to memory first and
           out under the lock. */
        char *table = NULL;
        size_t table_size = 0;
        FILE *summary = d->summary ? open_memstream(&table, &table_size) : NULL;
        double t0 = now_ms();
        j->result = ht_bundle_make(&(ht_bundle_request){ .material_path = d->materials[i],
                                                         .scene_path = d->scene,
                                                         .scene = b->scene,
                                                         .scene_bytes = b->scene_bytes,
                                                         .scene_size = b->scene_size,
                                                         .out_dir = j->dir,
                                                         .skip_unchanged = !d->force,
                                                         .store_lods = d->store_lods,
                                                         .lods_cache = &b->lods,
                                                         .depfile_names = d->depfile || d->depfile_per_bundle,
                                                         .summary = summary,
                                                         .threads = b->bundle_threads },
                                   &j->report, err, sizeof err);
        double ms = now_ms() - t0;
        if (summary) fclose(summary);

        pthread_mutex_lock(&b->lock);
        b->done++;
        if (j->result != HT_OK) {
            b->counts.failed++;
            /* err names the file that failed (material, texture, scene or
               bundle); a generic code's message is given the material. */
            fprintf(d->errors ? d->errors : stderr, "hairgen: %s\n",
                    err[0] ? err : ht_result_string(j->result));
            if (!err[0]) ht_print_line(d->errors ? d->errors : stderr, "hairgen: (in %s)", d->materials[i]);
        } else if (j->report.skipped) {
            b->counts.skipped++;
        } else {
            b->counts.generated++;
            if (table && d->summary) fputs(table, d->summary);
        }
        report_progress(b, i, ms);
        pthread_mutex_unlock(&b->lock);
        free(table);
    }
}

/* ---- depfiles ---- */

/* The depfiles of the bundles made or up to date. A failed material's
   depfile is left as it was: it still names the inputs that were wrong, so
   once they are fixed make or ninja runs hairgen again (an emptied one
   would say the stale bundle is up to date). */
static ht_result write_depfiles(const ht_batch_desc *d, const material_job *jobs, char *err, size_t err_size) {
    if (!d->depfile && !d->depfile_per_bundle) return HT_OK;
    ht_depfile_rule *rules = malloc(sizeof *rules * (size_t)d->material_count);
    if (!rules) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "depfile: out of memory");
    int count = 0;
    bool failed = false;
    ht_result r = HT_OK;
    for (int i = 0; i < d->material_count && r == HT_OK; i++) {
        if (jobs[i].result != HT_OK) {
            failed = true;
            continue;
        }
        rules[count] = (ht_depfile_rule){ jobs[i].dir, &jobs[i].report };
        if (d->depfile_per_bundle) {
            char path[4200];
            snprintf(path, sizeof path, "%s.d", jobs[i].dir);
            r = ht_depfile_write(path, &rules[count], 1, err, err_size);
        }
        count++;
    }
    /* One depfile for the batch: a failure anywhere leaves it as it was. */
    if (r == HT_OK && d->depfile && !d->depfile_per_bundle && !failed)
        r = ht_depfile_write(d->depfile, rules, count, err, err_size);
    free(rules);
    return r;
}

/* ---- the batch ---- */

static ht_result plan_dirs(const ht_batch_desc *d, material_job *jobs, char *err, size_t err_size) {
    if (d->in_place) {
        if (d->material_count != 1)
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT,
                           "%s: one bundle directory for %d materials (a batch puts each in DIR/NAME)",
                           d->out_dir, d->material_count);
        size_t len = strlen(d->out_dir);
        while (len > 1 && d->out_dir[len - 1] == '/') len--;
        snprintf(jobs[0].dir, sizeof jobs[0].dir, "%.*s", (int)len, d->out_dir);
        return HT_OK;
    }
    for (int i = 0; i < d->material_count; i++) {
        char name[1024];
        bundle_name(d->materials[i], name, sizeof name);
        if (!name[0] || strcmp(name, ".") == 0 || strcmp(name, "..") == 0)
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: no file name to name its bundle after",
                           d->materials[i]);
        int n = snprintf(jobs[i].dir, sizeof jobs[i].dir, "%s/%s", d->out_dir, name);
        if (n < 0 || (size_t)n >= sizeof jobs[i].dir)
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "%s: bundle path too long", d->materials[i]);
        for (int k = 0; k < i; k++)
            if (strcmp(jobs[k].dir, jobs[i].dir) == 0)
                return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT,
                               "%s and %s: both would be bundle %s (one bundle per material file name)",
                               d->materials[k], d->materials[i], jobs[i].dir);
    }
    return HT_OK;
}

/* The threads the batch may use: -j, else every online core. */
static int thread_budget(const ht_batch_desc *d) {
    long jobs = d->jobs > 0 ? d->jobs : sysconf(_SC_NPROCESSORS_ONLN);
    if (jobs < 1) jobs = 1;
    if (jobs > MAX_JOBS) jobs = MAX_JOBS;
    return (int)jobs;
}

/* Materials run at once: one per thread, at most one per material. */
static int job_count(const ht_batch_desc *d) {
    int jobs = thread_budget(d);
    return jobs > d->material_count ? d->material_count : jobs;
}

ht_result ht_generate_batch(const ht_batch_desc *d, ht_batch_result *result, char *err, size_t err_size) {
    if (result) memset(result, 0, sizeof *result);
    if (!d || !d->materials || d->material_count < 1 || !d->out_dir || !d->out_dir[0])
        return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_generate_batch: no material or no output directory");
    for (int i = 0; i < d->material_count; i++)
        if (!d->materials[i])
            return ht_fail(err, err_size, HT_ERR_INVALID_ARGUMENT, "ht_generate_batch: material %d: no path", i);

    batch_run b = { .desc = d, .start_ms = now_ms() };
    b.jobs = calloc((size_t)d->material_count, sizeof *b.jobs);
    if (!b.jobs) return ht_fail(err, err_size, HT_ERR_OUT_OF_MEMORY, "ht_generate_batch: out of memory");
    ht_result r = plan_dirs(d, b.jobs, err, err_size);
    /* The depfiles' paths before any work: a device or a FIFO there is
       refused with nothing written (file_atomic.h). */
    if (r == HT_OK && d->depfile && !d->depfile_per_bundle) r = ht_file_check_output(d->depfile, err, err_size);
    for (int i = 0; r == HT_OK && d->depfile_per_bundle && i < d->material_count; i++) {
        char path[4200];
        snprintf(path, sizeof path, "%s.d", b.jobs[i].dir);
        r = ht_file_check_output(path, err, err_size);
    }

    /* The scene once for every material: parsed, and its bytes kept for
       each bundle's input hash. */
    ht_scene scene;
    char *scene_text = NULL;
    if (r == HT_OK && d->scene) {
        r = ht_scene_load(d->scene, &scene, err, err_size);
        if (r == HT_OK) r = ht_scene_check_strands(&scene, d->scene, err, err_size);
        if (r == HT_OK) {
            scene_text = ht_file_read_text(d->scene, HT_FILE_MAX_JSON, err, err_size);
            if (!scene_text) r = HT_ERR_IO;
        }
        b.scene = &scene;
        b.scene_bytes = scene_text;
        b.scene_size = scene_text ? strlen(scene_text) : 0;
    }

    struct stat st;
    if (r == HT_OK && !d->in_place && mkdir(d->out_dir, 0777) != 0 &&
        (errno != EEXIST || stat(d->out_dir, &st) != 0 || !S_ISDIR(st.st_mode)))
        r = ht_fail(err, err_size, HT_ERR_IO, "%s: cannot create the bundles' folder: %s", d->out_dir,
                    errno == EEXIST ? "exists and is not a directory" : strerror(errno));

    if (r == HT_OK) {
        int threads = job_count(d);
        /* The threads left over when there are fewer materials than
           threads go to each material's own build (one material: all). */
        b.bundle_threads = thread_budget(d) / threads;
        pthread_t tids[MAX_JOBS];
        int started = 0;
        pthread_mutex_init(&b.lock, NULL);
        ht_lods_cache_init(&b.lods);
        /* The calling thread is one of the workers. */
        for (int t = 1; t < threads; t++) {
            if (pthread_create(&tids[started], NULL, worker, &b) != 0) break;
            started++;
        }
        worker(&b);
        for (int t = 0; t < started; t++) pthread_join(tids[t], NULL);
        pthread_mutex_destroy(&b.lock);
        ht_lods_cache_free(&b.lods);

        r = write_depfiles(d, b.jobs, err, err_size);
        if (result) *result = b.counts;
        if (b.counts.failed > 0) {
            ht_result first = HT_OK;
            for (int i = 0; i < d->material_count && first == HT_OK; i++) first = b.jobs[i].result;
            /* The failures were printed one per line; this is the total. */
            ht_set_error(err, err_size, "%d of %d materials failed (their bundles are as they were)",
                         b.counts.failed, d->material_count);
            r = first;
        }
    }
    free(scene_text);
    free(b.jobs);
    return r;
}

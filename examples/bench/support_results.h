/* support_results.h — one benchmark result, and the CSV form the benchmarks
   exchange and `make bench` leaves in bench/results.csv.

   A row is either a frame measurement (series "matrix" or "scaling": one
   tier of one scene on one driver, with its ratios to the geometry floor and
   to the full tier taken in the same run, with the camera still and with
   the eye orbiting a little every frame, and its error against full's
   image; series "gles2" or "gles3": a GLSL tier on a GL ES context,
   "full-gles2", ..., its ratios and error against desktop GL's "full" of
   the same run, the floor the ES context's) or a generator figure (series "generator": figure, value, unit,
   the other columns empty).

   Usage:
       bench_rows rows = { 0 };
       bench_row *r = bench_rows_add(&rows);          // NULL: out of memory
       ... fill *r ...
       bench_rows_write_csv(f, &rows);
       bench_rows_read_csv("part.csv", &rows, err, sizeof err);   // appends
       bench_rows_free(&rows);

   CSV: RFC 4180 (a field with a comma, quote or line break is quoted, quotes
   doubled), a header line first (BENCH_CSV_HEADER, checked on reading),
   numbers in C's %g form, "inf" for an infinite PSNR (identical images),
   an empty field for "not applicable" (read back as NAN, or -1 for counts). */
#ifndef HT_EXAMPLES_SUPPORT_RESULTS_H
#define HT_EXAMPLES_SUPPORT_RESULTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "metrics.h"

#define BENCH_CSV_HEADER                                                                                   \
    "series,scene,driver,renderer,hairs,triangles,width,height,frames,tier,ran,median_ms,per_floor,per_full," \
    "orbit_ms,orbit_per_full," \
    "psnr_db,ssim,de00_mean,de00_p95,hair_psnr_db,hair_ssim,hair_de00_mean,hair_de00_p95,"                  \
    "flip_mean,flip_p95,"                                                                                  \
    "cpu_vertices_still,cpu_vertices_orbit,figure,value,unit"

typedef struct bench_row {
    char series[16];            /* "matrix", "scaling", "gles2", "gles3" or "generator" */
    char scene[64];             /* scene file name without .json */
    char driver[32];            /* first word of GL_RENDERER: llvmpipe, softpipe */
    char renderer[128];         /* GL_RENDERER in full */
    long hairs;                 /* -1: not a fur ball */
    long triangles, width, height, frames;
    char tier[32];              /* "floor", "full", "vertex", ... */
    bool ran;                   /* false: the tier does not run here; numbers NAN */
    double median_ms, per_floor, per_full;   /* camera still */
    double orbit_ms, orbit_per_full;         /* the eye orbiting a little every frame (NAN: not timed) */
    ht_metrics whole, hair;     /* against full's image of the same run (pixels not exchanged) */
    double flip_mean, flip_p95; /* LDR-FLIP against the same image, whole frame */
    double cpu_still, cpu_orbit;   /* per-vertex CPU work per frame, camera still / orbiting */
    char figure[160];           /* generator rows */
    double value;
    char unit[16];
} bench_row;

typedef struct bench_rows {
    bench_row *row;
    size_t count, capacity;
} bench_rows;

/* BENCH_CSV_HEADER, built from the writer's column table; NULL if the two
   differ (a build error a test catches). */
const char *bench_csv_header(void);
/* A frame row or a figure row with every number NAN (counts -1), text empty. */
bench_row bench_row_blank(void);
/* Appends a blank row and returns it; NULL when out of memory. */
bench_row *bench_rows_add(bench_rows *rows);
void bench_rows_free(bench_rows *rows);

/* Header and rows; false when a write fails. */
bool bench_rows_write_csv(FILE *f, const bench_rows *rows);
/* Appends the rows of a file bench_rows_write_csv wrote. false with one line
   "FILE: line N: what is wrong" in err on a missing file, a different
   header, an unterminated quote, a wrong field count, a bad number or a
   text too long for its field; rows then holds what it held before. */
bool bench_rows_read_csv(const char *path, bench_rows *rows, char *err, size_t err_size);

/* ---- views the report writers share ---- */

/* A row of a frame measurement (series "matrix", "scaling", "gles2" or "gles3"). */
bool bench_row_is_frame(const bench_row *r);
/* A row of a GL ES run (series "gles2" or "gles3"). */
bool bench_row_is_es(const bench_row *r);
/* The distinct tiers of the desktop GL frame rows (matrix and scaling), in order of first appearance (the
   benchmark's order: floor, full, vertex, ...); at most max. A tier keeps its
   index, so its colour is the same in every plot. */
size_t bench_rows_tiers(const bench_rows *rows, const char *tiers[], size_t max);
/* Index of name in tiers[0..count), or -1. */
int bench_tier_index(const char *const tiers[], size_t count, const char *name);
/* a and b come from one run of the frame benchmark: the same series,
   scene, driver, hairs and size. */
bool bench_rows_same_run(const bench_row *a, const bench_row *b);
/* The first row of each run in the matrix series, in order; at most max. */
size_t bench_rows_matrix_runs(const bench_rows *rows, size_t first[], size_t max);
/* The same for any series ("gles2", ...). */
size_t bench_rows_series_runs(const bench_rows *rows, const char *series, size_t first[], size_t max);
/* The first row of each run of the scaling series, and of the matrix run
   with the same scene, driver and size (the point both series share),
   ordered by hair count; a hair count both have is taken from the scaling
   series. At most max. */
size_t bench_rows_scaling_runs(const bench_rows *rows, size_t first[], size_t max);
/* The row of tier in the run that starts at rows->row[first]; NULL if absent. */
const bench_row *bench_rows_find(const bench_rows *rows, size_t first, const char *tier);

#endif

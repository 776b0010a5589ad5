/* test_render_bundle_memory — a bundle in memory is a bundle directory in
   another place: ht_renderer_desc.bundle_memory draws the same pixels as
   bundle_dir on every tier, from the files read into memory, from
   ht_generate's output and from a header `hairgen --emit-header` wrote
   (the Makefile generates build/gen/dark_brown_furball.h from the fixture's
   inputs and compiles it in, and checks it builds warning-free as C99 and
   C++); the header is deterministic; and a broken memory bundle (a file
   missing, truncated, oversized, of the wrong size, with a NUL byte) fails
   with the log the same broken directory gives, word for word, its name
   standing where the directory's path stands. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <hairtier/hairgen.h>
#include <hairtier/hairtier.h>
#include <hairtier/image.h>
#include "support_log.h"
#include "support_osmesa.h"
#include "support_render.h"
#include "support_scratch.h"

/* materials/dark-brown.json x scenes/furball.json, the fixture's inputs. */
#include "dark_brown_furball.h"

#define SIZE 64

static ht_test_furball fx;

static const ht_tier every_tier[] = { HT_TIER_FULL, HT_TIER_VERTEX, HT_TIER_FIXED4, HT_TIER_FIXED, HT_TIER_GL11 };
#define EVERY_TIER (int)(sizeof every_tier / sizeof every_tier[0])

static int setup(void **state) {
    (void)state;
    return ht_test_furball_setup(&fx, "memory", SIZE) ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_furball_teardown(&fx);
}

/* ---- a directory read into an ht_bundle_memory ---- */

typedef struct memory_bundle {
    ht_bundle_memory memory;
    ht_bundle_file files[HT_BUNDLE_MEMORY_MAX_FILES];
    char names[HT_BUNDLE_MEMORY_MAX_FILES][64];
    unsigned char *data[HT_BUNDLE_MEMORY_MAX_FILES];
} memory_bundle;

static unsigned char *read_all(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot read %s", path);
    struct stat st;
    assert_int_equal(fstat(fileno(f), &st), 0);
    *size = (size_t)st.st_size;
    unsigned char *buf = malloc(*size ? *size : 1);
    assert_non_null(buf);
    assert_int_equal(fread(buf, 1, *size, f), *size);
    fclose(f);
    return buf;
}

static int by_name(const void *a, const void *b) {
    return strcmp(((const ht_bundle_file *)a)->name, ((const ht_bundle_file *)b)->name);
}

/* Every regular file of dir, named `label` (the directory's own path makes
   the two sources' messages comparable). */
static void memory_of_dir(const char *dir, const char *label, memory_bundle *m) {
    memset(m, 0, sizeof *m);
    DIR *d = opendir(dir);
    assert_non_null(d);
    struct dirent *e;
    int n = 0;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        assert_true(n < HT_BUNDLE_MEMORY_MAX_FILES);
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        assert_true(strlen(e->d_name) < sizeof m->names[n]);
        memcpy(m->names[n], e->d_name, strlen(e->d_name) + 1);
        m->data[n] = read_all(path, &m->files[n].size);
        m->files[n].name = m->names[n];
        m->files[n].data = m->data[n];
        n++;
    }
    closedir(d);
    qsort(m->files, (size_t)n, sizeof m->files[0], by_name);
    m->memory = (ht_bundle_memory){ .name = label, .files = m->files, .file_count = n };
}

static void memory_free(memory_bundle *m) {
    for (int i = 0; i < HT_BUNDLE_MEMORY_MAX_FILES; i++) free(m->data[i]);
    memset(m, 0, sizeof *m);
}

/* The file called name in m, or NULL. */
static const ht_bundle_file *find_file(const ht_bundle_memory *m, const char *name) {
    for (int i = 0; i < m->file_count; i++)
        if (strcmp(m->files[i].name, name) == 0) return &m->files[i];
    return NULL;
}

/* Same names, same bytes (order aside). */
static void assert_same_files(const ht_bundle_memory *a, const ht_bundle_memory *b) {
    assert_int_equal(a->file_count, b->file_count);
    for (int i = 0; i < a->file_count; i++) {
        const ht_bundle_file *o = find_file(b, a->files[i].name);
        if (!o) fail_msg("%s: missing", a->files[i].name);
        if (o->size != a->files[i].size || memcmp(o->data, a->files[i].data, o->size) != 0)
            fail_msg("%s: %zu bytes against %zu, or different bytes", o->name, o->size, a->files[i].size);
    }
}

/* ---- drawing ---- */

/* One frame of the fixture with `tier` (AUTO: the best) from desc's source;
   *tier_out the tier drawn. */
static void draw_from(ht_renderer_desc desc, ht_tier tier, ht_image *img, ht_tier *tier_out) {
    desc.tier = tier;
    desc.strict = tier != HT_TIER_AUTO;
    ht_renderer *r = ht_test_renderer_create(desc, NULL, HT_OK);
    assert_int_equal(ht_renderer_set_mesh(r, &fx.mesh), HT_OK);
    ht_frame_desc frame = ht_test_furball_frame(2.6f);
    ht_test_draw(&fx.gl, r, &frame, ht_test_background, img);
    if (tier_out) *tier_out = ht_renderer_tier(r);
    ht_renderer_destroy(r);
}

/* memory draws dir's pixels exactly with `tier`, and draws some hair. */
static void assert_same_pixels(const ht_bundle_memory *memory, ht_tier tier) {
    ht_image from_dir, from_memory;
    ht_tier drawn_dir, drawn_memory;
    draw_from((ht_renderer_desc){ .bundle_dir = fx.bundle_dir }, tier, &from_dir, &drawn_dir);
    draw_from((ht_renderer_desc){ .bundle_memory = memory }, tier, &from_memory, &drawn_memory);
    assert_int_equal(drawn_dir, drawn_memory);
    size_t bytes = (size_t)SIZE * SIZE * 4;
    int differ = 0;
    for (size_t i = 0; i < bytes; i++) differ += from_dir.pixels[i] != from_memory.pixels[i];
    ht_test_pixel_stats stats = ht_test_pixel_stats_of(&from_memory, ht_test_background);
    printf("  %-6s from memory: %d hair pixels, %d channel values differ from the directory's\n",
           ht_tier_name(drawn_memory), stats.changed, differ);
    assert_int_equal(differ, 0);
    assert_true(stats.changed > SIZE * SIZE / 20);
    ht_image_free(&from_dir);
    ht_image_free(&from_memory);
}

static void test_memory_bundle_draws_the_directorys_pixels_on_every_tier(void **state) {
    (void)state;
    memory_bundle m;
    memory_of_dir(fx.bundle_dir, "in-memory", &m);
    for (int i = 0; i < EVERY_TIER; i++) assert_same_pixels(&m.memory, every_tier[i]);
    memory_free(&m);
}

/* The header the Makefile wrote with hairgen --emit-header holds the
   directory's files byte for byte and draws its pixels. */
static void test_emitted_header_holds_the_directory_and_draws_its_pixels(void **state) {
    (void)state;
    memory_bundle m;
    memory_of_dir(fx.bundle_dir, fx.bundle_dir, &m);
    assert_same_files(&dark_brown_furball, &m.memory);
    assert_string_equal(dark_brown_furball.name, "dark_brown_furball");
    memory_free(&m);
    assert_same_pixels(&dark_brown_furball, HT_TIER_AUTO);
    assert_same_pixels(&dark_brown_furball, HT_TIER_FIXED);
}

/* ht_generate_files + ht_generated_file_bytes give the directory's bytes;
   the header text is the same every time and the same as the one hairgen
   wrote in another process. */
static void test_generated_bytes_and_header_text_are_deterministic(void **state) {
    (void)state;
    char err[1024];
    ht_material material;
    ht_generated g;
    assert_int_equal(ht_generate_files("materials/dark-brown.json", "scenes/furball.json", &material, &g, err,
                                       sizeof err), HT_OK);
    memory_bundle dir;
    memory_of_dir(fx.bundle_dir, "x", &dir);
    ht_bundle_file files[HT_GENERATED_MAX_FILES];
    unsigned char *data[HT_GENERATED_MAX_FILES] = { 0 };
    for (int i = 0; i < g.file_count; i++) {
        assert_int_equal(ht_generated_file_bytes(&g.files[i], &data[i], &files[i].size, err, sizeof err), HT_OK);
        files[i].name = g.files[i].name;
        files[i].data = data[i];
    }
    ht_bundle_memory generated = { "generated", files, g.file_count };
    assert_same_files(&generated, &dir.memory);
    memory_free(&dir);
    for (int i = 0; i < g.file_count; i++) free(data[i]);

    char *a, *b;
    assert_int_equal(ht_bundle_header_text(&g, material.name, "dark_brown_furball", &a, err, sizeof err), HT_OK);
    assert_int_equal(ht_bundle_header_text(&g, material.name, "dark_brown_furball", &b, err, sizeof err), HT_OK);
    assert_string_equal(a, b);
    const char *build = getenv("HAIRTIER_BUILD");
    char path[256];
    snprintf(path, sizeof path, "%s/gen/dark_brown_furball.h", build && build[0] ? build : "build");
    size_t size;
    unsigned char *written = read_all(path, &size);
    assert_int_equal(size, strlen(a));
    assert_memory_equal(written, a, size);
    printf("  header: %zu bytes, the same from two calls and from hairgen --emit-header\n", size);
    free(written);
    free(a);
    free(b);

    /* The default symbol comes from the material's name. */
    assert_int_equal(ht_bundle_header_text(&g, material.name, NULL, &a, err, sizeof err), HT_OK);
    assert_non_null(strstr(a, "static const ht_bundle_memory dark_brown_bundle = {"));
    free(a);
    ht_generated_free(&g);
}

static void test_header_symbols_are_checked_and_derived(void **state) {
    (void)state;
    char err[256], sym[HT_HEADER_SYMBOL_MAX + 1];
    static const char *const bad[] = { "", "1abc", "a-b", "_x", "int", "class", "a b",
                                       "x123456789012345678901234567890123456789012345678", NULL };
    for (int i = 0; bad[i]; i++) {
        err[0] = '\0';
        assert_int_equal(ht_header_symbol_check(bad[i], err, sizeof err), HT_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(err, "--header-symbol"));
        assert_null(strchr(err, '\n'));
    }
    assert_int_equal(ht_header_symbol_check("hair_2", err, sizeof err), HT_OK);
    ht_header_symbol_default("dark-brown", sym);
    assert_string_equal(sym, "dark_brown_bundle");
    ht_header_symbol_default("9 lives", sym);
    assert_string_equal(sym, "hair9_lives_bundle");
    ht_header_symbol_default("", sym);
    assert_string_equal(sym, "hair_bundle");
    ht_header_symbol_default("a-very-long-material-name-that-goes-on-and-on-and-on", sym);
    assert_int_equal(strlen(sym), HT_HEADER_SYMBOL_MAX);
    assert_int_equal(ht_header_symbol_check(sym, err, sizeof err), HT_OK);
}

/* ---- the same broken bundle from a directory and from memory ---- */

typedef enum breakage { REMOVE, TRUNCATE, REPLACE_WITH, INSERT_NUL, GROW } breakage;

typedef struct broken_case {
    const char *file;
    breakage how;
    long arg;               /* TRUNCATE: bytes kept; GROW: bytes appended */
    const char *with;       /* REPLACE_WITH: the bundle file copied over it */
    ht_tier tier;           /* forced and strict, or AUTO */
    ht_result expect;
    const char *logged;     /* in both logs, after "DIR/" */
} broken_case;

static void write_bytes(const char *path, const unsigned char *data, size_t size) {
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

static void break_file(const char *dir, const broken_case *c) {
    char path[512], other[512];
    snprintf(path, sizeof path, "%s/%s", dir, c->file);
    size_t size;
    unsigned char *data = read_all(path, &size);
    switch (c->how) {
    case REMOVE: assert_int_equal(unlink(path), 0); break;
    case TRUNCATE: write_bytes(path, data, (size_t)c->arg); break;
    case INSERT_NUL: data[size / 2] = '\0'; write_bytes(path, data, size); break;
    case GROW: {
        unsigned char *grown = malloc(size + (size_t)c->arg);
        assert_non_null(grown);
        memcpy(grown, data, size);
        memset(grown + size, ' ', (size_t)c->arg);
        write_bytes(path, grown, size + (size_t)c->arg);
        free(grown);
        break;
    }
    case REPLACE_WITH: {
        snprintf(other, sizeof other, "%s/%s", dir, c->with);
        size_t other_size;
        unsigned char *o = read_all(other, &other_size);
        write_bytes(path, o, other_size);
        free(o);
        break;
    }
    }
    free(data);
}

/* The log of creating a renderer on desc, or fails the test when the
   result is not expect. */
static void create_log(ht_renderer_desc desc, const broken_case *c, char *out, size_t size) {
    desc.tier = c->tier;
    desc.strict = c->tier != HT_TIER_AUTO;
    ht_renderer *r = ht_test_renderer_create(desc, NULL, c->expect);
    snprintf(out, size, "%s", ht_test_log_text);
    if (r) ht_renderer_destroy(r);
}

static void test_broken_memory_bundle_fails_like_the_broken_directory(void **state) {
    (void)state;
    const broken_case cases[] = {
        { "manifest.json", REMOVE, 0, NULL, HT_TIER_AUTO, HT_ERR_IO,
          "manifest.json: cannot read: No such file or directory" },
        { "manifest.json", TRUNCATE, 700, NULL, HT_TIER_AUTO, HT_ERR_PARSE, "manifest.json: line " },
        { "manifest.json", INSERT_NUL, 0, NULL, HT_TIER_AUTO, HT_ERR_IO, "NUL byte in a text file" },
        { "full.frag", REMOVE, 0, NULL, HT_TIER_AUTO, HT_OK, "full.frag: cannot read: No such file or directory" },
        { "full.frag", GROW, 1 << 20, NULL, HT_TIER_FULL, HT_ERR_UNSUPPORTED,
          /* the size is the text's own plus 1 MiB: not pinned, the text changes */
          " bytes, more than the 1048576 this kind of file may have" },
        { "vertex.vert", INSERT_NUL, 0, NULL, HT_TIER_VERTEX, HT_ERR_UNSUPPORTED,
          "vertex.vert: NUL byte in a text file" },
        { "albedo.png", TRUNCATE, 1000, NULL, HT_TIER_GL11, HT_ERR_UNSUPPORTED, "albedo.png: file is truncated" },
        { "albedo.png", TRUNCATE, 0, NULL, HT_TIER_FIXED4, HT_ERR_UNSUPPORTED, "albedo.png: file is empty" },
        { "fixed-lut.png", REPLACE_WITH, 0, "albedo.png", HT_TIER_FIXED, HT_ERR_UNSUPPORTED,
          "fixed-lut.png: 256x256, manifest says 32x512" },
        { "detail.png", REPLACE_WITH, 0, "fixed.json", HT_TIER_FULL, HT_ERR_UNSUPPORTED, "detail.png: not a PNG file" },
        { "fixed.json", TRUNCATE, 300, NULL, HT_TIER_FIXED, HT_ERR_UNSUPPORTED, "fixed.json: line " },
        { "gl11.json", REMOVE, 0, NULL, HT_TIER_GL11, HT_ERR_UNSUPPORTED,
          "gl11.json: cannot read: No such file or directory" },
    };
    char dir_log[16384], memory_log[16384];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const broken_case *c = &cases[i];
        char name[32], dir[128];
        snprintf(name, sizeof name, "broken-%zu", i);
        ht_test_furball_copy_bundle(&fx, name, dir, sizeof dir);
        break_file(dir, c);
        memory_bundle m;
        memory_of_dir(dir, dir, &m);
        create_log((ht_renderer_desc){ .bundle_dir = dir }, c, dir_log, sizeof dir_log);
        create_log((ht_renderer_desc){ .bundle_memory = &m.memory }, c, memory_log, sizeof memory_log);
        memory_free(&m);
        char want[256];
        snprintf(want, sizeof want, "%s/%s", dir, c->logged);
        if (!strstr(dir_log, want) && !strstr(dir_log, c->logged))
            fail_msg("case %zu: \"%s\" not in the directory's log:\n%s", i, c->logged, dir_log);
        if (strcmp(dir_log, memory_log) != 0)
            fail_msg("case %zu (%s): the logs differ\n-- directory:\n%s-- memory:\n%s", i, c->file, dir_log,
                     memory_log);
        printf("  %-14s %-12s same log from memory: %s\n", c->file,
               c->how == REMOVE ? "removed" : c->how == TRUNCATE ? "truncated" : c->how == GROW ? "oversized"
               : c->how == INSERT_NUL ? "NUL byte" : "wrong file", c->logged);
    }
}

/* What only a memory bundle can get wrong: its table. */
static void test_memory_bundle_table_is_checked_with_one_line(void **state) {
    (void)state;
    memory_bundle m;
    memory_of_dir(fx.bundle_dir, "tbl", &m);
    ht_bundle_file saved = m.files[1];
    struct { const char *logged; } want[] = {
        { "tbl: files[1].name: missing (NULL)" },
        { "tbl: files[1].name: \"albedo.png\" already listed as files[0]" },
        { "tbl: files[1].data: NULL with size" },
        { "tbl: files[1].name: not a plain file name inside the bundle" },
        { "tbl: file_count: 0, expected 1..64 files" },
        { "tbl: file_count: 65, expected 1..64 files" },
    };
    for (int i = 0; i < 6; i++) {
        m.files[1] = saved;
        int count = m.memory.file_count;
        if (i == 0) m.files[1].name = NULL;
        if (i == 1) m.files[1].name = m.files[0].name;
        if (i == 2) m.files[1].data = NULL;
        if (i == 3) m.files[1].name = "../albedo.png";
        if (i == 4) m.memory.file_count = 0;
        if (i == 5) m.memory.file_count = HT_BUNDLE_MEMORY_MAX_FILES + 1;
        ht_test_renderer_create((ht_renderer_desc){ .bundle_memory = &m.memory }, NULL, HT_ERR_INVALID_ARGUMENT);
        if (!ht_test_logged(want[i].logged)) fail_msg("want \"%s\" in:\n%s", want[i].logged, ht_test_log_text);
        m.memory.file_count = count;
    }
    m.files[1] = saved;
    /* Both sources at once is ambiguous. */
    ht_test_renderer_create((ht_renderer_desc){ .bundle_memory = &m.memory, .bundle_dir = fx.bundle_dir }, NULL,
                            HT_ERR_INVALID_ARGUMENT);
    assert_true(ht_test_logged("bundle_dir and bundle_memory: give one, not both"));
    /* Unnamed: messages say "memory". */
    m.memory.name = NULL;
    m.files[0].size = 10; /* albedo.png cut to its signature and a bit */
    ht_test_renderer_create((ht_renderer_desc){ .bundle_memory = &m.memory, .tier = HT_TIER_GL11, .strict = true },
                            NULL, HT_ERR_UNSUPPORTED);
    assert_true(ht_test_logged("memory/albedo.png: file is truncated"));
    memory_free(&m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_memory_bundle_draws_the_directorys_pixels_on_every_tier),
        cmocka_unit_test(test_emitted_header_holds_the_directory_and_draws_its_pixels),
        cmocka_unit_test(test_generated_bytes_and_header_text_are_deterministic),
        cmocka_unit_test(test_header_symbols_are_checked_and_derived),
        cmocka_unit_test(test_broken_memory_bundle_fails_like_the_broken_directory),
        cmocka_unit_test(test_memory_bundle_table_is_checked_with_one_line),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}

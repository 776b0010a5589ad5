/* test_hairgen_batch.c — hairgen on many materials in one run: a bundle
   per material, the same bytes whatever -j, skipped when its inputs are
   unchanged (--force redoes it), regenerated when a material, scene or
   texture changes, make/ninja depfiles that make obeys, a bad material
   failing alone, -q, and each distinct shader text validated once. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "emit.h"
#include <hairtier/hairgen.h>
#include <hairtier/image.h>
#include "support_scratch.h"

static char work[64];
static char hairgen[PATH_MAX];
static char repo[PATH_MAX];

static int setup(void **state) {
    (void)state;
    const char *build = getenv("HAIRTIER_BUILD");
    char rel[PATH_MAX];
    snprintf(rel, sizeof rel, "%s/hairgen", build ? build : "build");
    if (!realpath(rel, hairgen) || !getcwd(repo, sizeof repo)) return -1;
    return ht_test_scratch_create(work, sizeof work, "batch") ? 0 : -1;
}

static int teardown(void **state) {
    (void)state;
    return ht_test_scratch_remove(work);
}

/* hairgen with args, run in the scratch directory; stdout and stderr into
   out.txt and err.txt there. The exit status. */
static int run_hairgen(const char *args) {
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "cd %s && %s %s >out.txt 2>err.txt", work, hairgen, args);
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static char *scratch_text(const char *name) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", work, name);
    char *text = ht_test_read_all(path, NULL);
    if (!text) fail_msg("%s: cannot read", path);
    return text;
}

static int count_lines(const char *text, const char *containing) {
    int n = 0;
    for (const char *line = text; *line;) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) : strlen(line);
        char buf[2048];
        snprintf(buf, sizeof buf, "%.*s", (int)(len < sizeof buf ? len : sizeof buf - 1), line);
        if (strstr(buf, containing)) n++;
        line += len + (end ? 1 : 0);
    }
    return n;
}

static void copy_material(const char *shipped, const char *name) {
    char from[PATH_MAX + 128];
    snprintf(from, sizeof from, "%s/materials/%s.json", repo, shipped);
    char *text = ht_test_read_all(from, NULL);
    assert_non_null(text);
    ht_test_write_file(work, name, text);
    free(text);
}

static void copy_scene(const char *shipped, const char *name) {
    char from[PATH_MAX + 128];
    snprintf(from, sizeof from, "%s/scenes/%s.json", repo, shipped);
    char *text = ht_test_read_all(from, NULL);
    assert_non_null(text);
    ht_test_write_file(work, name, text);
    free(text);
}

static void append_to(const char *name, const char *text) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", work, name);
    FILE *f = fopen(path, "a");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void write_png(const char *name, uint8_t value) {
    char path[512], err[256];
    snprintf(path, sizeof path, "%s/%s", work, name);
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, 32, 32, 3), HT_OK);
    for (int i = 0; i < 32 * 32 * 3; i++) img.pixels[i] = (uint8_t)(value + i % 7);
    if (ht_image_write_png(path, &img, err, sizeof err) != HT_OK) fail_msg("%s", err);
    ht_image_free(&img);
}

/* A material whose base is a PNG file beside it. */
static void write_textured_material(const char *name, const char *png) {
    char text[1024];
    snprintf(text, sizeof text,
             "{ \"format\": \"hairtier-material/1\", \"name\": \"textured\", \"model\": \"scheuermann\",\n"
             "  \"diffuse\": {\"color\": [0.4,0.3,0.2], \"wrap\": 0.25},\n"
             "  \"primary\": {\"color\": [0.9,0.8,0.7], \"exponent\": 80, \"shift\": -0.1},\n"
             "  \"secondary\": {\"color\": [0.5,0.4,0.3], \"exponent\": 20, \"shift\": 0.1},\n"
             "  \"textures\": { \"base\": {\"file\": \"%s\"},\n"
             "                \"alpha\": {\"procedural\": \"strand-alpha\", \"size\": 64, \"seed\": 2} } }\n",
             png);
    ht_test_write_file(work, name, text);
}

/* The inode of DIR/manifest.json: a regenerated bundle is a new directory
   (renamed into place), so a new file; a skipped one keeps it. */
static ino_t manifest_inode(const char *dir) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s/manifest.json", work, dir);
    struct stat st;
    if (stat(path, &st) != 0) fail_msg("%s: missing", path);
    return st.st_ino;
}

static bool scratch_exists(const char *name) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", work, name);
    struct stat st;
    return stat(path, &st) == 0;
}

/* Every file of bundle a/NAME equals b/NAME byte for byte, and both hold
   the same file names. */
static void assert_same_bundle(const char *a, const char *b) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", work, a);
    DIR *d = opendir(path);
    assert_non_null(d);
    struct dirent *e;
    int files = 0;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.') continue;
        char pa[700], pb[700];
        snprintf(pa, sizeof pa, "%s/%s/%s", work, a, e->d_name);
        snprintf(pb, sizeof pb, "%s/%s/%s", work, b, e->d_name);
        size_t na, nb;
        char *ta = ht_test_read_all(pa, &na), *tb = ht_test_read_all(pb, &nb);
        if (!ta || !tb || na != nb || memcmp(ta, tb, na) != 0) fail_msg("%s and %s differ", pa, pb);
        free(ta);
        free(tb);
        files++;
    }
    closedir(d);
    snprintf(path, sizeof path, "%s/%s", work, b);
    d = opendir(path);
    assert_non_null(d);
    while ((e = readdir(d)))
        if (e->d_name[0] != '.') files--;
    closedir(d);
    assert_int_equal(files, 0);
}

static void test_batch_writes_one_bundle_per_material_with_a_progress_line_each(void **state) {
    (void)state;
    /* three files of the cheapest material to generate: the lines are what is checked */
    copy_material("kajiya-kay", "blond.json");
    copy_material("kajiya-kay", "kk.json");
    copy_material("kajiya-kay", "dark.json");
    assert_int_equal(run_hairgen("-o many blond.json kk.json dark.json --scene no-such-scene.json -q"), 1);
    assert_false(scratch_exists("many"));
    copy_scene("furball", "furball.json");
    assert_int_equal(run_hairgen("-o many blond.json kk.json dark.json --scene furball.json -j 2"), 0);
    assert_true(scratch_exists("many/blond/manifest.json"));
    assert_true(scratch_exists("many/kk/manifest.json"));
    assert_true(scratch_exists("many/dark/manifest.json"));
    char *out = scratch_text("out.txt");
    assert_int_equal(count_lines(out, "ETA"), 3);
    assert_int_equal(count_lines(out, "/3] "), 3);
    assert_int_equal(count_lines(out, "3 generated, 0 up to date"), 1);
    free(out);
    char *err;
    /* thread counts are 1..256; the bundles' folder must be a folder */
    assert_int_equal(run_hairgen("-o many blond.json -j 0"), 2);
    assert_int_equal(run_hairgen("-o many blond.json -jx"), 2);
    ht_test_write_file(work, "a-file", "not a folder\n");
    assert_int_equal(run_hairgen("-o a-file blond.json kk.json"), 1);
    err = scratch_text("err.txt");
    assert_int_equal(count_lines(err, "a-file: cannot create the bundles' folder: exists and is not a directory"), 1);
    assert_int_equal(count_lines(err, "hairgen:"), 1);
    free(err);
    /* one material with --batch goes in DIR/NAME too */
    assert_int_equal(run_hairgen("--batch -o one kk.json -q"), 0);
    assert_true(scratch_exists("one/kk/manifest.json"));
    /* two materials of one file name would be one bundle: refused first */
    char sub[512];
    snprintf(sub, sizeof sub, "%s/sub", work);
    assert_int_equal(mkdir(sub, 0755), 0);
    copy_material("kajiya-kay", "sub/blond.json");
    assert_int_equal(run_hairgen("-o clash blond.json sub/blond.json"), 1);
    err = scratch_text("err.txt");
    assert_non_null(strstr(err, "both would be bundle clash/blond"));
    free(err);
    assert_false(scratch_exists("clash/blond"));
}

static void test_batch_bytes_do_not_depend_on_thread_count(void **state) {
    (void)state;
    copy_material("blond", "blond.json");
    copy_material("kajiya-kay", "kk.json");
    copy_material("high-contrast", "hc.json");
    copy_scene("patches", "patches.json");
    assert_int_equal(run_hairgen("-o j1 -j1 blond.json kk.json hc.json --scene patches.json -q"), 0);
    /* and a batch's bundle is the single form's (on every core) */
    assert_int_equal(run_hairgen("kk.json --scene patches.json -o single-kk -q"), 0);
    assert_same_bundle("j1/kk", "single-kk");
    /* One material spreads its own jobs over the threads (build.c): the
       same bytes on one thread and with materials side by side, three
       threads left to each (-j 6, two materials). */
    assert_int_equal(run_hairgen("-o j6 -j6 blond.json hc.json --scene patches.json -q"), 0);
    assert_same_bundle("j1/blond", "j6/blond");
    assert_same_bundle("j1/hc", "j6/hc");
}

static void test_unchanged_inputs_are_skipped_and_force_regenerates(void **state) {
    (void)state;
    copy_material("kajiya-kay", "blond.json"); /* the cheapest to generate: any material serves */
    copy_material("kajiya-kay", "kk.json");
    assert_int_equal(run_hairgen("-o skip blond.json kk.json -q"), 0);
    ino_t blond = manifest_inode("skip/blond"), kk = manifest_inode("skip/kk");
    assert_int_equal(run_hairgen("-o skip blond.json kk.json"), 0);
    char *out = scratch_text("out.txt");
    assert_int_equal(count_lines(out, "up to date, skipped"), 2);
    assert_int_equal(count_lines(out, "skip/blond: up to date"), 1);
    assert_int_equal(count_lines(out, "0 generated, 2 up to date"), 1);
    free(out);
    assert_true(manifest_inode("skip/blond") == blond);
    assert_true(manifest_inode("skip/kk") == kk);
    assert_int_equal(run_hairgen("-o skip blond.json kk.json --force -q"), 0);
    assert_true(manifest_inode("skip/blond") != blond);
    assert_true(manifest_inode("skip/kk") != kk);
    kk = manifest_inode("skip/kk");
    /* a bundle whose manifest holds another hash (an older generator's) is redone */
    blond = manifest_inode("skip/blond");
    char path[512];
    snprintf(path, sizeof path, "%s/skip/blond/manifest.json", work);
    char *m = ht_test_read_all(path, NULL);
    char *h = strstr(m, "fnv1a64:");
    assert_non_null(h);
    h[8] = h[8] == '0' ? '1' : '0';
    ht_test_write_file(work, "skip/blond/manifest.json", m);
    free(m);
    blond = manifest_inode("skip/blond");
    assert_int_equal(run_hairgen("-o skip blond.json kk.json -q"), 0);
    assert_true(manifest_inode("skip/blond") != blond);
    assert_true(manifest_inode("skip/kk") == kk);
}

static void test_a_changed_texture_material_or_scene_regenerates_only_its_bundles(void **state) {
    (void)state;
    write_png("base.png", 100);
    write_textured_material("tex.json", "base.png");
    copy_material("kajiya-kay", "kk.json");
    copy_scene("furball", "scene.json");
    const char *args = "-o chg tex.json kk.json --scene scene.json -q";
    assert_int_equal(run_hairgen(args), 0);
    ino_t tex = manifest_inode("chg/tex"), kk = manifest_inode("chg/kk");

    write_png("base.png", 101); /* the texture file's bytes */
    assert_int_equal(run_hairgen(args), 0);
    assert_true(manifest_inode("chg/tex") != tex);
    assert_true(manifest_inode("chg/kk") == kk);
    tex = manifest_inode("chg/tex");

    append_to("kk.json", "\n"); /* the material file's bytes, even a blank */
    assert_int_equal(run_hairgen(args), 0);
    assert_true(manifest_inode("chg/tex") == tex);
    assert_true(manifest_inode("chg/kk") != kk);
    kk = manifest_inode("chg/kk");

    append_to("scene.json", " "); /* the scene: every bundle */
    assert_int_equal(run_hairgen(args), 0);
    assert_true(manifest_inode("chg/tex") != tex);
    assert_true(manifest_inode("chg/kk") != kk);
    tex = manifest_inode("chg/tex");
    kk = manifest_inode("chg/kk");

    /* no scene is another input set than a scene */
    assert_int_equal(run_hairgen("-o chg tex.json kk.json -q"), 0);
    assert_true(manifest_inode("chg/tex") != tex);
    assert_true(manifest_inode("chg/kk") != kk);
}

/* A re-run decides most materials without parsing them (a text that
   names no file is keyed by its bytes and the scene's): a file key spelt
   with an escape is still a file, and a strands scene's strand file is
   still an input. */
static void test_a_re_run_still_sees_an_escaped_file_key_and_the_strand_file(void **state) {
    (void)state;
    write_png("base.png", 100);
    write_textured_material("tex.json", "base.png");
    char *text = scratch_text("tex.json");
    char *key = strstr(text, "\"file\"");
    assert_non_null(key);
    char escaped[2048];
    snprintf(escaped, sizeof escaped, "%.*s\"fi\\u006ce\"%s", (int)(key - text), text, key + 6);
    free(text);
    ht_test_write_file(work, "esc.json", escaped);
    assert_int_equal(run_hairgen("-o esc --batch esc.json -q"), 0);
    ino_t esc = manifest_inode("esc/esc");
    assert_int_equal(run_hairgen("-o esc --batch esc.json -q"), 0);
    assert_true(manifest_inode("esc/esc") == esc);
    write_png("base.png", 101);
    assert_int_equal(run_hairgen("-o esc --batch esc.json -q"), 0);
    assert_true(manifest_inode("esc/esc") != esc);

    copy_material("kajiya-kay", "kk.json");
    copy_scene("ratboy", "rat.json");
    char from[PATH_MAX + 64];
    snprintf(from, sizeof from, "%s/scenes/ratboy-mohawk.tfx", repo);
    size_t size = 0;
    char *strands = ht_test_read_all(from, &size);
    assert_non_null(strands);
    char to[600];
    snprintf(to, sizeof to, "%s/ratboy-mohawk.tfx", work);
    FILE *f = fopen(to, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(strands, 1, size, f), size);
    fclose(f);
    const char *args = "-o rat --batch kk.json --scene rat.json -q";
    assert_int_equal(run_hairgen(args), 0);
    ino_t kk = manifest_inode("rat/kk");
    assert_int_equal(run_hairgen(args), 0);
    assert_true(manifest_inode("rat/kk") == kk);
    strands[size - 4] ^= 1; /* the last float's lowest mantissa bit: still a valid strand file */
    f = fopen(to, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(strands, 1, size, f), size);
    fclose(f);
    free(strands);
    assert_int_equal(run_hairgen(args), 0);
    assert_true(manifest_inode("rat/kk") != kk);
}

static void test_depfiles_list_the_material_scene_and_texture_files(void **state) {
    (void)state;
    write_png("my base.png", 90);
    write_textured_material("tex.json", "my base.png");
    copy_material("kajiya-kay", "kk.json");
    copy_scene("furball", "scene.json");
    assert_int_equal(run_hairgen("-o dep tex.json kk.json --scene scene.json -MF deps.d -q"), 0);
    char *d = scratch_text("deps.d");
    /* one rule per bundle, its target the manifest; the space escaped as
       make reads it; hairgen itself last, so a new hairgen rebuilds; an
       empty rule per prerequisite, as GCC's -MP writes */
    char want[5 * PATH_MAX];
    snprintf(want, sizeof want,
             "dep/tex/manifest.json: \\\n  tex.json \\\n  scene.json \\\n  my\\ base.png \\\n  %s\n"
             "\ntex.json:\n\nscene.json:\n\nmy\\ base.png:\n\n%s:\n"
             "\ndep/kk/manifest.json: \\\n  kk.json \\\n  scene.json \\\n  %s\n\nkk.json:\n\nscene.json:\n\n%s:\n",
             hairgen, hairgen, hairgen, hairgen);
    if (strcmp(d, want) != 0) fail_msg("depfile:\n%s\nwanted:\n%s", d, want);
    free(d);
    /* -MD: one beside each bundle; written for skipped bundles too */
    assert_int_equal(run_hairgen("-o dep tex.json kk.json --scene scene.json -MD -q"), 0);
    char *kk = scratch_text("dep/kk.d");
    snprintf(want, sizeof want,
             "dep/kk/manifest.json: \\\n  kk.json \\\n  scene.json \\\n  %s\n\nkk.json:\n\nscene.json:\n\n%s:\n",
             hairgen, hairgen);
    assert_string_equal(kk, want);
    free(kk);
    assert_true(scratch_exists("dep/tex.d"));
    /* the single form's -MD is DIR.d */
    assert_int_equal(run_hairgen("kk.json -o lone/ -MD -q"), 0);
    char *lone = scratch_text("lone.d");
    snprintf(want, sizeof want, "lone/manifest.json: \\\n  kk.json \\\n  %s\n\nkk.json:\n\n%s:\n", hairgen,
             hairgen);
    assert_string_equal(lone, want);
    free(lone);
    assert_int_equal(run_hairgen("kk.json -o lone -MD -MF x.d"), 2);
}

static void set_mtime(const char *name, time_t t) {
    char path[512];
    snprintf(path, sizeof path, "%s/%s", work, name);
    struct timespec times[2] = { { t, 0 }, { t, 0 } };
    if (utimensat(AT_FDCWD, path, times, 0) != 0) fail_msg("%s: cannot set its time", path);
}

/* make -q: 0 when the bundle is up to date, 1 when make would rebuild. */
static int make_question(void) {
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "make -s -q -C %s -f rules.mk >/dev/null 2>&1", work);
    int status = system(cmd);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

static void make_build(void) {
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "make -s -C %s -f rules.mk >/dev/null", work);
    assert_int_equal(system(cmd), 0);
}

static void test_make_rebuilds_exactly_when_a_listed_input_changes(void **state) {
    (void)state;
    write_png("base.png", 70);
    write_textured_material("tex.json", "base.png");
    copy_scene("furball", "scene.json");
    ht_test_write_file(work, "unrelated.txt", "not an input\n");
    char rules[PATH_MAX + 256];
    /* A copy of hairgen, whose time the test sets like the inputs' (the
       depfile lists the program too). */
    char cmd[2 * PATH_MAX];
    snprintf(cmd, sizeof cmd, "cp %s %s/hairgen-copy", hairgen, work);
    assert_int_equal(system(cmd), 0);
    snprintf(rules, sizeof rules,
             "bundle/manifest.json:\n\t%s/hairgen-copy tex.json --scene scene.json -o bundle -MD -q\n"
             "-include bundle.d\n", work);
    ht_test_write_file(work, "rules.mk", rules);
    /* Times are set, not waited for: every input an hour old, the bundle
       ten minutes old after each build; a changed input is then newer. */
    time_t now = time(NULL);
    const char *inputs[] = { "tex.json", "scene.json", "base.png", "hairgen-copy", "unrelated.txt" };
    for (int i = 0; i < 5; i++) set_mtime(inputs[i], now - 3600);
    assert_int_equal(make_question(), 1); /* no bundle yet */
    make_build();
    assert_true(scratch_exists("bundle.d"));
    set_mtime("bundle/manifest.json", now - 600);
    assert_int_equal(make_question(), 0);
    set_mtime("unrelated.txt", now - 60);
    assert_int_equal(make_question(), 0);
    /* make -q answers from the times and the depfile the build wrote: no
       rebuild is needed between the questions (the times are put back). */
    for (int i = 0; i < 4; i++) { /* a new hairgen too */
        set_mtime(inputs[i], now - 60);
        if (make_question() != 1) fail_msg("make does not rebuild when %s changes", inputs[i]);
        set_mtime(inputs[i], now - 3600);
        assert_int_equal(make_question(), 0);
    }
}

/* Row 4 of issue 19: the no-change check looked at the manifest only, so a
   bundle with a file deleted, cut short or changed in place was "up to
   date". Each is regenerated now; a whole bundle is still skipped. */
static void test_no_change_check_regenerates_a_bundle_with_a_missing_cut_or_changed_file(void **state) {
    (void)state;
    copy_material("kajiya-kay", "db.json"); /* the cheapest to generate: any material serves */
    assert_int_equal(run_hairgen("--batch db.json -o out -q"), 0);
    char *frag = scratch_text("out/db/full.frag");
    const char *damage[] = { "rm out/db/full.frag", "truncate -s 100 out/db/albedo.png",
                             "sed -i 's/void main/void mein/' out/db/full.frag", "rm out/db/albedo.png && mkfifo out/db/albedo.png" };
    for (size_t i = 0; i < sizeof damage / sizeof *damage; i++) {
        char cmd[512];
        snprintf(cmd, sizeof cmd, "cd %s && %s", work, damage[i]);
        assert_int_equal(system(cmd), 0);
        ino_t before = manifest_inode("out/db");
        assert_int_equal(run_hairgen("--batch db.json -o out"), 0);
        char *out = scratch_text("out.txt");
        if (strstr(out, "up to date, skipped")) fail_msg("after `%s`: %s", damage[i], out);
        free(out);
        assert_true(manifest_inode("out/db") != before);
        char *again = scratch_text("out/db/full.frag");
        assert_string_equal(again, frag);
        free(again);
        struct stat st;
        char png[512];
        snprintf(png, sizeof png, "%s/out/db/albedo.png", work);
        assert_int_equal(stat(png, &st), 0);
        assert_true(S_ISREG(st.st_mode) && st.st_size > 100);
    }
    free(frag);
    ino_t kept = manifest_inode("out/db");
    assert_int_equal(run_hairgen("--batch db.json -o out"), 0);
    char *out = scratch_text("out.txt");
    assert_non_null(strstr(out, "up to date, skipped"));
    free(out);
    assert_true(manifest_inode("out/db") == kept);
}

static void test_a_bad_material_fails_alone_and_leaves_its_old_bundle(void **state) {
    (void)state;
    copy_material("kajiya-kay", "good.json"); /* the cheapest to generate: any material serves */
    copy_material("kajiya-kay", "bad.json");
    copy_material("kajiya-kay", "also-good.json");
    assert_int_equal(run_hairgen("-o mixed good.json bad.json also-good.json -q"), 0);
    ino_t old_bad = manifest_inode("mixed/bad");
    char *bad_before = scratch_text("mixed/bad/manifest.json");
    ht_test_write_file(work, "bad.json",
                       "{ \"format\": \"hairtier-material/1\", \"name\": \"bad\", \"model\": \"kajiya-kay\",\n"
                       "  \"diffuse\": {\"color\": [0.4,0.3,0.2]},\n"
                       "  \"primary\": {\"color\": [0.9,0.8,0.7], \"exponent\": -5} }\n");
    append_to("good.json", "\n");
    append_to("also-good.json", "\n");
    ino_t good = manifest_inode("mixed/good");
    assert_int_equal(run_hairgen("-o mixed good.json bad.json also-good.json -j 2 -q"), 1);
    char *err = scratch_text("err.txt");
    assert_int_equal(count_lines(err, "hairgen: bad.json: primary.exponent: "), 1);
    assert_int_equal(count_lines(err, "1 of 3 materials failed"), 1);
    assert_int_equal(count_lines(err, "hairgen:"), 2);
    free(err);
    /* the others were regenerated; the bad one's bundle is the old one, whole */
    assert_true(manifest_inode("mixed/good") != good);
    assert_true(scratch_exists("mixed/also-good/manifest.json"));
    assert_true(manifest_inode("mixed/bad") == old_bad);
    char *bad_after = scratch_text("mixed/bad/manifest.json");
    assert_string_equal(bad_before, bad_after);
    free(bad_before);
    free(bad_after);
    /* no temporary left beside the bundles */
    char path[512];
    snprintf(path, sizeof path, "%s/mixed", work);
    DIR *d = opendir(path);
    struct dirent *e;
    while ((e = readdir(d))) assert_null(strstr(e->d_name, ".tmp-"));
    closedir(d);
}

static void test_quiet_prints_nothing_but_errors(void **state) {
    (void)state;
    copy_material("kajiya-kay", "blond.json"); /* the cheapest to generate: any material serves */
    assert_int_equal(run_hairgen("-o quiet blond.json --batch -q"), 0);
    char *out = scratch_text("out.txt"), *err = scratch_text("err.txt");
    assert_string_equal(out, "");
    assert_string_equal(err, "");
    free(out);
    free(err);
    assert_int_equal(run_hairgen("blond.json -o quiet-single -q"), 0);
    out = scratch_text("out.txt");
    assert_string_equal(out, "");
    free(out);
    /* without -q the single form prints its tier table as before */
    assert_int_equal(run_hairgen("blond.json -o quiet-single"), 0);
    out = scratch_text("out.txt");
    assert_non_null(strstr(out, "hairgen: kajiya-kay -> quiet-single\n"));
    free(out);
}

static int glsl_files(const char *dir) {
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        size_t len = strlen(e->d_name);
        if (len > 5 && (strcmp(e->d_name + len - 5, ".vert") == 0 || strcmp(e->d_name + len - 5, ".frag") == 0)) n++;
    }
    closedir(d);
    return n;
}

static void test_each_distinct_shader_text_is_validated_once_per_run(void **state) {
    (void)state;
    /* two materials with different names and the same shading: their
       shader texts are the same */
    copy_material("high-contrast", "first.json");
    copy_material("high-contrast", "second.json");
    char m1[600], m2[600], out_dir[600];
    snprintf(m1, sizeof m1, "%s/first.json", work);
    snprintf(m2, sizeof m2, "%s/second.json", work);
    snprintf(out_dir, sizeof out_dir, "%s/once", work);
    const char *materials[] = { m1, m2 };
    unsigned long parsed0, reused0, parsed1, reused1;
    ht_glsl_validate_counts(&parsed0, &reused0);
    char err[2048];
    ht_batch_result result;
    ht_result r = ht_generate_batch(&(ht_batch_desc){ .materials = materials, .material_count = 2,
                                                      .out_dir = out_dir, .jobs = 1, .force = true },
                                    &result, err, sizeof err);
    if (r != HT_OK) fail_msg("%s", err);
    assert_int_equal(result.generated, 2);
    ht_glsl_validate_counts(&parsed1, &reused1);
    char bundle[700];
    snprintf(bundle, sizeof bundle, "%s/first", out_dir);
    int texts = glsl_files(bundle);
    assert_true(texts >= 4);
    /* every text of the second material was found validated; the first
       parsed at most its own (fewer when an earlier test parsed them) */
    assert_true(reused1 - reused0 >= (unsigned long)texts);
    assert_true(parsed1 - parsed0 <= (unsigned long)texts);
    assert_int_equal((parsed1 - parsed0) + (reused1 - reused0), 2 * texts);
    snprintf(bundle, sizeof bundle, "%s/second", out_dir);
    assert_int_equal(glsl_files(bundle), texts);
}

/* A build farm starts hairgen once per material: it loads no GL (--measure
   dlopens libOSMesa) and no shared libstdc++, whose relocations were most
   of a start (docs/performance.md, "The generator"). ld.so lists what it
   would load and exits (what ldd does). */
static void test_hairgen_starts_without_gl_or_a_shared_libstdcxx(void **state) {
    (void)state;
    char cmd[PATH_MAX + 128];
    snprintf(cmd, sizeof cmd, "cd %s && LD_TRACE_LOADED_OBJECTS=1 %s >out.txt 2>err.txt", work, hairgen);
    int status = system(cmd);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    char *loaded = scratch_text("out.txt");
    if (!strstr(loaded, "libc.so")) fail_msg("no library list from ld.so:\n%s", loaded);
    static const char *const unwanted[] = { "libOSMesa", "libGL", "libEGL", "libLLVM", "libstdc++" };
    size_t count = sizeof unwanted / sizeof unwanted[0];
#if defined(__SANITIZE_ADDRESS__)
    count--; /* UBSan's runtime (libubsan) loads a shared libstdc++ itself */
#endif
    for (size_t i = 0; i < count; i++)
        if (strstr(loaded, unwanted[i])) fail_msg("hairgen loads %s at every start:\n%s", unwanted[i], loaded);
    free(loaded);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_batch_writes_one_bundle_per_material_with_a_progress_line_each, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_batch_bytes_do_not_depend_on_thread_count, setup, teardown),
        cmocka_unit_test_setup_teardown(test_unchanged_inputs_are_skipped_and_force_regenerates, setup, teardown),
        cmocka_unit_test_setup_teardown(test_no_change_check_regenerates_a_bundle_with_a_missing_cut_or_changed_file,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_a_changed_texture_material_or_scene_regenerates_only_its_bundles,
                                        setup, teardown),
        cmocka_unit_test_setup_teardown(test_a_re_run_still_sees_an_escaped_file_key_and_the_strand_file, setup,
                                        teardown),
        cmocka_unit_test_setup_teardown(test_depfiles_list_the_material_scene_and_texture_files, setup, teardown),
        cmocka_unit_test_setup_teardown(test_make_rebuilds_exactly_when_a_listed_input_changes, setup, teardown),
        cmocka_unit_test_setup_teardown(test_a_bad_material_fails_alone_and_leaves_its_old_bundle, setup, teardown),
        cmocka_unit_test_setup_teardown(test_quiet_prints_nothing_but_errors, setup, teardown),
        cmocka_unit_test_setup_teardown(test_each_distinct_shader_text_is_validated_once_per_run, setup, teardown),
        cmocka_unit_test_setup_teardown(test_hairgen_starts_without_gl_or_a_shared_libstdcxx, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

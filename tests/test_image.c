/* test_image.c — PNG round trips, every PNG flavour the reader expands, and
   the failures: missing, empty, truncated, corrupt, not a PNG, a directory
   that cannot take the file, a write that fails half way. */
#include <dirent.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmocka.h>
#include <png.h>
#include <zlib.h>

#include <hairtier/image.h>
#include "rng.h"
#include "support_scratch.h"

static char dir[64];

static int make_dir(void **state) {
    (void)state;
    return ht_test_scratch_create(dir, sizeof dir, "image") ? 0 : -1;
}

static int remove_dir(void **state) {
    (void)state;
    return ht_test_scratch_remove(dir);
}

static const char *in_dir(char *buf, size_t size, const char *name) {
    snprintf(buf, size, "%s/%s", dir, name);
    return buf;
}

static int count_entries(const char *path) {
    DIR *d = opendir(path);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) n++;
    closedir(d);
    return n;
}

static long file_size(const char *path) {
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

static uint8_t *read_all(const char *path, long *size) {
    *size = file_size(path);
    assert_true(*size > 0);
    uint8_t *bytes = malloc((size_t)*size);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    assert_int_equal(fread(bytes, 1, (size_t)*size, f), (size_t)*size);
    fclose(f);
    return bytes;
}

static void write_all(const char *path, const uint8_t *bytes, long size) {
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(bytes, 1, (size_t)size, f), (size_t)size);
    fclose(f);
}

/* Random bytes do not compress: the file is about as large as the pixels. */
static ht_image noise_image(int width, int height, int channels, uint64_t seed) {
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, width, height, channels), HT_OK);
    ht_rng rng = ht_rng_seed(seed);
    for (size_t i = 0; i < (size_t)width * height * channels; i++)
        img.pixels[i] = (uint8_t)(ht_rng_next(&rng) >> 56);
    return img;
}

static void assert_same_image(const ht_image *a, const ht_image *b) {
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    assert_int_equal(a->channels, b->channels);
    assert_memory_equal(a->pixels, b->pixels, (size_t)a->width * a->height * a->channels);
}

/* Reading `path` fails with HT_ERR_IO and a message naming the file. */
static void assert_read_fails(const char *path) {
    ht_image img = { .width = 7, .pixels = (uint8_t *)1 };
    char err[256] = "";
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_ERR_IO);
    assert_null(img.pixels);
    assert_int_equal(img.width, 0);
    assert_non_null(strstr(err, path));
    assert_null(strchr(err, '\n'));
    assert_true(strlen(err) > strlen(path) + 2);
}

static void test_alloc_rejects_bad_sizes(void **state) {
    (void)state;
    ht_image img;
    assert_int_equal(ht_image_alloc(&img, 0, 4, 1), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_image_alloc(&img, 4, -1, 1), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_image_alloc(&img, 4, 4, 0), HT_ERR_INVALID_ARGUMENT);
    assert_int_equal(ht_image_alloc(&img, 4, 4, 5), HT_ERR_INVALID_ARGUMENT);
    assert_null(img.pixels);
    assert_int_equal(ht_image_alloc(&img, 3, 2, 4), HT_OK);
    for (int i = 0; i < 3 * 2 * 4; i++) assert_int_equal(img.pixels[i], 0);
    ht_image_free(&img);
    assert_null(img.pixels);
    ht_image_free(&img); /* twice is harmless */
}

static void test_round_trip_keeps_every_channel_count(void **state) {
    (void)state;
    char path[256], err[256];
    for (int channels = 1; channels <= 4; channels++) {
        ht_image img = noise_image(37, 11, channels, 100 + channels), back;
        in_dir(path, sizeof path, "round.png");
        assert_int_equal(ht_image_write_png(path, &img, err, sizeof err), HT_OK);
        assert_int_equal(ht_image_read_png(path, &back, err, sizeof err), HT_OK);
        assert_same_image(&img, &back);
        ht_image_free(&img);
        ht_image_free(&back);
    }
    assert_int_equal(count_entries(dir), 1); /* no temporary left beside it */
    remove(path);
}

static void test_write_replaces_an_existing_file(void **state) {
    (void)state;
    char path[256], err[256];
    in_dir(path, sizeof path, "replace.png");
    ht_image first = noise_image(8, 8, 3, 1), second = noise_image(5, 9, 1, 2), back;
    assert_int_equal(ht_image_write_png(path, &first, err, sizeof err), HT_OK);
    assert_int_equal(ht_image_write_png(path, &second, err, sizeof err), HT_OK);
    assert_int_equal(ht_image_read_png(path, &back, err, sizeof err), HT_OK);
    assert_same_image(&second, &back);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0644);
    ht_image_free(&first);
    ht_image_free(&second);
    ht_image_free(&back);
    remove(path);
}

static void test_write_rejects_an_invalid_image(void **state) {
    (void)state;
    char path[256], err[256] = "";
    in_dir(path, sizeof path, "invalid.png");
    ht_image none = { .width = 4, .height = 4, .channels = 3, .pixels = NULL };
    assert_int_equal(ht_image_write_png(path, &none, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    uint8_t px[16] = { 0 };
    ht_image five = { .width = 2, .height = 2, .channels = 5, .pixels = px };
    assert_int_equal(ht_image_write_png(path, &five, err, sizeof err), HT_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err, path));
    assert_int_equal(file_size(path), -1);
}

/* ---- PNG flavours written directly with libpng ---- */

typedef struct raw_png {
    int width, height, bit_depth, color_type;
    const uint8_t *rows;      /* packed rows as libpng expects them */
    size_t row_bytes;
    const png_color *palette;
    int palette_size;
    const uint8_t *trns;      /* palette alpha, or NULL */
    int trns_count;
    const png_color_16 *trns_color; /* gray/rgb transparent colour, or NULL */
} raw_png;

static void write_raw_png(const char *path, const raw_png *r) {
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) fail_msg("libpng failed writing the fixture %s", path);
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)r->width, (png_uint_32)r->height, r->bit_depth,
                 r->color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (r->palette) png_set_PLTE(png, info, r->palette, r->palette_size);
    if (r->trns || r->trns_color)
        png_set_tRNS(png, info, r->trns, r->trns_count, r->trns_color);
    png_write_info(png, info);
    for (int y = 0; y < r->height; y++) png_write_row(png, r->rows + r->row_bytes * (size_t)y);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(f);
}

/* Appends one PNG chunk (length, type, data, CRC over type and data). */
static void put_chunk(FILE *f, const char type[4], const uint8_t *data, uint32_t size) {
    const uint8_t length[4] = { (uint8_t)(size >> 24), (uint8_t)(size >> 16), (uint8_t)(size >> 8), (uint8_t)size };
    uLong crc = crc32(0L, (const Bytef *)type, 4);
    crc = crc32(crc, data, size);
    const uint8_t crc_bytes[4] = { (uint8_t)(crc >> 24), (uint8_t)(crc >> 16), (uint8_t)(crc >> 8), (uint8_t)crc };
    fwrite(length, 1, 4, f);
    fwrite(type, 1, 4, f);
    if (size) fwrite(data, 1, size, f);
    fwrite(crc_bytes, 1, 4, f);
}

static void test_read_refuses_a_header_claiming_a_huge_image_before_allocating(void **state) {
    (void)state;
    char path[256];
    in_dir(path, sizeof path, "huge.png");
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    /* A well-formed chunk list whose header claims 100000 x 100000 RGBA
       (40 GB if a reader believed it) over a few bytes of image data. */
    static const uint8_t signature[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n' };
    fwrite(signature, 1, sizeof signature, f);
    const uint8_t ihdr[13] = { 0, 1, 0x86, 0xA0, 0, 1, 0x86, 0xA0, 8, PNG_COLOR_TYPE_RGB_ALPHA, 0, 0, 0 };
    put_chunk(f, "IHDR", ihdr, sizeof ihdr);
    uint8_t zeros[64] = { 0 }, packed[128];
    uLongf packed_size = sizeof packed;
    assert_int_equal(compress(packed, &packed_size, zeros, sizeof zeros), Z_OK);
    put_chunk(f, "IDAT", packed, (uint32_t)packed_size);
    put_chunk(f, "IEND", NULL, 0);
    fclose(f);
    ht_image img = { 0 };
    char err[256] = "";
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_ERR_IO);
    assert_null(img.pixels);
    if (!strstr(err, "too large")) fail_msg("unexpected error: %s", err);
    remove(path);
}

/* Peak virtual memory of this process in KiB (/proc/self/status VmPeak):
   a reservation counts even if its pages are never touched. */
static long vm_peak_kib(void) {
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return -1;
    char line[256];
    long kib = -1;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "VmPeak: %ld kB", &kib) == 1) break;
    fclose(f);
    return kib;
}

/* A 44-byte file: a valid IHDR, then a zTXt chunk whose length claims 2 GiB
   over 3 bytes. Read in a child so the peak is its own: a reader that
   believed the claim reserves 2 GiB (the defect: libpng allocated and
   zeroed it before finding the file truncated); one that bounds chunk
   memory stays within a few MiB. */
static void test_read_bounds_memory_when_a_chunk_claims_two_gibibytes(void **state) {
    (void)state;
    char path[256];
    in_dir(path, sizeof path, "ztxt.png");
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    static const uint8_t signature[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n' };
    fwrite(signature, 1, sizeof signature, f);
    const uint8_t ihdr[13] = { 0, 0, 0, 4, 0, 0, 0, 4, 8, PNG_COLOR_TYPE_RGB_ALPHA, 0, 0, 0 };
    put_chunk(f, "IHDR", ihdr, sizeof ihdr);
    static const uint8_t claim[8] = { 0x7F, 0xFF, 0xFF, 0xFF, 'z', 'T', 'X', 't' };
    fwrite(claim, 1, sizeof claim, f);
    fwrite("k\0\0", 1, 3, f);
    fclose(f);
    assert_int_equal(file_size(path), 44);

    int pipe_fd[2];
    assert_int_equal(pipe(pipe_fd), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        close(pipe_fd[0]);
        long before = vm_peak_kib();
        ht_image img = { 0 };
        char err[256] = "";
        ht_result r = ht_image_read_png(path, &img, err, sizeof err);
        long grown = vm_peak_kib() - before;
        dprintf(pipe_fd[1], "%d %ld %s", (int)r, grown, err);
        _exit(0);
    }
    close(pipe_fd[1]);
    char line[512] = "";
    ssize_t got = read(pipe_fd[0], line, sizeof line - 1);
    close(pipe_fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    assert_true(WIFEXITED(status));
    assert_true(got > 0);
    line[got] = '\0';
    int result = -1;
    long grown_kib = -1;
    assert_int_equal(sscanf(line, "%d %ld", &result, &grown_kib), 2);
    if (result != HT_ERR_IO || !strstr(line, "truncated")) fail_msg("unexpected result: %s", line);
    if (grown_kib < 0 || grown_kib > 64 * 1024) fail_msg("peak memory grew by %ld KiB reading it", grown_kib);
    remove(path);
}

static void test_read_refuses_what_is_not_a_regular_file(void **state) {
    (void)state;
    char path[256];
    char err[256] = "";
    ht_image img = { 0 };
    in_dir(path, sizeof path, "fifo.png");
    assert_int_equal(mkfifo(path, 0600), 0);
    /* Would block forever waiting for a writer if the reader opened it blindly. */
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_ERR_IO);
    if (!strstr(err, "not a regular file (a FIFO)") || !strstr(err, path)) fail_msg("unexpected error: %s", err);
    remove(path);
    in_dir(path, sizeof path, "folder.png");
    assert_int_equal(mkdir(path, 0700), 0);
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_ERR_IO);
    if (!strstr(err, "not a regular file (a directory)")) fail_msg("unexpected error: %s", err);
    rmdir(path);
    assert_int_equal(ht_image_read_png("/dev/zero", &img, err, sizeof err), HT_ERR_IO);
    if (!strstr(err, "/dev/zero: not a regular file (a character device)")) fail_msg("unexpected error: %s", err);
    assert_null(img.pixels);
}

static void test_read_expands_palette_with_transparency(void **state) {
    (void)state;
    const png_color palette[3] = { { 10, 20, 30 }, { 200, 100, 50 }, { 1, 2, 3 } };
    const uint8_t trns[2] = { 0, 128 };             /* entry 2 is opaque */
    const uint8_t rows[2 * 2] = { 0, 1, 2, 1 };     /* 8-bit indices */
    char path[256], err[256];
    in_dir(path, sizeof path, "palette.png");
    write_raw_png(path, &(raw_png){ .width = 2, .height = 2, .bit_depth = 8,
                                    .color_type = PNG_COLOR_TYPE_PALETTE, .rows = rows,
                                    .row_bytes = 2, .palette = palette, .palette_size = 3,
                                    .trns = trns, .trns_count = 2 });
    ht_image img;
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_OK);
    assert_int_equal(img.channels, 4);
    for (int i = 0; i < 4; i++) {
        int index = rows[i];
        assert_int_equal(img.pixels[4 * i + 0], palette[index].red);
        assert_int_equal(img.pixels[4 * i + 1], palette[index].green);
        assert_int_equal(img.pixels[4 * i + 2], palette[index].blue);
        assert_int_equal(img.pixels[4 * i + 3], index < 2 ? trns[index] : 255);
    }
    ht_image_free(&img);
    remove(path);
}

static void test_read_expands_two_bit_gray(void **state) {
    (void)state;
    /* 2-bit gray levels 0,1,2,3 packed in one byte: 00 01 10 11 */
    const uint8_t rows[1] = { 0x1B };
    char path[256], err[256];
    in_dir(path, sizeof path, "gray2.png");
    write_raw_png(path, &(raw_png){ .width = 4, .height = 1, .bit_depth = 2,
                                    .color_type = PNG_COLOR_TYPE_GRAY, .rows = rows,
                                    .row_bytes = 1 });
    ht_image img;
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_OK);
    assert_int_equal(img.channels, 1);
    assert_int_equal(img.width, 4);
    for (int level = 0; level < 4; level++) assert_int_equal(img.pixels[level], level * 255 / 3);
    ht_image_free(&img);
    remove(path);
}

static void test_read_turns_gray_transparent_colour_into_alpha(void **state) {
    (void)state;
    const uint8_t rows[3] = { 7, 99, 7 };
    const png_color_16 clear = { .gray = 7 };
    char path[256], err[256];
    in_dir(path, sizeof path, "gray-trns.png");
    write_raw_png(path, &(raw_png){ .width = 3, .height = 1, .bit_depth = 8,
                                    .color_type = PNG_COLOR_TYPE_GRAY, .rows = rows,
                                    .row_bytes = 3, .trns_color = &clear });
    ht_image img;
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_OK);
    assert_int_equal(img.channels, 2);
    const uint8_t expected[6] = { 7, 0, 99, 255, 7, 0 };
    assert_memory_equal(img.pixels, expected, 6);
    ht_image_free(&img);
    remove(path);
}

static void test_read_strips_sixteen_bits_to_eight(void **state) {
    (void)state;
    /* RGB 16-bit big endian: 0x12ff 0xab00 0xffff */
    const uint8_t rows[6] = { 0x12, 0xff, 0xab, 0x00, 0xff, 0xff };
    char path[256], err[256];
    in_dir(path, sizeof path, "rgb16.png");
    write_raw_png(path, &(raw_png){ .width = 1, .height = 1, .bit_depth = 16,
                                    .color_type = PNG_COLOR_TYPE_RGB, .rows = rows,
                                    .row_bytes = 6 });
    ht_image img;
    assert_int_equal(ht_image_read_png(path, &img, err, sizeof err), HT_OK);
    assert_int_equal(img.channels, 3);
    assert_int_equal(img.pixels[0], 0x12);
    assert_int_equal(img.pixels[1], 0xab);
    assert_int_equal(img.pixels[2], 0xff);
    ht_image_free(&img);
    remove(path);
}

/* ---- broken files ---- */

static void test_read_fails_on_missing_file(void **state) {
    (void)state;
    char path[256];
    assert_read_fails(in_dir(path, sizeof path, "no-such-file.png"));
}

static void test_read_fails_on_empty_file_and_text(void **state) {
    (void)state;
    char path[256];
    in_dir(path, sizeof path, "empty.png");
    write_all(path, (const uint8_t *)"", 0);
    assert_read_fails(path);
    const char *text = "{ \"this\": \"is json, not a PNG\" }\n";
    write_all(path, (const uint8_t *)text, (long)strlen(text));
    assert_read_fails(path);
    remove(path);
    assert_read_fails(dir); /* a directory is not a PNG either */
}

static void test_read_fails_on_every_truncation(void **state) {
    (void)state;
    char good[256], cut[256], err[256];
    in_dir(good, sizeof good, "good.png");
    in_dir(cut, sizeof cut, "cut.png");
    ht_image img = noise_image(32, 32, 3, 7);
    assert_int_equal(ht_image_write_png(good, &img, err, sizeof err), HT_OK);
    ht_image_free(&img);
    long size;
    uint8_t *bytes = read_all(good, &size);
    /* inside the signature, the header, the image data, and the last byte of IEND */
    const long lengths[] = { 1, 7, 8, 20, 40, size / 2, size - 13, size - 1 };
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
        write_all(cut, bytes, lengths[i]);
        assert_read_fails(cut);
    }
    free(bytes);
    remove(good);
    remove(cut);
}

static void test_read_fails_on_corrupt_image_data(void **state) {
    (void)state;
    char path[256], err[256];
    in_dir(path, sizeof path, "corrupt.png");
    ht_image img = noise_image(32, 32, 4, 9);
    assert_int_equal(ht_image_write_png(path, &img, err, sizeof err), HT_OK);
    ht_image_free(&img);
    long size;
    uint8_t *good = read_all(path, &size);
    uint8_t *bytes = malloc((size_t)size);
    memcpy(bytes, good, (size_t)size);
    for (long at = size / 3; at < size / 3 + 16; at++) bytes[at] ^= 0x5a;
    write_all(path, bytes, size);
    assert_read_fails(path);
    /* the header chunk's width field: its CRC no longer matches */
    memcpy(bytes, good, (size_t)size);
    bytes[16] = bytes[17] = bytes[18] = bytes[19] = 0;
    write_all(path, bytes, size);
    assert_read_fails(path);
    free(good);
    free(bytes);
    remove(path);
}

/* ---- failed writes leave nothing behind ---- */

static void test_write_into_missing_directory_leaves_nothing(void **state) {
    (void)state;
    char path[256], err[256] = "";
    in_dir(path, sizeof path, "missing/out.png");
    ht_image img = noise_image(4, 4, 1, 3);
    assert_int_equal(ht_image_write_png(path, &img, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, path));
    assert_int_equal(count_entries(dir), 0);
    ht_image_free(&img);
}

static void test_write_into_read_only_directory_leaves_nothing(void **state) {
    (void)state;
    /* Permission bits do not bind root; the file-size limit test below
       covers failing writes for every user. */
    if (geteuid() == 0) skip();
    char sub[200], path[256], err[256] = "";
    in_dir(sub, sizeof sub, "read-only");
    assert_int_equal(mkdir(sub, 0555), 0);
    snprintf(path, sizeof path, "%s/out.png", sub);
    ht_image img = noise_image(4, 4, 1, 3);
    assert_int_equal(ht_image_write_png(path, &img, err, sizeof err), HT_ERR_IO);
    assert_non_null(strstr(err, path));
    assert_int_equal(count_entries(sub), 0);
    ht_image_free(&img);
    rmdir(sub);
}

static void test_write_failing_half_way_keeps_the_old_file(void **state) {
    (void)state;
    char path[256], err[256] = "";
    in_dir(path, sizeof path, "limited.png");
    ht_image old = noise_image(8, 8, 3, 4), big = noise_image(256, 256, 4, 5), back;
    assert_int_equal(ht_image_write_png(path, &old, err, sizeof err), HT_OK);

    /* Over the file size limit write(2) fails with EFBIG once SIGXFSZ is ignored. */
    struct rlimit saved, limit;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &saved), 0);
    limit = saved;
    limit.rlim_cur = 64 * 1024;
    void (*saved_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &limit), 0);
    ht_result r = ht_image_write_png(path, &big, err, sizeof err);
    setrlimit(RLIMIT_FSIZE, &saved);
    signal(SIGXFSZ, saved_handler);

    assert_int_equal(r, HT_ERR_IO);
    assert_non_null(strstr(err, path));
    assert_int_equal(count_entries(dir), 1);
    assert_int_equal(ht_image_read_png(path, &back, err, sizeof err), HT_OK);
    assert_same_image(&old, &back);
    ht_image_free(&old);
    ht_image_free(&big);
    ht_image_free(&back);
    remove(path);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_alloc_rejects_bad_sizes),
        cmocka_unit_test(test_round_trip_keeps_every_channel_count),
        cmocka_unit_test(test_write_replaces_an_existing_file),
        cmocka_unit_test(test_write_rejects_an_invalid_image),
        cmocka_unit_test(test_read_expands_palette_with_transparency),
        cmocka_unit_test(test_read_expands_two_bit_gray),
        cmocka_unit_test(test_read_turns_gray_transparent_colour_into_alpha),
        cmocka_unit_test(test_read_strips_sixteen_bits_to_eight),
        cmocka_unit_test(test_read_fails_on_missing_file),
        cmocka_unit_test(test_read_fails_on_empty_file_and_text),
        cmocka_unit_test(test_read_fails_on_every_truncation),
        cmocka_unit_test(test_read_refuses_a_header_claiming_a_huge_image_before_allocating),
        cmocka_unit_test(test_read_fails_on_corrupt_image_data),
        cmocka_unit_test(test_read_bounds_memory_when_a_chunk_claims_two_gibibytes),
        cmocka_unit_test(test_read_refuses_what_is_not_a_regular_file),
        cmocka_unit_test(test_write_into_missing_directory_leaves_nothing),
        cmocka_unit_test(test_write_into_read_only_directory_leaves_nothing),
        cmocka_unit_test(test_write_failing_half_way_keeps_the_old_file),
    };
    return cmocka_run_group_tests(tests, make_dir, remove_dir);
}

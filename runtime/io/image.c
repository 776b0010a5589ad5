/* image.c — 8-bit images and PNG files through libpng.

   libpng reports errors by longjmp. Each libpng session keeps everything it
   must release (FILE, libpng structs, pixel buffers) in a state struct owned
   by the caller, and the setjmp lives in a small function whose own locals
   never change after setjmp; after a longjmp the caller frees what the
   state holds, so no error path leaks and no local is left indeterminate. */
#include <hairtier/image.h>

#include <errno.h>
#include <limits.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>

#include "errfmt.h"
#include "file_atomic.h"
#include "file_open.h"

/* Bytes of a width x height x channels image, 0 when it does not fit. */
static size_t image_bytes(int width, int height, int channels) {
    if (width < 1 || height < 1 || channels < 1 || channels > 4) return 0;
    size_t row = (size_t)width * (size_t)channels;
    if ((size_t)height > SIZE_MAX / row) return 0;
    return row * (size_t)height;
}

ht_result ht_image_alloc(ht_image *img, int width, int height, int channels) {
    if (!img) return HT_ERR_INVALID_ARGUMENT;
    *img = (ht_image){ 0 };
    size_t bytes = image_bytes(width, height, channels);
    if (bytes == 0) return HT_ERR_INVALID_ARGUMENT;
    img->pixels = calloc(bytes, 1);
    if (!img->pixels) return HT_ERR_OUT_OF_MEMORY;
    img->width = width;
    img->height = height;
    img->channels = channels;
    return HT_OK;
}

void ht_image_free(ht_image *img) {
    if (!img) return;
    free(img->pixels);
    *img = (ht_image){ 0 };
}

/* ---- what a libpng session must clean up, and its error line ---- */

typedef struct png_session {
    FILE *file;
    png_structp png;
    png_infop info;
    uint8_t *pixels;
    png_bytep *rows;
    char message[160];   /* libpng's or our own reason, without the path */
} png_session;

static void on_png_error(png_structp png, png_const_charp message) {
    png_session *s = png_get_error_ptr(png);
    if (!s->message[0]) snprintf(s->message, sizeof s->message, "%s", message);
    png_longjmp(png, 1);
}

/* Warnings (an ancillary chunk with a bad CRC, an odd sRGB profile) do not
   stop reading; libpng would print them to stderr, a library must not. */
static void on_png_warning(png_structp png, png_const_charp message) {
    (void)png;
    (void)message;
}

/* fread/fwrite through our own callbacks, to tell a truncated file from a
   failing device. */
static void read_bytes(png_structp png, png_bytep data, size_t length) {
    png_session *s = png_get_io_ptr(png);
    if (fread(data, 1, length, s->file) == length) return;
    if (feof(s->file)) png_error(png, "file is truncated");
    snprintf(s->message, sizeof s->message, "read failed: %s", strerror(errno));
    png_error(png, s->message);
}

static void write_bytes(png_structp png, png_bytep data, size_t length) {
    png_session *s = png_get_io_ptr(png);
    if (fwrite(data, 1, length, s->file) == length) return;
    snprintf(s->message, sizeof s->message, "write failed: %s", strerror(errno));
    png_error(png, s->message);
}

static void flush_bytes(png_structp png) {
    png_session *s = png_get_io_ptr(png);
    if (fflush(s->file) != 0) {
        snprintf(s->message, sizeof s->message, "write failed: %s", strerror(errno));
        png_error(png, s->message);
    }
}

/* ---- reading ---- */

/* The libpng part of reading, after the signature was checked. Returns 0 on
   success with s->pixels filled, nonzero after a libpng error. */
static int read_body(png_session *s, ht_image *out) {
    if (setjmp(png_jmpbuf(s->png))) return 1;

    png_set_read_fn(s->png, s, read_bytes);
    png_set_sig_bytes(s->png, 8);
    /* Memory is bounded by the image limits, not by what a chunk header
       claims: without these a 44-byte file whose zTXt says 2 GiB made
       libpng allocate and zero 2 GiB before finding the file truncated.
       Text, colour-profile and unknown chunks carry nothing a texture
       needs, so they are skipped unread into memory. */
    png_set_user_limits(s->png, HT_IMAGE_MAX_SIDE, HT_IMAGE_MAX_SIDE);
    png_set_chunk_malloc_max(s->png, HT_IMAGE_MAX_CHUNK_BYTES);
    png_set_chunk_cache_max(s->png, 64);
    static const png_byte ignored[] = { 't', 'E', 'X', 't', '\0', 'z', 'T', 'X', 't', '\0',
                                        'i', 'T', 'X', 't', '\0', 'i', 'C', 'C', 'P', '\0' };
    png_set_keep_unknown_chunks(s->png, PNG_HANDLE_CHUNK_NEVER, NULL, 0);
    png_set_keep_unknown_chunks(s->png, PNG_HANDLE_CHUNK_NEVER, ignored, 4);
    png_read_info(s->png, s->info);

    png_uint_32 width = 0, height = 0;
    int bit_depth = 0, color_type = 0;
    png_get_IHDR(s->png, s->info, &width, &height, &bit_depth, &color_type, NULL, NULL, NULL);

    if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(s->png);
    if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(s->png);
    if (png_get_valid(s->png, s->info, PNG_INFO_tRNS)) png_set_tRNS_to_alpha(s->png);
    if (bit_depth == 16) png_set_strip_16(s->png);
    png_set_interlace_handling(s->png);
    png_read_update_info(s->png, s->info);

    int channels = png_get_channels(s->png, s->info);
    if (width > INT_MAX || height > INT_MAX || (uint64_t)width * height > HT_IMAGE_MAX_PIXELS)
        png_error(s->png, "image is too large");
    size_t bytes = image_bytes((int)width, (int)height, channels);
    size_t row_bytes = (size_t)width * (size_t)channels;
    if (bytes == 0 || png_get_rowbytes(s->png, s->info) != row_bytes)
        png_error(s->png, "unsupported pixel layout");

    s->pixels = malloc(bytes);
    s->rows = malloc(sizeof *s->rows * height);
    if (!s->pixels || !s->rows) png_error(s->png, "out of memory");
    for (png_uint_32 y = 0; y < height; y++) s->rows[y] = s->pixels + row_bytes * y;
    png_read_image(s->png, s->rows);
    /* Reads the chunks after the image data up to IEND: a file cut after
       its last IDAT is still truncated. */
    png_read_end(s->png, NULL);

    out->width = (int)width;
    out->height = (int)height;
    out->channels = channels;
    return 0;
}

/* Decodes the PNG `file` holds (a file or a memory stream) and closes it;
   `name` labels the error line. */
static ht_result read_png_stream(FILE *file, const char *name, ht_image *out, char *err, size_t err_size) {
    png_session s = { .file = file };
    ht_result result = HT_ERR_IO;
    uint8_t signature[8];
    size_t got = fread(signature, 1, sizeof signature, s.file);
    if (got != sizeof signature || png_sig_cmp(signature, 0, sizeof signature) != 0) {
        if (ferror(s.file))
            snprintf(s.message, sizeof s.message, "cannot read: %s", strerror(errno));
        else
            snprintf(s.message, sizeof s.message, "%s", got == 0 ? "file is empty" : "not a PNG file");
        goto done;
    }
    s.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s, on_png_error, on_png_warning);
    if (s.png) s.info = png_create_info_struct(s.png);
    if (!s.png || !s.info) {
        snprintf(s.message, sizeof s.message, "out of memory");
        result = HT_ERR_OUT_OF_MEMORY;
        goto done;
    }
    if (read_body(&s, out) == 0) {
        out->pixels = s.pixels;
        s.pixels = NULL;
        result = HT_OK;
    } else {
        *out = (ht_image){ 0 };
    }

done:
    if (s.png) png_destroy_read_struct(&s.png, s.info ? &s.info : NULL, NULL);
    free(s.rows);
    free(s.pixels);
    fclose(s.file);
    if (result != HT_OK) ht_set_error(err, err_size, "%s: %s", name, s.message);
    return result;
}

ht_result ht_image_read_png(const char *path, ht_image *out, char *err, size_t err_size) {
    if (!path || !out) {
        ht_set_error(err, err_size, "ht_image_read_png: path and out are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    *out = (ht_image){ 0 };
    FILE *f;
    if (ht_file_open_regular(path, HT_FILE_MAX_PNG, &f, NULL, err, err_size) != HT_OK) return HT_ERR_IO;
    return read_png_stream(f, path, out, err, err_size);
}

ht_result ht_image_decode_png(const char *name, const void *data, size_t size, ht_image *out, char *err,
                              size_t err_size) {
    if (!name || !out || (!data && size)) {
        ht_set_error(err, err_size, "ht_image_decode_png: name, out and the data are required");
        return HT_ERR_INVALID_ARGUMENT;
    }
    *out = (ht_image){ 0 };
    if (ht_file_check_size(name, size, HT_FILE_MAX_PNG, err, err_size) != HT_OK) return HT_ERR_IO;
    if (size == 0) {
        ht_set_error(err, err_size, "%s: file is empty", name);
        return HT_ERR_IO;
    }
    /* A read-only stream over the bytes: the decoder, its limits and its
       messages ("file is truncated") are the file reader's own. fmemopen
       takes a non-const buffer but "rb" never writes to it. */
    FILE *f = fmemopen((void *)(uintptr_t)data, size, "rb");
    if (!f) {
        ht_set_error(err, err_size, "%s: cannot read: %s", name, strerror(errno));
        return HT_ERR_IO;
    }
    return read_png_stream(f, name, out, err, err_size);
}

/* ---- writing ---- */

static int write_body(png_session *s, const ht_image *img) {
    static const int color_types[5] = { 0, PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                        PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA };
    if (setjmp(png_jmpbuf(s->png))) return 1;

    png_set_write_fn(s->png, s, write_bytes, flush_bytes);
    png_set_IHDR(s->png, s->info, (png_uint_32)img->width, (png_uint_32)img->height, 8,
                 color_types[img->channels], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    /* Speed over size: zlib level 1 with the "up" filter alone encodes a
       bundle's textures about 3.5x faster than level 6 with adaptive
       filters (hairgen's largest cost); the files grow, the texels are the
       same (lossless either way). */
    png_set_compression_level(s->png, 1);
    png_set_filter(s->png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
    png_write_info(s->png, s->info);
    size_t row_bytes = (size_t)img->width * (size_t)img->channels;
    for (int y = 0; y < img->height; y++)
        png_write_row(s->png, img->pixels + row_bytes * (size_t)y);
    png_write_end(s->png, NULL);
    return 0;
}

/* ht_file_writer_fn: img as a PNG into f. */
static bool write_png_to(FILE *f, void *ctx, char *why, size_t why_size) {
    png_session s = { .file = f };
    s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &s, on_png_error, on_png_warning);
    if (s.png) s.info = png_create_info_struct(s.png);
    bool ok = s.png && s.info;
    if (!ok) snprintf(s.message, sizeof s.message, "out of memory");
    else ok = write_body(&s, ctx) == 0;
    if (!ok) snprintf(why, why_size, "%s", s.message);
    if (s.png) png_destroy_write_struct(&s.png, s.info ? &s.info : NULL);
    return ok;
}

ht_result ht_image_write_png(const char *path, const ht_image *img, char *err, size_t err_size) {
    if (!path || !img || !img->pixels || image_bytes(img->width, img->height, img->channels) == 0) {
        ht_set_error(err, err_size, "%s: not a valid image to write", path ? path : "(null)");
        return HT_ERR_INVALID_ARGUMENT;
    }
    return ht_file_write_atomic(path, write_png_to, (void *)img, err, err_size);
}

ht_result ht_image_encode_png(const ht_image *img, unsigned char **data, size_t *size, char *err, size_t err_size) {
    *data = NULL;
    *size = 0;
    if (!img || !img->pixels || image_bytes(img->width, img->height, img->channels) == 0) {
        ht_set_error(err, err_size, "ht_image_encode_png: not a valid image to encode");
        return HT_ERR_INVALID_ARGUMENT;
    }
    /* The file writer's body over a memory stream: the same bytes. */
    char *buf = NULL;
    size_t len = 0;
    png_session s = { .file = open_memstream(&buf, &len) };
    ht_result result = HT_ERR_OUT_OF_MEMORY;
    if (!s.file) goto done;
    s.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &s, on_png_error, on_png_warning);
    if (s.png) s.info = png_create_info_struct(s.png);
    if (!s.png || !s.info || write_body(&s, img) != 0) goto done;
    result = HT_OK;
done:
    if (s.png) png_destroy_write_struct(&s.png, s.info ? &s.info : NULL);
    if (s.file && fclose(s.file) != 0) result = HT_ERR_OUT_OF_MEMORY;
    if (result == HT_OK) {
        *data = (unsigned char *)buf;
        *size = len;
    } else {
        free(buf);
        ht_set_error(err, err_size, "ht_image_encode_png: %s", s.message[0] ? s.message : "out of memory");
    }
    return result;
}

/* The size a PNG's header declares, read before decoding: a corrupt or
   hostile header must not make us allocate what it claims. False when the
   bytes do not start like a PNG (the decoder then says why). */
bool ht_image_png_header_size_bytes(const void *data, size_t size, uint32_t *width, uint32_t *height) {
    static const unsigned char signature[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    const unsigned char *h = data;
    if (!h || size < 24 || memcmp(h, signature, sizeof signature) != 0 || memcmp(h + 12, "IHDR", 4) != 0)
        return false;
    *width = (uint32_t)h[16] << 24 | (uint32_t)h[17] << 16 | (uint32_t)h[18] << 8 | h[19];
    *height = (uint32_t)h[20] << 24 | (uint32_t)h[21] << 16 | (uint32_t)h[22] << 8 | h[23];
    return true;
}

bool ht_image_png_header_size(const char *path, uint32_t *width, uint32_t *height) {
    unsigned char h[24];
    FILE *f;
    char ignored[8];
    /* Regular files only: fopen on a FIFO would wait for a writer forever;
       ht_image_read_png then says what the file is. */
    if (ht_file_open_regular(path, HT_FILE_MAX_PNG, &f, NULL, ignored, sizeof ignored) != HT_OK) return false;
    size_t n = fread(h, 1, sizeof h, f);
    fclose(f);
    return ht_image_png_header_size_bytes(h, n, width, height);
}

/* png_encode.c — the PNG files of a bundle (hairgen_internal.h), written
   whole in memory: every row "up"-filtered (the first row unfiltered, which
   is what "up" means there) into one buffer, that buffer compressed in one
   call by libdeflate at level 1, and the PNG chunks (IHDR, one IDAT, IEND)
   laid around it: libdeflate compresses the whole image at once, libpng
   with zlib row by row, at about twice the instructions and larger files
   (docs/performance.md). Any PNG reader
   decodes these; the runtime reads them with libpng (runtime/io/image.c). */
#include <libdeflate.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "hairgen_internal.h"

static void put_u32(unsigned char *p, uint32_t v) {
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* A chunk's length and type at p, its data already at p + 8; writes its
   CRC after the data. The end of the chunk. */
static unsigned char *close_chunk(unsigned char *p, const char type[4], size_t data_size) {
    put_u32(p, (uint32_t)data_size);
    memcpy(p + 4, type, 4);
    put_u32(p + 8 + data_size, (uint32_t)libdeflate_crc32(0, p + 4, 4 + data_size));
    return p + 12 + data_size;
}

/* Row y of img, filter byte first, into out: row 0 as it is (type 0), every
   other row minus the one above (type 2, "up"). restrict lets the compiler
   vectorise the subtraction. */
static void filter_row(unsigned char *restrict out, const uint8_t *restrict row, const uint8_t *restrict above,
                       size_t row_bytes) {
    if (!above) {
        out[0] = 0;
        memcpy(out + 1, row, row_bytes);
        return;
    }
    out[0] = 2;
    for (size_t x = 0; x < row_bytes; x++) out[1 + x] = (unsigned char)(row[x] - above[x]);
}

ht_result ht_png_encode(const ht_image *img, unsigned char **data, size_t *size) {
    static const unsigned char signature[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    static const unsigned char colour_types[5] = { 0, 0, 4, 2, 6 }; /* grey, grey+alpha, rgb, rgba */
    *data = NULL;
    *size = 0;
    if (!img || !img->pixels || img->width < 1 || img->height < 1 || img->channels < 1 || img->channels > 4 ||
        (uint64_t)img->width > HT_IMAGE_MAX_SIDE || (uint64_t)img->height > HT_IMAGE_MAX_SIDE ||
        (uint64_t)img->width * (uint64_t)img->height > HT_IMAGE_MAX_PIXELS)
        return HT_ERR_INVALID_ARGUMENT;
    const size_t row_bytes = (size_t)img->width * (size_t)img->channels;
    const size_t filtered_size = (row_bytes + 1) * (size_t)img->height;
    unsigned char *filtered = malloc(filtered_size);
    struct libdeflate_compressor *c = libdeflate_alloc_compressor(1);
    unsigned char *out = NULL;
    ht_result r = HT_ERR_OUT_OF_MEMORY;
    if (!filtered || !c) goto done;
    for (int y = 0; y < img->height; y++) {
        const uint8_t *row = img->pixels + row_bytes * (size_t)y;
        filter_row(filtered + (row_bytes + 1) * (size_t)y, row, y ? row - row_bytes : NULL, row_bytes);
    }
    /* signature, IHDR (12 + 13), IDAT (12 + stream), IEND (12) */
    const size_t bound = libdeflate_zlib_compress_bound(c, filtered_size);
    out = malloc(sizeof signature + 25 + 12 + bound + 12);
    if (!out) goto done;
    unsigned char *p = out;
    memcpy(p, signature, sizeof signature);
    p += sizeof signature;
    put_u32(p + 8, (uint32_t)img->width);
    put_u32(p + 12, (uint32_t)img->height);
    memcpy(p + 16, (const unsigned char[5]){ 8, colour_types[img->channels], 0, 0, 0 }, 5);
    p = close_chunk(p, "IHDR", 13);
    const size_t stream = libdeflate_zlib_compress(c, filtered, filtered_size, p + 8, bound);
    /* Within the bound by libdeflate's promise, and a chunk holds at most
       2^31 - 1 bytes (a bundle texture compresses to far less). */
    if (stream == 0 || stream > 0x7fffffffu) {
        r = HT_ERR_INVALID_ARGUMENT;
        goto done;
    }
    p = close_chunk(p, "IDAT", stream);
    p = close_chunk(p, "IEND", 0);
    *data = out;
    *size = (size_t)(p - out);
    out = NULL;
    r = HT_OK;
done:
    free(out);
    libdeflate_free_compressor(c);
    free(filtered);
    return r;
}

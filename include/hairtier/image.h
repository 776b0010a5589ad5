/* image.h — 8-bit images and PNG files (libpng), shared by hairgen (textures,
   LUTs), the runtime (loading a bundle) and hairview (writing frames).
   Public: installed beside hairtier.h (hairgen.h's generated files hold
   ht_images); it includes only hairtier.h.

   Usage:
       ht_image img;
       char err[512];
       if (ht_image_read_png("out/bundle/albedo.png", &img, err, sizeof err) != HT_OK) {
           puts(err);   // "PATH: not a PNG file", "PATH: file is truncated", ...
           return;
       }
       printf("%dx%d, %d channels\n", img.width, img.height, img.channels);
       ht_image_free(&img); */
#ifndef HT_IMAGE_H
#define HT_IMAGE_H

#include "export.h"

#include <stddef.h>
#include <stdint.h>

#include "hairtier.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ht_image {
    int width, height;
    int channels;       /* 1 gray, 2 gray+alpha, 3 rgb, 4 rgba */
    uint8_t *pixels;    /* rows top to bottom, tightly packed */
} ht_image;

/* The most pixels a PNG may declare: 64 Mi, 256 MiB as RGBA (the largest
   texture hairgen writes is a 256 x 65536 LUT atlas). A header claiming more
   is refused before anything is allocated. */
#define HT_IMAGE_MAX_PIXELS (64u * 1024u * 1024u)
/* The longest side libpng lets a PNG declare; the pixel count above is
   the real bound (a 1 x 64 Mi strip is allowed), checked with its own
   message before any row is allocated. */
#define HT_IMAGE_MAX_SIDE HT_IMAGE_MAX_PIXELS
/* The most memory libpng may give one chunk (IDAT is streamed and never
   held whole; only ancillary chunks are buffered). */
#define HT_IMAGE_MAX_CHUNK_BYTES (8u << 20)

HT_API ht_result ht_image_alloc(ht_image *img, int width, int height, int channels);
HT_API void ht_image_free(ht_image *img);
/* Reads any PNG libpng reads; expands palette and low bit depths, strips 16
   bit to 8. A missing, truncated or corrupt file is HT_ERR_IO with a line
   naming the file in err. */
HT_API ht_result ht_image_read_png(const char *path, ht_image *out, char *err, size_t err_size);
/* The same decoder, limits and messages over a PNG file's bytes in memory
   (a bundle compiled in); `name` stands for the path in the error line. */
HT_API ht_result ht_image_decode_png(const char *name, const void *data, size_t size, ht_image *out, char *err,
                              size_t err_size);
/* The size a PNG's header declares, read before decoding (so a hostile
   header is refused before anything is allocated); false when the file
   (or the bytes) does not start like a PNG (the decoder then says why). */
HT_API bool ht_image_png_header_size(const char *path, uint32_t *width, uint32_t *height);
HT_API bool ht_image_png_header_size_bytes(const void *data, size_t size, uint32_t *width, uint32_t *height);
/* Writes to a temporary name beside path and renames it into place. */
HT_API ht_result ht_image_write_png(const char *path, const ht_image *img, char *err, size_t err_size);
/* The bytes ht_image_write_png would write, malloc'd into *data (free()). */
HT_API ht_result ht_image_encode_png(const ht_image *img, unsigned char **data, size_t *size, char *err, size_t err_size);

#ifdef __cplusplus
}
#endif

#endif

/* fuzz_png.c — ht_image_read_png (libpng with chunk and user limits) on
   arbitrary bytes. The reader takes a path: each input is written to one
   temporary file per process first. */
#include <stdio.h>
#include <unistd.h>

#include "fuzz_common.h"
#include <hairtier/image.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static char path[64];
    if (!path[0]) snprintf(path, sizeof path, "/tmp/hairtier-fuzz-png-%d.png", (int)getpid());
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    fwrite(data, 1, size, f);
    fclose(f);
    ht_image img = { 0 };
    char err[512];
    if (ht_image_read_png(path, &img, err, sizeof err) == HT_OK) ht_image_free(&img);
    return 0;
}

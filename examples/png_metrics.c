/* png_metrics — how far one rendered PNG is from another, by shadergen/metrics.h:
   PSNR, SSIM and CIEDE2000 over the whole frame and over the hair's pixels
   (those that differ from the background, the reference's first pixel),
   and LDR-FLIP over the whole frame at 67 pixels per degree (shadergen/flip.h).

   build/png_metrics REFERENCE.png TEST.png

   Prints one line on stdout:
     psnr_db=P ssim=S de00_mean=M de00_p95=Q hair_psnr_db=P hair_pixels=N flip_mean=F flip_p95=G max_diff=D
   (PSNR "inf" when the images are identical; D the largest channel
   difference, /255). Both images must have the same size; gray, RGB or
   RGBA PNGs (alpha ignored). Bad input: one line naming the file, exit 1;
   usage: exit 2. tools/device_nvidia.sh compares a device's images with
   llvmpipe's through it. Links the runtime only: no GL. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include <hairtier/image.h>
#include "flip.h"
#include "metrics.h"

static const cli_program program = {
    .name = "png_metrics",
    .synopsis = "usage: png_metrics REFERENCE.png TEST.png\n",
    .help = "Prints how far TEST is from REFERENCE on one line:\n"
            "  psnr_db=P ssim=S de00_mean=M de00_p95=Q hair_psnr_db=P hair_pixels=N max_diff=D\n"
            "over the whole frame and over the hair's pixels (those that differ from the background,\n"
            "the reference's first pixel); PSNR inf when identical, D the largest channel difference\n"
            "(/255). Same-size gray, RGB or RGBA PNGs (alpha ignored). Bad input: one line, exit 1.\n",
};

typedef struct operands {
    const char *path[2];
    int count;
} operands;

static const char *take(void *user, int key, const char *value) {
    operands *o = user;
    if (key != CLI_OPERAND || o->count == 2) return cli_unexpected(value);
    o->path[o->count++] = value;
    return NULL;
}

/* RGBA8 from any channel count ht_image_read_png returns. */
static unsigned char *to_rgba(const ht_image *img) {
    size_t n = (size_t)img->width * (size_t)img->height;
    unsigned char *out = malloc(n * 4);
    if (!out) return NULL;
    for (size_t i = 0; i < n; i++) {
        const unsigned char *p = img->pixels + i * (size_t)img->channels;
        bool gray = img->channels < 3;
        out[4 * i + 0] = p[0];
        out[4 * i + 1] = gray ? p[0] : p[1];
        out[4 * i + 2] = gray ? p[0] : p[2];
        out[4 * i + 3] = 255;
    }
    return out;
}

static void print_db(const char *name, double db) {
    if (isinf(db)) printf("%s=inf", name);
    else printf("%s=%.2f", name, db);
}

int main(int argc, char **argv) {
    operands files = { 0 };
    int rc = cli_parse(&program, argc, argv, take, &files);
    if (rc != CLI_RUN) return rc;
    if (files.count != 2) return cli_usage_error(&program, "two PNGs required");
    const char *path[2] = { files.path[0], files.path[1] };
    char err[1024];
    ht_image img[2] = { { 0 }, { 0 } };
    unsigned char *rgba[2] = { NULL, NULL };
    int status = 1;
    for (int k = 0; k < 2; k++) {
        if (ht_image_read_png(path[k], &img[k], err, sizeof err) != HT_OK) {
            fprintf(stderr, "png_metrics: %s\n", err);
            goto done;
        }
    }
    if (img[0].width != img[1].width || img[0].height != img[1].height) {
        fprintf(stderr, "png_metrics: %s: %dx%d, but %s is %dx%d\n", path[1], img[1].width, img[1].height, path[0],
                img[0].width, img[0].height);
        goto done;
    }
    for (int k = 0; k < 2; k++)
        if (!(rgba[k] = to_rgba(&img[k]))) {
            fprintf(stderr, "png_metrics: %s: out of memory\n", path[k]);
            goto done;
        }
    ht_metrics whole, hair;
    if (ht_metrics_compare(&(ht_metrics_desc){ .reference = rgba[0], .test = rgba[1], .width = img[0].width,
                                               .height = img[0].height }, &whole, &hair, err, sizeof err) != HT_OK) {
        fprintf(stderr, "png_metrics: %s: %s\n", path[1], err);
        goto done;
    }
    ht_flip_result flip;
    if (ht_flip_compare(&(ht_flip_desc){ .reference = rgba[0], .test = rgba[1], .width = img[0].width,
                                         .height = img[0].height }, NULL, &flip, err, sizeof err) != HT_OK) {
        fprintf(stderr, "png_metrics: %s: %s\n", argv[2], err);
        goto done;
    }
    int max = 0;
    for (size_t i = 0; i < (size_t)img[0].width * (size_t)img[0].height * 4; i++)
        if (i % 4 != 3 && abs(rgba[0][i] - rgba[1][i]) > max) max = abs(rgba[0][i] - rgba[1][i]);
    print_db("psnr_db", whole.psnr_db);
    printf(" ssim=%.4f de00_mean=%.3f de00_p95=%.3f ", whole.ssim, whole.delta_e00_mean, whole.delta_e00_p95);
    print_db("hair_psnr_db", hair.psnr_db);
    printf(" hair_pixels=%ld flip_mean=%.5f flip_p95=%.5f max_diff=%d\n", hair.pixels, flip.mean, flip.p95, max);
    status = 0;
done:
    for (int k = 0; k < 2; k++) {
        ht_image_free(&img[k]);
        free(rgba[k]);
    }
    return status;
}

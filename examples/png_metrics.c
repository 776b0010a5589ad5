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
   llvmpipe's through it. Links the runtime only: no GL.

   --parts adds a line saying where the error is (docs/lod.md, "Why the
   levels lose"): the mean colour difference (TEST - REFERENCE, per
   channel), ink (each pixel's largest channel difference from the
   background, summed) and covered pixels (ink over 2.5/255) of TEST over
   REFERENCE's, the gain on TEST's ink that fits REFERENCE best and the
   PSNR then, and for box blurs of radius 1, 2, 4 and 8 the PSNR of the
   blurred images (low) and of what the blur removed (high), and of
   REFERENCE against its own blur (smooth: how close an image without
   REFERENCE's pixel-scale detail can come). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include <hairtier/image.h>
#include "flip.h"
#include "metrics.h"

enum { KEY_PARTS = CLI_LONG_ONLY };
static const struct option long_options[] = { { "parts", no_argument, NULL, KEY_PARTS }, { 0 } };

static const cli_program program = {
    .name = "png_metrics",
    .synopsis = "usage: png_metrics [--parts] REFERENCE.png TEST.png\n",
    .help = "Prints how far TEST is from REFERENCE on one line:\n"
            "  psnr_db=P ssim=S de00_mean=M de00_p95=Q hair_psnr_db=P hair_pixels=N max_diff=D\n"
            "over the whole frame and over the hair's pixels (those that differ from the background,\n"
            "the reference's first pixel); PSNR inf when identical, D the largest channel difference\n"
            "(/255). Same-size gray, RGB or RGBA PNGs (alpha ignored). Bad input: one line, exit 1.\n"
            "  --parts  a second line: mean difference, ink and coverage ratios, best ink gain, and the PSNR\n"
            "           of box-blurred (low) and blur-removed (high) parts at radius 1, 2, 4, 8\n",
    .long_options = long_options,
};

typedef struct operands {
    const char *path[2];
    int count;
    bool parts;
} operands;

static const char *take(void *user, int key, const char *value) {
    operands *o = user;
    if (key == KEY_PARTS) {
        o->parts = true;
        return NULL;
    }
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

static double psnr_of(double sum_sq, size_t values) { return sum_sq > 0 ? 10 * log10((double)values / sum_sq) : INFINITY; }

/* One axis of a box blur of radius r over 3 channels in [0, 1] (edges: the
   mean of the pixels inside). */
static void box_axis(const double *in, double *out, int w, int h, int r, bool vertical) {
    const int n = vertical ? h : w, lines = vertical ? w : h;
    for (int line = 0; line < lines; line++)
        for (int i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                double sum = 0;
                int count = 0;
                for (int j = i - r < 0 ? 0 : i - r; j <= i + r && j < n; j++, count++)
                    sum += in[3 * (size_t)(vertical ? j * w + line : line * w + j) + c];
                out[3 * (size_t)(vertical ? i * w + line : line * w + i) + c] = sum / count;
            }
}

static void box_blur(const double *in, double *tmp, double *out, int w, int h, int r) {
    box_axis(in, tmp, w, h, r, false);
    box_axis(tmp, out, w, h, r, true);
}

/* --parts: see the header. rgba[0] is the reference; its first pixel the background. */
static bool print_parts(unsigned char *const rgba[2], int w, int h) {
    const size_t n = (size_t)w * h, values = 3 * n;
    double *img[2], *blur[2], *tmp = malloc(sizeof *tmp * values);
    blur[0] = malloc(sizeof *blur[0] * values);
    blur[1] = malloc(sizeof *blur[1] * values);
    img[0] = malloc(sizeof *img[0] * values);
    img[1] = malloc(sizeof *img[1] * values);
    const bool ok = tmp && blur[0] && blur[1] && img[0] && img[1];
    if (ok) {
        double mean[2][3] = { { 0 } }, ink[2] = { 0 }, covered[2] = { 0 }, cross = 0, self = 0;
        for (size_t i = 0; i < n; i++)
            for (int k = 0; k < 2; k++) {
                double most = 0;
                for (int c = 0; c < 3; c++) {
                    const double v = img[k][3 * i + c] = rgba[k][4 * i + c] / 255.0, d = v - rgba[0][c] / 255.0;
                    mean[k][c] += v / n;
                    most = fmax(most, fabs(d));
                    if (k == 1) {
                        cross += d * (img[0][3 * i + c] - rgba[0][c] / 255.0);
                        self += d * d;
                    }
                }
                ink[k] += most;
                covered[k] += most > 2.5 / 255;
            }
        const double gain = self > 0 ? cross / self : 1;
        double fitted = 0;
        for (size_t i = 0; i < values; i++) {
            const double bg = rgba[0][i % 3] / 255.0, d = img[0][i] - img[1][i] - (gain - 1) * (img[1][i] - bg);
            fitted += d * d;
        }
        printf("parts: mean_diff=%+.4f,%+.4f,%+.4f ink_ratio=%.3f covered_ratio=%.3f gain=%.3f ", mean[1][0] - mean[0][0],
               mean[1][1] - mean[0][1], mean[1][2] - mean[0][2], ink[0] > 0 ? ink[1] / ink[0] : 1,
               covered[0] > 0 ? covered[1] / covered[0] : 1, gain);
        print_db("gain_psnr_db", psnr_of(fitted, values));
        for (int r = 1; r <= 8; r *= 2) {
            box_blur(img[0], tmp, blur[0], w, h, r);
            box_blur(img[1], tmp, blur[1], w, h, r);
            double low = 0, high = 0, smooth = 0;
            for (size_t i = 0; i < values; i++) {
                const double dl = blur[0][i] - blur[1][i], dh = (img[0][i] - blur[0][i]) - (img[1][i] - blur[1][i]);
                low += dl * dl;
                high += dh * dh;
                smooth += (img[0][i] - blur[0][i]) * (img[0][i] - blur[0][i]);
            }
            printf(" r%d:", r);
            print_db("low", psnr_of(low, values));
            print_db(",high", psnr_of(high, values));
            print_db(",smooth", psnr_of(smooth, values));
        }
        printf("\n");
    }
    free(tmp);
    for (int k = 0; k < 2; k++) {
        free(blur[k]);
        free(img[k]);
    }
    return ok;
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
    if (files.parts && !print_parts(rgba, img[0].width, img[0].height)) {
        fprintf(stderr, "png_metrics: %s: out of memory\n", path[1]);
        goto done;
    }
    status = 0;
done:
    for (int k = 0; k < 2; k++) {
        ht_image_free(&img[k]);
        free(rgba[k]);
    }
    return status;
}

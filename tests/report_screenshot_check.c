/* report_screenshot_check — did every image of a haircompare report load
   in the browser? `make report-check` opens REPORT_DIR/index.html in
   headless Chromium, takes a screenshot, and runs

       build/tests/report_screenshot_check SCREENSHOT.png REPORT_DIR

   which reads every <img src="FILE"> of index.html, reads FILE beside it,
   and finds that image, at full size, in the screenshot: a broken image
   (Chromium's icon), a blank or cut region, a scaled image or one that
   never arrived is not found. Prints where each one sits; exit 0 when all
   are found, 1 otherwise (one line per failure), 2 on usage.

   Not a tests/test_*.c file: it needs Chromium's screenshot, so `make test`
   does not run it; `make report-check` does. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <hairtier/image.h>
#include "json_check.h"

#define MAX_IMAGES 64
#define PROBE_LEN 64        /* pixels of one row compared before a full check */
#define PIXEL_TOLERANCE 3   /* per channel: colour management may round */
#define MATCH_SHARE 0.999   /* share of pixels within tolerance for a match */

static const uint8_t *px(const ht_image *img, int x, int y) {
    return img->pixels + ((size_t)y * (size_t)img->width + (size_t)x) * (size_t)img->channels;
}

static bool close_rgb(const uint8_t *a, const uint8_t *b) {
    for (int c = 0; c < 3; c++)
        if (abs((int)a[c] - (int)b[c]) > PIXEL_TOLERANCE) return false;
    return true;
}

/* A run of PROBE_LEN pixels (or the row's remainder) starting at a pixel
   unlike the image's corner: it rejects almost every wrong position at its
   first pixel. false when the image is one colour (it could not be told
   from a blank region). */
static bool pick_probe(const ht_image *img, int *px0, int *py0) {
    const uint8_t *corner = px(img, 0, 0);
    int best = -1;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            const uint8_t *p = px(img, x, y);
            int d = abs(p[0] - corner[0]) + abs(p[1] - corner[1]) + abs(p[2] - corner[2]);
            if (d > best) {
                best = d;
                *px0 = x;
                *py0 = y;
            }
        }
    if (*px0 > img->width - PROBE_LEN) *px0 = img->width > PROBE_LEN ? img->width - PROBE_LEN : 0;
    return best > 3 * PIXEL_TOLERANCE;
}

static bool matches_at(const ht_image *shot, const ht_image *img, int sx, int sy) {
    long bad = 0, allowed = (long)((1.0 - MATCH_SHARE) * img->width * img->height);
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (!close_rgb(px(shot, sx + x, sy + y), px(img, x, y)) && ++bad > allowed) return false;
    return true;
}

/* Where img sits in shot, full size; false when nowhere. */
static bool find(const ht_image *shot, const ht_image *img, int *out_x, int *out_y) {
    int probe_x = 0, probe_y = 0;
    if (!pick_probe(img, &probe_x, &probe_y)) return false;
    int len = img->width - probe_x < PROBE_LEN ? img->width - probe_x : PROBE_LEN;
    for (int sy = 0; sy + img->height <= shot->height; sy++)
        for (int sx = 0; sx + img->width <= shot->width; sx++) {
            int k = 0;
            while (k < len && close_rgb(px(shot, sx + probe_x + k, sy + probe_y), px(img, probe_x + k, probe_y))) k++;
            if (k == len && matches_at(shot, img, sx, sy)) {
                *out_x = sx;
                *out_y = sy;
                return true;
            }
        }
    return false;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: report_screenshot_check SCREENSHOT.png REPORT_DIR\n");
        return 2;
    }
    const char *dir = argv[2];
    char err[1024], path[4200];
    ht_image shot = { 0 };
    if (ht_image_read_png(argv[1], &shot, err, sizeof err) != HT_OK) {
        fprintf(stderr, "report_screenshot_check: %s\n", err);
        return 1;
    }
    if (shot.channels < 3) {
        fprintf(stderr, "report_screenshot_check: %s: expected an RGB screenshot\n", argv[1]);
        ht_image_free(&shot);
        return 1;
    }
    snprintf(path, sizeof path, "%s/index.html", dir);
    char *html = NULL;
    if (ht_json_read_file(path, &html, err, sizeof err) != HT_OK) {
        fprintf(stderr, "report_screenshot_check: %s\n", err);
        ht_image_free(&shot);
        return 1;
    }
    int images = 0, failed = 0;
    const char *tag = "<img src=\"";
    for (const char *p = strstr(html, tag); p; p = strstr(p, tag)) {
        p += strlen(tag);
        const char *end = strchr(p, '"');
        if (!end || end - p >= 256 || memchr(p, '&', (size_t)(end - p)) || memchr(p, '/', (size_t)(end - p))) {
            fprintf(stderr, "report_screenshot_check: %s: an <img src> that is not a plain file name\n", path);
            failed++;
            break;
        }
        char name[256];
        memcpy(name, p, (size_t)(end - p));
        name[end - p] = '\0';
        images++;
        snprintf(path, sizeof path, "%s/%s", dir, name);
        ht_image img = { 0 };
        int x, y;
        if (ht_image_read_png(path, &img, err, sizeof err) != HT_OK) {
            fprintf(stderr, "report_screenshot_check: %s\n", err);
            failed++;
        } else if (img.channels < 3) {
            fprintf(stderr, "report_screenshot_check: %s: expected an RGB image\n", path);
            failed++;
        } else if (!find(&shot, &img, &x, &y)) {
            fprintf(stderr, "report_screenshot_check: %s (%dx%d): not in the screenshot at full size "
                    "(not loaded, blank, cut or one colour)\n", name, img.width, img.height);
            failed++;
        } else {
            printf("%-20s %dx%d at (%d, %d)\n", name, img.width, img.height, x, y);
        }
        ht_image_free(&img);
    }
    free(html);
    ht_image_free(&shot);
    if (images == 0) {
        fprintf(stderr, "report_screenshot_check: %s/index.html: no <img> to check\n", dir);
        return 1;
    }
    printf("report_screenshot_check: %d of %d images found in %s\n", images - failed, images, argv[1]);
    return failed ? 1 : 0;
}

/* densegroom — writes a dense, deterministic groom as a Cem Yuksel `.hair`
   file (runtime/io/strands_hair.c reads it) and a "strands" scene that
   draws it: the asset the geometry LODs are measured on (docs/lod.md).

   tools/densegroom [--strands N] [--points P] -o OUT.hair --scene OUT.json

   Head: the unit sphere at the origin, y up, face towards +z. Roots: the
   points of a Fibonacci (golden-angle) spiral over the sphere, the i-th at
   height y = 1 - 2 (i + 0.5) / M, taken in order while they lie on the
   scalp (above y = -0.1, and off the face: not z > 0.35 with y < 0.55),
   M chosen so N of them do; a strand starts 1.01 from the centre. Growth:
   P points (P - 1 equal steps of L / (P - 1), L = 0.55 + 0.45 b + 0.15 r,
   b = (1 - z) / 2 longer at the back, r a per-strand random in [0, 1)),
   the direction starting outward and each step pulled by gravity
   (0, -0.3, 0) plus a per-strand wave (amplitude 0.04, sideways to the
   outward direction); a point that would fall inside the head (radius
   1.01) is pushed out to it. splitmix64 with a fixed seed: the same bytes
   on every machine. The scene: ratboy's camera and lights turned to the
   side of the head, ribbons 0.004 wide (about a pixel at 512 x 512).
   Bad arguments: one line, exit 2; a file not written: one line, exit 1
   (nothing half-written: written to OUT.tmp, then renamed). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HAIR_POINTS_BIT 2u
#define MAX_STRANDS 1000000
#define MAX_POINTS 64

static uint64_t rng_state = 0x5eed5eedull;
static double unit_random(void) {
    uint64_t z = (rng_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static int on_scalp(const double p[3]) { return p[1] > -0.1 && !(p[2] > 0.35 && p[1] < 0.55); }

static void fibonacci_point(long i, long m, double p[3]) {
    const double y = 1.0 - 2.0 * (i + 0.5) / m, r = sqrt(fmax(0.0, 1.0 - y * y));
    const double phi = i * M_PI * (3.0 - sqrt(5.0));
    p[0] = r * cos(phi);
    p[1] = y;
    p[2] = r * sin(phi);
}

static void normalize(double v[3]) {
    const double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0) for (int k = 0; k < 3; k++) v[k] /= l;
}

static void grow(const double root[3], int points, float (*out)[3]) {
    double p[3] = { root[0] * 1.01, root[1] * 1.01, root[2] * 1.01 }, d[3] = { root[0], root[1], root[2] };
    const double length = 0.55 + 0.45 * (1.0 - root[2]) / 2.0 + 0.15 * unit_random();
    const double step = length / (points - 1), phase = 2 * M_PI * unit_random(), freq = 2.0 + 2.0 * unit_random();
    double side[3] = { -root[2], 0, root[0] }; /* sideways: around the vertical axis */
    normalize(side);
    for (int i = 0; i < points; i++) {
        for (int k = 0; k < 3; k++) out[i][k] = (float)p[k];
        const double wave = 0.04 * sin(phase + freq * 2 * M_PI * i / (points - 1));
        for (int k = 0; k < 3; k++) d[k] += (k == 1 ? -0.3 : 0.0) + wave * side[k];
        normalize(d);
        for (int k = 0; k < 3; k++) p[k] += step * d[k];
        const double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        if (r < 1.01) for (int k = 0; k < 3; k++) p[k] *= 1.01 / r;
    }
}

static void put_u32(unsigned char *b, uint32_t v) { for (int i = 0; i < 4; i++) b[i] = (unsigned char)(v >> 8 * i); }

static int write_hair(const char *path, long strands, int points) {
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "wb");
    if (!f) { fprintf(stderr, "densegroom: %s: cannot write\n", path); return 1; }
    unsigned char header[128] = { 'H', 'A', 'I', 'R' };
    put_u32(header + 4, (uint32_t)strands);
    put_u32(header + 8, (uint32_t)(strands * points));
    put_u32(header + 12, HAIR_POINTS_BIT);
    put_u32(header + 16, (uint32_t)(points - 1));
    snprintf((char *)header + 40, 88, "hairtier tools/densegroom: %ld strands", strands);
    int ok = fwrite(header, sizeof header, 1, f) == 1;
    /* Enough spiral points that `strands` of them land on the scalp (about
       half the sphere); counted exactly by a first walk. */
    long m = strands * 2;
    for (;;) {
        long on = 0;
        double p[3];
        for (long i = 0; i < m; i++) { fibonacci_point(i, m, p); on += on_scalp(p); }
        if (on >= strands) break;
        m += m / 50 + 1;
    }
    float pts[MAX_POINTS][3];
    long written = 0;
    for (long i = 0; i < m && written < strands && ok; i++) {
        double root[3];
        fibonacci_point(i, m, root);
        if (!on_scalp(root)) continue;
        grow(root, points, pts);
        /* Little-endian floats: the file's byte order, this machine's too
           (the reader checks every value). */
        ok = fwrite(pts, sizeof pts[0], (size_t)points, f) == (size_t)points;
        written++;
    }
    if (fclose(f) != 0 || !ok || rename(tmp, path) != 0) {
        remove(tmp);
        fprintf(stderr, "densegroom: %s: cannot write\n", path);
        return 1;
    }
    return 0;
}

static const char *base_name(const char *path) {
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

static int write_scene(const char *path, const char *hair_path) {
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    FILE *f = fopen(tmp, "w");
    if (!f) { fprintf(stderr, "densegroom: %s: cannot write\n", path); return 1; }
    const int ok = fprintf(f,
        "{\n  \"format\": \"hairtier-scene/1\",\n  \"resolution\": [512, 512],\n"
        "  \"camera\": {\"eye\": [4.6, 1.0, -3.0], \"target\": [0.0, -0.2, 0.0], \"up\": [0, 1, 0],\n"
        "             \"fov_y\": 40, \"near\": 0.05, \"far\": 100},\n"
        "  \"lights\": [\n"
        "    {\"type\": \"directional\", \"direction\": [0.6, 0.7, 0.5], \"color\": [1.1, 1.06, 1.0]},\n"
        "    {\"type\": \"directional\", \"direction\": [-0.5, 0.3, -0.8], \"color\": [0.35, 0.4, 0.5]}\n"
        "  ],\n  \"background\": [0.08, 0.08, 0.1],\n"
        "  \"geometry\": {\"type\": \"strands\", \"file\": \"%s\", \"scale\": 1, \"center\": [0, 0, 0],\n"
        "               \"width\": 0.004, \"tip_width\": 0.5, \"ao\": 0.3,\n"
        "               \"head\": {\"radius\": 1.0, \"center\": [0, 0, 0]}}\n}\n",
        base_name(hair_path)) > 0;
    if (fclose(f) != 0 || !ok || rename(tmp, path) != 0) {
        remove(tmp);
        fprintf(stderr, "densegroom: %s: cannot write\n", path);
        return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    long strands = 100000, points = 16;
    const char *out = NULL, *scene = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (!v) { fprintf(stderr, "densegroom: %s: needs a value\n", a); return 2; }
        if (strcmp(a, "--strands") == 0) strands = strtol(v, &end, 10);
        else if (strcmp(a, "--points") == 0) points = strtol(v, &end, 10);
        else if (strcmp(a, "-o") == 0) out = v;
        else if (strcmp(a, "--scene") == 0) scene = v;
        else { fprintf(stderr, "densegroom: %s: unknown option\n", a); return 2; }
        if (end && *end) { fprintf(stderr, "densegroom: %s: not an integer: %s\n", a, v); return 2; }
        i++;
    }
    if (strands < 1 || strands > MAX_STRANDS) { fprintf(stderr, "densegroom: --strands: 1..%d\n", MAX_STRANDS); return 2; }
    if (points < 2 || points > MAX_POINTS) { fprintf(stderr, "densegroom: --points: 2..%d\n", MAX_POINTS); return 2; }
    if (!out || !scene) { fprintf(stderr, "usage: densegroom [--strands N] [--points P] -o OUT.hair --scene OUT.json\n"); return 2; }
    return write_hair(out, strands, (int)points) || write_scene(scene, out);
}

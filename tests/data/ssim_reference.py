#!/usr/bin/env python3
"""The SSIM reference value tests/test_metrics.c pins, computed independently
of runtime/metrics.c: pure Python (no numpy or scikit-image on the build
machine), a direct 2-D weighted sum over every 11x11 window (not the
separable filter the C code uses), Wang et al. 2004's constants.

The images are the test's: 32 x 24 RGBA, made by the same 32-bit LCG."""
import math

W, H = 32, 24

def lcg(state):
    return (state * 1664525 + 1013904223) & 0xFFFFFFFF

def images():
    state = 12345
    ref, test = [], []
    for y in range(H):
        for x in range(W):
            px_a, px_b = [], []
            for c in range(3):
                a = (x * 6 + y * 4 + c * 50) % 256
                state = lcg(state)
                noise = (state >> 24) % 41 - 20
                px_a.append(a)
                px_b.append(min(255, max(0, a + noise)))
            ref.append(px_a)
            test.append(px_b)
    return ref, test

def luma(p):
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]

def ssim(ref, test):
    g = [[math.exp(-((i - 5) ** 2 + (j - 5) ** 2) / (2 * 1.5 ** 2)) for i in range(11)] for j in range(11)]
    total = sum(sum(r) for r in g)
    g = [[v / total for v in r] for r in g]
    c1, c2 = (0.01 * 255) ** 2, (0.03 * 255) ** 2
    ya = [luma(p) for p in ref]
    yb = [luma(p) for p in test]
    values = []
    for y0 in range(H - 10):
        for x0 in range(W - 10):
            m1 = m2 = s11 = s22 = s12 = 0.0
            for j in range(11):
                for i in range(11):
                    wgt = g[j][i]
                    a = ya[(y0 + j) * W + x0 + i]
                    b = yb[(y0 + j) * W + x0 + i]
                    m1 += wgt * a
                    m2 += wgt * b
                    s11 += wgt * a * a
                    s22 += wgt * b * b
                    s12 += wgt * a * b
            s11 -= m1 * m1
            s22 -= m2 * m2
            s12 -= m1 * m2
            values.append(((2 * m1 * m2 + c1) * (2 * s12 + c2)) / ((m1 * m1 + m2 * m2 + c1) * (s11 + s22 + c2)))
    return sum(values) / len(values)

ref, test = images()
print("%.10f" % ssim(ref, test))

#!/usr/bin/env python3
"""marschner_reference.py -- reference values of Marschner's fibre model in
mpmath (24 significant digits), for tests/test_model_marschner.c.

Written from the equations of include/hairtier/model_marschner.h, Marschner
et al. 2003 (exit azimuth, eq. 10; Bravais indices; the caustic spread over
an azimuthal width) and d'Eon et al. 2011 (the normalised longitudinal
function), not from runtime/shading/model_marschner.c, and by other means:
N_R and N_TT from roots found by bisection on the cubic's monotone pieces,
N_TRT, the rest, the lobes' energies and N_TRT's Fourier coefficients by
tanh-sinh quadrature in h (mpmath.quad) split where the integrand is not
smooth, M with mpmath's Bessel I0.

Run once; its output is committed (make test does not need Python):
    python3 tools/marschner_reference.py > tests/data/marschner_reference.h

Rows (angles in degrees, absorption per fibre radius):
    M: lobe, alpha_R, beta_R, theta_i, theta_r -> M_p
    A: lobe, eta, sigma_a rgb, theta_r, h -> A_p rgb
    N: lobe, eta, sigma_a rgb, theta_r, phi -> N_p rgb (rest: uniform in phi)
    E: lobe, eta, theta_r -> the lobe's white-furnace energy: the integral
       of M_p N_p cos(theta_i) over the sphere with sigma_a = 0, i.e. the
       mean of A_p over h (M_p integrates to 1)
    F: k, eta, sigma_a rgb, theta_r -> the integral over phi of
       N_TRT(phi) cos(k phi): exp(-k^2 w^2 / 2) times that of the unspread
       caustic (a wrapped Gaussian's Fourier coefficient), w = 15 degrees
"""
import random
import sys

import mpmath as mp

mp.mp.dps = 24
PI = mp.pi
CAUSTIC_WIDTH = 15 * PI / 180


def rad(deg):
    return mp.mpf(deg) * PI / 180


def lobe_shift(alpha, p):
    return [alpha, -alpha / 2, -3 * alpha / 2, mp.mpf(0)][p]


def lobe_width(beta, p):
    return [beta, beta / 2, 2 * beta, 2 * beta][p]


def longitudinal(p, alpha, beta, theta_i, theta_r):
    """d'Eon 2011: csch(1/v) / (2 v) exp(-sin ti sin tr / v) I0(cos ti cos tr / v),
    v = beta_p^2, theta_r rotated by -2 alpha_p (folding past a pole: |cos|)."""
    v = lobe_width(beta, p) ** 2
    tr = theta_r - 2 * lobe_shift(alpha, p)
    x = mp.cos(theta_i) * abs(mp.cos(tr)) / v
    return mp.csch(1 / v) / (2 * v) * mp.exp(-mp.sin(theta_i) * mp.sin(tr) / v) * mp.besseli(0, x)


def bravais(eta, theta_r):
    """Bravais' indices: perpendicular eta', parallel eta''."""
    s2 = mp.sin(theta_r) ** 2
    c = mp.cos(theta_r)
    root = mp.sqrt(eta * eta - s2)
    return root / c, eta * eta * c / root


def fresnel_polarised(n, sin_i, parallel):
    """Reflectance of a dielectric of relative index n for one polarisation."""
    cos_i = mp.sqrt(1 - sin_i * sin_i)
    sin_t = sin_i / n
    if sin_t >= 1:
        return mp.mpf(1)
    cos_t = mp.sqrt(1 - sin_t * sin_t)
    if parallel:
        r = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    else:
        r = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    return r * r


def attenuation(p, eta, sigma, theta_r, h):
    """A_p(h) for the three absorption coefficients `sigma`."""
    ep, epp = bravais(eta, theta_r)
    s = abs(mp.mpf(h))
    if s >= 1:
        f = mp.mpf(1)
    else:
        f = (fresnel_polarised(ep, s, False) + fresnel_polarised(epp, s, True)) / 2
    if p == 0:
        return [f, f, f]
    cos_gt = mp.sqrt(1 - (s / ep) ** 2)
    cos_tt = mp.sqrt(1 - (mp.sin(theta_r) / eta) ** 2)
    out = []
    for sa in sigma:
        t = mp.exp(-2 * sa * cos_gt / cos_tt)
        a = (1 - f) ** 2 * t
        if p >= 2:
            a *= f * t
        if p == 3:
            a = a * f * t / (1 - f * t) if 1 - f * t > 0 else mp.mpf(0)
        out.append(a)
    return out


def exit_azimuth(p, c, g):
    return (6 * p * c / PI - 2) * g - 8 * p * c / PI ** 3 * g ** 3 + p * PI


def bisect(f, lo, hi):
    flo = f(lo)
    for _ in range(120):
        mid = (lo + hi) / 2
        fm = f(mid)
        if (fm < 0) == (flo < 0):
            lo, flo = mid, fm
        else:
            hi = mid
    return (lo + hi) / 2


def exit_gammas(p, c, phi):
    """Every gamma in [-pi/2, pi/2] whose exit azimuth is phi modulo 2 pi."""
    a1, a3 = 6 * p * c / PI - 2, -8 * p * c / PI ** 3
    cuts = [-PI / 2, PI / 2]
    if a3 != 0 and -a1 / (3 * a3) > 0:
        g0 = mp.sqrt(-a1 / (3 * a3))
        cuts += [x for x in (-g0, g0) if abs(x) < PI / 2]
    cuts.sort()
    found = []
    for lo, hi in zip(cuts, cuts[1:]):
        for k in range(-4, 5):
            target = phi + 2 * PI * k
            f = lambda g: exit_azimuth(p, c, g) - target
            if f(lo) == 0:
                found.append(lo)
            elif (f(lo) < 0) != (f(hi) < 0):
                found.append(bisect(f, lo, hi))
    return found


def azimuthal_roots(p, eta, sigma, theta_r, phi):
    """N_R, N_TT: the sum over the exit rays of A_p(h) / |2 dphi/dh|."""
    ep, _ = bravais(eta, theta_r)
    c = mp.asin(1 / ep)
    a1, a3 = 6 * p * c / PI - 2, -8 * p * c / PI ** 3
    total = [mp.mpf(0)] * 3
    for g in exit_gammas(p, c, phi):
        a = attenuation(p, eta, sigma, theta_r, mp.sin(g))
        jac = mp.cos(g) / (2 * abs(a1 + 3 * a3 * g * g))
        total = [t + x * jac for t, x in zip(total, a)]
    return total


def h_breaks(eta, theta_r, extra=()):
    """Where A(h) is not smooth: 0 (|h|), +-eta'' (total reflection of the
    parallel polarisation), plus the given points."""
    _, epp = bravais(eta, theta_r)
    pts = {mp.mpf(-1), mp.mpf(0), mp.mpf(1)}
    if epp < 1:
        pts |= {-epp, epp}
    pts |= {x for x in extra if -1 < x < 1}
    return sorted(pts)


def integrate(f, pts):
    return mp.quad(f, pts, maxdegree=10)


def integrate_rgb(f, pts):
    """The three channels of f(h) (a list), each by quad, f evaluated once per node."""
    memo = {}

    def cached(h):
        if h not in memo:
            memo[h] = f(h)
        return memo[h]
    return [integrate(lambda h, ch=ch: cached(h)[ch], pts) for ch in range(3)]


def wrapped_gaussian(d, w):
    return sum(mp.exp(-(d + 2 * PI * j) ** 2 / (2 * w * w)) for j in range(-4, 5)) / (mp.sqrt(2 * PI) * w)


def azimuthal_trt(eta, sigma, theta_r, phi):
    """N_TRT: the integral over h of A_TRT(h) / 2 times the caustic's
    Gaussian at phi - phi(2, h)."""
    ep, _ = bravais(eta, theta_r)
    c = mp.asin(1 / ep)
    peaks = [mp.sin(g) for g in exit_gammas(2, c, phi)]
    pts = h_breaks(eta, theta_r, peaks)

    def f(h):
        g = wrapped_gaussian(phi - exit_azimuth(2, c, mp.asin(h)), CAUSTIC_WIDTH)
        return [a / 2 * g for a in attenuation(2, eta, sigma, theta_r, h)]
    return integrate_rgb(f, pts)


def mean_attenuation(p, eta, sigma, theta_r):
    pts = h_breaks(eta, theta_r)
    return [x / 2 for x in integrate_rgb(lambda h: attenuation(p, eta, sigma, theta_r, h), pts)]


def trt_fourier(k, eta, sigma, theta_r):
    ep, _ = bravais(eta, theta_r)
    c = mp.asin(1 / ep)
    pts = h_breaks(eta, theta_r)
    damp = mp.exp(-(k * CAUSTIC_WIDTH) ** 2 / 2)

    def f(h):
        w = mp.cos(k * exit_azimuth(2, c, mp.asin(h))) / 2
        return [a * w for a in attenuation(2, eta, sigma, theta_r, h)]
    return [damp * x for x in integrate_rgb(f, pts)]


SIGMAS = [(0, 0, 0), (0.06, 0.10, 0.20), (0.42, 0.70, 1.25), (2, 5, 10), (20, 35, 50)]


def pick_theta_r(rng):
    """Half uniform, half past 57 degrees where the old midpoint rule failed."""
    if rng.random() < 0.5:
        return round(rng.uniform(-89.99, 89.99), 4)
    return round(rng.choice([-1, 1]) * rng.uniform(57, 89.99), 4)


def pick_sigma(rng):
    if rng.random() < 0.7:
        return rng.choice(SIGMAS)
    return tuple(round(rng.uniform(0, 5), 3) for _ in range(3))


def pick_eta(rng):
    return rng.choice([1.33, 1.55, 1.55, 2.0, 3.0, round(rng.uniform(1.2, 3), 3)])


def fmt(x):
    return repr(float(x))


def main():
    rng = random.Random(22)
    n_m, n_a, n_n, n_trt = 60, 40, 60, 160
    lines = []

    def row(kind, lobe, params, values):
        vals = ", ".join(fmt(v) for v in values)
        ps = ", ".join(repr(float(x)) for x in params)
        lines.append("    { '%s', %d, { %s }, { %s } }," % (kind, lobe, ps, vals))

    for p in range(4):
        for _ in range(n_m):
            alpha = round(rng.uniform(-12, 12), 3)
            beta = round(rng.choice([rng.uniform(1, 15), rng.uniform(1, 60)]), 3)
            ti, tr = round(rng.uniform(-90, 90), 4), pick_theta_r(rng)
            if rng.random() < 0.3:  # near the lobe's centre, where M is large
                ti = round(-tr + 2 * float(lobe_shift(alpha, p)) + rng.gauss(0, 2 * float(lobe_width(beta, p))), 4)
                ti = max(-90, min(90, ti))
            v = longitudinal(p, rad(alpha) , rad(beta), rad(ti), rad(tr))
            row("M", p, (alpha, beta, ti, tr), [v])
    for p in range(4):
        for _ in range(n_a):
            eta = rng.choice([1.1, pick_eta(rng)])
            sig, tr = pick_sigma(rng), pick_theta_r(rng)
            h = round(rng.uniform(-1, 1), 5)
            row("A", p, (eta,) + tuple(sig) + (tr, h), attenuation(p, mp.mpf(eta), [mp.mpf(s) for s in sig], rad(tr), h))
    issue_points = [  # the issue's cells: blond and brown at grazing theta_r
        (1.55, (0.06, 0.10, 0.20), -87.91, 9.87), (1.55, (0.42, 0.70, 1.25), -86.53, 5.9038)]
    for p in range(3):
        count = n_trt if p == 2 else n_n
        for i in range(count):
            if p == 2 and i < len(issue_points):
                eta, sig, tr, phi = issue_points[i]
            else:
                eta, sig, tr = pick_eta(rng), pick_sigma(rng), pick_theta_r(rng)
                phi = round(rng.uniform(-200, 200) if rng.random() < 0.2 else rng.uniform(0, 180), 4)
            e, s = mp.mpf(eta), [mp.mpf(x) for x in sig]
            vals = azimuthal_trt(e, s, rad(tr), rad(phi)) if p == 2 else azimuthal_roots(p, e, s, rad(tr), rad(phi))
            row("N", p, (eta,) + tuple(sig) + (tr, phi), vals)
    for _ in range(n_n):
        eta, sig, tr = pick_eta(rng), pick_sigma(rng), pick_theta_r(rng)
        vals = [v / (2 * PI) for v in mean_attenuation(3, mp.mpf(eta), [mp.mpf(x) for x in sig], rad(tr))]
        row("N", 3, (eta, ) + tuple(sig) + (tr, 0), vals)
    furnace_cases = [(1.55, 0), (1.55, 35), (1.55, -60), (1.55, 75), (1.55, 89.5), (1.33, 20), (2.0, -45), (3.0, 80)]
    for eta, tr in furnace_cases:
        for p in range(4):
            row("E", p, (eta, tr), mean_attenuation(p, mp.mpf(eta), [0, 0, 0], rad(tr))[:1])
    for eta, sig, tr in [(1.55, (0, 0, 0), 0), (1.55, (0.42, 0.70, 1.25), 30), (1.55, (0.06, 0.10, 0.20), -70),
                         (1.33, (0, 0, 0), 50), (2.0, (2, 5, 10), -20), (1.55, (0, 0, 0), 88)]:
        for k in (1, 2, 3):
            row("F", k, (eta,) + tuple(sig) + (tr,), trt_fourier(k, mp.mpf(eta), [mp.mpf(x) for x in sig], rad(tr)))
        print(".", end="", file=sys.stderr, flush=True)

    out = sys.stdout
    out.write("/* marschner_reference.h -- generated by tools/marschner_reference.py (Python %s, mpmath %s,\n"
              "   %d digits); do not edit. Rows: see the script's docstring. */\n"
              % (sys.version.split()[0], mp.__version__, mp.mp.dps))
    out.write("#define HT_MARSCHNER_REFERENCE_ROWS %d\n" % len(lines))
    out.write("static const struct ht_marschner_reference {\n    char kind;\n    int lobe;\n"
              "    double in[6];\n    double out[3];\n} ht_marschner_reference[] = {\n")
    out.write("\n".join(lines) + "\n};\n")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""lanecast's column-density maps against SPLASH's (Debian `splash`, issue 27's
verification), run by meson test `sph_splash` (tests/test_sph_splash.sh).

usage: sph_splash.py LANECAST WORK_DIR [--break]

Two GADGET format-1 snapshots of gas particles with masses, densities and
smoothing lengths are written here (bench/peers_splash.py's writer; the
positions are random, so no shared data is needed; HSML = the M4 support H,
which SPLASH halves into its h):
  centre: 400 particles with H from 1.2 to 4 pixels of a 64^2 map. SPLASH's
          default projection samples each pixel centre and raises h to half a
          pixel (H to one pixel) without renormalising; with every H >= 1
          pixel that floor never acts, so `lanecast render --mode project
          --sample centre` must give the same map.
  exact:  300 particles with H from 0.2 to 0.45 pixels. SPLASH's exact
          rendering (exact_rendering = T, Petkova et al. 2018) is exact only
          for particles whose pixel index range ipixmax - ipixmin spans at
          most 2 (interpolate3D_projection.f90), i.e. a support diameter
          2H < 1 pixel wherever the particle sits; larger particles fall back
          to pixel centres there. So the exact comparison is for particles
          below half a pixel: lanecast's exact pixel averages against it.
SPLASH runs non-interactively: a splash.defaults with npix = 64 and
exact_rendering, a splash.limits with the x and y range (the pixel grid:
pixel i covers xmin + [i, i + 1) dx, its centre at xmin + (i + 1/2) dx), the
density column rendered (-r), `-dev /null -o ascii` writing the pixel map as
text (1pe14.6: 7 digits; its .pfm is a Fortran sequential record, not a
plain PFM), `--codeunits` so the map is in the file's mass / length^2.
lanecast looks down -z at the same square (--ortho = the map's height, --eye
above its centre); its rows run top to bottom, SPLASH's bottom to top.
Both maps hold sum_j m_j F(R_j / H_j) / H_j^2 (SPLASH: m / (rho h^3) * h * rho
per particle times its integrated kernel). Checks: max |lanecast - SPLASH|
over the map below 1e-4 of the map's largest pixel and the median relative
difference over pixels above 1e-3 of it below 1e-4; --break scales one
particle's mass by 1.01 in lanecast's file only, which must fail.
Exit 0 pass, 1 fail, 2 error, 77 skip (no splash).
"""
import os
import re
import shutil
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "bench"))
import peers_splash as ps  # noqa: E402  (the GADGET format-1 writer)

NPIX = 64
BOX = 1.0


def die(msg):
    """Errors exit 2: exit 1 is a failed comparison (--break expects it)."""
    print("sph_splash.py: " + msg, file=sys.stderr)
    sys.exit(2)


def snapshot(path, n, hmin, hmax, seed, bump=1.0):
    rng = np.random.default_rng(seed)
    pix = BOX / NPIX
    H = rng.uniform(hmin, hmax, n) * pix
    pos = np.column_stack([rng.uniform(H, BOX - H), rng.uniform(H, BOX - H), rng.uniform(0.0, BOX, n)])
    mass = rng.uniform(0.5, 1.5, n) / n
    mass[0] *= bump
    rho = rng.uniform(1.0, 3.0, n)  # any positive density: the column of rho is sum m W (rho cancels)
    ps.write_snapshot(path, bytes(256), n, 0.0, pos, np.zeros((n, 3)), mass, np.ones(n), rho, H)
    return pos, mass, H


def splash_map(snap, work, exact, npix=NPIX, lim=(0.0, BOX, 0.0, BOX, 0.0, BOX)):
    """SPLASH's column density map of snap's density column on npix pixels
    across the x, y limits lim (x0, x1, y0, y1, z0, z1), as (map with rows top to bottom, x0, y0, dx,
    SPLASH's log)."""
    menu = subprocess.run(["splash", "-f", "gadget", snap], input="q\n", capture_output=True, text=True, cwd=work,
                          timeout=120)
    cols = [int(c) for c in re.findall(r"^\s*(\d+)\)", menu.stdout, re.M)]
    m = re.search(r"(\d+)\)\s*density", menu.stdout, re.I)
    if not m or not cols:
        die("no density column in SPLASH's menu:\n" + menu.stdout[-1500:])
    with open(os.path.join(work, "splash.defaults"), "w") as f:
        # the groups before renderopts, empty, so the namelist reads reach it in order
        f.write("&dataopts\n/\n&plotopts\n/\n&pageopts\n/\n")
        f.write("&renderopts\n npix = %d,\n exact_rendering = %s,\n/\n" % (npix, "T" if exact else "F"))
    with open(os.path.join(work, "splash.limits"), "w") as f:
        for c in range(1, max(cols) + 1):
            f.write("%r %r\n" % (tuple(lim[2 * c - 2:2 * c]) if c <= 3 else (0.0, 1.0)))
    for p in os.listdir(work):
        if p.endswith(".pix"):
            os.remove(os.path.join(work, p))
    p = subprocess.run(["splash", "-f", "gadget", snap, "-r", m.group(1), "--codeunits", "-dev", "/null", "-o",
                        "ascii"], capture_output=True, text=True, cwd=work, stdin=subprocess.DEVNULL, timeout=300)
    pix = sorted(f for f in os.listdir(work) if f.endswith(".pix"))
    if p.returncode or not pix:
        die("splash failed (%d): %s" % (p.returncode, (p.stdout + p.stderr)[-1500:]))
    text = open(os.path.join(work, pix[0])).read()
    hx = re.search(r"x axis: min =\s*(\S+) max =\s*(\S+)", text)
    hy = re.search(r"y axis: min =\s*(\S+) max =\s*(\S+)", text)
    a = np.loadtxt(os.path.join(work, pix[0]), comments="#")
    ny, nx = a.shape
    dx = (float(hx.group(2)) - float(hx.group(1))) / (nx - 1)
    return a[::-1], float(hx.group(1)), float(hy.group(1)), dx, p.stdout


def lanecast_map(exe, snap, work, sample, x0, y0, nx, ny, dx):
    """lanecast's column map of snap (M4) on SPLASH's pixel grid."""
    out = os.path.join(work, "lc_%s.npy" % sample)
    cx, cy = x0 + 0.5 * nx * dx, y0 + 0.5 * ny * dx
    # --value rho: the SPH column of the density, sum (m / rho) rho W = sum m W (SPLASH's column density)
    args = [exe, "render", snap, "--types", "0", "--mode", "project", "--kernel", "m4", "--value", "rho", "--sample",
            sample, "--size",
            "%dx%d" % (nx, ny), "--ortho", repr(ny * dx), "--eye", "%r,%r,%r" % (cx, cy, 10.0), "--at",
            "%r,%r,%r" % (cx, cy, 0.5), "-o", out, "--threads", "2", "--quiet"]
    p = subprocess.run(args, capture_output=True, text=True, timeout=300)
    if p.returncode:
        die("lanecast failed: " + p.stderr)
    return np.load(out).astype(np.float64)


def compare(name, a, b, pixel, mass, failures):
    big = b.max()
    diff = np.abs(a - b)
    m = b > 1e-3 * big
    rel = diff[m] / b[m]
    line = ("%s: %d x %d pixels, max |lanecast - SPLASH| = %.2e of the largest pixel, relative difference over "
            "%d pixels above 1e-3 of it: median %.2e, 99th percentile %.2e; map mass lanecast %.6f SPLASH %.6f, "
            "sum m %.6f" % (name, a.shape[1], a.shape[0], diff.max() / big, int(m.sum()), np.median(rel),
                            np.percentile(rel, 99), a.sum() * pixel * pixel, b.sum() * pixel * pixel, mass.sum()))
    ok = diff.max() < 1e-4 * big and np.median(rel) < 1e-4
    print(("ok   " if ok else "FAIL ") + line)
    if not ok:
        failures.append(name)


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    exe, work = sys.argv[1], sys.argv[2]
    broken = "--break" in sys.argv[3:]
    if not shutil.which("splash"):
        print("skip: SPLASH (Debian package splash) is not installed")
        return 77
    os.makedirs(work, exist_ok=True)
    failures = []
    for name, n, hmin, hmax, sample, exact in (("centre", 400, 1.2, 4.0, "centre", False),
                                               ("exact", 300, 0.2, 0.45, "exact", True)):
        snap = os.path.join(work, "%s.dat" % name)
        pos, mass, H = snapshot(snap, n, hmin, hmax, seed=len(name))
        b, x0, y0, dx, log = splash_map(snap, work, exact)
        if exact and "exact" not in log:
            die("SPLASH did not say it rendered exactly:\n" + log[-1500:])
        lsnap = snap
        if broken:
            lsnap = os.path.join(work, "%s_broken.dat" % name)
            snapshot(lsnap, n, hmin, hmax, seed=len(name), bump=1.01)
        a = lanecast_map(exe, lsnap, work, sample, x0, y0, b.shape[1], b.shape[0], dx)
        if a.shape != b.shape:
            die("%s: lanecast map %s, SPLASH's %s" % (name, a.shape, b.shape))
        compare(name, a, b, dx, mass, failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

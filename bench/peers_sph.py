#!/usr/bin/python3
"""Column-density projections: lanecast --mode project against SPLASH (Debian
`splash`) and yt (python3-yt) on the same GADGET snapshots (run by
bench/peers_sph.sh).

usage: peers_sph.py LANECAST DATA_DIR RECORDS.jsonl [N_GENERATED] [SIZES]
environment: LANECAST_BASE  a second lanecast (a build of another commit), run
                            side by side with the first on the same maps
             REPS           runs of each program per map (default 3; medians)
             BIG=N          instead: lanecast alone on a generated file of N particles
                            (analytic smoothing lengths, big_clumps) at SIZES
             BIG_FILE=PATH  with BIG: write that file there and keep it, or reuse it

Snapshots: the shared LCDM gas initial conditions (32,768 particles, HSML =
distance to the 32nd neighbour, RHO from GADGET-2's cubic spline: the file
that bench/peers_splash.py writes), and a generated one of N_GENERATED
(default 1e6) particles in 64 Plummer clumps of random sizes in a unit box
with the same HSML and RHO rules. Each program projects the whole box along
z onto SIZE^2 pixels (SIZES default 1024,2048) with the M4 kernel (support
HSML), all over the same frame (x, y in [0, box]): lanecast's exact pixel
averages of --value rho (with an SPH kernel the SPH interpolant of rho, whose
column is sum m W: the surface density); SPLASH's default column-density render (pixel centres, h floor),
framed by a splash.limits file and dumped as a pixel map (-o ascii); yt's
ProjectionPlot of ("gas", "density"). Recorded per map: the median wall time
of each program's whole run (every run's too) and its peak resident memory,
lanecast's projection time and kernel-pixel evaluations, each map's mass (sum
of pixels x pixel area) against the particles' mass inside the image, the
agreement of the maps (median and 99th percentile of |a - b| / b where
b > 1e-3 max) and the load average before and after.
"""
import glob
import json
import math
import os
import re
import struct
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import cKDTree

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peers_splash as ps  # noqa: E402  (GADGET reading and writing, the cubic spline)

K = 32


def sph(pos, mass):
    tree = cKDTree(pos)
    dist, idx = tree.query(pos, k=K + 1)
    hsml = dist[:, K]
    rho = np.sum(mass[idx] * ps.w_gadget(dist, hsml[:, None]), axis=1)
    return hsml, rho


def clumps(n, seed=1):
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.15, 0.85, (64, 3))
    sizes = 10 ** rng.uniform(-2.2, -1.2, 64)
    which = rng.integers(0, 64, n)
    x = rng.uniform(0, 1, n) * 0.999 + 5e-4
    r = sizes[which] / np.sqrt(x ** (-2.0 / 3.0) - 1.0)
    r = np.minimum(r, 0.5)
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=1)[:, None]
    pos = np.clip(centres[which] + r[:, None] * v, 0.0, 1.0)
    return pos


def big_clumps(path, n, template_hdr, seed=2, chunk=10 ** 7):
    """A GADGET file of n particles in 64 Plummer clumps as clumps() draws them, with the
    analytic HSML of 32 neighbours at the clump's density (no neighbour search at this size:
    H = (24 / (pi n(r)))^(1/3), n(r) = 3 n_c / (4 pi a^3) (1 + r^2 / a^2)^(-5/2)), equal masses
    1 / n in the header's mass table (no MASS block); written block by block."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.15, 0.85, (64, 3))
    sizes = 10 ** rng.uniform(-2.2, -1.2, 64)
    pos = np.empty((n, 3), np.float32)
    hsml = np.empty(n, np.float32)
    rho = np.empty(n, np.float32)
    for o in range(0, n, chunk):
        m = min(chunk, n - o)
        which = rng.integers(0, 64, m)
        x = rng.uniform(0, 1, m) * 0.999 + 5e-4
        a = sizes[which]
        r = np.minimum(a / np.sqrt(x ** (-2.0 / 3.0) - 1.0), 0.5)
        v = rng.normal(size=(m, 3))
        v /= np.linalg.norm(v, axis=1)[:, None]
        pos[o:o + m] = np.clip(centres[which] + r[:, None] * v, 0.0, 1.0)
        dens = 3 * (n / 64.0) / (4 * math.pi * a ** 3) * (1 + (r / a) ** 2) ** -2.5
        hsml[o:o + m] = (24.0 / (math.pi * dens)) ** (1.0 / 3.0)
        rho[o:o + m] = dens / n
    h = bytearray(template_hdr)
    struct.pack_into("<6i", h, 0, n, 0, 0, 0, 0, 0)
    struct.pack_into("<6d", h, 24, 1.0 / n, 0, 0, 0, 0, 0)
    struct.pack_into("<6I", h, 24 + 48 + 16 + 8, n, 0, 0, 0, 0, 0)
    struct.pack_into("<i", h, 24 + 48 + 16 + 8 + 24, 0)
    struct.pack_into("<i", h, 24 + 48 + 16 + 8 + 24 + 4, 1)

    def rec(f, parts, nbytes):
        f.write(struct.pack("<i", nbytes))
        for b in parts:
            f.write(b)
        f.write(struct.pack("<i", nbytes))

    with open(path, "wb") as f:
        rec(f, [bytes(h)], len(h))
        rec(f, [pos.tobytes()], 12 * n)
        zeros = np.zeros(3 * chunk, np.float32).tobytes()
        rec(f, [zeros[:12 * min(chunk, n - o)] for o in range(0, n, chunk)], 12 * n)
        rec(f, [np.arange(o + 1, o + 1 + min(chunk, n - o), dtype="<u4").tobytes() for o in range(0, n, chunk)], 4 * n)
        rec(f, [np.ones(min(chunk, n - o), np.float32).tobytes() for o in range(0, n, chunk)], 4 * n)
        rec(f, [rho.tobytes()], 4 * n)
        rec(f, [hsml.tobytes()], 4 * n)
    return hsml


def big(exe, n, sizes, recs, work):
    """lanecast alone on a generated snapshot of n particles (peers would not fit or finish)."""
    path = os.environ.get("BIG_FILE") or os.path.join(work, "big_%d.dat" % n)
    keep = bool(os.environ.get("BIG_FILE")) and os.path.exists(path)
    if keep:  # a file big_clumps wrote before (BIG_FILE): its HSML block is the last, n floats
        hs = np.memmap(path, dtype="<f4", mode="r", offset=os.path.getsize(path) - 4 - 4 * n, shape=(n,))
        gen = None
    else:
        src = os.path.join(work, "lcdm.dat")
        hdr = ps.records(open(src, "rb").read(64 * 1024))[0] if os.path.exists(src) else bytes(256)
        t0 = time.perf_counter()
        hs = big_clumps(path, n, hdr)
        gen = time.perf_counter() - t0
    for size in sizes:
        rec = {"record": "peer_sph_big", "scene": "clumps %d (analytic HSML)" % n, "size": size, "threads": 2,
               "generate_s": gen, "hsml_pixels_median": float(np.median(hs) * size), "loadavg_before": os.getloadavg()[0]}
        lc = lanecast(exe, path, size, 1.0, work)
        pix = lc["side"]["pixel"]
        rec.update(lanecast_wall_s=lc["wall"], lanecast_project_s=lc["project"], lanecast_load_s=lc["load"],
                   lanecast_rss_mb=lc["rss_mb"], kernel_pixels=lc["evals"], kernel_pixels_per_s=lc["evals"] / lc["project"],
                   lanecast_mass=float(lc["map"].astype(np.float64).sum() * pix * pix), loadavg_after=os.getloadavg()[0])
        print(json.dumps(rec))
        with open(recs, "a") as f:
            f.write(json.dumps(rec) + "\n")
    if not os.environ.get("BIG_FILE"):
        os.remove(path)


def write(path, pos, mass, hsml, rho, template_hdr):
    n = len(pos)
    ps.write_snapshot(path, template_hdr, n, 0.0, pos, np.zeros((n, 3)), mass, np.ones(n), rho, hsml)


def run(args, cwd=None, stdin=None):
    """Wall time, exit code, output and the peak resident memory (MB) of the program: through
    /usr/bin/time (-f %M), since a child forked from this (large) Python keeps its parent's
    high-water mark across exec in wait4's ru_maxrss."""
    import tempfile
    with tempfile.NamedTemporaryFile("w+", suffix=".rss") as fr:
        t0 = time.perf_counter()
        p = subprocess.run(["/usr/bin/time", "-f", "%M", "-o", fr.name] + args, capture_output=True, text=True, cwd=cwd,
                           input=stdin or "", timeout=3600)
        wall = time.perf_counter() - t0
        fr.seek(0)
        kb = re.findall(r"^(\d+)\s*$", fr.read(), re.M)
    return {"wall": wall, "rc": p.returncode, "out": p.stdout, "err": p.stderr, "rss_mb": int(kb[-1]) / 1024 if kb else None}


def median(fn, reps):
    """The run of median wall time among reps runs of fn() (a dict with "wall" when it worked)."""
    runs = [fn() for _ in range(reps)]
    ok = sorted((r for r in runs if "wall" in r), key=lambda r: r["wall"])
    if not ok:
        return runs[-1]
    best = dict(ok[len(ok) // 2])
    best["walls"] = [round(r["wall"], 3) for r in ok]
    return best


def inside_mass(pos, mass, hsml, lo, hi):
    ok = np.all((pos[:, :2] - hsml[:, None] >= lo) & (pos[:, :2] + hsml[:, None] <= hi), axis=1)
    return float(mass[ok].sum()), float(mass.sum())


def agreement(a, b):
    m = b > 1e-3 * b.max()
    d = np.abs(a[m] - b[m]) / b[m]
    return float(np.median(d)), float(np.percentile(d, 99))


def lanecast(exe, snap, size, box, work):
    """The map over x, y in [0, box] (rows top to bottom), down -z."""
    out = os.path.join(work, "lc_%d.npy" % size)
    c = box / 2
    r = run([exe, "render", snap, "--types", "0", "--mode", "project", "--kernel", "m4", "--value", "rho", "--size",
             "%dx%d" % (size, size), "--at", "%r,%r,%r" % (c, c, c), "--eye", "%r,%r,%r" % (c, c, 3 * box + 1),
             "--up", "0,1,0", "--ortho", "%r" % box, "-o", out, "--stats", "--threads", "2"])
    if r["rc"]:
        sys.exit("lanecast failed: " + r["err"])
    st = r["out"]
    r["project"] = float(re.search(r"^project\s+([0-9.]+) s", st, re.M).group(1))
    r["load"] = float(re.search(r"^load\s+([0-9.]+) s", st, re.M).group(1))
    r["evals"] = int(re.search(r"^kernel-pixels\s+(\d+)", st, re.M).group(1))
    r["map"] = np.load(out)
    r["side"] = json.load(open(out + ".json"))
    return r


def splash_column(snap, work):
    """The density column of SPLASH's menu, and its own settings files saved (S) for splash() to edit."""
    for f in ("splash.defaults", "splash.limits"):
        if os.path.exists(os.path.join(work, f)):
            os.remove(os.path.join(work, f))
    menu = run(["splash", "-f", "gadget", snap], cwd=work, stdin="S\nq\n")
    m = re.search(r"(\d+)\)\s*density", menu["out"], re.I)
    ok = all(os.path.exists(os.path.join(work, f)) for f in ("splash.defaults", "splash.limits"))
    return m.group(1) if m and ok else None


def splash(snap, size, box, col, work):
    """SPLASH's column-density map over x, y in [0, box] (rows top to bottom): the pixel count
    is NPIX of its saved splash.defaults, the frame the first two lines (x, y) of splash.limits."""
    for f in glob.glob(os.path.join(work, "*.pix")):
        os.remove(f)
    dpath, lpath = os.path.join(work, "splash.defaults"), os.path.join(work, "splash.limits")
    d = re.sub(r"NPIX=\s*\d+", "NPIX=%d" % size, open(dpath).read())
    open(dpath, "w").write(d)
    lines = open(lpath).read().splitlines()
    lines[0] = lines[1] = "%.9g %.9g" % (0.0, box)
    open(lpath, "w").write("\n".join(lines) + "\n")
    r = run(["splash", "-f", "gadget", snap, "-r", col, "-dev", "/null", "-o", "ascii"], cwd=work)
    pix = sorted(glob.glob(os.path.join(work, "*.pix")))
    if r["rc"] or not pix:
        return {"error": (r["out"] + r["err"])[-400:]}
    a = np.atleast_2d(np.loadtxt(pix[0], comments="#"))
    if a.shape != (size, size):
        return {"error": "SPLASH wrote a %dx%d pixel map (%s)" % (a.shape[0], a.shape[1], os.path.basename(pix[0]))}
    r["map"] = a[::-1]
    return r


def yt_project(snap, size, box, work):
    code = """
import sys, time, numpy as np, yt
t0 = time.perf_counter()
ds = yt.load(sys.argv[1], unit_base={"length": (1.0, "cm"), "mass": (1.0, "g"), "velocity": (1.0, "cm/s")},
             bounding_box=[[0, %r], [0, %r], [0, %r]])
p = yt.ProjectionPlot(ds, "z", ("gas", "density"), buff_size=(%d, %d), width=(%r, "cm"), center=[%r, %r, %r])
a = np.array(p.frb[("gas", "density")].to("g/cm**2"))
np.save(sys.argv[2], a)
print("yt_seconds", time.perf_counter() - t0)
""" % (box, box, box, size, size, box, box / 2, box / 2, box / 2)
    out = os.path.join(work, "yt_%d.npy" % size)
    r = run(["/usr/bin/python3", "-c", code, snap, out], cwd=work)
    if r["rc"]:
        return {"error": (r["out"] + r["err"])[-600:]}
    r["map"] = np.load(out)[::-1]  # yt's frb: row 0 at the bottom
    return r


def main():
    exe, data, recs = sys.argv[1:4]
    base = os.environ.get("LANECAST_BASE")
    reps = int(os.environ.get("REPS", "3"))
    ngen = int(float(sys.argv[4])) if len(sys.argv) > 4 else 1000000
    sizes = [int(s) for s in (sys.argv[5] if len(sys.argv) > 5 else "1024,2048").split(",")]
    work = "/tmp/lanecast_peers_sph"
    os.makedirs(work, exist_ok=True)
    if os.environ.get("BIG"):  # only the generated large projection
        big(exe, int(float(os.environ["BIG"])), sizes, recs, work)
        return
    src = os.path.join(data, "particles", "gadget_lcdm_gas.dat")
    hdr, npart, massarr, box, pos, vel, mass, u = ps.read_gas(src)
    snaps = []
    lpos = pos.copy()
    lbox = float(np.max(lpos) - np.min(lpos))
    lpos -= np.min(lpos)
    h, r = sph(lpos, mass)
    p1 = os.path.join(work, "lcdm.dat")
    write(p1, lpos, mass, h, r, hdr)
    snaps.append(("lcdm gas %d" % len(lpos), p1, lpos, mass, h, lbox))
    gpos = clumps(ngen)
    gmass = np.full(ngen, 1.0 / ngen)
    h, r = sph(gpos, gmass)
    p2 = os.path.join(work, "clumps.dat")
    write(p2, gpos, gmass, h, r, hdr)
    snaps.append(("clumps %d" % ngen, p2, gpos, gmass, h, 1.0))
    have_splash = subprocess.run(["which", "splash"], capture_output=True).returncode == 0
    for name, snap, P, M, Hs, bx in snaps:
        col = splash_column(snap, work) if have_splash else None
        for size in sizes:
            rec = {"record": "peer_sph", "scene": name, "size": size, "threads": 2, "reps": reps,
                   "loadavg_before": os.getloadavg()[0]}
            lc = median(lambda: lanecast(exe, snap, size, bx, work), reps)
            m, e, pix = lc["map"], lc["side"]["extent"], lc["side"]["pixel"]
            mi, mt = inside_mass(P, M, Hs, np.array([e[0], e[2]]), np.array([e[1], e[3]]))
            rec.update(lanecast_wall_s=lc["wall"], lanecast_walls=lc["walls"], lanecast_project_s=lc["project"],
                       lanecast_load_s=lc["load"], lanecast_rss_mb=lc["rss_mb"], kernel_pixels=lc["evals"],
                       kernel_pixels_per_s=lc["evals"] / lc["project"], lanecast_mass=float(m.sum() * pix * pix),
                       mass_inside=mi, mass_total=mt, extent=e)
            if base:
                b = median(lambda: lanecast(base, snap, size, bx, work), reps)
                rec.update(base_wall_s=b["wall"], base_walls=b["walls"], base_project_s=b["project"],
                           base_rss_mb=b["rss_mb"], base_vs_lanecast_max=float(np.max(np.abs(b["map"] - m)) / m.max()))
            maps = {}
            peers = [("yt", lambda: yt_project(snap, size, bx, work))]
            if col:
                peers.insert(0, ("splash", lambda: splash(snap, size, bx, col, work)))
            for peer, fn in peers:
                pr = median(fn, reps)
                if "wall" not in pr:
                    rec[peer + "_error"] = pr["error"]
                    continue
                maps[peer] = pr["map"]
                rec.update({peer + "_wall_s": pr["wall"], peer + "_walls": pr["walls"], peer + "_rss_mb": pr["rss_mb"],
                            peer + "_mass": float(pr["map"].sum() * (bx / size) ** 2)})
            for peer, pm in maps.items():
                if pm.shape == m.shape:
                    med, p99 = agreement(m, pm)
                    rec[peer + "_vs_lanecast_median"], rec[peer + "_vs_lanecast_p99"] = med, p99
                rec[peer + "_over_lanecast"] = rec[peer + "_wall_s"] / rec["lanecast_wall_s"]
            rec["loadavg_after"] = os.getloadavg()[0]
            print(json.dumps(rec))
            with open(recs, "a") as f:
                f.write(json.dumps(rec) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Column-density projections: lanecast --mode project against SPLASH (Debian
`splash`) and yt (python3-yt) on the same GADGET snapshots (run by
bench/peers_sph.sh).

usage: peers_sph.py LANECAST DATA_DIR RECORDS.jsonl [N_GENERATED] [SIZES]

Snapshots: the shared LCDM gas initial conditions (32,768 particles, HSML =
distance to the 32nd neighbour, RHO from GADGET-2's cubic spline: the file
that bench/peers_splash.py writes), and a generated one of N_GENERATED
(default 1e6) particles in 64 Plummer clumps of random sizes in a unit box
with the same HSML and RHO rules. Each program projects the whole box along
z onto SIZE^2 pixels (SIZES default 1024,2048) with the M4 kernel (support
HSML): lanecast's exact pixel averages; SPLASH's default column-density
render (pixel centres, h floor) dumped as a pixel map (-o ascii); yt's
ProjectionPlot of ("gas", "density"). Recorded per run: wall time of the
whole run, lanecast's projection time and kernel-pixel evaluations, the map's
mass (sum of pixels x pixel area) against the particles' mass inside the
image, and the agreement of the maps (median and 99th percentile of
|a - b| / b where b > 1e-3 max).
"""
import glob
import json
import math
import os
import re
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


def write(path, pos, mass, hsml, rho, template_hdr):
    n = len(pos)
    ps.write_snapshot(path, template_hdr, n, 0.0, pos, np.zeros((n, 3)), mass, np.ones(n), rho, hsml)


def run(args, cwd=None, stdin=None):
    t0 = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True, cwd=cwd, input=stdin, timeout=3600)
    return time.perf_counter() - t0, p


def inside_mass(pos, mass, hsml, lo, hi):
    ok = np.all((pos[:, :2] - hsml[:, None] >= lo) & (pos[:, :2] + hsml[:, None] <= hi), axis=1)
    return float(mass[ok].sum()), float(mass.sum())


def agreement(a, b):
    m = b > 1e-3 * b.max()
    d = np.abs(a[m] - b[m]) / b[m]
    return float(np.median(d)), float(np.percentile(d, 99))


def lanecast(exe, snap, size, work):
    out = os.path.join(work, "lc_%d.npy" % size)
    wall, p = run([exe, "render", snap, "--types", "0", "--mode", "project", "--kernel", "m4", "--size",
                   "%dx%d" % (size, size), "-o", out, "--stats", "--threads", "2"])
    if p.returncode:
        sys.exit("lanecast failed: " + p.stderr)
    st = p.stdout
    proj = float(re.search(r"^project\s+([0-9.]+) s", st, re.M).group(1))
    evals = int(re.search(r"^kernel-pixels\s+(\d+)", st, re.M).group(1))
    side = json.load(open(out + ".json"))
    return wall, proj, evals, np.load(out), side


def splash(snap, size, work):
    for f in glob.glob(os.path.join(work, "*.pix")):
        os.remove(f)
    with open(os.path.join(work, "splash.defaults"), "w") as f:
        pass
    menu = subprocess.run(["splash", "-f", "gadget", snap], input="q\n", capture_output=True, text=True, cwd=work,
                          timeout=120)
    m = re.search(r"(\d+)\)\s*density", menu.stdout, re.I)
    if not m:
        return None
    col = m.group(1)
    wall, p = run(["splash", "-f", "gadget", snap, "-r", col, "-dev", "/null", "-o", "ascii"], cwd=work,
                  stdin="")
    pix = sorted(glob.glob(os.path.join(work, "*.pix")))
    if p.returncode or not pix:
        return {"error": (p.stdout + p.stderr)[-400:]}
    a = np.atleast_2d(np.loadtxt(pix[0], comments="#"))
    if a.size < 4:  # SPLASH could not frame the data (its limits came out empty)
        return {"error": "SPLASH wrote a %dx%d pixel map (%s)" % (a.shape[0], a.shape[1], os.path.basename(pix[0]))}
    return {"wall": wall, "map": a[::-1], "file": os.path.basename(pix[0])}


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
    wall, p = run(["/usr/bin/python3", "-c", code, snap, out], cwd=work)
    if p.returncode:
        return {"error": (p.stdout + p.stderr)[-600:]}
    return {"wall": wall, "map": np.load(out)}


def main():
    exe, data, recs = sys.argv[1:4]
    ngen = int(float(sys.argv[4])) if len(sys.argv) > 4 else 1000000
    sizes = [int(s) for s in (sys.argv[5] if len(sys.argv) > 5 else "1024,2048").split(",")]
    work = "/tmp/lanecast_peers_sph"
    os.makedirs(work, exist_ok=True)
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
    for name, snap, P, M, Hs, bx in snaps:
        for size in sizes:
            rec = {"record": "peer_sph", "scene": name, "size": size, "threads": 2, "loadavg": os.getloadavg()[0]}
            wall, proj, evals, m, side = lanecast(exe, snap, size, work)
            e = side["extent"]
            pix = side["pixel"]
            mi, mt = inside_mass(P, M, Hs, np.array([e[0], e[2]]), np.array([e[1], e[3]]))
            rec.update(lanecast_wall_s=wall, lanecast_project_s=proj, kernel_pixels=evals,
                       kernel_pixels_per_s=evals / proj, lanecast_mass=float(m.sum() * pix * pix), mass_inside=mi,
                       mass_total=mt)
            sp = splash(snap, size, work) if subprocess.run(["which", "splash"], capture_output=True).returncode == 0 else None
            if sp and "wall" in sp:
                a = sp["map"]
                rec.update(splash_wall_s=sp["wall"], splash_pixels=list(a.shape))
                # SPLASH frames the particles' own x, y range: its pixel is the range / its pixel count
                spix = (float(np.ptp(P[:, 0]))) / a.shape[1]
                rec["splash_mass"] = float(a.sum() * spix * (float(np.ptp(P[:, 1])) / a.shape[0]))
            elif sp:
                rec["splash_error"] = sp["error"]
            yt = yt_project(snap, size, bx, work)
            if "wall" in yt:
                ym = yt["map"]
                rec.update(yt_wall_s=yt["wall"], yt_mass=float(ym.sum() * (bx / size) ** 2))
                if ym.shape == m.shape:
                    med, p99 = agreement(m, ym.T[::-1])
                    rec.update(yt_vs_lanecast_median=med, yt_vs_lanecast_p99=p99)
            else:
                rec["yt_error"] = yt["error"]
            print(json.dumps(rec))
            with open(recs, "a") as f:
                f.write(json.dumps(rec) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""lanecast against SPLASH (Debian `splash`) on the same SPH gas particles
(run by bench/peers.sh; it installs splash when asked).

usage: peers_splash.py LANECAST DATA_DIR OUT_DIR RECORDS.jsonl [SPLIT]

SPLIT (default 1) refines the gas SPLIT times by particle splitting before
anything else: each particle becomes 8 at its position +-1/4 of the mean
particle spacing on each axis, with 1/8 of its mass and its velocity and
internal energy, so the 32,768 gas particles become 262,144 (SPLIT 1) or
2,097,152 (SPLIT 2) that sample the same density field; SPLIT 0 keeps them.

The shared GADGET initial conditions (particles/gadget_lcdm_gas.dat: 32,768
gas particles) carry no densities or smoothing lengths, which SPLASH needs,
so this writes a GADGET format-1 snapshot of the gas that has them:
HSML = distance to the 32nd nearest neighbour (periodic when the header
has a BoxSize; the shared file has 0: then an open box; GADGET-2's
convention: the kernel's support is HSML), RHO = the SPH density
sum_j m_j W(r_ij, HSML_i) with GADGET-2's cubic spline. SPLASH renders RHO
with opacity rendering (--kappa: opacity per unit column density, projected
along z, orthographic). lanecast renders the same particles from a CSV of
the same positions: each a Gaussian with the standard deviation of the
cubic spline of support HSML (computed below) and weight
m / ((2 pi)^1.5 r^3), so the sum approximates the same density field; its TF
has tau = kappa * rho (linear opacity over [0, max rho]), grey colours, and
an orthographic camera looking down -z over the whole box.
Times: each program's whole run (start, read, render, write a PNG) and, for
lanecast, the render alone (--stats).
"""
import json
import math
import os
import re
import statistics
import struct
import subprocess
import sys
import time

import numpy as np
from scipy.spatial import cKDTree

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

K = 32
SIZE = 512


def records(buf):
    """GADGET format-1: Fortran records (int32 length, payload, int32 length)."""
    out, o = [], 0
    while o + 4 <= len(buf):
        (n,) = struct.unpack_from("<i", buf, o)
        out.append(buf[o + 4:o + 4 + n])
        o += 8 + n
    return out


def read_gas(path):
    recs = records(open(path, "rb").read())
    hdr = recs[0]
    npart = struct.unpack_from("<6i", hdr, 0)
    massarr = struct.unpack_from("<6d", hdr, 24)
    box = struct.unpack_from("<d", hdr, 24 + 48 + 16 + 8 + 24 + 8)[0]
    ng, ntot = npart[0], sum(npart)
    pos = np.frombuffer(recs[1], "<f4", 3 * ntot).reshape(-1, 3)[:ng].astype(np.float64)
    vel = np.frombuffer(recs[2], "<f4", 3 * ntot).reshape(-1, 3)[:ng]
    has_mass_block = any(n > 0 and m == 0 for m, n in zip(massarr, npart))
    if massarr[0] > 0:
        mass = np.full(ng, massarr[0])
    else:
        mass = np.frombuffer(recs[4], "<f4", ng).astype(np.float64)
    u_rec = recs[5] if has_mass_block else recs[4]
    u = np.frombuffer(u_rec, "<f4", ng)
    return hdr, npart, massarr, box, pos, vel, mass, u


def w_gadget(r, h):
    """GADGET-2's cubic spline, support h."""
    q = r / h
    w = np.where(q < 0.5, 1 - 6 * q ** 2 + 6 * q ** 3, np.where(q < 1, 2 * (1 - q) ** 3, 0.0))
    return 8 / (math.pi * h ** 3) * w


def spline_sigma(h=1.0):
    """Standard deviation per axis of the cubic spline with support h."""
    r = np.linspace(0, h, 20001)
    w = w_gadget(r, h) * 4 * math.pi * r ** 2
    return math.sqrt(np.trapz(w * r ** 2, r) / np.trapz(w, r) / 3)


def write_snapshot(path, hdr, ng, mass_const, pos, vel, mass, u, rho, hsml):
    h = bytearray(hdr)
    struct.pack_into("<6i", h, 0, ng, 0, 0, 0, 0, 0)
    struct.pack_into("<6d", h, 24, mass_const, 0, 0, 0, 0, 0)
    struct.pack_into("<6I", h, 24 + 48 + 16 + 8, ng, 0, 0, 0, 0, 0)
    struct.pack_into("<i", h, 24 + 48 + 16 + 8 + 24, 0)  # no cooling: no NE, NH blocks
    struct.pack_into("<i", h, 24 + 48 + 16 + 8 + 24 + 4, 1)

    def rec(f, b):
        f.write(struct.pack("<i", len(b)) + b + struct.pack("<i", len(b)))

    with open(path, "wb") as f:
        rec(f, bytes(h))
        rec(f, pos.astype("<f4").tobytes())
        rec(f, np.ascontiguousarray(vel, "<f4").tobytes())
        rec(f, np.arange(1, ng + 1, dtype="<u4").tobytes())
        if mass_const == 0:
            rec(f, mass.astype("<f4").tobytes())
        for a in (u, rho, hsml):
            rec(f, np.asarray(a, "<f4").tobytes())


def main():
    exe, data, out_dir, recs_path = sys.argv[1:5]
    src = os.path.join(data, "particles", "gadget_lcdm_gas.dat")
    if not os.path.exists(src):
        print("peers_splash.py: %s absent, skipped" % src)
        return
    work = os.path.join("/tmp", "lanecast_peers_splash")
    os.makedirs(work, exist_ok=True)
    hdr, npart, massarr, box, pos, vel, mass, u = read_gas(src)
    ng = npart[0]
    split = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    ng0 = ng
    for _ in range(split):  # particle splitting: 8 children a quarter spacing around each parent
        span = box if box > 0 else float(np.max(pos) - np.min(pos))
        d = 0.25 * span / ng ** (1.0 / 3.0)
        off = np.array([[sx, sy, sz] for sx in (-d, d) for sy in (-d, d) for sz in (-d, d)])
        pos = (pos[:, None, :] + off[None, :, :]).reshape(-1, 3)
        vel = np.repeat(vel, 8, axis=0)
        u = np.repeat(u, 8)
        mass = np.repeat(mass / 8.0, 8)
        massarr = list(massarr)
        massarr[0] = massarr[0] / 8.0
        ng *= 8
    if box > 0:  # periodic
        pos = np.mod(pos, box)
        tree = cKDTree(pos, boxsize=box)
    else:  # these initial conditions leave BoxSize 0: an open box over the positions
        box = float(np.max(pos) - np.min(pos))
        tree = cKDTree(pos)
    dist, idx = tree.query(pos, k=K + 1)
    hsml = dist[:, K]
    rho = np.sum(mass[idx] * w_gadget(dist, hsml[:, None]), axis=1)
    snap = os.path.join(work, "lcdm_gas_sph.dat")
    write_snapshot(snap, hdr, ng, massarr[0], pos, vel, mass, u, rho, hsml)
    sig = spline_sigma(1.0) * hsml
    val = mass / ((2 * math.pi) ** 1.5 * sig ** 3)
    csv = os.path.join(work, "lcdm_gas.csv")
    np.savetxt(csv, np.column_stack([pos, sig, val]), fmt="%.7g", delimiter=",", header="x,y,z,radius,value",
               comments="")
    # opacity: mean optical depth ~2 through the box
    kappa = 2.0 / (float(np.mean(rho)) * box)
    rmax = float(np.percentile(rho, 99.5))
    tf = os.path.join(work, "tf.json")
    with open(tf, "w") as f:
        json.dump({"range": [0.0, rmax], "color": [[0, 0, 0, 0], [1, 1, 1, 1]], "opacity": [[0, 0], [1, kappa * rmax]]}, f)
    c0 = np.min(pos, axis=0)
    c = c0 + box / 2
    lc_png = os.path.join(work, "lanecast.png")
    args = [exe, "render", csv, "-o", lc_png, "--size", "%dx%d" % (SIZE, SIZE), "--tf", tf, "--ortho", "%g" % box,
            "--eye", "%g,%g,%g" % (c[0], c[1], c[2] + 3 * box), "--at", "%g,%g,%g" % tuple(c), "--threads", "2", "--stats",
            "--quiet"]
    walls, renders = [], []
    for _ in range(3):
        t0 = time.perf_counter()
        p = subprocess.run(args, capture_output=True, text=True)
        walls.append(time.perf_counter() - t0)
        if p.returncode:
            sys.exit("peers_splash.py: lanecast failed: " + p.stderr.strip())
        m = re.search(r"^render\s+([0-9.]+) s", p.stdout + p.stderr, re.M)
        renders.append(float(m.group(1)) if m else float("nan"))
    # SPLASH: columns 1, 2 = x, y; the density column from its menu (answered "q")
    menu = subprocess.run(["splash", "-f", "gadget", snap], input="q\n", capture_output=True, text=True, cwd=work,
                          timeout=120)
    m = re.search(r"(\d+)\)\s*density", menu.stdout, re.I)
    if not m:
        sys.exit("peers_splash.py: no density column in SPLASH's menu:\n" + menu.stdout[-1500:])
    col = int(m.group(1))
    sp_walls = []
    for _ in range(3):
        for f in os.listdir(work):
            if f.startswith("splash_") and f.endswith(".png"):
                os.remove(os.path.join(work, f))
        t0 = time.perf_counter()
        p = subprocess.run(["splash", "-f", "gadget", snap, "-r", str(col), "--kappa=%g" % kappa, "-dev", "/png"],
                           capture_output=True, text=True, cwd=work, stdin=subprocess.DEVNULL)
        sp_walls.append(time.perf_counter() - t0)
    pngs = sorted(f for f in os.listdir(work) if f.startswith("splash") and f.endswith(".png"))
    if p.returncode or not pngs:
        sys.exit("peers_splash.py: splash failed (%d): %s" % (p.returncode, (p.stdout + p.stderr)[-800:]))
    sp_png = os.path.join(work, pngs[0])
    a, b = plt.imread(lc_png), plt.imread(sp_png)
    comp = os.path.join(out_dir, "peer_splash_lcdm.png")
    fig, axs = plt.subplots(1, 2, figsize=(10, 5))
    for ax, img, name in zip(axs, [a, b], ["lanecast (Gaussians, tau = kappa rho)", "SPLASH opacity rendering"]):
        ax.imshow(img)
        ax.set_title(name, fontsize=9)
        ax.axis("off")
    fig.suptitle("LCDM gas, %d particles (%d split %dx), HSML from the %dth neighbour, kappa %.3g"
                 % (ng, ng0, 8 ** split, K, kappa), fontsize=10)
    fig.tight_layout()
    fig.savefig(comp, dpi=90)
    plt.close(fig)
    rec = {"record": "peer", "peer": "splash", "peer_version": subprocess.run(["dpkg-query", "-W", "-f", "${Version}", "splash"], capture_output=True,
                                                        text=True).stdout or "?", "peer_mapper": "opacity rendering",
           "scene": "lcdm gas %d" % ng, "split_from": ng0, "size": SIZE, "threads": 2, "dt": None, "kappa": kappa,
           "density_column": col, "lanecast_first_s": statistics.median(walls),
           "lanecast_frame_s": statistics.median(renders), "peer_first_s": statistics.median(sp_walls),
           "peer_frame_s": statistics.median(sp_walls),
           "frame_ratio_peer_over_lanecast": statistics.median(sp_walls) / statistics.median(walls),
           "psnr_db_between": None, "composite": os.path.basename(comp), "loadavg": os.getloadavg()[0],
           "note": "ratio of whole runs (SPLASH has no per-frame time); images compared by eye only"}
    with open(recs_path, "a") as f:
        f.write(json.dumps(rec) + "\n")
    print("peers_splash.py: lanecast run %.3f s (render %.3f s), SPLASH run %.3f s -> %s"
          % (rec["lanecast_first_s"], rec["lanecast_frame_s"], rec["peer_first_s"], comp))


if __name__ == "__main__":
    main()

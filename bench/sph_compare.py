#!/usr/bin/python3
"""lanecast, SPLASH and yt side by side on one GADGET snapshot: the column
density of the shared LCDM gas (docs/SPH.md's picture and mass table).

usage: sph_compare.py LANECAST DATA_DIR OUT.png [SIZE]

The snapshot is bench/peers_sph.py's: the 32,768 gas particles of
particles/gadget_lcdm_gas.dat shifted to start at 0, HSML = the distance to
the 32nd neighbour (the M4 support H), RHO from GADGET-2's cubic spline.
Each program projects it along z onto SIZE^2 pixels (default 512) over the
particles' x, y range: lanecast's exact pixel averages (--mode project) and
its pixel-centre map (--sample centre), SPLASH's default projection
(tests/sph_splash.py drives it: npix, splash.limits, -o ascii; pixel
centres, h raised to half a pixel), yt 4.1's ProjectionPlot of ("gas",
"density") (bench/peers_sph.py; unit_base cm, g, so its g/cm^2 are the
file's units). The mass table: each map's sum of pixels x pixel area against
the mass of the particles whose support lies inside the image and the total.
Prints the table as Markdown; writes the picture (log colour scale, one
range for all panels, the differences to lanecast's exact map below).
"""
import os
import shutil
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(here, "..", "tests"))
import peers_sph  # noqa: E402  (the snapshot, yt's projection)
import peers_splash as ps  # noqa: E402
import sph_splash  # noqa: E402  (SPLASH on a given pixel grid, lanecast on SPLASH's grid)

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    exe, data, out_png = sys.argv[1:4]
    size = int(sys.argv[4]) if len(sys.argv) > 4 else 512
    src = os.path.join(data, "particles", "gadget_lcdm_gas.dat")
    if not os.path.exists(src):
        print("sph_compare.py: %s absent, nothing to compare" % src)
        return 0
    work = "/tmp/lanecast_sph_compare"
    os.makedirs(work, exist_ok=True)
    hdr, npart, massarr, box, pos, vel, mass, u = ps.read_gas(src)
    pos = pos - pos.min(axis=0)
    hsml, rho = peers_sph.sph(pos, mass)
    pos = pos + hsml.max()  # a margin of the largest support: every particle lies wholly inside the maps
    snap = os.path.join(work, "lcdm.dat")
    peers_sph.write(snap, pos, mass, hsml, rho, hdr)
    side = float((pos + hsml.max()).max())
    lim = (0.0, side, 0.0, side, 0.0, side)
    maps, notes = {}, {}
    if shutil.which("splash"):
        sp, x0, y0, dx, _ = sph_splash.splash_map(snap, work, False, size, lim)
        maps["SPLASH 3.6 (default projection)"] = sp
    else:
        x0, y0, dx = lim[0], lim[2], side / size
        notes["SPLASH"] = "not installed (Debian package splash)"
    ny = nx = size
    if "SPLASH 3.6 (default projection)" in maps:
        ny, nx = maps["SPLASH 3.6 (default projection)"].shape
    maps["lanecast (exact pixel averages)"] = sph_splash.lanecast_map(exe, snap, work, "exact", x0, y0, nx, ny, dx)
    maps["lanecast --sample centre"] = sph_splash.lanecast_map(exe, snap, work, "centre", x0, y0, nx, ny, dx)
    # yt projects its own bounding box [0, side]^3 centred on side / 2: the same square when the data start at 0
    yt = peers_sph.yt_project(snap, nx, side, work)
    if "map" in yt:
        # yt's buffer axes: the orientation whose mass-weighted x and y centroids match the particles'
        cands = [yt["map"][::-1], yt["map"].T[::-1]]
        xc = x0 + dx * (np.arange(nx) + 0.5)
        want = np.array([np.sum(mass * pos[:, 0]), np.sum(mass * pos[:, 1])]) / mass.sum()

        def centroid(m):
            return np.array([np.sum(m.sum(axis=0) * xc), np.sum(m.sum(axis=1) * xc[::-1])]) / m.sum()
        maps["yt 4.1 ProjectionPlot"] = min(cands, key=lambda m: float(np.abs(centroid(m) - want).sum()))
    else:
        notes["yt"] = yt["error"].strip().splitlines()[-1]
    ext = (x0, x0 + nx * dx, y0, y0 + ny * dx)
    m_in, m_all = peers_sph.inside_mass(pos, mass, hsml, np.array([ext[0], ext[2]]), np.array([ext[1], ext[3]]))
    ref = maps["lanecast (exact pixel averages)"]
    print("| map | total mass in the map | / sum m | max abs difference to lanecast exact / its max |")
    print("|---|---|---|---|")
    for name, m in maps.items():
        tot = float(m.sum() * dx * dx)
        print("| %s | %.7g | %.6f | %.2e |" % (name, tot, tot / m_all, float(np.abs(m - ref).max() / ref.max())))
    print("| particles: sum m (%d of %d with their support inside the image) | %.7g | 1 | |" % (
        int(round(m_in / m_all * len(pos))), len(pos), m_all))
    for k, v in notes.items():
        print("%s: %s" % (k, v))
    vmax = float(ref.max())
    norm = LogNorm(vmin=vmax * 1e-2, vmax=vmax)
    n = len(maps)
    fig, axs = plt.subplots(2, n, figsize=(3.6 * n, 7.4), squeeze=False)
    for i, (name, m) in enumerate(maps.items()):
        ax = axs[0][i]
        im = ax.imshow(np.maximum(m, vmax * 1e-3), extent=ext, norm=norm, cmap="inferno")
        ax.set_title("%s\nmass / sum m = %.6f" % (name, m.sum() * dx * dx / m_all), fontsize=8)
        ax.tick_params(labelsize=6)
        d = axs[1][i]
        rel = (m - ref) / vmax
        di = d.imshow(rel, extent=ext, cmap="coolwarm", vmin=-1e-3, vmax=1e-3)
        d.set_title("(map - lanecast exact) / max\nmax |.| %.1e" % np.abs(rel).max(), fontsize=8)
        d.tick_params(labelsize=6)
    fig.colorbar(im, ax=axs[0].tolist(), shrink=0.8, label="column density (file units)")
    fig.colorbar(di, ax=axs[1].tolist(), shrink=0.8)
    fig.suptitle("LCDM gas, %d particles, M4, %d^2 pixels" % (len(pos), nx), fontsize=10)
    fig.savefig(out_png, dpi=90)
    print("wrote %s" % out_png)
    return 0


if __name__ == "__main__":
    sys.exit(main())

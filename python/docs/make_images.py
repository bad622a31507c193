"""Makes the pictures of docs/PYTHON.md (run from the source root after a build):
    PYTHONPATH=build/python /usr/bin/python3 python/docs/make_images.py [../shared/data]
Each block below is the walk-through's code as the page shows it."""

import os
import sys
import warnings

import numpy as np

import lanecast as lc

data = sys.argv[1] if len(sys.argv) > 1 else os.path.join("..", "shared", "data")
out = os.path.join("docs", "images")
os.makedirs(out, exist_ok=True)
dev = lc.Device()

# --- a molecule through MDAnalysis: heavy atoms of the protein, one field per element
import MDAnalysis as mda  # noqa: E402
import lanecast.mdanalysis  # noqa: E402

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    u = mda.Universe(os.path.join(data, "particles", "1tii.pdb"))
img = lanecast.mdanalysis.render(u, dev, select="protein and not element H", fields="element",
                                 width=480, height=360, shade="phong", view=(30, 15))
img.save(os.path.join(out, "python-molecule.png"))

# --- a CT/MRI volume read by lanecast, the default (histogram) TF, then an iso-surface
head = lc.load(dev, os.path.join(data, "volumes", "HeadMRVolume.mhd"))
print(head.info["size"], head.info["values"])
lc.render(head, width=400, height=400).save(os.path.join(out, "python-ct.png"))
lc.render(head, width=400, height=400, mode="iso", iso=90, shade="phong",
          tf=lc.TransferFunction.from_colormap("grayscale")).save(os.path.join(out, "python-ct-iso.png"))

# --- a NumPy array as a grid: axis 0 is z (C order), spacing and origin are x, y, z
z, y, x = np.mgrid[-1:1:64j, -1:1:96j, -1:1:128j]
field = np.exp(-8 * (x ** 2 + 2 * y ** 2 + 4 * z ** 2)) + 0.5 * np.exp(-40 * ((x - 0.5) ** 2 + y ** 2 + z ** 2))
g = lc.Grid(dev, field, spacing=(2 / 127, 2 / 95, 2 / 63), origin=(-1, -1, -1))
tf = lc.TransferFunction.from_colormap("inferno", range=(0.05, 1.0), opacity=[(0, 0), (0.3, 2), (1, 30)])
lc.render(g, tf, 400, 300, view=(30, 20)).save(os.path.join(out, "python-grid.png"))

# --- SPH particles through yt: an in-memory particle dataset with smoothing lengths
import yt  # noqa: E402
import lanecast.yt  # noqa: E402

yt.set_log_level(40)
rng = np.random.default_rng(4)
n = 20000
r = rng.standard_normal((n, 3)) * [0.12, 0.05, 0.12]
r[: n // 2] = rng.standard_normal((n // 2, 3)) * 0.03 + [0.2, 0.0, -0.1]  # a dense clump
pos = 0.5 + r
data_sph = {("io", "particle_position_" + c): pos[:, i] for i, c in enumerate("xyz")}
data_sph["io", "smoothing_length"] = np.full(n, 0.02)
data_sph["io", "brightness"] = (np.exp(-(r ** 2).sum(1) / 0.01), "dimensionless")
data_sph["io", "particle_mass"] = np.ones(n)
ds = yt.load_particles(data_sph, length_unit=3.086e21, bbox=np.array([[0, 1]] * 3))
img = lanecast.yt.render(ds, ("io", "brightness"), dev, width=400, height=400, view=(20, 40),
                         tf=lc.TransferFunction.from_colormap("magma", range=(0, 1), opacity=[(0, 0), (1, 40)]))
img.save(os.path.join(out, "python-sph.png"))
print("wrote", sorted(f for f in os.listdir(out) if f.startswith("python-")))

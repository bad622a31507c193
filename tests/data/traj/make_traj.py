#!/usr/bin/python3
"""Writes the trajectory test files of tests/data/traj with MDAnalysis (Debian
python3-mdanalysis, whose XTC/TRR writers are GROMACS's xdrfile) from the shared
adk.psf + adk.dcd, and reference files of what MDAnalysis reads back from them.
Run: /usr/bin/python3 tests/data/traj/make_traj.py ../shared/data/particles OUTDIR
Reference lines (Angstrom, as MDAnalysis reports them):
  frame K natoms N step S time T sum SX SY SZ   (sums over every atom, float64)
  atom I X Y Z                                  (every 7th atom and the last)
"""
import glob
import os
import shutil
import subprocess
import sys
import warnings
import numpy as np
warnings.filterwarnings("ignore")
import MDAnalysis as mda
from MDAnalysis.coordinates.XTC import XTCWriter
from MDAnalysis.coordinates.TRR import TRRWriter

data, out = sys.argv[1], sys.argv[2]
u = mda.Universe(f"{data}/adk.psf", f"{data}/adk.dcd")


def reference(path, ref, step=7, extra=""):
    rd = mda.coordinates.core.reader(path, refresh_offsets=True)
    with open(ref, "w") as f:
        for k, ts in enumerate(rd):
            x = ts.positions.astype(np.float64)
            s = x.sum(axis=0)
            f.write(f"frame {k} natoms {ts.n_atoms} step {ts.data.get('step', 0)} time {ts.time:.9g} "
                    f"sum {s[0]:.17g} {s[1]:.17g} {s[2]:.17g}\n")
            idx = sorted(set(range(0, ts.n_atoms, step)) | {ts.n_atoms - 1})
            for i in idx:
                p = ts.positions[i]
                f.write(f"atom {i} {p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n")
                for name in ("velocities", "forces"):
                    if getattr(ts, "has_" + name, False):
                        v = getattr(ts, name)[i]
                        f.write(f"{name[0]} {i} {v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")


def write_xtc(path, atoms, frames, precision=3, scale=1.0):
    with XTCWriter(path, atoms.n_atoms, precision=precision) as w:
        for k in frames:
            u.trajectory[k]
            ts = u.trajectory.ts
            if scale != 1.0:
                saved = atoms.positions.copy()
                atoms.positions = saved * scale
            w.write(atoms)
            if scale != 1.0:
                atoms.positions = saved


ca = u.select_atoms("name CA")
u.trajectory[0]
ca.write(f"{out}/adk_ca.gro")
write_xtc(f"{out}/adk_ca.xtc", ca, range(0, 98, 10))
reference(f"{out}/adk_ca.xtc", f"{out}/adk_ca.xtc.ref", step=5)
write_xtc(f"{out}/adk2.xtc", u.atoms, [0, 60])
reference(f"{out}/adk2.xtc", f"{out}/adk2.xtc.ref", step=37)
small = u.atoms[:7]
write_xtc(f"{out}/small.xtc", small, [0, 40, 80])
reference(f"{out}/small.xtc", f"{out}/small.xtc.ref", step=1)
wide = u.atoms[:40]
write_xtc(f"{out}/wide.xtc", wide, [0, 1], precision=2, scale=3e5)  # ranges over 2^24: the large-integer path
reference(f"{out}/wide.xtc", f"{out}/wide.xtc.ref", step=1)

# TRR: the CA atoms with velocities and forces (made up, deterministic: MDAnalysis
# writes what the timestep holds), single precision
ca_u = mda.Merge(ca)
frames = list(range(0, 98, 20))
pos = np.array([ca.positions.copy() for _ in (u.trajectory[k] for k in frames)], dtype=np.float32)
rng = np.random.default_rng(29)
vel = rng.normal(0.0, 5.0, pos.shape).astype(np.float32)
frc = rng.normal(0.0, 300.0, pos.shape).astype(np.float32)
ca_u.load_new(pos, velocities=vel, forces=frc, format=mda.coordinates.memory.MemoryReader)
with TRRWriter(f"{out}/adk_ca.trr", ca.n_atoms) as w:
    for ts in ca_u.trajectory:
        w.write(ca_u.atoms)
reference(f"{out}/adk_ca.trr", f"{out}/adk_ca.trr.ref", step=9)

# AMBER NetCDF (MDAnalysis NCDFWriter, scipy's netCDF 3 64-bit-offset writer): the
# same CA frames with velocities
from MDAnalysis.coordinates.TRJ import NCDFWriter
with NCDFWriter(f"{out}/adk_ca.ncdf", ca.n_atoms, velocities=True) as w:
    for ts in ca_u.trajectory:
        w.write(ca_u.atoms)
reference(f"{out}/adk_ca.ncdf", f"{out}/adk_ca.ncdf.ref", step=9)
# a restart (no frame dimension) and a scale_factor on velocities, from a CDL by ncgen
if shutil.which("ncgen"):
    subprocess.run(["ncgen", "-k", "nc3", "-o", f"{out}/restart.ncrst", f"{out}/restart.cdl"], check=True)

# GROMACS itself (Debian gromacs): the CA trajectory rewritten at precision 100 with
# a box, and as a double-precision TRR (gmx_d) with velocities
if shutil.which("gmx") and shutil.which("gmx_d"):
    q = ["-quiet"]
    os.environ["GMX_MAXBACKUP"] = "-1"  # no #file.1# backups
    subprocess.run(["gmx", *q, "trjconv", "-f", f"{out}/adk_ca.xtc", "-o", f"{out}/gmx_ca.xtc", "-ndec", "2",
                    "-box", "8", "9", "10"], stdin=subprocess.DEVNULL, capture_output=True, check=True)
    reference(f"{out}/gmx_ca.xtc", f"{out}/gmx_ca.xtc.ref", step=11)
    subprocess.run(["gmx_d", *q, "trjconv", "-f", f"{out}/adk_ca.trr", "-o", f"{out}/gmx_ca_d.trr", "-e", "2"],
                   stdin=subprocess.DEVNULL, capture_output=True, check=True)
    reference(f"{out}/gmx_ca_d.trr", f"{out}/gmx_ca_d.trr.ref", step=11)

for f in glob.glob(f"{out}/.*_offsets.*"):
    os.remove(f)

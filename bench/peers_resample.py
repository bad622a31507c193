#!/usr/bin/python3
"""Particles deposited to grids: lanecast resample against VTK's proxy step
(peers_vtk.particle_image: vtkPointInterpolator with a Gaussian kernel of
radius 2r and sharpness sqrt 2, weights not normalised, i.e. lanecast's
particle field with sigma 2) on the same points (a .pdb, every atom of
radius r; or dense:N, the dense clustered set of issue 28's VTK figure,
written as raw float32 for both), the same box and the same nodes (cubic cells: N nodes along the
longest side), both with 2 threads. Writes one "peer_resample" record per N:
VTK's interpolation time, lanecast's deposit time (its own "deposit" line:
no loading, BVH build or writing) and whole run, and the largest difference
between the two grids relative to the field's maximum.

usage: peers_resample.py LANECAST PDB|dense:N RADIUS N[,N...] RECORDS.jsonl
(needs python3-vtk9, as bench/peers.sh --install installs it)
"""
import json
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np
import vtk
from vtk.util import numpy_support

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import peers_vtk  # noqa: E402  (read_pdb, particle_image: the one proxy path)

THREADS = 2


def read_nrrd(path):
    """A float32 .nrrd as lanecast resample writes it: (z, y, x) array."""
    raw = open(path, "rb").read()
    head, data = raw.split(b"\n\n", 1)
    hdr = {}
    for line in head.decode().splitlines()[1:]:
        if ": " in line and not line.startswith("#"):
            k, v = line.split(": ", 1)
            hdr[k] = v
    sizes = [int(x) for x in hdr["sizes"].split()]
    return np.frombuffer(data, dtype="<f4").reshape(sizes[::-1])


def dense_set(n, path):
    """The dense clustered set of issue 28's VTK figure (dense1e6, docs/bench/particles.md): in a
    cube of side 2 n^(1/3) (one particle per 8 cubic units), 90 % of the points in 40 Gaussian
    clusters (standard deviation 3, centres uniform in the inner 80 % of the cube), 10 % uniform
    background; numpy's generator with seed 0 (the layout, not the same points); written to path
    as raw float32 x y z. Rendered with radius 1, a cluster core holds ~2000 overlapping terms."""
    rng = np.random.default_rng(0)
    side = 2.0 * n ** (1.0 / 3.0)
    centres = side * (0.1 + 0.8 * rng.random((40, 3)))
    nc = n * 9 // 10
    inner = centres[np.arange(nc) % 40] + 3.0 * rng.standard_normal((nc, 3))
    xyz = np.concatenate([inner, side * rng.random((n - nc, 3))]).astype(np.float32)
    xyz.tofile(path)
    return xyz


def main():
    exe, src, radius, sides, records = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4], sys.argv[5]
    tmpdir = tempfile.TemporaryDirectory()
    if src.startswith("dense:"):
        pdb = os.path.join(tmpdir.name, "dense.f32")
        xyz = dense_set(int(float(src[6:])), pdb)
        raw_flags = ["--raw-particles", str(len(xyz))]  # one field already: --field-by does not apply
    else:
        pdb, raw_flags = src, ["--field-by", "none"]
        xyz = peers_vtk.read_pdb(pdb).astype(np.float32)
    lo = xyz.min(axis=0).astype(np.float64) - 2 * radius
    hi = xyz.max(axis=0).astype(np.float64) + 2 * radius
    vtk.vtkMultiThreader.SetGlobalMaximumNumberOfThreads(THREADS)
    vtk.vtkSMPTools.Initialize(THREADS)
    for n in [int(s) for s in sides.split(",")]:
        spacing = float(max(hi - lo)) / (n - 1)
        dims = [int(math.ceil((h - l) / spacing - 1e-9)) + 1 for l, h in zip(lo, hi)]
        top = [l + (d - 1) * spacing for l, d in zip(lo, dims)]
        t0, c0 = time.perf_counter(), time.process_time()
        img = peers_vtk.particle_image(xyz, radius, list(lo), spacing, dims)
        vtk_s, vtk_cpu = time.perf_counter() - t0, time.process_time() - c0
        ref = numpy_support.vtk_to_numpy(img.GetPointData().GetArray("one")).reshape(dims[::-1])
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "g.nrrd")
            box = ",".join("%.9g" % v for v in list(lo) + top)
            cmd = [exe, "resample", pdb] + raw_flags + ["--radius", "%g" % radius, "--dims",
                   ",".join(str(d) for d in dims), "--box", box, "--threads", str(THREADS), "-o", out]
            t1, r1 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
            text = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
            run_s, r2 = time.perf_counter() - t1, resource.getrusage(resource.RUSAGE_CHILDREN)
            run_cpu = (r2.ru_utime + r2.ru_stime) - (r1.ru_utime + r1.ru_stime)
            got = read_nrrd(out)
        dep = float(re.search(r"^deposit\s+([0-9.]+) s", text, re.M).group(1))
        peak = float(ref.max())
        absdiff = float(np.max(np.abs(got.astype(np.float64) - ref)))
        diff = absdiff / peak if peak > 0 else None
        rec = {"record": "peer_resample", "peer": "vtk", "peer_version": vtk.vtkVersion.GetVTKVersion(),
               "peer_method": "vtkPointInterpolator + vtkGaussianKernel (radius 2r, sharpness sqrt 2, not normalised)",
               "file": src if src.startswith("dense:") else os.path.basename(pdb), "count": int(len(xyz)), "radius": radius, "dims": dims,
               "threads": THREADS, "peer_s": vtk_s, "peer_cpu_s": vtk_cpu, "lanecast_run_cpu_s": run_cpu, "lanecast_deposit_s": dep, "lanecast_run_s": run_s,
               "ratio_peer_over_deposit": vtk_s / dep if dep > 0 else None, "max_diff_rel_peak": diff, "max_diff": absdiff, "peak": peak,
               "lanecast_command": " ".join(cmd[1:]).replace(out, "g.nrrd"), "loadavg": os.getloadavg()[0]}
        with open(records, "a") as f:
            f.write(json.dumps(rec) + "\n")
        print("peers_resample.py: %s %s: VTK %.3f s, lanecast deposit %.3f s (%.1fx; whole run %.2f s), "
              "max difference %.2g of the peak (%.4g); CPU s: VTK %.2f, lanecast's whole run %.2f (%.1fx)"
              % (os.path.basename(pdb), "x".join(map(str, dims)), vtk_s, dep, vtk_s / dep, run_s, diff, absdiff, vtk_cpu,
                 run_cpu, vtk_cpu / run_cpu))


if __name__ == "__main__":
    main()

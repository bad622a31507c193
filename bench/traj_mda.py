#!/usr/bin/python3
"""MDAnalysis's reading rate of the same trajectory `lanecast bench --read` reads
(docs/bench/traj.md): every frame in order, in atoms per second, and one
frame in the middle by random access (its offsets index built first, as
MDAnalysis does on opening). usage: traj_mda.py FILE [REPEATS]"""
import sys
import time
import warnings
warnings.filterwarnings("ignore")
from MDAnalysis.coordinates.core import reader

path, reps = sys.argv[1], int(sys.argv[2]) if len(sys.argv) > 2 else 3
t0 = time.perf_counter()
r = reader(path, refresh_offsets=True)
topen = time.perf_counter() - t0
best = mid = 1e30
for _ in range(reps):
    t0 = time.perf_counter()
    s = 0.0
    for ts in r:
        s += float(ts.positions[0, 0])
    best = min(best, time.perf_counter() - t0)
    t0 = time.perf_counter()
    r[len(r) // 2]
    mid = min(mid, time.perf_counter() - t0)
n, f = r.n_atoms, len(r)
print(f"mda file={path} frames={f} atoms={n} open_s={topen:.4f} all_s={best:.3f} frames_per_s={f / best:.1f} "
      f"atoms_per_s={f * n / best:.3g} frame{f // 2}_s={mid:.5f}")

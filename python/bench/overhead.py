"""The Python bindings' cost per call (docs/PYTHON.md "Overhead").

Run from the source root after a build, with the interpreter meson found:
    PYTHONPATH=build/python /usr/bin/python3 python/bench/overhead.py [--particles 10000000]

1. render: wall time of lanecast.render at 512x512 minus the C render's own wall time
   (img.stats["seconds"], measured inside lc_render), median over repeated calls, for a
   fresh output array per call and for a reused one (out=).
2. handing a large NumPy array over: lanecast.Particles with N particles, total time against the
   BVH build the library reports (info["build_seconds"]); float32 C-contiguous (used in place)
   and float64 (converted first).
"""

import argparse
import statistics
import time

import numpy as np

import lanecast as lc


def render_overhead(dev, reps):
    rng = np.random.default_rng(1)
    vol = lc.Particles(dev, (rng.normal(size=(2000, 3)) * 8).astype(np.float32), radii=1.0)
    tf = lc.TransferFunction.preset("heat", 1, 1.0)
    cam = lc.Camera.frame(vol)
    out = np.empty((512, 512, 4), np.float32)
    rows = {}
    for name, kw in [("new image", {}), ("out= reused", {"out": out})]:
        lc.render(vol, tf, 512, 512, camera=cam, **kw)  # warm up
        d = []
        for _ in range(reps):
            t0 = time.perf_counter()
            img = lc.render(vol, tf, 512, 512, camera=cam, **kw)
            d.append(time.perf_counter() - t0 - img.stats["seconds"])
        c = [lc.render(vol, tf, 512, 512, camera=cam, **kw).stats["seconds"] for _ in range(5)]
        rows[name] = (statistics.median(d), min(d), max(d), statistics.median(c))
    return rows


def handover(dev, n):
    rng = np.random.default_rng(2)
    pos = (rng.random((n, 3), dtype=np.float32) * 1000).astype(np.float32)
    rows = {}
    for name, arr in [("float32 C-contiguous", pos), ("float64", pos.astype(np.float64))]:
        t0 = time.perf_counter()
        vol = lc.Particles(dev, arr, radii=0.5)
        t = time.perf_counter() - t0
        rows[name] = (t, vol.info["build_seconds"])
        del vol
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=40)
    ap.add_argument("--particles", type=int, default=10_000_000)
    a = ap.parse_args()
    dev = lc.Device()
    print(f"device {dev.target}, {dev.threads} threads; lanecast {lc.__version__}")
    for name, (med, lo, hi, c) in render_overhead(dev, a.reps).items():
        print(f"render 512x512, {name}: overhead median {med * 1e3:.3f} ms (min {lo * 1e3:.3f}, max {hi * 1e3:.3f}) "
              f"beyond the C render's {c * 1e3:.1f} ms")
    for name, (t, b) in handover(dev, a.particles).items():
        print(f"Particles({a.particles} x 3 {name}): {t:.3f} s, of which BVH build {b:.3f} s, "
              f"rest {t - b:.3f} s")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Tables for docs/bench/particles.md "The exp-free deposit": A/B of
bench_particles lines (base file, new file), one line per render case and
round; prints per (set, view, method, target) the median over rounds of the
CPU seconds per frame (all threads) and of the wall seconds, their ranges, the
ratio base/new and Gaussian contributions per second (per wall second, and
per 2 CPU-seconds, i.e. two busy cores). usage: partspeed_table.py BASE NEW"""
import statistics
import sys


def load(path):
    rows = {}
    for line in open(path):
        if not line.startswith("particles "):
            continue
        kv = dict(t.split("=", 1) for t in line.split()[1:] if "=" in t)
        key = (kv["set"], kv["view"], kv["method"], kv["target"], kv["threads"])
        evals = float(kv["gauss_per_s"]) * float(kv["median_s"])
        rows.setdefault(key, []).append((float(kv["cpu_median_s"]), float(kv["median_s"]), evals))
    return rows


def main():
    base, new = load(sys.argv[1]), load(sys.argv[2])
    print("| set | view | method | target | thr | base CPU s (range) | new CPU s (range) | CPU speed-up "
          "| base wall s | new wall s | wall speed-up | new G contrib/s (wall) | new G contrib/s (2 CPU-s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key in sorted(new):
        if key not in base:
            continue
        b, n = base[key], new[key]
        bc, nc = statistics.median(r[0] for r in b), statistics.median(r[0] for r in n)
        bw, nw = statistics.median(r[1] for r in b), statistics.median(r[1] for r in n)
        ev = statistics.median(r[2] for r in n)
        print(f"| {key[0]} | {key[1]} | {key[2]} | {key[3]} | {key[4]} | {bc:.3f} ({min(r[0] for r in b):.3f}-"
              f"{max(r[0] for r in b):.3f}) | {nc:.3f} ({min(r[0] for r in n):.3f}-{max(r[0] for r in n):.3f}) | "
              f"{bc / nc:.2f}x | {bw:.3f} | {nw:.3f} | {bw / nw:.2f}x | {ev / nw / 1e9:.3f} | "
              f"{ev / (nc / 2) / 1e9:.3f} |")


if __name__ == "__main__":
    main()

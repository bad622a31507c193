#!/usr/bin/env python3
"""Table for docs/bench/particles.md "One BVH walk per group": one
file of bench_particles lines from interleaved rounds of several binaries,
each run preceded by a line "# bin=PATH round=N" (bench/results/pgroup_ab.txt).
Prints per (set, view) the median over rounds of the CPU seconds per frame
(all threads) of each binary with its range, and the speed-up of the last
binary against each of the others; then Gaussian contributions per 2
CPU-seconds of the last. usage: pgroup_table.py FILE [LABEL ...] (labels for
the binaries in order of first appearance)"""
import statistics
import sys


def main():
    rows, bins, cur = {}, [], None
    for line in open(sys.argv[1]):
        if line.startswith("# bin="):
            cur = line.split()[1][4:]
            if cur not in bins:
                bins.append(cur)
            continue
        if not line.startswith("particles ") or cur is None:
            continue
        kv = dict(t.split("=", 1) for t in line.split()[1:] if "=" in t)
        key = (kv["set"], kv["view"], kv["method"])
        evals = float(kv["gauss_per_s"]) * float(kv["median_s"])
        rows.setdefault((cur, key), []).append((float(kv["cpu_median_s"]), evals))
    labels = sys.argv[2:] + bins[len(sys.argv) - 2:]
    keys = sorted({k for (_, k) in rows})
    head = " | ".join(f"{l} CPU s (range)" for l in labels)
    ups = " | ".join(f"{labels[-1]} vs {l}" for l in labels[:-1])
    print(f"| set | view | method | {head} | {ups} | G contrib/s (2 CPU-s) |")
    print("|---" * (3 + len(labels) + len(labels) - 1 + 1) + "|")
    for k in keys:
        med, cells = [], []
        for b in bins:
            r = rows.get((b, k), [])
            if not r:
                med.append(None), cells.append("-")
                continue
            m = statistics.median(x[0] for x in r)
            med.append(m)
            cells.append(f"{m:.3f} ({min(x[0] for x in r):.3f}-{max(x[0] for x in r):.3f}, n={len(r)})")
        sp = [f"{med[i] / med[-1]:.2f}x" if med[i] and med[-1] else "-" for i in range(len(bins) - 1)]
        last = rows.get((bins[-1], k), [])
        ev = statistics.median(x[1] for x in last) if last else 0
        g = f"{ev / (med[-1] / 2) / 1e9:.3f}" if med[-1] else "-"
        print(f"| {k[0]} | {k[1]} | {k[2]} | " + " | ".join(cells) + " | " + " | ".join(sp) + f" | {g} |")


if __name__ == "__main__":
    main()

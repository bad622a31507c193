#!/usr/bin/env python3
"""A/B table from bench_grid lines tagged build=base|new (bench/results/grid_ab_*.txt):
per case the median over all rounds of the per-run medians, wall ms and CPU ms
(all threads), the speed-ups new/base, and samples/s: per wall second and per
CPU second times the thread count (what the threads give when they own their
cores). Usage: grid_ab_table.py FILE [base-tag new-tag]"""
import statistics
import sys


def parse(path):
    rows = []
    for line in open(path):
        if not line.startswith("grid "):
            continue
        kv = dict(t.split("=", 1) for t in line.split()[1:] if "=" in t)
        rows.append(kv)
    return rows


def main():
    path = sys.argv[1]
    a, b = (sys.argv[2], sys.argv[3]) if len(sys.argv) > 3 else ("base", "new")
    cases = {}
    for r in parse(path):
        key = (r["volume"], r["size"], r["view"], r["shade"], r["method"], r["target"], r["threads"])
        cases.setdefault(key, {}).setdefault(r["build"], []).append(r)
    print("| volume | view | shading | method | target | threads | base wall ms | new wall ms | wall x | base CPU ms"
          " (min-max) | new CPU ms (min-max) | CPU x | M samples | new M samples/s (wall) | new M samples/s (CPU x threads) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key, d in cases.items():
        if a not in d or b not in d:
            continue
        def med(rs, f):
            return statistics.median(float(r[f]) for r in rs)
        wa, wb = med(d[a], "ms"), med(d[b], "ms")
        ca, cb = med(d[a], "cpu_ms"), med(d[b], "cpu_ms")
        cal, cah = min(float(r["cpu_ms_min"]) for r in d[a]), max(float(r["cpu_ms_max"]) for r in d[a])
        cbl, cbh = min(float(r["cpu_ms_min"]) for r in d[b]), max(float(r["cpu_ms_max"]) for r in d[b])
        ms = float(d[b][0]["msamples"])
        th = int(key[6])
        print(f"| {key[0]} | {key[2]} | {key[3]} | {key[4]} | {key[5]} | {th} | {wa:.0f} | {wb:.0f} | {wa / wb:.2f} | "
              f"{ca:.0f} ({cal:.0f}-{cah:.0f}) | {cb:.0f} ({cbl:.0f}-{cbh:.0f}) | {ca / cb:.2f} | {ms:.2f} | "
              f"{ms / (wb / 1e3):.0f} | {ms / (cb / 1e3) * th:.0f} |")


main()

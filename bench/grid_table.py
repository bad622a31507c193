#!/usr/bin/env python3
"""Turns bench_grid's result lines into markdown tables: one row per case
without the method, with brute-force and BVH fps side by side and their ratio.
usage: grid_table.py RESULTS.txt"""
import sys

rows = {}
order = []
for line in open(sys.argv[1]):
    if not line.startswith("grid "):
        continue
    kv = dict(f.split("=", 1) for f in line.split()[1:])
    key = tuple(kv[k] for k in ("volume", "size", "view", "shade", "target", "threads", "packet", "heuristics"))
    if key not in rows:
        rows[key] = {}
        order.append(key)
    rows[key][kv["method"]] = kv
print("| volume | image | view | shading | target | threads | packet | brute fps (min-max) | BVH fps (min-max) | BVH/brute | samples brute / BVH (M) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for key in order:
    r = rows[key]
    b, h = r.get("brute"), r.get("bvh")
    def cell(x):
        return f"{float(x['fps']):.2f} ({float(x['fps_min']):.2f}-{float(x['fps_max']):.2f})" if x else "-"
    ratio = f"{float(h['fps']) / float(b['fps']):.2f}x" if b and h else "-"
    samples = f"{b['msamples'] if b else '-'} / {h['msamples'] if h else '-'}"
    v, size, view, shade, target, threads, packet, heur = key
    print(f"| {v} | {size}² | {view} | {shade} | {target} | {threads} | {packet} | {cell(b)} | {cell(h)} | {ratio} | {samples} |")

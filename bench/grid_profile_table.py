#!/usr/bin/env python3
"""Turns bench_grid --profile lines (gridprof ...) into a markdown table: per
case the time each stage's removal saved (ms per frame and share of the
full no-early-termination frame), the rest (ray setup, traversal, stores,
per-frame setup) and the full time with its spread; lines carrying
build=NAME (issue 9's A/B runs) get build, target, size and view columns.
usage: grid_profile_table.py RESULTS.txt"""
import sys

stages = ["fetch", "interpolation", "classification", "shading", "blending", "sample_loop"]
build = any(" build=" in l for l in open(sys.argv[1]))
print(("| build | target | size | view " if build else "") + "| volume | shading | method | full ms (min-max) | " + " | ".join(stages) +
      " | rest (setup, traversal, store) | shipped ms (alpha_stop 0.97) | same samples |")
print(("|---|---|---|---" if build else "") + "|---|---|---|---|" + "---|" * len(stages) + "---|---|---|")
for line in open(sys.argv[1]):
    if not line.startswith("gridprof "):
        continue
    kv = dict(f.split("=", 1) for f in line.split()[1:])
    tot = float(kv["v0_ms"])
    cells = []
    for s in stages + ["rest"]:
        v = float(kv[s + "_ms"])
        cells.append("%.0f (%.0f%%)" % (v, 100 * v / tot))
    if build:
        print("| %s | %s | %s | %s " % (kv["build"], kv["target"], kv["size"], kv["view"]), end="")
    print("| %s | %s | %s | %.0f (%s-%s) | %s | %s | %s |" % (
        kv["volume"], kv["shade"], kv["method"], tot, kv["v0_min"], kv["v0_max"], " | ".join(cells),
        kv["shipped_ms"], kv["same_samples"]))

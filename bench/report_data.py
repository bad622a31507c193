"""The records of `lanecast bench` for bench/report.py: loading, grouping, the
machine's ceilings, and the Markdown table helpers every section uses.
"""
import collections
import json
import os
import sys

TARGETS = ["scalar", "sse4", "avx2", "avx512_8", "avx512"]
GROUP_KEYS = ["file", "scene", "view", "width", "height", "mode", "method", "packet", "shading", "threads",
              "alpha_stop", "sigma"]


def load(paths):
    cases, roofs, skips, peers, jobs = [], [], [], [], []
    for p in paths:
        with open(p) as f:
            for n, line in enumerate(f, 1):
                line = line.strip()
                if not line:
                    continue
                try:
                    r = json.loads(line)
                except json.JSONDecodeError as e:
                    sys.exit("report.py: %s line %d: not JSON (%s)" % (p, n, e))
                r["file"] = os.path.basename(p)
                {"case": cases, "roofline": roofs, "skip": skips, "peer": peers,
                 "job": jobs}.get(r.get("record"), []).append(r)
    return cases, roofs, skips, peers, jobs


def machine(r):
    """The machine a record was made on: CPU model and SIMD flags (one model name can hide CPUs with and
    without AVX-512)."""
    return (r.get("cpu"), r.get("cpu_flags"))


def fma_ratios(roofs):
    """avx512 / avx2 FMA peak per machine, from the roofline records (the CPU's FMA-pipe width ratio:
    2 = full-width 512-bit FMA pipes, 1 = a 512-bit FMA issues as two 256-bit halves)."""
    peak = collections.defaultdict(dict)
    for r in roofs:
        peak[machine(r)][r["target"]] = r["fma_gflops"]
    return {m: p["avx512"] / p["avx2"] for m, p in peak.items() if p.get("avx2") and p.get("avx512")}


def sources(records):
    """The record files a table was made from."""
    return "*Records: %s.*\n" % ", ".join("`bench/results/%s`" % f for f in sorted({r["file"] for r in records}))


GRID_PEAK = "trilinear samples streamed along rays"


def fraction(r):
    """A case's fraction of this machine's ceiling; grids only against the grid-stream ceiling (older
    records' random-load ceiling was not an upper bound of a ray caster)."""
    if r["kind"] == "grid" and r.get("peak") != GRID_PEAK:
        return None
    return r.get("fraction_of_peak")


def groups(cases):
    g = collections.OrderedDict()
    for r in cases:
        g.setdefault(tuple(r.get(k) for k in GROUP_KEYS), {})[r["target"]] = r
    return g


def is_default(r):
    return abs(r.get("alpha_stop", 0.97) - 0.97) < 1e-6 and abs(r.get("sigma", 2.0) - 2.0) < 1e-6


def target_groups(cases, kinds, threads=1):
    """One group per scene (the one with the most targets): threads 1, default parameters."""
    best = collections.OrderedDict()
    for key, g in groups(cases).items():
        r = next(iter(g.values()))
        if r["kind"] not in kinds or r["threads"] != threads or not is_default(r) or "median_s" not in r:
            continue
        if r["scene"] not in best or len(g) > len(best[r["scene"]]):
            best[r["scene"]] = g
    # procedural families by count, then the real data sets
    order = lambda s: (0, s.split(":")[0], float(s.split(":")[1])) if ":" in s else (1, s, 0)
    return collections.OrderedDict(sorted(best.items(), key=lambda kv: order(kv[0])))


def fmt(v, d=3):
    if v is None:
        return "-"
    if abs(v) >= 1000 or (abs(v) < 0.01 and v != 0):
        return "%.3g" % v
    return ("%." + str(d) + "g") % v


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(out) + "\n"

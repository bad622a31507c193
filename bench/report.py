#!/usr/bin/python3
"""Turns `lanecast bench` JSON-lines records into one page with tables and
PNG plots (docs/BENCHMARKS.md by default).

usage: /usr/bin/python3 bench/report.py RECORDS.jsonl... [-o DIR] [--command CMD]

Needs matplotlib (Debian: apt-get install python3-matplotlib; use the system
python3, /usr/bin/python3, where a pyenv python3 lacks it). Tables follow the
papers' layout: Knoll 2014 Tables 1-2 (data sets with counts, build time,
BVH size and frame rates per target) and Figures 6-7 (speedups per SIMD
width, frame rate against count); Knoll 2011 Figures 5-6 (frame rate per
volume and view, thread scaling). Records are grouped by file and case; a
case's targets were timed in interleaved rounds, so ratios inside a group are
the trustworthy numbers on a loaded machine.
"""
import argparse
import collections
import json
import os
import re
import statistics
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("report.py: matplotlib is missing: apt-get install python3-matplotlib (and run /usr/bin/python3)")

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


def targets_table(best, kind_word):
    present = [t for t in TARGETS if any(t in g for g in best.values())]
    header = ["scene", "count", "build s", "BVH MB", "rays"] + ["%s fps (x)" % t for t in present] + [
        "best %s/s" % kind_word, "check"]
    rows = []
    for scene, g in best.items():
        r0 = next(iter(g.values()))
        cells = [scene, "%d" % r0["count"], fmt(r0["build_s"]), fmt(r0["bvh_bytes"] / 1e6), "%d" % r0.get("rays", 0)]
        for t in present:
            r = g.get(t)
            if not r or "fps" not in r:
                cells.append("-")
                continue
            sp = r.get("speedup_vs_scalar")
            cells.append("%s (%s)" % (fmt(r["fps"]), fmt(sp, 2) if sp else "-"))
        key = "voxel_evals_per_s" if r0["kind"] == "grid" else "gauss_per_s"
        cells.append(fmt(max(r.get(key, 0) for r in g.values())))
        fails = [t for t, r in g.items() if r.get("check") and not r["check"]["pass"]]
        cells.append("FAIL " + ",".join(fails) if fails else "pass")
        rows.append(cells)
    return table(header, rows)


def plot_speedup(best, path):
    scenes = list(best)
    present = [t for t in TARGETS if any(t in g for g in best.values())]
    fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(scenes)), 4))
    w = 0.8 / max(1, len(present))
    for i, t in enumerate(present):
        ys = [best[s][t].get("speedup_vs_scalar", 0) if t in best[s] else 0 for s in scenes]
        ax.bar([k + i * w for k in range(len(scenes))], ys, w, label="%s (%d lanes)" % (t, {"scalar": 1, "sse4": 4,
               "avx2": 8, "avx512_8": 8, "avx512": 16}[t]))
    ax.set_xticks([k + 0.4 - w / 2 for k in range(len(scenes))], scenes, rotation=30, ha="right", fontsize=8)
    ax.set_ylabel("speedup over scalar (median frame time)")
    ax.set_title("Speedup per SIMD target, 1 thread")
    ax.legend(fontsize=7)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_fps_count(best, path):
    fig, ax = plt.subplots(figsize=(6, 4))
    for t in TARGETS:
        pts = sorted((g[t]["count"], g[t]["fps"], g[t]["min_s"], g[t]["max_s"]) for s, g in best.items()
                     if s.startswith("uniform:") and t in g and "fps" in g[t])
        if len(pts) < 2:
            continue
        xs = [p[0] for p in pts]
        ys = [p[1] for p in pts]
        lo = [y - 1 / p[3] for y, p in zip(ys, pts)]
        hi = [1 / p[2] - y for y, p in zip(ys, pts)]
        ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", capsize=3, label=t)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles (uniform radii)")
    ax.set_ylabel("frames per second (min..max bars)")
    ax.set_title("Frame rate against particle count, 1 thread")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def sweep(cases, param, path, title):
    series = collections.defaultdict(list)
    for r in cases:
        if "median_s" not in r or r["threads"] != 1:
            continue
        other = "sigma" if param == "alpha_stop" else "alpha_stop"
        default = 2.0 if other == "sigma" else 0.97
        if abs(r.get(other, default) - default) > 1e-6:
            continue
        series[(r["scene"], r["target"], r["file"])].append(r)
    series = {k: sorted(v, key=lambda r: r[param]) for k, v in series.items()
              if len({r[param] for r in v}) >= 3}
    if not series:
        return None
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    rows = []
    for (scene, t, _), rs in series.items():
        xs = [r[param] for r in rs]
        a1.plot(xs, [r["fps"] for r in rs], marker="o", label="%s %s" % (scene, t))
        a2.plot(xs, [r["samples"] / rs[-1]["samples"] if rs[-1]["samples"] else 0 for r in rs], marker="o",
                label="%s %s" % (scene, t))
        for r in rs:
            rows.append([scene, t, fmt(r[param]), fmt(r["fps"]), "%d" % r["samples"], "%d" % r["kernel_evals"],
                         fmt(r.get("fraction_of_peak"))])
    a1.set_xlabel(param)
    a1.set_ylabel("frames per second")
    a2.set_xlabel(param)
    a2.set_ylabel("samples, relative to the last point")
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return table(["scene", "target", param, "fps", "samples", "kernel evals", "of peak"], rows)


def threads_section(cases, path):
    """Thread scaling of the bench_threads records: fps per thread count, the 1-thread frame time (the
    scenes are sized to 0.1 s or more, so thread start-up and tile imbalance do not hide the scaling),
    and the load average the records carry (1-minute, lanecast's own threads included): a load above
    the CPUs online means other work shared the cores, and the scaling then says as much about that as
    about lanecast."""
    series = collections.defaultdict(dict)
    for r in cases:
        if "median_s" in r and is_default(r) and r["file"].startswith("bench_threads"):
            series[(r["scene"], r["target"], r["width"], r["height"])][r["threads"]] = r
    series = {k: v for k, v in series.items() if len(v) >= 2}
    if not series:
        return None
    fig, ax = plt.subplots(figsize=(6, 4))
    rows = []
    nth = sorted({n for v in series.values() for n in v})
    for (scene, t, w, h), v in series.items():
        ths = sorted(v)
        ax.plot(ths, [v[n]["fps"] / v[ths[0]]["fps"] for n in ths], marker="o", label="%s %s" % (scene, t))
        top = v[ths[-1]]
        loads = [v[n].get("loadavg", -1) for n in ths]
        # the load average counts lanecast's own threads: more runnable work than CPUs is another's
        loaded = any(l > v[n]["cpus_online"] + 0.5 for n, l in zip(ths, loads))
        rows.append([scene, t, "%dx%d" % (w, h), fmt(v[ths[0]]["median_s"])] +
                    [fmt(v[n]["fps"]) if n in v else "-" for n in nth] +
                    [fmt(top["fps"] / v[ths[0]]["fps"], 3), fmt(top["cpu_median_s"] / v[ths[0]]["cpu_median_s"], 3)
                     if top.get("cpu_median_s") and v[ths[0]].get("cpu_median_s") else "-",
                     " / ".join(fmt(l, 2) for l in loads), "**loaded**" if loaded else "quiet"])
    top = max(nth)
    ax.plot([1, top], [1, top], "k--", lw=0.8, label="linear")
    ax.set_xlabel("threads")
    ax.set_ylabel("speedup over 1 thread")
    ax.set_title("Thread scaling (%d CPUs)" % next(iter(series.values()))[nth[0]]["cpus_online"])
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    recs = [r for v in series.values() for r in v.values()]
    return table(["scene", "target", "image", "1-thread s"] + ["fps %d thr" % n for n in nth] +
                 ["scaling (wall)", "CPU s ratio", "load avg per run", "machine"], rows) + "\n" + sources(recs)


def width_section(cases, roofs):
    ratios = fma_ratios(roofs)
    rows, recs = [], []
    for key, g in groups(cases).items():
        r0 = next(iter(g.values()))
        if r0.get("study") != "width" or not all(t in g and "fps" in g[t] for t in ("avx2", "avx512_8", "avx512")):
            continue
        a, b, c = (g[t]["median_s"] for t in ("avx2", "avx512_8", "avx512"))
        rows.append([r0["scene"], r0["kind"], fmt(g["avx2"]["fps"]), fmt(g["avx512_8"]["fps"]), fmt(g["avx512"]["fps"]),
                     fmt(a / b, 3), fmt(b / c, 3), fmt(a / c, 3), fmt(ratios.get(machine(r0)), 3)])
        recs += list(g.values())
    if not rows:
        return None
    return table(["scene", "kind", "avx2 fps", "avx512_8 fps", "avx512 fps", "ISA (avx512_8 / avx2)",
                  "width (avx512 / avx512_8)", "both (avx512 / avx2)", "FMA peak avx512 / avx2 (roofline)"], rows) + \
        "\n" + sources(recs + [r for r in roofs if machine(r) in {machine(x) for x in recs}])


def views_section(cases):
    """Every case of the bench_views file: view x mode x method, targets side by side."""
    rows = []
    for key, g in groups([r for r in cases if r["file"].startswith("bench_views")]).items():
        r0 = next(iter(g.values()))
        ts = [t for t in TARGETS if t in g and "fps" in g[t]]
        fails = [t for t, r in g.items() if r.get("check") and not r["check"]["pass"]]
        rows.append([r0["scene"], r0["view"], r0["mode"], r0["method"]] +
                    [" / ".join("%s %s" % (t, fmt(g[t]["fps"])) for t in ts)] +
                    [fmt(g[ts[-1]].get("speedup_vs_scalar"), 3) if ts else "-",
                     fmt(g[ts[-1]]["samples"] / 1e6) if ts else "-", "FAIL " + ",".join(fails) if fails else "pass"])
    if not rows:
        return None
    return table(["scene", "view", "mode", "method", "fps", "widest / scalar", "M samples", "check"], rows)


def large_section(cases):
    rows = []
    for r in cases:
        if not r["file"].startswith("bench_large") or "fps" not in r:
            continue
        rows.append([r["scene"], "%d" % r["count"], r["target"], r["threads"], fmt(r["build_s"]),
                     fmt(r["bvh_bytes"] / 1e6), fmt(r["data_bytes"] / 1e6), fmt(r["fps"]),
                     "%s..%s" % (fmt(1 / r["max_s"]), fmt(1 / r["min_s"])), fmt(r["rss_peak_kb"] / 1024),
                     "pass" if r["check"] and r["check"]["pass"] else "FAIL"])
    if not rows:
        return None
    return table(["scene", "count", "target", "threads", "build s", "BVH MB", "data MB", "fps", "fps min..max",
                  "peak RSS MB (process)", "check"], rows)


def builders_section(cases):
    """`--builders` records: per scene and builder the build (wall and CPU s, BVH MB, the build's peak memory)
    and the CPU s per frame of each view, with the ratio to Embree MEDIUM's (below 1: faster)."""
    rows, recs = [], []
    per = collections.OrderedDict()
    for r in cases:
        if "/builder:" in r["scene"] and "cpu_median_s" in r:
            base, b = r["scene"].split("/builder:")
            base = "%s (%dx%d)" % (base, r["width"], r["height"])
            per.setdefault(base, collections.OrderedDict()).setdefault(b, {})[r["view"]] = r
            recs.append(r)
    if not per:
        return None
    views = sorted({v for bs in per.values() for vs in bs.values() for v in vs}, key=["far", "medium", "close"].index)
    for base, bs in per.items():
        ref = bs.get("embree", {})
        for b, vs in bs.items():
            r0 = next(iter(vs.values()))
            cells = []
            for v in views:
                if v not in vs:
                    cells.append("-")
                    continue
                c = vs[v]["cpu_median_s"]
                x = " (%s)" % fmt(c / ref[v]["cpu_median_s"], 3) if v in ref and b != "embree" else ""
                cells.append(fmt(c) + x)
            rows.append([base, b, fmt(r0["build_s"]), fmt(r0.get("build_cpu_s")), fmt(r0["bvh_bytes"] / 1e6),
                         fmt(r0["build_peak_kb"] / 1024) if r0.get("build_peak_kb", -1) >= 0 and
                         r0.get("build_peak_trimmed") else "-"] + cells +
                        [fmt(r0.get("loadavg"), 2)])
    return table(["scene", "builder", "build s", "build CPU s", "BVH MB", "build peak MB"] +
                 ["%s CPU s/frame (x embree)" % v for v in views] + ["load"], rows) + "\n" + sources(recs)


def roof_section(roofs):
    """One table per machine (the last record per target)."""
    per = collections.OrderedDict()
    for r in roofs:
        per.setdefault(machine(r), {})[r["target"]] = r
    ratios = fma_ratios(roofs)
    out = []
    for m, last in per.items():
        g = lambda t, k, sc=1.0: fmt(last[t][k] / sc) if last[t].get(k) else "-"
        rows = [[t, last[t]["lanes"], g(t, "fma_gflops"), g(t, "gauss_per_s", 1e9), g(t, "gather_l1_per_s", 1e9),
                 g(t, "gather_mem_per_s", 1e9), g(t, "gather_over_scalar_l1"), g(t, "gather_over_scalar_mem"),
                 g(t, "grid_cache_samples_per_s", 1e6), g(t, "grid_mem_samples_per_s", 1e6)]
                for t in TARGETS if t in last]
        r0 = next(iter(last.values()))
        out.append("%s (%s), commit %s%s; FMA-pipe width ratio (avx512 / avx2 FMA peak): %s\n\n" %
                   (m[0], m[1], r0["commit"], ", " + r0["date"] if r0.get("date") else "",
                    fmt(ratios.get(m), 3) if m in ratios else "not measured (no AVX-512 here)") +
                   table(["target", "lanes", "FMA GFLOP/s", "Gaussians G/s", "gather L1 G floats/s",
                          "gather 16 MiB G floats/s", "gather/scalar L1", "gather/scalar 16 MiB",
                          "grid stream M samples/s (40^3)", "grid stream M samples/s (320^3)"], rows) + "\n" +
                   sources(list(last.values())))
    return "\n".join(out)


def plot_fraction(best, path):
    labels, vals, colors = [], [], []
    cmap = {t: c for t, c in zip(TARGETS, ["C0", "C1", "C2", "C3", "C4"])}
    for scene, g in best.items():
        for t in TARGETS:
            if t in g and fraction(g[t]) is not None:
                labels.append("%s %s" % (scene, t))
                vals.append(100 * fraction(g[t]))
                colors.append(cmap[t])
    if not vals:
        return
    fig, ax = plt.subplots(figsize=(7, max(3, 0.18 * len(vals))))
    ax.barh(range(len(vals)), vals, color=colors)
    ax.set_yticks(range(len(vals)), labels, fontsize=6)
    ax.invert_yaxis()
    ax.set_xlabel("% of this machine's ceiling per core (see the text)")
    ax.set_title("Fraction of peak, 1 thread")
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def checks_section(cases):
    worst = {}
    for r in cases:
        c = r.get("check")
        if not c:
            continue
        w = worst.setdefault(r["target"], [0.0, float("inf"), 0, 0])
        w[0] = max(w[0], c["max_diff_255"] or 0)
        if c.get("psnr_db") is not None:
            w[1] = min(w[1], c["psnr_db"])
        w[2] += 1
        w[3] += 0 if c["pass"] else 1
    rows = [[t, "%.3g" % worst[t][0], "identical" if worst[t][1] == float("inf") else "%.1f" % worst[t][1],
             worst[t][2], worst[t][3]] for t in TARGETS if t in worst]
    return table(["target", "worst max diff (/255)", "worst PSNR dB", "cases", "failed"], rows)


def jobs_section(jobs):
    """Interactive timings (lanecast bench --jobs): one row per scene, mode and target."""
    rows = []
    for r in jobs:
        rows.append([r["scene"], r["view"], "%dx%d" % (r["width"], r["height"]), r["mode"], r["target"], r["threads"],
                     fmt(1e3 * r["full_s"], 3), fmt(1e3 * r["nav_s"], 3), fmt(1e3 * r["preview_s"], 3),
                     fmt(1e3 * r["refined_s"], 3), "%s / %s / %s" % (fmt(r["cancel_median_ms"], 2), fmt(r["cancel_p95_ms"], 2),
                                                                     fmt(r["cancel_worst_ms"], 2)),
                     "%d (+%d done first)" % (r["cancels"], r["finished_before_cancel"]), fmt(r.get("loadavg"), 2),
                     r.get("commit", "-")])
    intro = ("What an interactive user waits for: the full frame (`lc_render`), the navigation frame (`pixel_scale` 2, "
             "what `lanecast view` renders while the camera moves), a render job's preview pass (pixel scale 4 at "
             "1024^2) and refined image, and the cancel latency, from `lc_job_cancel` to `lc_job_wait` returning, "
             "at random points of a frame (median / p95 / worst, ms). Times in ms.\n\n")
    return "\n## Interactive use (`--jobs`)\n\n" + intro + table(
        ["scene", "view", "size", "mode", "target", "threads", "full", "navigation", "preview", "refined",
         "cancel med / p95 / worst", "cancels", "load", "commit"], rows)


def peers_section(peers):
    rows = [[r["scene"], "%s %s" % (r["peer"], r["peer_version"]), r["peer_mapper"], "%dx%d" % (r["size"], r["size"]),
             r["threads"], fmt(r.get("dt")), fmt(r["lanecast_first_s"]), fmt(r["peer_first_s"]), fmt(r["lanecast_frame_s"]),
             fmt(r["peer_frame_s"]), fmt(r["frame_ratio_peer_over_lanecast"], 3), fmt(r["psnr_db_between"], 3),
             fmt(r.get("loadavg"))] for r in peers]
    out = ["\n## Peers, same run (`bench/peers.sh`)\n\n",
           "Same data, TF (colour points; tau per world unit given to VTK as alpha = 1 - exp(-tau) at unit "
           "distance 1), camera, sample distance and image size; 2 threads each; black background, no shading. "
           "First image: lanecast's whole process (start, read, build, render, write) against VTK's read, "
           "upload and first render inside Python; per frame: medians of 5.\n\n",
           table(["scene", "peer", "mapper", "image", "threads", "dt", "lanecast first s", "peer first s",
                  "lanecast s/frame", "peer s/frame", "peer / lanecast", "PSNR between dB", "load"], rows)]
    if any(r["peer"] == "vtk" for r in peers):
        out.append("\nVTK: what differs between the pipelines. VTK's fixed-point mapper classifies through 15-bit "
                   "fixed-point lookup tables built over the scalar range and composites in fixed point; it places "
                   "samples from the ray's entry into the volume's box, while lanecast samples on a lattice of "
                   "planes (SPEC.md) and reconstructs in float; VTK skips empty space with a min-max grid of blocks, "
                   "lanecast with its implicit BVH. Small differences in colour and in the sampling pattern are "
                   "expected; the PSNR between the two images says how far apart they are. For particles VTK has no "
                   "direct path: users interpolate onto a grid first (`vtkPointInterpolator` with a `vtkGaussianKernel` "
                   "of radius 2r and sharpness sqrt 2, weights not normalised, i.e. exactly lanecast's truncated "
                   "Gaussian sum with sigma 2, on a grid of spacing r/2) and ray cast the grid; its first image "
                   "includes the interpolation, and the grid's trilinear reconstruction blurs the field (the lower "
                   "PSNR).\n")
    if any(r["peer"] == "splash" for r in peers):
        out.append("\nSPLASH: the shared GADGET initial conditions have no densities or smoothing lengths, so "
                   "`bench/peers_splash.py` writes a snapshot of the 32,768 gas particles (or, with SPLIT 1, of the "
                   "262,144 made by splitting each into 8 a quarter spacing around it, 1/8 of its mass) with HSML = distance to "
                   "the 32nd neighbour and SPH densities (GADGET-2 cubic spline); SPLASH renders its density column "
                   "with opacity rendering (`--kappa`, orthographic along z, its own colour table over the density's "
                   "min..max, one image per run). lanecast renders the same particles from a CSV: one Gaussian per "
                   "particle with the spline's standard deviation and weight m / ((2 pi)^1.5 r^3), so the field is "
                   "the same density to first order, tau = kappa rho, grey colours over [0, 99.5th percentile]. The "
                   "pictures differ in colour mapping, and lanecast's narrower Gaussians let the initial conditions' "
                   "lattice show through; the structures (over- and under-dense regions) agree. SPLASH has no "
                   "per-frame time, so the ratio compares whole runs (start, read, render, write PNG), with "
                   "lanecast's render alone beside it. These particles are initial conditions (nearly uniform): a "
                   "timing and pipeline check, not a showcase.\n")
    for r in peers:
        what = "lanecast | VTK | difference" if r["peer"] == "vtk" else "lanecast | SPLASH"
        out.append("\n![%s: %s](%s)\n" % (r["scene"], what, r["composite"]))
    return "".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("records", nargs="+")
    ap.add_argument("-o", "--out", default="docs/bench")
    ap.add_argument("--command", default="", help="the command(s) that made the records, for the page's top")
    ap.add_argument("--page", default="", help="where the page goes (default OUT/REPORT.md); its image links "
                    "are made relative to it")
    a = ap.parse_args()
    cases, roofs, skips, peers, jobs = load(a.records)
    if not cases and not roofs:
        sys.exit("report.py: no records in %s" % " ".join(a.records))
    os.makedirs(a.out, exist_ok=True)
    P = lambda name: os.path.join(a.out, name)
    m = (cases or roofs)[0]
    loads = [r["loadavg"] for r in cases + roofs if r.get("loadavg", -1) >= 0]
    commits = sorted({r["commit"] for r in cases + roofs})
    doc = ["# Benchmarks\n",
           "`lanecast bench` is the project's one benchmark: for each case of a matrix (scenes, views, sizes, "
           "targets, threads, methods, modes, packets; `lanecast bench --help`) it first checks every SIMD target's "
           "image against the scalar target's (SPEC.md tolerances; a mismatch is recorded and makes it exit 1), then "
           "times the targets in interleaved rounds and writes one JSON line per case and target (median and spread, "
           "fps, ns per ray, samples/s, Gaussians/s, build time and bytes, peak RSS, CPU, commit, compiler). "
           "`--quick` runs as a test, `--roofline` measures this machine's ceilings, `--width-study` separates "
           "instruction set from width, `--jobs N` times what an interactive user waits for (navigation frames, "
           "a render job's passes, cancel latency), `--baseline EXE` compares this build with another build "
           "of lanecast in interleaved rounds (ratios of wall and CPU time per case), `--profile` splits a grid "
           "frame's CPU time into its stages, `--builders` compares particle BVH builders and `--read` times "
           "trajectory reading. Records from another machine (the `_avx512` files) are marked by their CPU "
           "flags in the tables that use them. "
           "`bench/report.py` made this page from the records in `bench/results/`; "
           "`bench/peers.sh` measures VTK and SPLASH on the same data.\n"]
    if a.command:
        doc.append("Made with:\n\n```sh\n%s\n```\n" % a.command.strip())
    doc.append("Machine: %s (%s), %d CPUs online, host `%s`; commit %s; %s. Load average during the run: %s to %s "
               "(median %s): **the machine was shared with other engineers' builds and tests**, so absolute frame "
               "rates are low and noisy; targets inside one case were timed in interleaved rounds, so the ratios "
               "between targets are the numbers to trust. Image %s, default TF (`lc_tf_auto`), default step, "
               "alpha_stop 0.97 unless swept. Every target's image was checked against the scalar target's "
               "(alpha_stop 1, SPEC.md tolerances) before timing.\n"
               % (m["cpu"], m["cpu_flags"], m["cpus_online"], m["host"], ", ".join(commits), m["compiler"],
                  fmt(min(loads)) if loads else "?", fmt(max(loads)) if loads else "?",
                  fmt(statistics.median(loads)) if loads else "?",
                  "%dx%d" % (cases[0]["width"], cases[0]["height"]) if cases else "-"))
    if roofs:
        doc.append("## This machine's ceilings (`lanecast bench --roofline`, 1 thread, best pass)\n")
        doc.append(roof_section(roofs))
    doc.append("\n## Checks against the scalar target\n")
    doc.append(checks_section(cases))
    pbest = target_groups(cases, {"particles"})
    vbest = target_groups(cases, {"grid", "rbf"})
    if pbest:
        doc.append("\n## Particles per target (Knoll 2014 Table 1 / Figure 6 style)\n")
        doc.append("Frames per second (median) and, in brackets, speedup over scalar in the same interleaved case; "
                   "1 thread, far view.\n\n")
        doc.append(targets_table(pbest, "Gaussians"))
        plot_speedup(pbest, P("speedup_particles.png"))
        doc.append("\n![speedup per SIMD width, particles](speedup_particles.png)\n")
        plot_fps_count(pbest, P("fps_vs_count.png"))
        doc.append("\n![fps against particle count](fps_vs_count.png)\n")
    if vbest:
        doc.append("\n## Grids and RBF sets per target (Knoll 2011 Figures 5-6 style)\n")
        doc.append(targets_table(vbest, "evals"))
        plot_speedup(vbest, P("speedup_volumes.png"))
        doc.append("\n![speedup per SIMD width, grids and RBF sets](speedup_volumes.png)\n")
    allbest = collections.OrderedDict(list(pbest.items()) + list(vbest.items()))
    if allbest:
        plot_fraction(allbest, P("fraction_of_peak.png"))
        doc.append("\n## Fraction of peak\n\nAchieved Gaussians/s (particles, RBF sets) over the Gaussian micro-kernel's "
                   "rate, or samples/s over the grid ceiling (grids: the grid-stream kernel of `--roofline`, trilinear "
                   "samples streamed along rays through the kernels' uint8 quad copy with no traversal, "
                   "classification or blending, the faster of its two volume sizes), per core used. A frame does "
                   "all of the ceiling's work per sample and more, so each fraction is at most 1; what is left is "
                   "traversal, classification, shading and compositing.\n\n"
                   "![fraction of peak](fraction_of_peak.png)\n")
    w = width_section(cases, roofs)
    if w:
        doc.append("\n## Width study: instruction set vs lane width (`--width-study`)\n\n"
                   "Ratios of median frame times within one interleaved case: avx512_8 / avx2 isolates the AVX-512 "
                   "instruction set at 8 lanes; avx512 / avx512_8 isolates the width at the same instruction set.\n\n")
        doc.append(w)
    t = views_section(cases)
    if t:
        doc.append("\n## Views, modes and methods (Knoll 2011 Figure 5 style)\n\nfar frames the data, medium is "
                   "0.55 of that distance, close 0.3 (inside the particle cube); iso at the middle of the value "
                   "range; `direct` applies to particles and `brute` to grids, each skipped for the other kind.\n\n" + t)
    t = large_section(cases)
    if t:
        doc.append("\n## Large sets\n\nPeak RSS is the process's peak so far (getrusage), so it includes the "
                   "sets built before in the same run.\n\n" + t)
    t = sweep(cases, "alpha_stop", P("alpha_sweep.png"), "Early termination sweep")
    if t:
        doc.append("\n## Early-termination sweep (alpha_stop)\n\n![alpha_stop sweep](alpha_sweep.png)\n\n" + t)
    t = sweep([r for r in cases if r["kind"] == "particles"], "sigma", P("sigma_sweep.png"), "Truncation radius sweep")
    if t:
        doc.append("\n## Sigma sweep (particle truncation radius)\n\n![sigma sweep](sigma_sweep.png)\n\n" + t)
    t = builders_section(cases)
    if t:
        doc.append("\n## Particle BVH builders (`--builders`)\n\nEach scene built once per builder "
                   "(`scene/builder:NAME`), then its frames timed; CPU seconds of the process per frame "
                   "(every thread), which a shared machine's load moves far less than wall time. The build peak "
                   "is the create call's VmHWM rise above the resident memory before it, after malloc_trim (records "
                   "without `build_peak_trimmed` show none: later builds reused heap freed by earlier ones); a "
                   "scene measured twice shows its last records.\n\n" + t)
    t = threads_section(cases, P("threads.png"))
    if t:
        doc.append("\n## Thread scaling\n\n![thread scaling](threads.png)\n\n" + t)
    if jobs:
        doc.append(jobs_section(jobs))
    if peers:
        doc.append(peers_section(peers))
    if skips:
        doc.append("\n## Skipped\n\n" + "".join("- %s: %s\n" % (s["scene"], s["note"]) for s in skips))
    page = a.page or P("REPORT.md")
    rel = os.path.relpath(a.out, os.path.dirname(os.path.abspath(page)) or ".")
    docs = os.path.relpath(os.path.join(a.out), os.path.dirname(os.path.abspath(page)))
    doc.append("\n## Why the kernels are as they are\n\nEach design choice of the kernels with the figure that "
               "decided it (machine, commit and raw file, `git show COMMIT:bench/results/FILE`), and a ledger of "
               "what was tried and not kept: [particles](%s/particles.md), [grids](%s/grid.md), "
               "[RBF sets and the encoder](%s/rbf.md); the benchmark's modes and how the older harnesses' "
               "cases map onto them: [bench/README.md](%s/README.md).\n\nData-parallel rendering over MPI (compositing time "
               "and bytes per rank at P = 2, 1024²): [mpi.md](mpi.md).\n" % (docs, docs, docs, docs))
    text = "\n".join(doc)
    if rel != ".":  # plots and composites live in OUT
        text = re.sub(r"\]\(([^/()]+\.png)\)", lambda mm: "](%s/%s)" % (rel, mm.group(1)), text)
    with open(page, "w") as f:
        f.write(text)
    print("report.py: wrote %s (%d case records, %d roofline)" % (page, len(cases), len(roofs)))


if __name__ == "__main__":
    main()

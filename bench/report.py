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
import os
import re
import statistics
import sys

try:
    import matplotlib  # noqa: F401 (report_plots uses it; a missing one is said here)
except ImportError:
    sys.exit("report.py: matplotlib is missing: apt-get install python3-matplotlib (and run /usr/bin/python3)")

from report_data import fmt, load, target_groups  # noqa: E402 (after the matplotlib check)
from report_plots import plot_fps_count, plot_fraction, plot_speedup, sweep, threads_section  # noqa: E402
from report_tables import (builders_section, checks_section, jobs_section, large_section,  # noqa: E402
                           peers_section, roof_section, targets_table, views_section, width_section)


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

"""bench/report.py's table-only sections.
"""
import collections

from report_data import TARGETS, machine, fma_ratios, sources, groups, fmt, table


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
             "at random points of a frame (median / p95 / worst, ms). Times in ms. The 67f2366 rows check the "
             "cancel between tiles only, later rows inside the kernels too; the window's own figures (navigation "
             "frames in `lanecast view`, adaptive scale) are in [bench/view.md](bench/view.md).\n\n")
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

"""bench/report.py's plots (PNG through matplotlib) and the sections that come
with one.
"""
import collections
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

from report_data import TARGETS, sources, fraction, is_default, fmt, table


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

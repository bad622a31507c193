#!/usr/bin/env python3
"""Tables for docs/bench/particles.md "Build peak" from bench/pbuild_ab.sh output.

Build table: per set and builder, the median over rounds of each build figure;
the budget test is on the build's own peak plus the caller's input arrays
(16 bytes per particle), i.e. without the process's baseline (program,
libraries, device threads).
Frame table: per set, view and builder, the median over rounds of the per-run
median CPU seconds per frame (min-max over rounds), and the ratio to the
embree row of the same set and view.
usage: pbuild_table.py RAW.txt [RAW2.txt ...]
"""
import statistics
import sys


def parse(paths):
    builds, frames = {}, {}
    for path in paths:
        for line in open(path):
            if line.startswith('#') or '=' not in line:
                continue
            kv = dict(f.split('=', 1) for f in line.split() if '=' in f)
            if 'view' in kv:
                frames.setdefault((kv['set'], kv['view'], kv['builder']), []).append(kv)
            elif 'build_s' in kv:
                builds.setdefault((kv['set'], kv['builder']), []).append(kv)
    return builds, frames


def med(rows, key):
    return statistics.median(float(r[key]) for r in rows)


def main():
    builds, frames = parse(sys.argv[1:])
    order = ['embree', 'embree-low', 'chunked', 'sah']
    sets = sorted({s for s, _ in builds}, key=lambda s: (s.split(':')[0] != 'uniform', s))
    print('| set | builder | runs | build CPU s | build wall s | nodes | depth | BVH MB | process peak MB |'
          ' build peak MB | input MB | build peak + input MB | budget MB (2 x data + BVH) | within budget |')
    print('|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|')
    for s in sets:
        for b in order:
            rows = builds.get((s, b))
            if not rows:
                continue
            # the caller's arrays: positions and radii (bench_pbuild always passes radii)
            inp = 16 * int(rows[0]['n']) / 1e6
            peak, budget = med(rows, 'build_peak_mb') + inp, med(rows, 'budget_mb')
            print(f"| {s} | {b} | {len(rows)} | {med(rows, 'build_cpu_s'):.2f} | {med(rows, 'build_s'):.2f} |"
                  f" {int(med(rows, 'nodes')):,} | {int(med(rows, 'depth'))} | {med(rows, 'bvh_mb'):.1f} |"
                  f" {med(rows, 'process_peak_mb'):.1f} | {med(rows, 'build_peak_mb'):.1f} | {inp:.1f} | {peak:.1f} |"
                  f" {budget:.1f} |"
                  f" {'yes' if peak <= budget else 'no'} |")
    print()
    print('| set | view | builder | runs | CPU s / frame, median (min-max) | vs embree | nodes tested / frame |')
    print('|---|---|---|---:|---:|---:|---:|')
    for s in sets:
        for v in ['far', 'close']:
            base = frames.get((s, v, 'embree'))
            for b in order:
                rows = frames.get((s, v, b))
                if not rows:
                    continue
                m = med(rows, 'cpu_median_s')
                lo = min(float(r['cpu_median_s']) for r in rows)
                hi = max(float(r['cpu_median_s']) for r in rows)
                ratio = f'{m / med(base, "cpu_median_s"):.3f}' if base else '-'
                nodes = f"{int(med(rows, 'nodes_visited')):,}" if 'nodes_visited' in rows[0] else '-'
                print(f'| {s} | {v} | {b} | {len(rows)} | {m:.4f} ({lo:.4f}-{hi:.4f}) | {ratio} | {nodes} |')


if __name__ == '__main__':
    main()

"""Table of bench/ab_compare.sh NAME's runs: per case, the median over rounds
of each build's task-clock, the difference per frame, and that difference
relative to the before build's best wall-clock frame (its cost on a quiet
core). Usage: python3 bench/ab_table.py NAME"""
import statistics, sys
name = sys.argv[1]
runs = {}
for line in open(f'bench/results/{name}_ab.txt'):
    w = line.split()
    who = w[0]
    f = dict(kv.split('=', 1) for kv in w if '=' in kv)
    if 'set' in f:
        key = ('particles', f['set'], f['view'], '-', f['method'], f['target'])
        best = float(f['min_s']) * 1000.0
    else:
        key = ('grid', f['volume'], f['view'], f['shade'], f['method'], f['target'])
        best = 1000.0 / float(f['fps_max'])
    d = runs.setdefault(key, {}).setdefault(who, {'cpu': [], 'best': []})
    d['cpu'].append(float(f['task_ms']) / int(f['frames']))
    d['best'].append(best)
print("| kind | data | view | shade | method | target | CPU ms/frame before | after | after - before | (after - before) / best frame |")
print("|---|---|---|---|---|---|---:|---:|---:|---:|")
rel = []
for key in sorted(runs):
    v = runs[key]
    if 'base' not in v or 'main' not in v: continue
    b, m = statistics.median(v['base']['cpu']), statistics.median(v['main']['cpu'])
    best = min(v['base']['best'])
    r = (m - b) / best
    rel.append(r)
    print("| " + " | ".join(key) + f" | {b:.2f} | {m:.2f} | {m - b:+.2f} | {100 * r:+.1f}% |")
print(f"\n{len(rel)} cases: (after - before) / frame median {100 * statistics.median(rel):+.1f}%, "
      f"range {100 * min(rel):+.1f}% to {100 * max(rel):+.1f}%")

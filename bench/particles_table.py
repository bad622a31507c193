#!/usr/bin/env python3
"""Markdown tables and ratios from bench_particles output (bench/results/particles_*.txt)."""
import sys
from collections import defaultdict

rows = []
for path in sys.argv[1:]:
    for line in open(path):
        if not line.startswith('particles '):
            continue
        kv = dict(tok.split('=', 1) for tok in line.split()[1:])
        rows.append(kv)

def key(r, *ks):
    return tuple(r[k] for k in ks)

def table(title, rs):
    print(f'\n#### {title}\n')
    print('| set | n | view | target | threads | method | packet | median s | min–max s | fps | Gaussians/s |')
    print('|---|---:|---|---|---:|---|---:|---:|---:|---:|---:|')
    for r in rs:
        print(f"| {r['set']} | {r['n']} | {r['view']} | {r['target']} | {r['threads']} | {r['method']} | {r['packet']} "
              f"| {float(r['median_s']):.3f} | {float(r['min_s']):.3f}–{float(r['max_s']):.3f} | {float(r['fps']):.2f} "
              f"| {float(r['gauss_per_s']):.3g} |")

table('All cases', rows)

by = {key(r, 'set', 'view', 'target', 'threads', 'method', 'packet', 'size'): float(r['median_s']) for r in rows}
print('\n#### coherent vs direct (same set, view, target, threads)\n')
print('| set | view | target | threads | coherent s | direct s | direct / coherent |')
print('|---|---|---|---:|---:|---:|---:|')
for k, t in sorted(by.items()):
    s, v, tg, th, m, p, sz = k
    if m == 'coherent' and p == '8':
        d = by.get((s, v, tg, th, 'direct', '8', sz))
        if d:
            print(f'| {s} | {v} | {tg} | {th} | {t:.3f} | {d:.3f} | {d / t:.2f}x |')

print('\n#### SIMD width (coherent, packet 8, one thread): speed-up over the previous column\n')
order = ['scalar', 'sse4', 'avx2', 'avx512_8', 'avx512']
pairs = [('scalar', 'sse4'), ('sse4', 'avx2'), ('avx2', 'avx512_8'), ('avx512_8', 'avx512'), ('avx2', 'avx512')]
print('| set | view | ' + ' | '.join(order) + ' | ' + ' | '.join(f'{b}/{a}' for a, b in pairs) + ' |')
print('|---|---|' + '---:|' * (len(order) + len(pairs)))
groups = defaultdict(dict)
for k, t in by.items():
    s, v, tg, th, m, p, sz = k
    if m == 'coherent' and p == '8' and th == '1':
        groups[(s, v)][tg] = t
for (s, v), g in sorted(groups.items()):
    if len(g) < 2:
        continue
    cells = [f'{g[o]:.3f}' if o in g else '—' for o in order]
    rat = [f'{g[a] / g[b]:.2f}x' if a in g and b in g else '—' for a, b in pairs]  # time(a) / time(b)
    print(f'| {s} | {v} | ' + ' | '.join(cells) + ' | ' + ' | '.join(rat) + ' |')

print('\n#### threads (coherent): 2 threads over 1\n')
print('| set | view | target | packet | 1 thread s | 2 threads s | speed-up |')
print('|---|---|---|---:|---:|---:|---:|')
for k, t in sorted(by.items()):
    s, v, tg, th, m, p, sz = k
    if m == 'coherent' and th == '1':
        t2 = by.get((s, v, tg, '2', m, p, sz))
        if t2:
            print(f'| {s} | {v} | {tg} | {p} | {t:.3f} | {t2:.3f} | {t / t2:.2f}x |')

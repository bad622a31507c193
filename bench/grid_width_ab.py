#!/usr/bin/env python3
"""Width A/B of interleaved bench_grid rounds (docs/bench/grid.md, session 9): a
file of "### BINARY round N" headers, each followed by bench_grid lines with
several --targets. Per case (volume, size, view, shade, target) and binary: the
median of the rounds' cpu_ms (each already a median over --repeats), min-max over
rounds, new vs base; then per binary the width ratio avx2 / avx512 of the medians.
usage: grid_width_ab.py RESULTS.txt BASE_BINARY NEW_BINARY"""
import sys, re, statistics, collections

f, base, new = sys.argv[1:4]
cur = None
d = collections.OrderedDict()
for l in open(f):
    if l.startswith('###'):
        cur = l.split()[1]
        continue
    if not l.startswith('grid '):
        continue
    kv = dict(re.findall(r'(\w+)=(\S+)', l))
    key = (kv['volume'], kv['size'], kv['view'], kv['shade'], kv['target'])
    d.setdefault(key, {}).setdefault(cur, []).append(float(kv['cpu_ms']))

med = {}
print('| volume | view | shading | target | base CPU ms (min-max) | new CPU ms (min-max) | new vs base |')
print('|---|---|---|---|---|---|---|')
for k, v in d.items():
    if base not in v or new not in v:
        continue
    b, n = v[base], v[new]
    mb, mn = statistics.median(b), statistics.median(n)
    med[(k, 'base')], med[(k, 'new')] = mb, mn
    print('| %s | %s | %s | %s | %.1f (%.1f-%.1f) | %.1f (%.1f-%.1f) | %.3fx |' %
          (k[0], k[2], k[3], k[4], mb, min(b), max(b), mn, min(n), max(n), mb / mn))

rows = sorted({k[:4] for k in d})
if any((k + ('avx2',), 'base') in med and (k + ('avx512',), 'base') in med for k in rows):
    print()
    print('| volume | view | shading | base avx2 / avx512 | new avx2 / avx512 |')
    print('|---|---|---|---|---|')
    for k in rows:
        a2, a5 = k + ('avx2',), k + ('avx512',)
        if (a2, 'base') not in med or (a5, 'base') not in med:
            continue
        print('| %s | %s | %s | %.2fx | %.2fx |' % (k[0], k[2], k[3], med[(a2, 'base')] / med[(a5, 'base')],
                                                 med[(a2, 'new')] / med[(a5, 'new')]))

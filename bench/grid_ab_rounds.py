#!/usr/bin/env python3
"""A/B of interleaved bench_grid rounds: a file of "### BINARY round N" headers,
each followed by bench_grid lines (one or more --targets). Per case (volume,
size, view, shade and mode unless dvr, target) and binary: the median of the rounds' cpu_ms (each
already a median over --repeats) with the min-max over rounds, and new vs base;
when the runs hold both avx2 and avx512, then per binary the width ratio
avx2 / avx512 of the medians. usage: grid_ab_rounds.py RESULTS.txt BASE_BINARY NEW_BINARY"""
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
    key = (kv['volume'], kv['size'], kv['view'], kv['shade'] + ('' if kv.get('mode', 'dvr') == 'dvr' else ' ' + kv['mode']),
           kv.get('target', '-'))
    d.setdefault(key, {}).setdefault(cur, []).append((float(kv['cpu_ms']), kv['msamples'], kv.get('nodes', '')))

med = {}
print('| volume | size | view | shading | target | base CPU ms (min-max) | new CPU ms (min-max) | new vs base '
      '| M samples base/new | nodes base/new |')
print('|---|---|---|---|---|---|---|---|---|---|')
for k, v in d.items():
    if base not in v or new not in v:
        continue
    b = [x[0] for x in v[base]]
    n = [x[0] for x in v[new]]
    mb, mn = statistics.median(b), statistics.median(n)
    med[(k, 'base')], med[(k, 'new')] = mb, mn
    print('| %s | %s | %s | %s | %s | %.1f (%.1f-%.1f) | %.1f (%.1f-%.1f) | %.3fx | %s/%s | %s/%s |' %
          (k[0], k[1], k[2], k[3], k[4], mb, min(b), max(b), mn, min(n), max(n), mb / mn, v[base][0][1],
           v[new][0][1], v[base][0][2], v[new][0][2]))

rows = sorted({k[:4] for k in d})
width = [k for k in rows if (k + ('avx2',), 'base') in med and (k + ('avx512',), 'base') in med]
if width:
    print()
    print('| volume | size | view | shading | base avx2 / avx512 | new avx2 / avx512 |')
    print('|---|---|---|---|---|---|')
    for k in width:
        a2, a5 = k + ('avx2',), k + ('avx512',)
        print('| %s | %s | %s | %s | %.2fx | %.2fx |' % (k[0], k[1], k[2], k[3], med[(a2, 'base')] / med[(a5, 'base')],
                                                      med[(a2, 'new')] / med[(a5, 'new')]))

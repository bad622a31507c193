#!/usr/bin/env python3
"""A/B of interleaved bench_grid rounds: a file of "### BINARY round N" headers,
each followed by bench_grid lines. Per case and binary: the median of the rounds'
cpu_ms (each already a median over --repeats) with the min-max over rounds, and
new vs base. usage: grid_ab_rounds.py RESULTS.txt BASE_BINARY NEW_BINARY"""
import sys, re, statistics, collections
f, base, new = sys.argv[1:4]
cur = None
d = collections.OrderedDict()
for l in open(f):
    if l.startswith('###'):
        cur = l.split()[1]
        continue
    if not l.startswith('grid '): continue
    kv = dict(re.findall(r'(\w+)=(\S+)', l))
    key = (kv['volume'], kv['size'], kv['view'], kv['shade'])
    d.setdefault(key, {}).setdefault(cur, []).append((float(kv['cpu_ms']), kv['msamples'], kv.get('nodes', '')))
print('| volume | size | view | shading | base CPU ms (min-max) | new CPU ms (min-max) | new vs base | M samples base/new | nodes base/new |')
print('|---|---|---|---|---|---|---|---|---|')
for k, v in d.items():
    if base not in v or new not in v: continue
    b = [x[0] for x in v[base]]; n = [x[0] for x in v[new]]
    mb, mn = statistics.median(b), statistics.median(n)
    print('| %s | %s | %s | %s | %.0f (%.0f-%.0f) | %.0f (%.0f-%.0f) | %.3fx | %s/%s | %s/%s |' % (k[0], k[1], k[2], k[3], mb, min(b), max(b), mn, min(n), max(n), mb / mn, v[base][0][1], v[new][0][1], v[base][0][2], v[new][0][2]))

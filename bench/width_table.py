#!/usr/bin/env python3
"""Width vs ISA tables from bench/run_width.sh output: per case the median over
rounds of each target's per-round median time, and speed ratios both as the
ratio of those medians and as the median of the per-round (paired) ratios.

usage: width_table.py bench/results/width_particles.txt bench/results/width_grid.txt"""
import statistics
import sys
from collections import defaultdict

TARGETS = ['avx2', 'avx512_8', 'avx512']
# (label, faster-or-slower target, reference): speed of a over b = time b / time a
RATIOS = [('ISA at 8 lanes: avx512_8 vs avx2', 'avx512_8', 'avx2'),
          ('width at AVX-512: avx512 vs avx512_8', 'avx512', 'avx512_8'),
          ('both: avx512 vs avx2', 'avx512', 'avx2')]

times = defaultdict(lambda: defaultdict(dict))  # case -> target -> round -> seconds
for path in sys.argv[1:]:
    for line in open(path):
        kind = line.split(' ', 1)[0]
        if kind not in ('particles', 'grid'):
            continue
        kv = dict(tok.split('=', 1) for tok in line.split()[1:])
        if kind == 'particles':
            case = ('particles', kv['set'], kv['view'], kv['method'])
            t = float(kv['median_s'])
        else:
            case = ('grid', kv['volume'], kv['view'], kv['method'])
            t = float(kv['ms']) / 1000.0
        times[case][kv['target']][int(kv['round'])] = t

print('| data | set | view | method | ' + ' | '.join(f'{t} s (min–max)' for t in TARGETS) +
      ' | ' + ' | '.join(f'{a}/{b} speed' for _, a, b in RATIOS) + ' |')
print('|---|---|---|---|' + '---:|' * (len(TARGETS) + len(RATIOS)))
for case in sorted(times):
    by = times[case]
    med = {t: statistics.median(by[t].values()) for t in TARGETS if by.get(t)}
    cells = [f'{med[t]:.3f} ({min(by[t].values()):.3f}–{max(by[t].values()):.3f})' if t in med else '—'
             for t in TARGETS]
    rats = []
    for _, a, b in RATIOS:
        if a not in med or b not in med:
            rats.append('—')
            continue
        rounds = sorted(set(by[a]) & set(by[b]))
        paired = statistics.median(by[b][r] / by[a][r] for r in rounds)
        rats.append(f'{med[b] / med[a]:.2f}x ({paired:.2f}x)')
    n = min(len(by[t]) for t in TARGETS if t in by)
    print(f'| {case[0]} | {case[1]} | {case[2]} | {case[3]} | ' + ' | '.join(cells) + ' | ' + ' | '.join(rats) + ' |')
print(f'\nrounds per case: {n}; ratio cells: ratio of medians (median of per-round ratios)')

# Under a shared machine's load the fastest round is the least disturbed one:
# the same ratios from each target's minimum over rounds, as a cross-check.
print('\n| data | set | view | method | ' + ' | '.join(f'{t} min s' for t in TARGETS) + ' | ' +
      ' | '.join(f'{a}/{b} (min)' for _, a, b in RATIOS) + ' |')
print('|---|---|---|---|' + '---:|' * (len(TARGETS) + len(RATIOS)))
for case in sorted(times):
    by = times[case]
    mn = {t: min(by[t].values()) for t in TARGETS if by.get(t)}
    cells = [f'{mn[t]:.3f}' if t in mn else '—' for t in TARGETS]
    rats = [f'{mn[b] / mn[a]:.2f}x' if a in mn and b in mn else '—' for _, a, b in RATIOS]
    print(f'| {case[0]} | {case[1]} | {case[2]} | {case[3]} | ' + ' | '.join(cells) + ' | ' + ' | '.join(rats) + ' |')

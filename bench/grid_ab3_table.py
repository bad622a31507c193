#!/usr/bin/env python3
"""A/B/C table of bench_grid lines tagged build=bench_base (2c56912), build=gf_main_start
(main before this round) and one other build (this round): CPU ms medians with spread,
ratios new vs each. usage: grid_ab3_table.py RESULTS.txt"""
import sys,re,collections
rows=collections.OrderedDict()
for l in open(sys.argv[1]):
    if not l.startswith('build='): continue
    kv=dict(re.findall(r'(\w+)=(\S+)',l))
    key=(kv['volume'],kv['view'],kv['shade'],kv['target'],kv['threads'])
    rows.setdefault(key,{})[kv['build']]=kv
print('| volume | view | shading | target | threads | M samples base/start/new | base CPU ms (min-max) | start CPU ms (min-max) | new CPU ms (min-max) | new x base | new x start | new M samples/s (CPU x threads) |')
print('|---|---|---|---|---|---|---|---|---|---|---|---|')
names=['bench_base','gf_main_start']
names+=[b for b in dict.fromkeys(b for d in rows.values() for b in d) if b not in names][:1]
for k,d in rows.items():
    if not all(n in d for n in names):
        if all(n in d for n in names[1:]):  # width rows: start and new only
            c=[float(d[n]['cpu_ms']) for n in names[1:]]
            print('| %s | %s | %s | %s | %s | -/%s/%s | - | %s | %s | - | %.2f | %.0f |'%(k[0],k[1],k[2],k[3],k[4],d[names[1]]['msamples'],d[names[2]]['msamples'],d[names[1]]['cpu_ms'],d[names[2]]['cpu_ms'],c[0]/c[1],float(d[names[2]]['msamples'])/(c[1]/1e3)*int(k[4])))
        continue
    c=[float(d[n]['cpu_ms']) for n in names]
    cs=['%.0f (%.0f-%.0f)'%(float(d[n]['cpu_ms']),float(d[n]['cpu_ms_min']),float(d[n]['cpu_ms_max'])) for n in names]
    ms='/'.join(d[n]['msamples'] for n in names)
    nn=d[names[2]]; sps=float(nn['msamples'])/(c[2]/1e3)*int(k[4])
    print('| %s | %s | %s | %s | %s | %s | %s | %s | %s | %.2f | %.2f | %.0f |'%(k[0],k[1],k[2],k[3],k[4],ms,cs[0],cs[1],cs[2],c[0]/c[2],c[1]/c[2],sps))

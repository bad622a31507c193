import re, sys, statistics
def load(path, key_fields, val):
    d = {}
    for line in open(path):
        if line.split()[2].startswith('#'): continue
        f = dict(kv.split('=',1) for kv in line.split() if '=' in kv)
        who = line.split()[0]
        if val not in f: continue
        k = tuple(f.get(x,'') for x in key_fields)
        d.setdefault(k, {}).setdefault(who, []).append(float(f[val]))
    return d
def report(title, d, keys):
    print(f"### {title}\n")
    print("| " + " | ".join(keys) + " | before | after | after/before |")
    print("|" + "---|" * (len(keys) + 3))
    rs = []
    for k, v in sorted(d.items()):
        if 'base' not in v or 'main' not in v: continue
        b, m = statistics.median(v['base']), statistics.median(v['main'])
        rs.append(m / b)
        print("| " + " | ".join(k) + f" | {b:.4g} | {m:.4g} | {m/b:.3f} |")
    print(f"\n{len(rs)} cases: after/before median {statistics.median(rs):.3f}, range {min(rs):.3f} to {max(rs):.3f}\n")
name = sys.argv[1] if len(sys.argv) > 1 else 'seams'  # bench/seams_compare.sh's NAME
kp = ['set', 'view', 'target', 'method']
report("Particles, 512x512, 2 threads (median seconds per frame)", load(f'bench/results/{name}_particles.txt', kp, 'median_s'), kp)
kg = ['volume', 'view', 'shade', 'method', 'target']
report("Grids, 512x512, 2 threads (median ms per frame)", load(f'bench/results/{name}_grid.txt', kg, 'ms'), kg)

#!/usr/bin/env python3
"""Stage profile of the coherent particle kernel (docs/bench/particles.md):
shares of perf samples by stage, from the inline chain of each sampled address
(addr2line -i) in a release build with debug info (meson setup BUILD
--buildtype=release -Ddebug=true: the same code, with line tables).

  perf record -o p.data BUILD/tools/lanecast bench --scenes cluster:1e6 --targets avx512 \\
      --threads 2 --methods coherent --views far --repeats 2 --no-check
  perf script -i p.data -F ip,sym,symoff | awk '{print $2}' | grep + | sort | uniq -c > p.sym
  nm BUILD/tools/lanecast | grep -E ' (traverse_pass|collect_group|deposit_list|coherent_dvr.isra.0)$'
  python3 bench/particle_stages.py BUILD/tools/lanecast p.sym traverse_pass=ADDR ...

--deposit-loop-from LINE (first): for sources before deposit_samples existed
(main at 4046397: the `for (int k0 = kal` line of deposit), deposit's lines
from LINE on count as the deposit loop. NAME=ADDR picks the copy of each function of the target profiled (one per
compiled target; `objdump -d` shows which uses zmm). Stages: traversal (node
tests, leaf lists), chord setup (per particle and ray vector), anchor (the
direct exp every 8 samples), deposit loop (recurrence and buffer adds),
integration, list scan (per pass over the group list)."""
import collections
import subprocess
import sys


LOOP_FROM = None  # --deposit-loop-from LINE: before the split into deposit_samples, deposit's lines from LINE on


def stage(fn, f, ln):
    if fn == "deposit" and LOOP_FROM is not None and ln >= LOOP_FROM:
        return "deposit loop"
    if fn == "pgauss_anchor":
        return "anchor"
    if fn in ("pgauss_step", "deposit_samples"):
        return "deposit loop"
    if fn in ("vcone_bits", "vcone_make"):
        return "cone pre-test"
    if fn in ("perp2", "deposit", "deposit_entry", "support_reach", "particle_cstep"):
        return "chord setup"
    if fn in ("grow", "walk_group", "traverse_pass", "collect_group", "node_clear", "dvr_slab", "slab_eye",
              "gcull_make", "gcull_axis", "gcull_misses", "vcull_make", "vcull_node", "fmin2", "fmax2"):
        return "traversal"
    if fn in ("deposit_list", "deposit_list_as"):
        return "list scan"
    if fn in ("integrate_buffer", "integrate_two", "integrate_pass", "ivec_load", "ivec_sample", "ivec_store"):
        return "integration"
    return None


def main():
    global LOOP_FROM
    args = sys.argv[1:]
    if args[0] == "--deposit-loop-from":
        LOOP_FROM, args = int(args[1]), args[2:]
    binary, symfile = args[0], args[1]
    base = dict((a.split("=")[0], int(a.split("=")[1], 16)) for a in args[2:])
    counts = collections.Counter()
    for line in open(symfile):
        c, so = line.split()
        n, off = so.rsplit("+", 1)
        if n in base:
            counts[base[n] + int(off, 16)] += int(c)
    addrs = sorted(counts)
    out = subprocess.run(["addr2line", "-a", "-i", "-f", "-e", binary] + [hex(a) for a in addrs],
                         capture_output=True, text=True).stdout.split("\n")
    frames, cur, i = {}, None, 0
    while i < len(out):
        if out[i].startswith("0x"):
            cur = int(out[i], 16)
            frames[cur] = []
            i += 1
        elif not out[i]:
            i += 1
        else:
            frames[cur].append((out[i], out[i + 1].split("/")[-1].split(" ")[0]))  # (function, file:line)
            i += 2
    st = collections.Counter()
    for a in addrs:
        k = None
        for fn, loc in frames[a]:  # innermost first: the first frame of the kernel files decides
            if loc.startswith("particles_co") or loc.startswith("particles_walk"):
                ln = loc.split(":")[1] if ":" in loc else "0"
                k = stage(fn, loc, int(ln) if ln.isdigit() else 0)
                if k:
                    break
        st[k or "other"] += counts[a]
    tot = sum(counts.values())
    for k, v in sorted(st.items(), key=lambda x: -x[1]):
        print(f"{v:7d} {100 * v / tot:5.1f}% {k}")
    print(f"{tot:7d} samples in the functions named")


if __name__ == "__main__":
    main()

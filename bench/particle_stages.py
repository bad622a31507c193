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
integration, list scan (per pass over the group list).

--script BINARY p.script: every sample of the render, whatever the function
and target, from `perf script -F ip,sym,symoff,dso -i p.data > p.script`
(the load offset of a PIE binary is taken from the samples themselves, so
no NAME=ADDR is needed); only samples whose inline chain reaches kernels/
count (scene generation, BVH build and the host are left out; run the
bench with --no-check and one target). It also names the direct method's
stages: traversal (node tests, node skip), range test (a particle's
distance to the samples, sample_d2), evaluation (the Gaussian and its exp),
accumulation (the loop over a leaf's particles: loads, adds), integration
(classification and blending, mode.h, for both methods), ray set-up and
finish (setup_vector, finish_vector, camera and box clip), sample loop
(direct_tile's own lines); libm (floorf), the scalar target's rounding in the
exp, which is a call without SSE4.1; the coherent method's buffer clear (clear_buffer)
and pass control (coherent_tile, set_windows, pass lengths). Prints CPU shares; with --frame-s S also each
stage's seconds of a frame of S CPU seconds."""
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
    if fn in ("integrate_buffer", "integrate_two", "integrate_pass", "ivec_load", "ivec_sample", "ivec_store",
              "ivec_mask", "ivec_die"):
        return "integration"
    # the direct method (particles.c, particles_common.h) and the modes (mode.h), for both methods
    if fn == "sample_d2":
        return "range test"
    if fn == "gaussian":
        return "evaluation"
    if fn == "gather_fields_as":
        return "traversal" if ln < GATHER_LEAF_LINE else "accumulation"
    if fn.startswith("mode_sample") or fn in ("mip_sample", "iso_sample", "iso_refine", "mode_point"):
        return "integration"
    if fn in ("setup_vector", "setup_group", "finish_vector", "finish_group", "trace_spheres") or \
            fn.startswith("mode_finish") or fn.startswith("mode_store"):
        return "ray set-up and finish"
    if fn == "direct_tile":
        return "sample loop"
    if fn == "clear_buffer":
        return "buffer clear"
    if fn in ("coherent_tile", "set_windows", "pass_end", "pass_first", "pass_adapt"):
        return "pass control"
    return None


GATHER_LEAF_LINE = 1 << 30  # first line of gather_fields_as's loop over a leaf's particles (set in main)


def gather_leaf_line():
    """The line of `for (int32_t i = node->first` in gather_fields_as (particles_common.h)."""
    import os
    src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "kernels", "particles_common.h")
    inside = False
    for i, line in enumerate(open(src), 1):
        if "gather_fields_as(" in line and "static" in line:
            inside = True
        if inside and "for (int32_t i = node->first" in line:
            return i
    return 1 << 30


def script_counts(binary, path):
    """Counts per file address of the binary's samples in `perf script -F ip,sym,symoff,dso` output."""
    nm = subprocess.run(["nm", binary], capture_output=True, text=True).stdout.split("\n")
    addr = collections.defaultdict(list)
    for line in nm:
        f = line.split()
        if len(f) == 3 and f[1] in "tTwW":
            addr[f[2]].append(int(f[0], 16))
    name = binary.split("/")[-1]
    raw, bias = collections.Counter(), None
    for line in open(path):
        f = line.split()
        if len(f) >= 2 and "libm" in f[-1]:
            # the scalar target's floorf (the exp's rounding without SSE4.1) is a libm call; libm's
            # other functions (expf, fmaxf, ...) are the host's and the scene generator's
            if "floor" in f[1]:
                raw[-1] += 1
            continue
        if len(f) < 3 or name not in f[-1] or "+0x" not in f[1]:
            continue
        ip = int(f[0], 16)
        sym, off = f[1].rsplit("+", 1)
        if bias is None and len(addr.get(sym, [])) == 1:
            bias = ip - int(off, 16) - addr[sym][0]
        raw[ip] += 1
    if bias is None:
        sys.exit("particle_stages.py: no sample in a uniquely named function of " + binary)
    return collections.Counter({(ip - bias if ip >= 0 else ip): c for ip, c in raw.items()})


def chains(binary, addrs):
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
            frames[cur].append((out[i], out[i + 1].split(" ")[0]))  # (function, path:line)
            i += 2
    return frames


def main_script(args):
    global GATHER_LEAF_LINE
    frame_s = None
    if "--frame-s" in args:
        j = args.index("--frame-s")
        frame_s, args = float(args[j + 1]), args[:j] + args[j + 2:]
    binary, path = args[0], args[1]
    GATHER_LEAF_LINE = gather_leaf_line()
    counts = script_counts(binary, path)
    addrs = sorted(counts)
    frames, known = {}, [a for a in addrs if a >= 0]
    for i in range(0, len(known), 4000):
        frames.update(chains(binary, known[i:i + 4000]))
    st, tot = collections.Counter(), 0
    for a in addrs:
        if a < 0:
            tot += counts[a]
            st["libm (floorf)"] += counts[a]
            continue
        fr = frames.get(a, [])
        if not any("/kernels/" in loc for _, loc in fr):
            continue  # not the render: scene, build, host
        tot += counts[a]
        k = None
        for fn, loc in fr:  # innermost first: the first frame with a stage decides
            base = loc.split("/")[-1]
            if base.startswith("particles") or base.startswith("mode.h"):
                ln = base.split(":")[1] if ":" in base else "0"
                k = stage(fn, base, int(ln) if ln.isdigit() else 0)
                if k:
                    break
        st[k or "other kernel code"] += counts[a]
    for k, v in sorted(st.items(), key=lambda x: -x[1]):
        extra = f"  {frame_s * v / tot:.4f} s" if frame_s else ""
        print(f"{v:7d} {100 * v / tot:5.1f}% {k}{extra}")
    print(f"{tot:7d} samples in the kernels")


def main():
    global LOOP_FROM
    args = sys.argv[1:]
    if args[0] == "--script":
        return main_script(args[1:])
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
    # (function, file:line), innermost first
    frames = {a: [(fn, loc.split("/")[-1]) for fn, loc in fs] for a, fs in chains(binary, addrs).items()}
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

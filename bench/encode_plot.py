#!/usr/bin/python3
"""RMS error against RBF count (bench/results/encode_rms.txt, written by
bench/encode_bench.sh) as docs/bench/encode_rms.png. Needs Debian's
python3-matplotlib: /usr/bin/python3 bench/encode_plot.py [IN] [OUT]."""
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

src = sys.argv[1] if len(sys.argv) > 1 else "bench/results/encode_rms.txt"
dst = sys.argv[2] if len(sys.argv) > 2 else "docs/bench/encode_rms.png"
curves = {}
for line in open(src):
    f = line.split()
    if len(f) == 4 and f[1] != "final":
        curves.setdefault(f[0], []).append((int(f[1]), float(f[2])))
fig, ax = plt.subplots(figsize=(6, 4))
for name, pts in curves.items():
    ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
ax.axhline(2.0, color="gray", ls="--", lw=0.8, label="2% target")
ax.set_xlabel("RBFs")
ax.set_ylabel("RMS error, % of the value range")
ax.set_title("lanecast encode --centre maxerr (with polish sweeps)")
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(dst, dpi=100)
print("wrote", dst)

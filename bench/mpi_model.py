"""The compositing model of docs/BENCHMARKS.md "Compositing" from
bench/mpi_composite.sh's JSON lines (the last run in the file):
T(P) = sum over steps (alpha + beta * bytes + gamma * pixels), with
alpha the median time of a 1x1 image's swap step at P = 2 (messages of a
header), gamma the time per blended pixel from lci_cblend's throughput
(mpi_blend), beta fitted (least squares through the origin) to the P = 2
swap steps' time less alpha and gamma * pixels, against bytes. Prints the
constants, the model against the measured steps at P = 2, the bytes per
rank against binary swap's S (1 - 1/P), and the model's figure for IceT's
published case (radix-k: 64 Mpixel in 0.08 s on 32K processes).
usage: python3 bench/mpi_model.py [bench/results/mpi_composite.jsonl]"""
import json
import math
import sys

path = sys.argv[1] if len(sys.argv) > 1 else "bench/results/mpi_composite.jsonl"
rows = []
for line in open(path):
    r = json.loads(line)
    if r.get("bench") == "mpi_composite_run":
        rows = [r]  # the last run only
    else:
        rows.append(r)
run = rows[0]
blend = [r for r in rows if r.get("bench") == "mpi_blend"]
comp = [r for r in rows if r.get("bench") == "mpi_composite"]
gamma = sum(r["seconds"] / (r["w"] * r["h"]) for r in blend) / len(blend)
p2 = sorted((r for r in comp if r["ranks"] == 2), key=lambda r: r["w"])
alpha = p2[0]["steps_rank0"][0]["s"] if p2 and p2[0]["w"] == 1 else 0.0
num = den = 0.0
for r in p2:
    st = r["steps_rank0"][0]  # the swap step (send half, receive and blend half)
    y = st["s"] - alpha - gamma * st["pixels"]
    num += y * st["bytes"]
    den += st["bytes"] ** 2
beta = num / den if den else 0.0
print("run %s at %s, load %s" % (run.get("commit"), run.get("date"), run.get("load")))
print("alpha %.2f us, beta %.3f ns/byte (%.2f GB/s), gamma %.2f ns/pixel (%.0f Mpixel/s)" %
      (alpha * 1e6, beta * 1e9, 1e-9 / beta if beta > 0 else float("inf"), gamma * 1e9, 1e-6 / gamma))
print("P=2 steps of rank 0 (the fastest run): size, measured swap step s, model s; whole composite median (min) s")
for r in p2:
    st = r["steps_rank0"][0]
    model = alpha + beta * st["bytes"] + gamma * st["pixels"]
    print("  %5d^2  %.6f  %.6f   %.6f (%.6f)" % (r["w"], st["s"], model, r["median_s"], r["min_s"]))
print("bytes per rank / S (1 - 1/P) (swap and fold; non-root ranks add S/P for the gather):")
for r in comp:
    if r["w"] < 64:
        continue
    b = r["swap_bound_bytes"]
    print("  P=%d %4d^2: %s" % (r["ranks"], r["w"], " ".join("%.3f" % (x / b) if b else "-" for x in r["bytes_per_rank"])))
# IceT's case: 64 Mpixel, P = 32768, binary swap over 15 rounds of halving pieces
S_px, P = 64 * 2 ** 20, 32768
rounds = int(math.log2(P))
t = sum(alpha + beta * 16 * S_px / 2 ** (k + 1) + gamma * S_px / 2 ** (k + 1) for k in range(rounds))
print("model for 64 Mpixel at P = 32768 (15 rounds, float RGBA, this machine's alpha, beta, gamma): %.3f s "
      "(IceT radix-k: 0.08 s)" % t)

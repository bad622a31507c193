#!/bin/sh
# Compositing measurements of docs/BENCHMARKS.md "Compositing" (lanecast bench's
# --blend and --composite modes, tools/bench_mpi.c): blend and
# pack throughput in one process, then lci_mpi_composite on P = 1..4 ranks
# for images of 1^2 .. 2048^2, one JSON line each, appended to
# bench/results/mpi_composite.jsonl with the machine's load average.
# On this 2-core machine P > 2 shares cores: those rows measure
# correctness of the counts, not speed. usage: bench/mpi_composite.sh [BUILD]
set -eu
b=${1:-build}
exe=$b/tools/lanecast
out=bench/results/mpi_composite.jsonl
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
echo "{\"bench\": \"mpi_composite_run\", \"date\": \"$(date -u +%FT%TZ)\", \"commit\": \"$(git rev-parse --short HEAD)\", \"load\": \"$(cut -d' ' -f1-3 /proc/loadavg)\"}" >> "$out"
"$exe" bench --blend --repeats 15 | tee -a "$out"
for p in 1 2 3 4; do
    mpiexec --oversubscribe --bind-to none -np "$p" "$exe" bench --composite --repeats 15 | tee -a "$out"
done

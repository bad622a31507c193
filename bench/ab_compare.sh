#!/bin/sh
# Before/after frame cost on a shared, busy machine. Wall-clock frame times
# swing by 2x here when other jobs run; the CPU time a process is charged
# (perf stat's task-clock) does not count the time it waits for a core. Each
# case runs BEFORE and AFTER back to back (the order alternating per round),
# ROUNDS times, one thread, 1 warm-up + REPEATS frames per run; a line per
# run records the task-clock of the whole run (load and BVH build included,
# the same work in both builds) and the bench's own line.
# bench/ab_table.py NAME turns them into per-frame CPU costs and ratios.
# Usage: bench/ab_compare.sh BEFORE AFTER NAME [ROUNDS] [REPEATS]
#   (BEFORE/build/bench/bench_*; default 5 rounds of 10 frames)
# Appends to bench/results/NAME_ab.txt. Needs perf (linux-perf).
set -eu
BEFORE=$1 AFTER=$2 NAME=$3 ROUNDS=${4:-5} REPEATS=${5:-10}
D=${DATA:-../shared/data}
OUT=bench/results/${NAME}_ab.txt
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
run() { # round, build (base|main), bench, args...
    r=$1 b=$2 exe=$3
    shift 3
    dir=$BEFORE; [ "$b" = main ] && dir=$AFTER
    line=$(perf stat -x, -e task-clock -o "$tmp" "$dir/build/bench/$exe" "$@" --threads 1 --repeats "$REPEATS" \
           --data "$D" | grep -v '^#')
    ms=$(grep task-clock "$tmp" | cut -d, -f1)
    echo "$b round=$r task_ms=$ms frames=$((REPEATS + 1)) $line" >> "$OUT"
}
i=0
while [ "$i" -lt "$ROUNDS" ]; do
    i=$((i + 1))
    first=base second=main
    [ $((i % 2)) -eq 0 ] && first=main second=base
    for t in avx2 avx512; do
        for c in "1e5 coherent" "1e5 direct" "1tw7 coherent"; do
            set -- $c
            for b in $first $second; do
                run $i $b bench_particles --sets "$1" --views far --methods "$2" --targets $t --size 512x512
            done
        done
        for v in engine embryo; do
            for s in none phong; do
                for m in bvh brute; do
                    for b in $first $second; do
                        run $i $b bench_grid --volumes $v --views medium --shades $s --methods $m --targets $t \
                            --sizes 512
                    done
                done
            done
        done
    done
done

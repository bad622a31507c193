#!/bin/sh
# Width vs ISA (docs/BENCHMARKS.md, "Width vs ISA (avx512_8)"): avx2, avx512_8
# and avx512 on one thread, in ROUNDS rounds that cycle through all six orders
# of the three targets, so slow drift of a shared machine's load falls on every
# target alike. Raw lines go to bench/results/width_{particles,grid}.txt with a
# "round=" token added; bench/width_table.py makes the tables. Run from the
# source root after ./scripts/build.sh.
set -eu
P=./build/bench/bench_particles
G=./build/bench/bench_grid
D=${LANECAST_DATA:-../shared/data}
ROUNDS=${ROUNDS:-6}
mkdir -p bench/results
op=bench/results/width_particles.txt og=bench/results/width_grid.txt
: >"$op"; : >"$og"
orders="avx2,avx512_8,avx512 avx512_8,avx512,avx2 avx512,avx2,avx512_8 avx2,avx512,avx512_8 avx512,avx512_8,avx2 avx512_8,avx2,avx512"
r=0
while [ "$r" -lt "$ROUNDS" ]; do
    order=$(echo $orders | tr ' ' '\n' | sed -n "$((r % 6 + 1))p")
    echo "# round $r: $order" >&2
    # bench_particles runs its --targets in enum order: one call per target
    for t in $(echo "$order" | tr ',' ' '); do
        $P --data "$D" --sets 1e6,1tw7 --targets "$t" --threads 1 --methods coherent --views far,close --repeats 3 \
            | sed "s/^particles /particles round=$r /" >>"$op"
    done
    # bench_grid runs its --targets in the order given
    $G --data "$D" --volumes engine --methods brute,bvh --threads 1 --views far,medium,close --targets "$order" \
        --repeats 3 | sed "s/^grid /grid round=$r /" >>"$og"
    r=$((r + 1))
done

#!/bin/sh
# A/B of the particle BVH builders (docs/bench/particles.md "Build peak"):
# ROUNDS rounds; in each, every builder (order rotating) builds and renders
# every set in its own process. Raw lines on stdout; tables by
# bench/pbuild_table.py. Usage: bench/pbuild_ab.sh BENCH_PBUILD [ROUNDS] [BUILDERS] [SETS]
set -e
bin=${1:?usage: pbuild_ab.sh path/to/bench_pbuild [rounds] [builders] [sets]}
rounds=${2:-3}
builders=${3:-embree sah}
sets=${4:-uniform:1e7 dense:1e6 cluster:1e6}
nb=$(echo $builders | wc -w)
r=0
while [ $r -lt $rounds ]; do
    # rotate the builder order by one each round
    order=$(echo $builders | tr ' ' '\n' | awk -v s=$r -v n=$nb '{a[NR-1]=$0} END {for (i=0;i<n;i++) print a[(i+s)%n]}')
    for set in $sets; do
        for b in $order; do
            echo "# round=$r load=$(cut -d' ' -f1 /proc/loadavg)"
            LANECAST_PBVH_BUILDER=$b "$bin" $set --renders 5 --threads 2
        done
    done
    r=$((r + 1))
done

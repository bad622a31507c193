#!/bin/sh
# Side by side, alternating, two rounds: a build of an earlier commit (BEFORE,
# e.g. a worktree of e55f05e, the commit before the kind and mode seams, built
# in BEFORE/build) and this tree's build (AFTER).
# Usage: bench/seams_compare.sh BEFORE AFTER [NAME]
# Appends to bench/results/NAME_{particles,grid}.txt (NAME: seams);
# bench/seams_table.py [NAME] makes their tables (docs/bench/particles.md "Kind and
# mode seams"). Wall-clock times: on a busy machine use bench/ab_compare.sh.
set -eu
BEFORE=$1 AFTER=$2 NAME=${3:-seams}
D=${DATA:-../shared/data}
P="--sets 1e5,1tw7 --targets avx2,avx512 --threads 2 --methods coherent,direct --views far,close --size 512x512 --repeats 5 --data $D"
G="--data $D --volumes engine,embryo --views medium,close --shades none,phong --methods bvh,brute --sizes 512 --targets avx2,avx512 --threads 2 --repeats 5"
for round in 1 2; do
  for b in base main; do
    dir=$BEFORE; [ $b = main ] && dir=$AFTER
    "$dir/build/bench/bench_particles" $P | sed "s/^/$b round=$round /" >> bench/results/${NAME}_particles.txt
    "$dir/build/bench/bench_grid" $G | sed "s/^/$b round=$round /" >> bench/results/${NAME}_grid.txt
  done
done

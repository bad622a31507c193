#!/bin/sh
# The particle benchmark matrix behind docs/BENCHMARKS.md. Writes raw
# machine-readable lines to bench/results/particles_*.txt; run on a quiet
# machine from the source root after ./scripts/build.sh. Takes ~15 minutes.
set -eu
B=./build/bench/bench_particles
D=${LANECAST_DATA:-../shared/data}
mkdir -p bench/results
# coherent vs direct, sizes 1e4..1e6 and the real molecules, 1024x1024, widest target, 2 threads
$B --data "$D" --sets 1e4,1e5,1e6,1tii,1tw7 --targets avx512 --threads 2 --methods coherent,direct \
   --views far,close --repeats 3 | tee bench/results/particles_methods.txt
# every target on one thread, whole frame
$B --data "$D" --sets 1e6,1tw7 --threads 1 --methods coherent --views far,close --repeats 3 \
   | tee bench/results/particles_targets.txt
# threads and packet sizes
$B --data "$D" --sets 1e6,1tw7 --targets avx512,avx2 --threads 1,2 --methods coherent --packets 8,1 \
   --views far,close --repeats 3 | tee bench/results/particles_threads.txt
# 10 million particles: time and memory
$B --data "$D" --sets 1e7 --targets avx512 --threads 2 --methods coherent --views far,close --repeats 2 \
   | tee bench/results/particles_10m.txt

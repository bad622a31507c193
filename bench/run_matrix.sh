#!/bin/sh
# The matrix behind docs/BENCHMARKS.md: lanecast bench records into
# bench/results/bench_*.jsonl (appended), then bench/report.py. Sized for a
# shared 2-core machine: 256x256 images, few rounds, interleaved targets;
# thread scaling at 1024^2 on scenes of 0.1 s or more a frame. "--targets
# avx2,avx512" picks the widest of the two this CPU runs (the other is skipped
# with a note). The bench_*_avx512.jsonl files are kept from a machine with
# AVX-512 (commit 98c1067: the width study needs it; views and large sets not
# rerun since).
# usage: bench/run_matrix.sh BUILD_DIR   (from the source root)
set -u
exe=${1:-build}/tools/lanecast
out=bench/results
# a check failure makes lanecast bench exit 1 after writing every record: go on
run() { "$exe" bench "$@" || echo "run_matrix.sh: lanecast bench $* exited $? (see the records)" >&2; }
common="--sizes 256 --repeats 5 --min-repeats 3 --seconds 6 --roof-seconds 0.3"
wide="--targets avx2,avx512"
run --roofline --roof-seconds 0.5 -o $out/bench_roofline.jsonl
# every target, particle count and radius distribution (speedup per width, fps vs count)
run $common --scenes uniform:1e4,uniform:1e5,uniform:1e6,heavy:1e5,cluster:1e5,1tii,1tw7 -o $out/bench_particles.jsonl
# every target on grids and RBF sets
run $common --scenes grid:256,engine,neghip,headsq,rbf:1e4,rbfc:1e4 -o $out/bench_volumes.jsonl
# early termination and sigma sweeps on the widest target
run $common --scenes uniform:1e5,engine $wide --alpha-stop 0.9,0.95,0.97,0.99,1 -o $out/bench_alpha.jsonl
run $common --scenes uniform:1e5 $wide --sigma 1,1.5,2,2.5,3 -o $out/bench_sigma.jsonl
# thread scaling: 1024^2, frames of 0.1 s or more at 1 thread (loadavg in every record)
run --sizes 1024 --repeats 5 --min-repeats 3 --seconds 10 --roof-seconds 0.3 --no-check \
    --scenes uniform:1e6,1tw7,engine,grid:256,rbf:1e4 $wide --threads 1,2 -o $out/bench_threads.jsonl
# width study: instruction set vs width (needs AVX-512; elsewhere only avx2 runs)
run $common --width-study --scenes uniform:1e5,heavy:1e5,grid:256,engine,rbf:1e4 -o $out/bench_width.jsonl
# views, modes and methods on two scenes (scalar as the check's reference and for speedups)
run $common --scenes uniform:1e5,engine --targets scalar,avx2,avx512 --views far,medium,close --modes dvr,mip,iso \
    --methods default,direct,brute -o $out/bench_views.jsonl
# the large sets, widest target only, 2 threads (memory: rss_peak_kb)
run $common --scenes uniform:1e7,grid:512 $wide --threads 2 --repeats 3 -o $out/bench_large.jsonl
# interactive timings (issue 24): 1024^2, 2 threads, 50 cancels per case
run --jobs 50 --scenes demo,engine,1tw7,uniform:1e6,rbf:1e4 --sizes 1024 --threads 2 $wide \
    --modes dvr,iso --roof-seconds 0.01 -o $out/bench_jobs.jsonl
/usr/bin/python3 bench/report.py $out/bench_*.jsonl -o docs/bench --page docs/BENCHMARKS.md \
    --command "bench/run_matrix.sh ${1:-build}   # every lanecast bench run in this script, then report.py
bench/peers.sh ${1:-build}   # VTK and SPLASH side by side (records in bench_peers.jsonl; --install installs them)"

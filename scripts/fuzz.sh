#!/bin/sh
# Builds the libFuzzer harnesses of fuzz/ with clang, ASan and UBSan in
# ./build-fuzz, makes their seed corpora (fuzz/make_seeds.py: hand-made
# inputs plus small cuts of ../shared/data when present) and runs each
# harness for a bounded time or number of executions. Findings (crashes,
# leaks, sanitizer reports, timeouts, out-of-memory) land in
# build-fuzz/findings/<harness>/; the summary (executions, cov, ft, corpus,
# findings per harness) in build-fuzz/fuzz-summary.md (docs/FUZZING.md).
#
# usage: scripts/fuzz.sh [--seconds N] [--runs N] [--jobs J] [--only a,b,...] [--rss MB]
#   --seconds N   at most N seconds per harness (default 600)
#   --runs N      stop a harness after N executions (default 1000000; 0 = time only)
#   --jobs J      harnesses run side by side (default: online CPUs)
#   --only LIST   harness names without the fuzz_ prefix (default: all built)
#   --rss MB      libFuzzer's memory limit per harness (default 2048)
# example: scripts/fuzz.sh --seconds 60 --runs 0 --only nrrd,metaimage
# Reproduce a finding: build-fuzz/fuzz/fuzz_NAME FILE
set -eu
cd "$(dirname "$0")/.."
seconds=600 runs=1000000 jobs=$(nproc 2>/dev/null || echo 2) only="" rss=2048
while [ $# -gt 0 ]; do
    case "$1" in
    --seconds) seconds=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --only) only=$(echo "$2" | tr ',' ' '); shift 2 ;;
    --rss) rss=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -eu/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "fuzz.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
    esac
done
./scripts/install-deps.sh
# clang and its runtime libraries (libFuzzer, ASan, UBSan) from Debian
missing=""
for p in clang libclang-rt-dev; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "fuzz.sh: installing$missing" >&2
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi
b=build-fuzz
if [ ! -f $b/build.ninja ]; then
    # only the scalar kernels: the loaders are the target, and instrumented
    # SIMD kernels only cost build time
    CC=clang CXX=clang++ meson setup $b --buildtype=debugoptimized -Db_sanitize=address,undefined \
        -Db_lundef=false -Dfuzz=true -Dtargets=[] \
        -Dc_args=-fsanitize=fuzzer-no-link -Dcpp_args=-fsanitize=fuzzer-no-link >/dev/null
fi
ninja -C $b fuzzers >/dev/null
data=${LANECAST_DATA:-../shared/data}
rm -rf $b/seeds
python3 fuzz/make_seeds.py $b/seeds "$data"
# HDF5 seeds: files the test suite writes (test_vformats), when a build has them
for f in build/tests/*.hdf5 build/tests/*.h5; do
    [ -f "$f" ] || continue
    mkdir -p $b/seeds/hdf5
    for opt in "" "dataset=/fields/rho" "dataset=/fields/points radius=0.5" "value=mass"; do
        { echo "$opt"; cat "$f"; } > "$b/seeds/hdf5/$(basename "$f")_$(echo "$opt" | tr -c 'a-z0-9' _)"
    done
done
[ -d $b/seeds/hdf5 ] || { mkdir -p $b/seeds/hdf5; printf 'dataset=/a\nnot hdf5\n' > $b/seeds/hdf5/none; }
names=""
for exe in $b/fuzz/fuzz_*; do
    [ -x "$exe" ] && [ -f "$exe" ] || continue
    n=${exe##*/fuzz_}
    if [ -n "$only" ]; then case " $only " in *" $n "*) ;; *) continue ;; esac; fi
    names="$names $n"
done
# a report fails the run: UBSan stops at the first one; ASan checks leaks
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0:allocator_may_return_null=1:suppressions=$(pwd)/fuzz/asan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$(pwd)/fuzz/lsan.supp}"
mkdir -p $b/logs
run_one() {
    n=$1
    mkdir -p "$b/corpus/$n" "$b/findings/$n"
    # libhdf5 allocates the sizes a damaged file declares (a 12 GB local heap
    # for a 9 KB file) and fails cleanly when the read runs past the end; the
    # allocation is never touched, so for hdf5 only the resident size counts
    mlimit=$rss
    [ "$n" = hdf5 ] && mlimit=1048576
    set -- -max_total_time="$seconds" -rss_limit_mb="$rss" -malloc_limit_mb="$mlimit" -timeout=20 \
        -print_final_stats=1 -artifact_prefix="$b/findings/$n/"
    [ "$runs" -gt 0 ] && set -- "$@" -runs="$runs"
    [ -f "fuzz/$n.dict" ] && set -- "$@" -dict="fuzz/$n.dict"
    "$b/fuzz/fuzz_$n" "$@" "$b/corpus/$n" "$b/seeds/$n" </dev/null >"$b/logs/$n.log" 2>&1 || true
}
limit="at most ${seconds}s"
[ "$runs" -gt 0 ] && limit="$limit and $runs executions"
echo "fuzz.sh: running$names ($jobs at a time, $limit each)" >&2
# $jobs lanes, each running every jobs-th harness in turn
lane=0
while [ $lane -lt "$jobs" ]; do
    (
        k=0
        for n in $names; do
            [ $((k % jobs)) -eq $lane ] && run_one "$n"
            k=$((k + 1))
        done
    ) &
    lane=$((lane + 1))
done
wait
# the summary: one row per harness
{
    echo "| harness | executions | exec/s | cov | ft | corpus | findings |"
    echo "|---|---|---|---|---|---|---|"
    for n in $names; do
        log=$b/logs/$n.log
        execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
        rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
        last=$(grep -E '^#[0-9]+' "$log" | grep -E 'cov: ' | tail -1)
        cov=$(echo "$last" | sed -n 's/.*cov: \([0-9]*\).*/\1/p')
        ft=$(echo "$last" | sed -n 's/.*ft: \([0-9]*\).*/\1/p')
        corp=$(echo "$last" | sed -n 's/.*corp: \([0-9]*\).*/\1/p')
        finds=$(ls "$b/findings/$n" 2>/dev/null | tr '\n' ' ')
        echo "| $n | ${execs:-?} | ${rate:-?} | ${cov:-?} | ${ft:-?} | ${corp:-?} | ${finds:-none} |"
    done
} > $b/fuzz-summary.md
cat $b/fuzz-summary.md
if ls $b/findings/*/* >/dev/null 2>&1; then
    echo "fuzz.sh: findings above (reproduce: $b/fuzz/fuzz_NAME FILE; logs in $b/logs)" >&2
    exit 1
fi

#!/bin/sh
# A rank that runs out of memory inside a data-parallel load (host/mpi/:
# the kd-tree build with its distributed selection, the particle exchange,
# the part's creation, the scatter of a grid read by rank 0; and past it,
# the default TF from the ranks' summed histogram) makes every
# rank exit non-zero with that rank's message, within a timeout: no rank
# waits in a collective the failing one skipped. The failure is injected on
# one rank by LANECAST_TEST_FAULT=POINT (MPMD: `env` sets it for that rank
# alone). usage: test_cli_mpi_faults.sh LANECAST MPIEXEC
set -eu
exe=$1
mpiexec=$2
. "$(dirname "$0")/cli_mpi_run.sh" # $dir, fail
python3 "$(dirname "$0")/cli_scenes.py" "$dir" # ball.raw, ballz.nhdr, set.rbf
python3 - "$dir" <<'PY'
import struct, sys
seed = [11]
def rnd():
    seed[0] = (seed[0] * 1103515245 + 12345) % 2147483648
    return seed[0] / 2147483648.0
with open(sys.argv[1] + "/pts.f32", "wb") as f:
    for i in range(2000):
        f.write(struct.pack("<3f", *[2.0 * rnd() - 1.0 for _ in range(3)]))
PY
# fault K BAD POINT NAME ARGS...: K ranks render ARGS, rank BAD with POINT
# failing; mpiexec must exit non-zero (not 124, the timeout), each of the K
# ranks must print the failing rank's message (the others name it "rank BAD:";
# its own may stand alone), and no image.
fault() {
    k=$1 bad=$2 point=$3 name=$4
    shift 4
    args="render $* --size 40x30 --threads 1 -o $dir/$name.png" # every app context takes its own arguments
    cmd=""
    r=0
    while [ $r -lt "$k" ]; do
        [ $r -gt 0 ] && cmd="$cmd :"
        if [ $r -eq "$bad" ]; then cmd="$cmd -np 1 env LANECAST_TEST_FAULT=$point $exe $args"
        else cmd="$cmd -np 1 $exe $args"; fi
        r=$((r + 1))
    done
    set +e
    # shellcheck disable=SC2086 # cmd is words by design ($dir has no spaces: mktemp)
    timeout 60 "$mpiexec" --oversubscribe $cmd > "$dir/out" 2> "$dir/err"
    rc=$?
    set -e
    n=$(grep -c "^lanecast render: .*out of memory" "$dir/err" || true)
    named=$(grep -c "^lanecast render: rank $bad: .*out of memory" "$dir/err" || true)
    if [ $rc -ne 0 ] && [ $rc -ne 124 ] && [ "$n" -eq "$k" ] && [ "$named" -ge $((k - 1)) ] && [ ! -e "$dir/$name.png" ]; then
        echo "ok   $name: exit $rc: $(grep -m1 "rank $bad:" "$dir/err")"
    else
        echo "FAIL $name: exit $rc (124: timed out), $n of $k ranks name rank $bad: $(cat "$dir/err")"
        fail=1
    fi
}
raw="$dir/pts.f32 --raw-particles 2000 --radius 0.05"
fault 3 1 kd particles-kd-rank1 $raw
fault 3 0 kd particles-kd-rank0 $raw --mode mip
fault 2 1 exchange particles-exchange $raw
fault 4 3 part particles-part $raw
fault 3 2 kd rbf-kd "$dir/set.rbf"
fault 3 1 exchange rbf-exchange "$dir/set.rbf"
if "$exe" formats 2>/dev/null | grep -q "^ *zlib  *yes"; then
    fault 3 0 scatter grid-scatter-cut "$dir/ballz.nhdr"
    fault 3 2 scatter grid-scatter-receive "$dir/ballz.nhdr"
fi
fault 3 1 kd grid-kd "$dir/ball.nhdr"
# past the load: the default TF (the ranks' summed histogram, then the TF on each rank)
fault 3 1 tf grid-tf "$dir/ball.nhdr"
exit $fail

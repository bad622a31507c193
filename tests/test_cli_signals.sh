#!/bin/sh
# Crash safety (issue 13): SIGINT or SIGTERM during `lanecast render` leaves
# no partial output and no temporary file, keeps an existing image of that
# name unchanged, and ends the process by that signal (exit 128 + signal).
# Each signal is sent twice: while rays are cast (before any file exists)
# and while the image is encoded and written (a temporary file exists: the
# handler removes it). usage: test_cli_signals.sh LANECAST BUILD_DIR
set -u
exe=$1
dir=$(mktemp -d "${2:-/tmp}/signals.XXXXXX")
trap 'rm -rf "$dir"' EXIT
fail=0
# SIGINT is ignored by a non-interactive shell's background jobs; start them
# with default dispositions so that the test sends what a terminal would.
envd="env"
env --default-signal=INT true 2>/dev/null && envd="env --default-signal=INT,TERM"
echo "old" > "$dir/keep"

# start SIZE [DELAY_MS]: a render of the demo to $dir/out.png in the
# background (pid in $pid); DELAY_MS holds the temporary file open that long
# before writing it (the test hook LANECAST_TEST_WRITE_DELAY_MS)
start() {
    cp "$dir/keep" "$dir/out.png"
    LANECAST_TEST_WRITE_DELAY_MS=${2:-0} LANECAST_THREADS=1 $envd "$exe" demo --size "$1" -o "$dir/out.png" \
        --quiet 2> "$dir/err" &
    pid=$!
}
# waits up to 20 s for a temporary file next to the output; 0 when seen
wait_temp() {
    i=0
    while [ $i -lt 400 ]; do
        ls "$dir" | grep -q '\.lanecast-' && return 0
        kill -0 "$pid" 2>/dev/null || return 1
        sleep 0.05
        i=$((i + 1))
    done
    return 1
}
check() { # check LABEL SIGNUM
    wait "$pid"
    rc=$?
    left=$(ls "$dir" | grep -c '\.lanecast-' || true)
    if [ "$rc" -ne $((128 + $2)) ]; then
        echo "FAIL $1: exit $rc, expected $((128 + $2)) (killed by the signal): $(cat "$dir/err")"; fail=1
    elif [ "$left" -ne 0 ]; then
        echo "FAIL $1: $left temporary files left: $(ls "$dir")"; fail=1
    elif ! cmp -s "$dir/out.png" "$dir/keep"; then
        echo "FAIL $1: the existing output was replaced or changed"; fail=1
    else
        echo "ok   $1: exit $rc, old output kept, no temporary file"
    fi
}
for sig in INT TERM; do
    num=$(kill -l "$sig" 2>/dev/null || echo 0)
    [ "$sig" = INT ] && num=2
    [ "$sig" = TERM ] && num=15
    # during the render: no file of ours exists yet
    start 2048x2048
    sleep 0.3
    kill -s "$sig" "$pid"
    check "SIG$sig while rendering" "$num"
    # during the write: the temporary file exists
    start 200x150 20000
    if wait_temp; then
        kill -s "$sig" "$pid"
        check "SIG$sig while writing" "$num"
    else
        wait "$pid"
        echo "FAIL SIG$sig while writing: no temporary file appeared (exit $?): $(cat "$dir/err")"; fail=1
    fi
done
# lanecast encode writes its .rbf the same way: SIGTERM while the temporary
# .rbf exists removes it and keeps an existing file (needs LAPACKE)
if "$exe" formats | grep -Eq '^ *lapacke +yes'; then
    printf 'x,y,z,value\n' > "$dir/s.csv"
    for i in 0 1 2 3 4 5 6 7 8 9 10 11; do
        printf '%d,%d,%d,%d\n' $((i % 3)) $((i / 3 % 2)) $((i / 6)) $((i * i % 7)) >> "$dir/s.csv"
    done
    cp "$dir/keep" "$dir/out.rbf"
    LANECAST_TEST_WRITE_DELAY_MS=20000 $envd "$exe" encode "$dir/s.csv" -o "$dir/out.rbf" --max-rbfs 2 --quiet \
        2> "$dir/err" &
    pid=$!
    if wait_temp; then
        kill -s TERM "$pid"
        wait "$pid"
        rc=$?
        left=$(ls "$dir" | grep -c '\.lanecast-' || true)
        if [ "$rc" -ne 143 ] || [ "$left" -ne 0 ] || ! cmp -s "$dir/out.rbf" "$dir/keep"; then
            echo "FAIL SIGTERM while encode writes: exit $rc, $left temporary files, $(ls "$dir")"; fail=1
        else
            echo "ok   SIGTERM while encode writes: exit $rc, old .rbf kept, no temporary file"
        fi
    else
        wait "$pid"
        echo "FAIL SIGTERM while encode writes: no temporary file appeared (exit $?): $(cat "$dir/err")"; fail=1
    fi
    rm -f "$dir/out.rbf" "$dir/s.csv"
else
    echo "skip encode: this build has no LAPACKE"
fi
# control: without a signal the same render replaces the old output
LANECAST_THREADS=1 "$exe" demo --size 64x48 -o "$dir/out.png" --quiet
if cmp -s "$dir/out.png" "$dir/keep" || [ "$(ls "$dir" | grep -c '\.lanecast-')" -ne 0 ]; then
    echo "FAIL control: an uninterrupted render did not replace the output cleanly"; fail=1
else
    echo "ok   control: an uninterrupted render replaces the output"
fi
exit $fail

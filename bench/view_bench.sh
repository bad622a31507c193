#!/bin/sh
# Navigation and full frame times of lanecast view at SIZE (default
# 1024x1024), measured through --script under an Xvfb: N drag moves, each
# waited for (wait-frame) and timed by its job (stats), at the fixed
# navigation scale 2 and then adaptive (50 ms target); then the release and
# the refined frame (preview and full passes). Prints the stats lines and
# the medians. usage: bench/view_bench.sh INPUT|--demo [SIZE [N]] [-- view options]
set -eu
cd "$(dirname "$0")/.."
exe=$PWD/build/tools/lanecast
input=$1
size=${2:-1024x1024}
n=${3:-12}
shift; [ $# -gt 0 ] && shift; [ $# -gt 0 ] && shift
[ "${1:-}" = "--" ] && shift
tmp=$(mktemp -d)
xpid=""
trap '[ -n "$xpid" ] && kill $xpid 2> /dev/null; rm -rf "$tmp"' EXIT
mkfifo "$tmp/xfd"
Xvfb -displayfd 3 -screen 0 1280x1280x24 -nolisten tcp 3> "$tmp/xfd" 2> /dev/null &
xpid=$!
read -r dnum < "$tmp/xfd"
w=${size%x*}
{
    echo "wait"
    echo "stats"
    echo "down $((w / 2)) $((w / 2))"
    i=1
    while [ $i -le "$n" ]; do echo "move $((w / 2 + 6 * i)) $((w / 2 + 2 * i))"; echo wait-frame; echo stats; i=$((i + 1)); done
    echo "up"
    echo "wait"
    echo "stats"
    echo "quit"
} > "$tmp/s.txt"
median() { sort -n | awk '{a[NR] = $1} END {if (NR) print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2); else print "-"}'; }
if [ "$input" = --demo ]; then set -- --demo "$@"; else set -- "$input" "$@"; fi
for mode in fixed adaptive; do
    flag=""
    [ $mode = fixed ] && flag=--no-adaptive
    # shellcheck disable=SC2086
    DISPLAY=":$dnum" "$exe" view "$@" --size "$size" $flag --script "$tmp/s.txt" > "$tmp/$mode.out"
    nav=$(grep '^stats nav 1' "$tmp/$mode.out" | awk '{print $11}' | median)
    scales=$(grep '^stats nav 1' "$tmp/$mode.out" | awk '{print $5}' | tr '\n' ' ')
    full=$(grep '^stats nav 0' "$tmp/$mode.out" | tail -n1 | awk '{print $11}')
    echo "$mode: navigation frame median $nav ms over $n moves (scales $scales); release to refined frame $full ms"
done
grep '^stats' "$tmp/fixed.out" | head -n3

#!/bin/sh
# The input flags are one table (tools/cli_input.c): the same raw volume given
# to lanecast render, info and encode by the same flags loads the same grid
# (render's and info's "volume" lines: sizes, type, spacing, value range;
# encode's sample count and value range), and a flag left out (--big-endian)
# changes it, so the comparison can fail.
# usage: test_cli_input.sh LANECAST_EXE
set -u
exe=$1
fail=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
check() { # check DESCRIPTION COMMAND...
    desc=$1; shift
    if "$@"; then echo "ok   $desc"; else echo "FAIL $desc"; fail=1; fi
}
head -c 480 /dev/urandom > "$tmp/v.raw" # 8 x 6 x 5 uint16
set -- --dims 8,6,5 --type uint16 --big-endian --spacing 0.5,1,2
"$exe" render "$tmp/v.raw" "$@" --size 16x16 --stats -o "$tmp/v.png" > "$tmp/render.txt" 2>&1
check "render loads the raw volume" grep -q '^volume *8x6x5 uint16, spacing 0.5,1,2' "$tmp/render.txt"
"$exe" info "$tmp/v.raw" "$@" > "$tmp/info.txt" 2>&1
check "info takes render's raw-volume flags" grep -q '^volume' "$tmp/info.txt"
check "info and render: the same grid" sh -c "[ \"\$(grep '^volume' '$tmp/render.txt')\" = \"\$(grep '^volume' '$tmp/info.txt')\" ]"
"$exe" info "$tmp/v.raw" --dims 8,6,5 --type uint16 --spacing 0.5,1,2 > "$tmp/little.txt" 2>&1
check "without --big-endian another grid (the comparison can fail)" \
    sh -c "[ \"\$(grep '^volume' '$tmp/little.txt')\" != \"\$(grep '^volume' '$tmp/render.txt')\" ]"
range=$(sed -n 's/.*values \([^ ]*\)\.\.\([^ ]*\)$/\1..\2/p' "$tmp/render.txt")
if "$exe" formats | grep -q 'lapacke.*yes'; then
    "$exe" encode "$tmp/v.raw" "$@" -o "$tmp/v.rbf" --max-rbfs 4 > "$tmp/encode.txt" 2>&1
    check "encode takes render's raw-volume flags: 240 samples over render's range $range" \
        grep -q "^samples *240 (240 in the fit range $range)" "$tmp/encode.txt"
else
    echo "note: this build has no LAPACKE: the encode part is skipped"
fi
"$exe" info "$tmp/v.raw" --dims 8,6 > /dev/null 2>"$tmp/err"; rc=$?
check "a bad --dims in info: exit 2 naming it" sh -c "[ $rc -eq 2 ] && grep -q -- '--dims' '$tmp/err'"
"$exe" encode "$tmp/v.raw" --type int7 -o "$tmp/x.rbf" > /dev/null 2>"$tmp/err"; rc=$?
check "a bad --type in encode: exit 2 naming it" sh -c "[ $rc -eq 2 ] && grep -q -- \"--type: 'int7'\" '$tmp/err'"
exit $fail

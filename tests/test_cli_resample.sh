#!/bin/sh
# lanecast resample and lanecast render --resample (issue 28): grids written
# as .nrrd and .nhdr + .raw read back by lanecast info; u8 with a range; the
# same bytes for 1 and 2 threads; `render --resample N` equals `render` of
# the grid file that `resample --dims N` wrote (same camera, TF and range);
# bad flags and inputs give one line on stderr, a non-zero exit and no file.
# usage: test_cli_resample.sh LANECAST IMGCMP
set -eu
exe=$1
imgcmp=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fail=1; }
# 300 particles in two clumps (a fixed LCG), radii 0.3..0.7, values 0.5..1.5
awk 'BEGIN { s = 12345; print "x,y,z,radius,value";
    for (i = 0; i < 300; i++) { for (a = 0; a < 5; a++) { s = (s * 1103515245 + 12345) % 2147483648; u[a] = s / 2147483648 }
        c = (i % 2) ? 2.0 : -1.5;
        printf "%.5f,%.5f,%.5f,%.4f,%.4f\n", c + 3 * (u[0] - 0.5), 3 * (u[1] - 0.5), 2 * (u[2] - 0.5), 0.3 + 0.4 * u[3], 0.5 + u[4] } }' \
    > "$dir/p.csv"

"$exe" resample "$dir/p.csv" -o "$dir/g.nrrd" --dims 24 --quiet && [ -s "$dir/g.nrrd" ] && ok "resample to .nrrd" ||
    bad "resample to .nrrd"
"$exe" info "$dir/g.nrrd" > "$dir/info" 2>&1 && grep -q "kind *grid" "$dir/info" && grep -q "24 x 24 x 24\|24x24x24\|24 24 24" "$dir/info" &&
    ok "lanecast info reads the grid back" || { bad "lanecast info on the grid"; cat "$dir/info"; }
"$exe" resample "$dir/p.csv" -o "$dir/d.nhdr" --dims 20,16,12 --type u8 --range 0,1 --quiet &&
    [ "$(wc -c < "$dir/d.raw")" -eq $((20 * 16 * 12)) ] && grep -q "data file: d.raw" "$dir/d.nhdr" &&
    grep -q "old max: 1" "$dir/d.nhdr" && ok "detached .nhdr + .raw, uint8 over 0,1" || bad "detached u8 grid"
"$exe" info "$dir/d.nhdr" > /dev/null 2>&1 && ok "the detached grid reads back" || bad "the detached grid reads back"
"$exe" resample "$dir/p.csv" -o "$dir/t1.nrrd" --dims 40 --threads 1 --quiet &&
    "$exe" resample "$dir/p.csv" -o "$dir/t2.nrrd" --dims 40 --threads 2 --quiet && cmp -s "$dir/t1.nrrd" "$dir/t2.nrrd" &&
    ok "1 and 2 threads write the same bytes" || bad "1 and 2 threads write the same bytes"

# render --resample N against render of the grid that resample --dims N wrote
range=$("$exe" info "$dir/p.csv" | awk '/^range/ { print $2 "," $4 }')
# the same TF for both: a preset's tau and the step default by kind, so both are given
view="--eye 9,6,12 --at 0.2,0,0 --size 64x64 --tf heat --tau 2 --dt 0.05 --range $range --quiet"
"$exe" resample "$dir/p.csv" -o "$dir/r.nrrd" --dims 32 --quiet
# shellcheck disable=SC2086
"$exe" render "$dir/r.nrrd" -o "$dir/file.png" $view
# shellcheck disable=SC2086
"$exe" render "$dir/p.csv" --resample 32 -o "$dir/via.png" $view
"$imgcmp" "$dir/via.png" "$dir/file.png" exact && ok "render --resample 32 = render of the written 32^3 grid" ||
    bad "render --resample 32 differs from the written grid's image"
# shellcheck disable=SC2086
"$exe" render "$dir/p.csv" --resample 32 -o "$dir/s.png" $view --stats | grep -q "^resample .*32^3 grid" &&
    ok "--stats states the resample" || bad "--stats states the resample"
# shellcheck disable=SC2086
"$exe" render "$dir/p.csv" -o "$dir/exact.png" $view
"$imgcmp" "$dir/via.png" "$dir/exact.png" exact > /dev/null 2>&1 && bad "the 32^3 grid image equals the exact one (no resample?)" ||
    ok "the grid image is not the exact particle image"

# bad flags and inputs: one line, non-zero exit, no output file
expect() { # name, expected status, output file, args...
    name=$1 want=$2 out=$3
    shift 3
    set +e
    "$exe" "$@" 2> "$dir/err" > /dev/null
    rc=$?
    set -e
    lines=$(wc -l < "$dir/err")
    if [ "$rc" -ne "$want" ] || [ "$lines" -ne 1 ] || [ -e "$out" ]; then
        bad "$name: exit $rc (want $want), $lines stderr lines, output $([ -e "$out" ] && echo written || echo absent)"
        cat "$dir/err"
    else
        ok "$name: $(cat "$dir/err")"
    fi
}
o="$dir/x.nrrd"
expect "no --dims" 2 "$o" resample "$dir/p.csv" -o "$o"
expect "--dims 0" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 0
expect "--dims 4,4" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4,4
expect "--box with five numbers" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --box 0,0,0,1,1
expect "--box inverted" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --box 0,0,0,1,-1,1
expect "--type f64" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --type f64
expect "--range without u8/u16" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --range 0,1
expect "--range 1,0" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --type u8 --range 1,0
expect "-o grid.png" 2 "$dir/x.png" resample "$dir/p.csv" -o "$dir/x.png" --dims 4
expect "no -o" 2 "$o" resample "$dir/p.csv" --dims 4
expect "an unknown flag" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --bogus
expect "a grid flag (--spacing)" 2 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --spacing 1,1,1
expect "--field 3 of one field" 1 "$o" resample "$dir/p.csv" -o "$o" --dims 4 --field 3
expect "a missing input" 1 "$o" resample "$dir/none.csv" -o "$o" --dims 4
expect "a volume as input" 1 "$o" resample "$dir/g.nrrd" -o "$o" --dims 4
expect "an unwritable folder" 1 "$dir/no/x.nrrd" resample "$dir/p.csv" -o "$dir/no/x.nrrd" --dims 4
expect "over --max-memory" 1 "$o" resample "$dir/p.csv" -o "$o" --dims 512 --max-memory 64M
expect "render --resample 1" 2 "$dir/x.png" render "$dir/p.csv" --resample 1 -o "$dir/x.png"
expect "render --resample of a volume" 1 "$dir/x.png" render "$dir/g.nrrd" --resample 16 -o "$dir/x.png"
expect "render --resample over --max-memory" 1 "$dir/x.png" render "$dir/p.csv" --resample 600 --max-memory 256M -o "$dir/x.png"
expect "render --resample with --mode project" 2 "$dir/x.png" render "$dir/p.csv" --resample 16 --mode project -o "$dir/x.png"
ls "$dir" | grep -q "\.tmp\|lanecast-tmp" && bad "temporary files left behind" || ok "no temporary files left"
exit $fail

#!/bin/sh
# lanecast encode: hydrogen and neghip reach 2% RMS and render; neghip at
# 256 RBFs (the text variant) is worse than at 2%; bad input gives one
# line, exit 1 and no file.
# Args: the lanecast executable, the shared data folder, a scratch folder.
set -u
exe=$1 data=$2 tmp=$3
fail=0
check() { if eval "$2"; then echo "ok   $1"; else echo "FAIL $1"; fail=1; fi; }
rms() { sed -n 's/^error  *RMS \([0-9.]*\)%.*/\1/p' "$1"; }

check "--help has examples" '"$exe" encode --help | grep -q "^  lanecast encode neghip.nhdr"'
check "listed in lanecast --help" '"$exe" --help | grep -q "^  encode "'
"$exe" encode --bogus x >/dev/null 2>&1
rc=$?
check "unknown flag is a usage error (2)" '[ $rc -eq 2 ]'

if ! "$exe" formats | grep -Eq "^  lapacke +yes"; then
    rm -f "$tmp/x.rbf"
    printf 'x,y,z,value\n0,0,0,1\n1,0,0,2\n' > "$tmp/two.csv"
    err=$("$exe" encode "$tmp/two.csv" -o "$tmp/x.rbf" 2>&1 >/dev/null)
    check "without LAPACKE: one line naming liblapacke-dev" '[ "$(printf "%s\n" "$err" | wc -l)" -eq 1 ] && printf "%s" "$err" | grep -q liblapacke-dev && [ ! -e "$tmp/x.rbf" ]'
    exit $fail
fi

# bad input: one line on stderr, exit 1, nothing written
bad() { # name, expected text, then the command's arguments
    name=$1 want=$2
    shift 2
    rm -f "$tmp/bad.rbf"
    err=$("$exe" encode "$@" -o "$tmp/bad.rbf" 2>&1 >/dev/null)
    rc=$?
    check "$name: exit 1, one line, no file ($err)" '[ $rc -eq 1 ] && [ "$(printf "%s\n" "$err" | wc -l)" -eq 1 ] && printf "%s" "$err" | grep -q "$want" && [ -z "$(ls "$tmp" | grep "^bad.rbf")" ]'
}
printf 'x,y,z,value\n0,0,0,1\n1,0,0,NaN\n' > "$tmp/nan.csv"
bad "NaN in a CSV" "nan.csv:3: value 'NaN' is not finite" "$tmp/nan.csv"
printf 'x,y,z,value\n0,0,0,1\n1,0,0\n' > "$tmp/short.csv"
bad "malformed CSV" "short.csv:3: 3 columns" "$tmp/short.csv"
printf '# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 x 0\n' > "$tmp/bad.vtk"
bad "malformed VTK" "bad.vtk:6: POINTS: value 4 is not a number" "$tmp/bad.vtk"
printf 'x,y,z,value\n0,0,0,1\n1,0,0,2\n2,0,0,3\n' > "$tmp/three.csv"
bad "empty fit range" "no sample has a value in the fit range" "$tmp/three.csv" --fit-range 5,6
bad "fewer samples than RBFs" "fewer than max_rbfs 5" "$tmp/three.csv" --max-rbfs 5

if [ ! -f "$data/volumes/hydrogen.nhdr" ] || [ ! -f "$data/volumes/neghip.nhdr" ]; then
    echo "skip: the shared volumes are not in $data"
    [ $fail -eq 0 ] && exit 77
    exit 1
fi
"$exe" encode "$data/volumes/hydrogen.nhdr" -o "$tmp/hydrogen.rbf" --centre maxerr > "$tmp/hydrogen.txt"
check "hydrogen encodes" '[ $? -eq 0 ]'
sed 's/^/     /' "$tmp/hydrogen.txt"
r=$(rms "$tmp/hydrogen.txt")
check "hydrogen: RMS $r% <= 2%" 'awk "BEGIN { exit !($r <= 2.0) }"'
check "hydrogen.rbf renders" '"$exe" render "$tmp/hydrogen.rbf" -o "$tmp/hydrogen_rbf.png" --size 64x64 --quiet'

"$exe" encode "$data/volumes/neghip.nhdr" -o "$tmp/neghip256.rbf" --centre maxerr --max-rbfs 256 --text > "$tmp/n256.txt"
check "neghip, 256 RBFs, text" '[ $? -eq 0 ] && grep -q "^lanecast-rbf 1$" "$tmp/neghip256.rbf" && grep -q "^count 256$" "$tmp/neghip256.rbf"'
# the full neghip to 2 % (issue 10; docs/bench/rbf.md): the report, the
# count (at most one RBF per 36 voxels, the paper's density) in the report
# and in the file, lower than at 256 RBFs, and the set renders.
# (about 40 s under ASan + UBSan on 2 cores)
"$exe" encode "$data/volumes/neghip.nhdr" -o "$tmp/neghip.rbf" --centre maxerr --text > "$tmp/n.txt"
check "neghip encodes" '[ $? -eq 0 ]'
sed 's/^/     /' "$tmp/n.txt"
a=$(rms "$tmp/n256.txt") b=$(rms "$tmp/n.txt")
n=$(sed -n 's/^rbfs  *\([0-9]*\), .*target RMS [0-9.]*%: reached$/\1/p' "$tmp/n.txt")
check "neghip: the report says reached, RMS $b% <= 2%" '[ -n "$n" ] && awk "BEGIN { exit !($b <= 2.0) }"'
check "neghip: $n RBFs <= 7986 (287496 voxels / 36), as in the file" '[ -n "$n" ] && [ "$n" -le 7986 ] && grep -q "^count $n$" "$tmp/neghip.rbf" && [ "$(grep -c "^[-0-9]" "$tmp/neghip.rbf")" -eq "$n" ]'
check "neghip: RMS $a% at 256 RBFs > $b% at $n" 'awk "BEGIN { exit !($a > $b) }"'
check "neghip.rbf renders" '"$exe" render "$tmp/neghip.rbf" -o "$tmp/neghip_rbf.png" --size 64x64 --quiet && [ -s "$tmp/neghip_rbf.png" ]'
exit $fail

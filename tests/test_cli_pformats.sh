#!/bin/sh
# lanecast info and the trajectory flags of lanecast render (--frame,
# --frames, --topology) on the shared adk.dcd + adk.psf and on a small
# LAMMPS dump this script writes: what info prints, the images a sequence
# writes, and the failures (one line on stderr, the right exit status, no
# image left behind, a sequence stopped at its first bad frame).
# usage: test_cli_pformats.sh LANECAST_EXE DATA_DIR
set -u
exe=$1
data=$2
fail=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ok() { echo "ok   $*"; }
no() { echo "FAIL $*"; fail=1; }

# a 3-frame LAMMPS dump whose third frame is broken
{
    for t in 0 1; do
        printf 'ITEM: TIMESTEP\n%s\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n' $t
        printf 'ITEM: ATOMS id type x y z\n1 1 1 1 1\n2 2 2 2 2\n3 1 3 3 %s\n' $t
    done
    printf 'ITEM: TIMESTEP\n2\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\n'
    printf 'ITEM: ATOMS id type x y z\n1 1 1 1 1\n2 2 2 2\n3 1 3 3 3\n'
} >"$tmp/melt.lammpstrj"

"$exe" info "$tmp/melt.lammpstrj" --option fields=type >"$tmp/out" 2>&1
if grep -q '^format        lammps$' "$tmp/out" && grep -q '^frames        3$' "$tmp/out" &&
   grep -q '^fields        2$' "$tmp/out" && grep -q '^particles     3 ' "$tmp/out"; then
    ok "info melt.lammpstrj: lammps, 3 frames (counted by their ITEM lines), 2 fields, 3 particles"
else
    no "info melt.lammpstrj:"; sed 's/^/     /' "$tmp/out"
fi

# a sequence stops at the first bad frame, naming it; the good frames are written whole
"$exe" render "$tmp/melt.lammpstrj" --frames 0:3 --size 32x32 --quiet -o "$tmp/m_%02d.png" 2>"$tmp/err"
rc=$?
if [ $rc -eq 1 ] && [ -s "$tmp/m_00.png" ] && [ -s "$tmp/m_01.png" ] && [ ! -e "$tmp/m_02.png" ] &&
   [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q 'frame 2 (.*m_02.png): .*melt.lammpstrj:35: atom 2 has 4 columns' "$tmp/err" &&
   [ "$(ls "$tmp" | grep -c '^m_')" -eq 2 ]; then
    ok "render --frames 0:3: frames 0 and 1 written, stops at frame 2: $(cat "$tmp/err")"
else
    no "render --frames 0:3 -> exit $rc:"; ls "$tmp"; sed 's/^/     /' "$tmp/err"
fi

# --field-by and --select on a LAMMPS dump of 10 atoms of types 1..10 (issue 11)
{
    printf 'ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n10\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\nITEM: ATOMS id type x y z q\n'
    for i in 1 2 3 4 5 6 7 8 9 10; do echo "$i $i $((i % 4)) $((i % 3)) 1 0.$((i % 3))"; done
} >"$tmp/ten.lammpstrj"
info_has() { # info_has DESCRIPTION PATTERN... -- ARGS: every PATTERN in the info output
    desc=$1; shift
    pats=""
    while [ "$1" != "--" ]; do pats="$pats|$1"; shift; done
    shift
    "$exe" info "$tmp/ten.lammpstrj" "$@" >"$tmp/out" 2>"$tmp/err"
    good=1
    for p in $(echo "${pats#|}" | tr '|' ' '); do grep -q "^$(echo "$p" | tr '_' ' ')" "$tmp/out" || good=0; done
    if [ $good -eq 1 ]; then ok "$desc"; else no "$desc:"; sed 's/^/     /' "$tmp/out" "$tmp/err"; fi
}
info_has "field_by=type: 10 types in 8 fields" "fields________8" "particles_____10_" -- --option field_by=type
grep -q "2 atom types above 8 (first '9') share field 7" "$tmp/err" && ok "... with a warning counting the merged types" ||
    no "no merge warning: $(cat "$tmp/err")"
info_has "field_by=column:q: 3 distinct values, 3 fields" "fields________3" -- --option field_by=column:q
info_has "select='type 1 2': 2 atoms" "particles_____2_" -- --option "select=type 1 2"
info_has "select='index 2:5': 4 atoms" "particles_____4_" -- --option "select=index 2:5"
bad_opt() { # bad_opt NEEDLE OPTION: exit 1, one line naming the file and NEEDLE
    "$exe" render "$tmp/ten.lammpstrj" -o "$tmp/bad.png" --size 8x8 "$@" >/dev/null 2>"$tmp/err"
    rc=$?
    if [ $rc -eq 1 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -q "ten.lammpstrj:.*$needle" "$tmp/err" && [ ! -e "$tmp/bad.png" ]
    then ok "$* -> exit 1: $(cat "$tmp/err")"
    else no "$* -> exit $rc:"; sed 's/^/     /' "$tmp/err"; fi
}
needle="lammps files give no chain identifiers"; bad_opt --field-by chain
needle="lammps files cannot answer 'resname'"; bad_opt --select 'resname ALA'
needle="has no such column"; bad_opt --field-by column nosuch

# usage errors: exit 2, one line
usage() {
    needle=$1; shift
    "$exe" "$@" >/dev/null 2>"$tmp/err"
    rc=$?
    if [ $rc -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] && grep -qF -- "$needle" "$tmp/err"; then
        ok "$* -> exit 2: $(cat "$tmp/err")"
    else
        no "$* -> exit $rc (want 2 naming '$needle'):"; sed 's/^/     /' "$tmp/err"
    fi
}
usage "one frame number in it" render "$tmp/melt.lammpstrj" --frames 0:2 -o "$tmp/x.png"
usage "not A:B[:S]" render "$tmp/melt.lammpstrj" --frames 2:1 -o "$tmp/x_%d.png"
usage "not A:B[:S]" render "$tmp/melt.lammpstrj" --frames 0:2:0 -o "$tmp/x_%d.png"
usage "--frame or --frames, not both" render "$tmp/melt.lammpstrj" --frame 1 --frames 0:2 -o "$tmp/x_%d.png"
usage "not a frame number" info "$tmp/melt.lammpstrj" --frame -1
usage "expected KEY=VALUE" info "$tmp/melt.lammpstrj" --option fields
"$exe" info --help | grep -q 'example: lanecast info' && ok "info --help has an example" || no "info --help"
"$exe" render --help | grep -q -- '--frames 0:98:10 -o adk_%02d.png' && ok "render --help shows --frames" ||
    no "render --help lacks --frames"
"$exe" --help | grep -q '^  info FILE' && ok "lanecast --help lists info" || no "lanecast --help lacks info"

if [ ! -f "$data/particles/adk.dcd" ]; then
    echo "skip: $data/particles/adk.dcd is absent"
    [ $fail -eq 0 ] && exit 77 || exit 1
fi
dcd=$data/particles/adk.dcd
psf=$data/particles/adk.psf
"$exe" info "$dcd" --frame 50 >"$tmp/out" 2>&1
if grep -q '^format        dcd$' "$tmp/out" && grep -q '^frames        98$' "$tmp/out" &&
   grep -q '^frame         50 ' "$tmp/out" && grep -q '^particles     3341 ' "$tmp/out" &&
   grep -q 'radius 0.31..1.05' "$tmp/out"; then
    ok "info adk.dcd --frame 50: dcd, 98 frames, 3341 atoms, element radii from adk.psf"
else
    no "info adk.dcd:"; sed 's/^/     /' "$tmp/out"
fi
"$exe" render "$dcd" --topology "$psf" --frames 0:98:45 --size 32x32 -o "$tmp/adk_%03d.png" >"$tmp/out" 2>"$tmp/err"
if [ $? -eq 0 ] && [ -s "$tmp/adk_000.png" ] && [ -s "$tmp/adk_045.png" ] && [ -s "$tmp/adk_090.png" ] &&
   [ "$(ls "$tmp" | grep -c '^adk_')" -eq 3 ] && [ ! -s "$tmp/err" ]; then
    ok "render adk.dcd --frames 0:98:45: adk_000, adk_045, adk_090"
else
    no "render adk.dcd --frames 0:98:45:"; ls "$tmp"; sed 's/^/     /' "$tmp/err"
fi
"$exe" render "$dcd" --frames 90:100 --size 32x32 -o "$tmp/late_%d.png" 2>"$tmp/err"
[ $? -eq 1 ] && grep -q 'holds 98 frames (0 to 97); frames 90:100' "$tmp/err" && [ -z "$(ls "$tmp" | grep '^late_')" ] &&
    ok "--frames 90:100 refused before any work: $(cat "$tmp/err")" || { no "--frames 90:100:"; cat "$tmp/err"; }
"$exe" render "$dcd" --topology "$tmp/none.psf" --size 32x32 -o "$tmp/t.png" 2>"$tmp/err"
[ $? -eq 1 ] && grep -q 'adk.dcd: topology: .*none.psf: cannot open' "$tmp/err" && [ ! -e "$tmp/t.png" ] &&
    ok "a missing --topology fails: $(cat "$tmp/err")" || { no "missing --topology:"; cat "$tmp/err"; }
cp "$dcd" "$tmp/alone.dcd"
"$exe" render "$tmp/alone.dcd" --size 32x32 -o "$tmp/alone.png" >/dev/null 2>"$tmp/err"
[ $? -eq 0 ] && [ -s "$tmp/alone.png" ] && grep -q 'warning: .*alone.psf does not exist.*radius 1.5' "$tmp/err" &&
    ok "no PSF next to the DCD: rendered with a warning: $(cat "$tmp/err")" || { no "no PSF:"; cat "$tmp/err"; }
exit $fail

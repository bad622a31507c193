#!/bin/sh
# Malformed input across the formats (issue 11): for each format and each
# class of damage the test can produce (truncated, counts that disagree, bad
# numbers, wrong endianness, a missing companion, corrupt gzip, sizes that
# would overflow memory), `lanecast render BAD -o out.png` must exit 1 with
# exactly one line on stderr naming the file, and leave a pre-existing
# out.png byte for byte as it was. A well-formed control of each generator
# must render (so the damage, not the generator, is what fails).
# usage: test_cli_malformed.sh LANECAST_EXE DATA_DIR [TRAJ_DIR]
set -u
exe=$1
data=${2:-}
traj=${3:-}
case $traj in /* | "") ;; *) traj=$(pwd)/$traj ;; esac
case $exe in /*) ;; *) exe=$(pwd)/$exe ;; esac
case $data in /* | "") ;; *) data=$(pwd)/$data ;; esac
fail=0
n=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1

le32() { printf "\\$(printf %03o $(($1 & 255)))\\$(printf %03o $((($1 >> 8) & 255)))\\$(printf %03o $((($1 >> 16) & 255)))\\$(printf %03o $((($1 >> 24) & 255)))"; }
be32() { printf "\\$(printf %03o $((($1 >> 24) & 255)))\\$(printf %03o $((($1 >> 16) & 255)))\\$(printf %03o $((($1 >> 8) & 255)))\\$(printf %03o $(($1 & 255)))"; }
# A GADGET format-1 snapshot: ENDIAN(header markers) NPART1 POSBYTES ENDIAN(block markers)
gadget() {
    $1 256; $1 0; $1 "$2"; head -c 248 /dev/zero; $1 256
    $4 "$3"; head -c "$3" /dev/zero; $4 "$3"
}
# Flips bytes in the middle of a file (corrupts gzip's deflate stream or CRC).
flip() {
    size=$(wc -c <"$1")
    at=$((size / 2))
    { head -c "$at" "$1"; printf '\377\377\377\377\377\377\377\377'; tail -c +$((at + 9)) "$1"; } >"$1.tmp" && mv "$1.tmp" "$1"
}
have_gzip=0
command -v gzip >/dev/null 2>&1 && "$exe" formats | grep -Eq '^ *zlib +yes' && have_gzip=1

printf 'an image that must survive\n' >keep.ref

# case NAME FILE [ARGS...]: the file must fail as described above
case_bad() {
    name=$1 file=$2
    shift 2
    n=$((n + 1))
    cp keep.ref out.png
    "$exe" render "$file" -o out.png --size 16x16 --quiet "$@" >stdout 2>stderr
    rc=$?
    base=$(basename "$file")
    lines=$(wc -l <stderr)
    why=""
    [ $rc -eq 1 ] || why="exit $rc, expected 1"
    [ -z "$why" ] && [ "$lines" -ne 1 ] && why="$lines lines on stderr, expected 1"
    [ -z "$why" ] && ! grep -qF "$base" stderr && why="stderr does not name $base"
    [ -z "$why" ] && ! cmp -s keep.ref out.png && why="out.png was changed"
    [ -z "$why" ] && ls .lanecast* out.png.* >/dev/null 2>&1 && why="a temporary output was left behind"
    if [ -z "$why" ]; then
        echo "ok   $name: $(cat stderr)"
    else
        echo "FAIL $name: $why"
        sed 's/^/     stderr: /' stderr
        fail=1
    fi
}
case_good() {
    name=$1 file=$2
    shift 2
    if "$exe" render "$file" -o good.png --size 16x16 --quiet "$@" >/dev/null 2>stderr; then
        echo "ok   control $name renders"
    else
        echo "FAIL control $name does not render"; sed 's/^/     /' stderr; fail=1
    fi
}

# ---- XYZ
printf '3\nc\nC 0 0 0\nO 1 1 1\nN 2 2 2\n' >good.xyz
case_good xyz good.xyz
printf '3\nc\nC 0 0 0\nO 1 1 1\n' >trunc.xyz
case_bad "xyz truncated (3 atoms declared, 2 given)" trunc.xyz
printf '2\nc\nC 0 x 0\nO 1 1 1\n' >num.xyz
case_bad "xyz bad number" num.xyz
printf '99999999999999999999\nc\nC 0 0 0\n' >huge.xyz
case_bad "xyz count that would overflow memory" huge.xyz
printf '2\nc\nC 0 0 0\nO 1 1 1\nN 2 2 2\nextra\n' >count.xyz
case_bad "xyz counts disagree (a second frame's count line is not a number)" count.xyz
if [ $have_gzip -eq 1 ]; then
    awk 'BEGIN { print 3000; print "c"; for (i = 0; i < 3000; i++) print "C", i % 17, i % 13, i % 11 }' >big.xyz
    gzip -c big.xyz >good.xyz.gz
    case_good xyz.gz good.xyz.gz
    cp good.xyz.gz corrupt.xyz.gz
    flip corrupt.xyz.gz
    case_bad "xyz.gz corrupt gzip (bytes flipped)" corrupt.xyz.gz
    head -c 200 good.xyz.gz >short.xyz.gz
    case_bad "xyz.gz truncated gzip stream" short.xyz.gz
fi

# ---- PDB
printf 'ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N\n' >good.pdb
case_good pdb good.pdb
printf 'ATOM      1  N   ALA A   1      11.104   6.1x4  -6.504  1.00  0.00           N\n' >num.pdb
case_bad "pdb bad number" num.pdb
printf 'ATOM      1  N   ALA A   1      11.104\n' >trunc.pdb
case_bad "pdb truncated record" trunc.pdb

# ---- GRO
printf 't\n2\n    1SOL     OW    1   0.126   1.624   1.679\n    1SOL    HW1    2   0.190   1.661   1.747\n   1.0 1.0 1.0\n' >good.gro
case_good gro good.gro
printf 't\n3\n    1SOL     OW    1   0.126   1.624   1.679\n    1SOL    HW1    2   0.190   1.661   1.747\n' >trunc.gro
case_bad "gro truncated (3 atoms declared)" trunc.gro
printf 't\n2\n    1SOL     OW    1   0.126   1.6x4   1.679\n    1SOL    HW1    2   0.190   1.661   1.747\n   1.0 1.0 1.0\n' >num.gro
case_bad "gro bad number" num.gro

# ---- LAMMPS
lmp_head() { printf 'ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n%s\nITEM: BOX BOUNDS pp pp pp\n0 4\n0 4\n0 4\nITEM: ATOMS id type x y z\n' "$1"; }
{ lmp_head 2; printf '1 1 1 1 1\n2 2 2 2 2\n'; } >good.lammpstrj
case_good lammps good.lammpstrj
{ lmp_head 3; printf '1 1 1 1 1\n2 2 2 2 2\n'; } >trunc.lammpstrj
case_bad "lammps truncated (3 atoms declared)" trunc.lammpstrj
{ lmp_head 2; printf '1 1 1 1 1\n2 2 2 2\n'; } >cols.lammpstrj
case_bad "lammps columns disagree with ITEM: ATOMS" cols.lammpstrj
{ lmp_head 2; printf '1 1 1 1 1\n2 2 2 2 nan\n'; } >num.lammpstrj
case_bad "lammps bad number" num.lammpstrj
{ lmp_head 99999999999999; printf '1 1 1 1 1\n'; } >huge.lammpstrj
case_bad "lammps count that would overflow memory" huge.lammpstrj

# ---- CSV
printf 'x,y,z,radius\n0,0,0,1\n1,1,1,1\n' >good.csv
case_good csv good.csv
printf 'x,y,z,radius\n0,0,0,1\n1,1,1,1,5\n' >cols.csv
case_bad "csv row longer than the header" cols.csv
printf 'x,y,z,radius\n0,0,0,1\n1,1e999,1,1\n' >num.csv
case_bad "csv bad number (overflows float)" num.csv

# ---- mmCIF
cif_head() { printf 'data_t\nloop_\n_atom_site.group_PDB\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n'; }
{ cif_head; printf 'ATOM C 0 0 0\nATOM N 1 1 1\n'; } >good.cif
case_good mmcif good.cif
{ cif_head; printf 'ATOM C 0 0 0\nATOM N 1 z 1\n'; } >num.cif
case_bad "mmcif bad number" num.cif
{ cif_head; printf 'ATOM C 0 0 0\nATOM N 1 1\n'; } >trunc.cif
case_bad "mmcif truncated loop (values not a multiple of the columns)" trunc.cif

# ---- GADGET (binary, either byte order)
gadget le32 2 24 le32 >good.gadget
case_good gadget good.gadget --radius 1
gadget be32 2 24 be32 >goodbe.gadget
case_good "gadget big-endian" goodbe.gadget --radius 1
head -c 280 good.gadget >trunc.gadget
case_bad "gadget truncated" trunc.gadget --radius 1
gadget le32 2 24 be32 >endian.gadget
case_bad "gadget wrong endianness (big-endian block markers in a little-endian file)" endian.gadget --radius 1
gadget le32 3 24 le32 >count.gadget
case_bad "gadget counts disagree (header 3 particles, POS of 2)" count.gadget --radius 1
gadget le32 1000000000 24 le32 >huge.gadget
case_bad "gadget header count that would overflow memory" huge.gadget --radius 1

# ---- NRRD and raw volumes
nrrd_head() { printf 'NRRD0004\ntype: %s\ndimension: 3\nsizes: %s\nencoding: %s\nendian: big\n\n' "$1" "$2" "$3"; }
{ nrrd_head float "2 2 2" raw; head -c 32 /dev/zero; } >good.nrrd
case_good nrrd good.nrrd
{ nrrd_head float "2 2 2" raw; head -c 31 /dev/zero; } >trunc.nrrd
case_bad "nrrd raw data one byte short" trunc.nrrd
{ nrrd_head float "2 2 2" raw; head -c 16 /dev/zero; } >endian.nrrd
case_bad "nrrd big-endian float of the wrong size" endian.nrrd
{ nrrd_head float "2 2 2" raw; printf '\177\300\000\000'; head -c 28 /dev/zero; } >nan.nrrd
case_bad "nrrd big-endian value that is not finite" nan.nrrd
{ nrrd_head float "100000 100000 100000" raw; head -c 32 /dev/zero; } >huge.nrrd
case_bad "nrrd sizes that would overflow memory" huge.nrrd
{ nrrd_head float "2 x 2" raw; head -c 32 /dev/zero; } >num.nrrd
case_bad "nrrd bad number in sizes" num.nrrd
if [ $have_gzip -eq 1 ]; then
    awk 'BEGIN { for (i = 0; i < 4096; i++) printf "%c", (i * 7) % 97 + 32 }' >vox.bin
    { nrrd_head uchar "16 16 16" gzip; gzip -c vox.bin; } >goodgz.nrrd
    case_good "nrrd gzip" goodgz.nrrd
    cp goodgz.nrrd corrupt.nrrd
    flip corrupt.nrrd
    case_bad "nrrd corrupt gzip (bytes flipped)" corrupt.nrrd
fi
head -c 32 /dev/zero >vol.raw
case_good raw vol.raw --dims 2,2,2 --type float32 --big-endian
head -c 30 /dev/zero >short.raw
case_bad "raw big-endian volume of the wrong size" short.raw --dims 2,2,2 --type float32 --big-endian

# ---- MetaImage: a missing companion (the data file)
printf 'ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = nowhere.raw\n' >nodata.mhd
case_bad "mhd data file missing" nodata.mhd

# ---- DCD: a missing companion, truncation (the shared trajectory)
if [ -n "$data" ] && [ -f "$data/particles/adk.dcd" ]; then
    cp "$data/particles/adk.dcd" adk.dcd
    case_bad "dcd with --topology pointing nowhere" adk.dcd --topology nowhere.psf
    head -c 5000 "$data/particles/adk.dcd" >short.dcd
    case_bad "dcd truncated" short.dcd --radius 1
else
    echo "skip: dcd cases ($data/particles/adk.dcd is absent)"
fi

# ---- GROMACS XTC / TRR (tests/data/traj): truncation, bad magic, a lying
# count, a topology pointing nowhere or of the wrong size, a frame past the end
if [ -n "$traj" ] && [ -f "$traj/adk_ca.xtc" ]; then
    cp "$traj/adk_ca.xtc" "$traj/adk_ca.gro" "$traj/adk_ca.trr" "$traj/small.xtc" .
    case_good xtc adk_ca.xtc
    case_good trr adk_ca.trr --frame 4
    head -c 300 adk_ca.xtc >cut.xtc
    case_bad "xtc truncated in frame 0" cut.xtc
    { be32 1996; tail -c +5 adk_ca.xtc; } >magic.xtc
    case_bad "xtc bad magic" magic.xtc
    { head -c 4 adk_ca.xtc; be32 215; tail -c +9 adk_ca.xtc; } >count.xtc
    case_bad "xtc atom counts that disagree" count.xtc
    case_bad "xtc with --topology pointing nowhere" adk_ca.xtc --topology nowhere.gro
    case_bad "xtc with a topology of another size" small.xtc --topology adk_ca.gro
    case_bad "xtc frame past the end" adk_ca.xtc --frame 10
    head -c 2000 adk_ca.trr >cut.trr
    case_bad "trr truncated in frame 0" cut.trr
    { be32 1990; tail -c +5 adk_ca.trr; } >magic.trr
    case_bad "trr bad magic" magic.trr
else
    echo "skip: xtc/trr cases (no trajectory directory given)"
fi

echo "$n malformed cases"
[ $fail -eq 0 ] && echo "PASS test_cli_malformed" || echo "FAIL test_cli_malformed"
exit $fail

#!/bin/sh
# Hardening of the loaders and the command line (issue 13, classes 3, 4, 5,
# 7 and 8; docs/HARDENING.md): each case runs `lanecast render` and checks
# the exit code (1: bad input, 2: bad flags), that stderr is one line
# holding the expected words, and for bad input that no image was written.
# Controls show each generator makes a file that renders when not damaged.
# usage: test_cli_hardening.sh LANECAST_EXE
set -u
exe=$1
case $exe in /*) ;; *) exe=$(pwd)/$exe ;; esac
fail=0
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
have_gzip=0
command -v gzip >/dev/null 2>&1 && "$exe" formats | grep -Eq '^ *zlib +yes' && have_gzip=1
have_json=0
"$exe" formats | grep -Eq '^ *json +yes' && have_json=1

# expect NAME RC WORDS -- ARGS...: exit RC, one stderr line containing WORDS
expect() {
    name=$1 want=$2 words=$3
    shift 4
    rm -f out.png
    timeout 20 "$exe" render "$@" >stdout 2>stderr
    rc=$?
    why=""
    [ $rc -eq "$want" ] || why="exit $rc, expected $want"
    if [ "$want" -ne 0 ]; then
        [ -z "$why" ] && [ "$(wc -l <stderr)" -ne 1 ] && why="$(wc -l <stderr) lines on stderr, expected 1"
        [ -z "$why" ] && ! grep -qF -- "$words" stderr && why="stderr lacks '$words'"
        [ -z "$why" ] && [ -e out.png ] && why="an image was written"
    fi
    if [ -z "$why" ]; then echo "ok   $name: $(head -c 300 stderr)"
    else
        echo "FAIL $name: $why"
        sed 's/^/     stderr: /' stderr
        fail=1
    fi
}
R="-o out.png --size 8x8 --quiet"
nhdr() { # nhdr FILE EXTRA-LINES DATAFILE [ENCODING]
    printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: %s\n%sdata file: %s\n\n' "${4:-raw}" "$2" "$3" >"$1"
}
printf '\001\002\003\004\005\006\007\010' >d8
nhdr good.nhdr "" d8
expect "control: detached NRRD" 0 "" -- good.nhdr $R

# ---- class 3: not a regular file (no allocation, no hang)
mkdir dir
nhdr dirdata.nhdr "" dir
expect "data file is a directory" 1 "its data file dir: is a directory" -- dirdata.nhdr $R
mkfifo fifo
nhdr fifodata.nhdr "" fifo
expect "data file is a FIFO (no hang)" 1 "its data file fifo: is a FIFO" -- fifodata.nhdr $R
expect "input is a FIFO (no hang)" 1 "fifo: is a FIFO" -- fifo $R --dims 2,2,2 --type uint8
expect "input is a directory" 1 "dir: is a directory" -- dir $R
expect "input is a device" 1 "null: is a device" -- /dev/null $R --dims 2,2,2 --type uint8
printf 'ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = dir\n' >dir.mhd
expect "MetaImage data file is a directory" 1 "its data file dir: is a directory" -- dir.mhd $R
# a load option at its bound, compared in float like the flag itself
printf '1\none atom\nH 0 0 0\n' >one.xyz
expect "control: --radius at its lower bound" 0 "" -- one.xyz --radius 1e-30 $R
# a TF argument naming a directory is a path, not an unknown colour map; a
# preset name stays a preset even when a directory of that name exists
expect "TF is a directory" 1 "dir: is a directory" -- good.nhdr --tf dir $R
mkdir heat
expect "control: preset name beside a directory" 0 "" -- good.nhdr --tf heat $R
rmdir heat
expect "TF file is a FIFO (no hang)" 1 "fifo: is a FIFO" -- good.nhdr $R --tf ./fifo

# ---- class 4: header offsets
for v in abc -2 -5 99999999999999999999 "12 junk" 4611686018427387905; do
    nhdr skip.nhdr "byte skip: $v
" d8
    expect "NRRD byte skip '$v'" 1 "skip.nhdr:6: byte skip" -- skip.nhdr $R
done
{ printf 'XXXX'; cat d8; } >d12
nhdr skipend.nhdr "byte skip: -1
" d12
expect "control: NRRD byte skip -1 (data at the end)" 0 "" -- skipend.nhdr $R
nhdr skip4.nhdr "byte skip: 4
" d12
expect "control: NRRD byte skip 4" 0 "" -- skip4.nhdr $R
mhd() { printf 'ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nHeaderSize = %s\nElementDataFile = %s\n' "$2" "$3" >"$1"; }
for v in -2 -100 9223372036854775807 x "4 4"; do
    mhd hs.mhd "$v" d12
    expect "MetaImage HeaderSize '$v'" 1 "hs.mhd:5: HeaderSize" -- hs.mhd $R
done
mhd hs.mhd -1 d12
expect "control: MetaImage HeaderSize -1" 0 "" -- hs.mhd $R
mhd hs.mhd 5 d12
expect "MetaImage HeaderSize past the data" 1 "holds 7 bytes of data but the sizes and type need 8" -- hs.mhd $R

# ---- class 5: memory limit, sizes before allocating
expect "--max-memory below the volume" 1 "more than the memory limit of 16 bytes" -- good.nhdr $R --max-memory 16
expect "control: --max-memory above the volume" 0 "" -- good.nhdr $R --max-memory 1M
expect "--max-memory not a size" 2 "--max-memory: '12Q' is not a size" -- good.nhdr $R --max-memory 12Q
head -c 36 /dev/zero >p.f32
expect "raw particles: count far over the file" 1 "holds 36 bytes, but a count of 1000000000 particles" -- p.f32 $R --raw-particles 1000000000 --radius 1
printf 'NRRD0004\ntype: float\ndimension: 3\nsizes: 1200 1200 1200\nencoding: raw\ndata file: d8\n\n' >big.nhdr
expect "7 GB volume from an 8-byte file" 1 "holds 8 bytes of data but the sizes and type need 6912000000" -- big.nhdr $R
if [ $have_gzip -eq 1 ]; then
    head -c 100000 /dev/zero | gzip >big.gz
    nhdr gzbig.nhdr "" big.gz gzip
    expect "gzip member larger than the volume" 1 "inflates to more than the 8 bytes" -- gzbig.nhdr $R
    { cat d8 | gzip; printf 'trailing'; } >trail.gz
    nhdr gztrail.nhdr "" trail.gz gzip
    expect "bytes after the gzip stream" 1 "8 bytes follow the end of the compressed data" -- gztrail.nhdr $R
    { head -c 4 d8 | gzip; tail -c 4 d8 | gzip; } >two.gz
    nhdr gztwo.nhdr "" two.gz gzip
    expect "control: two gzip members read as one" 0 "" -- gztwo.nhdr $R
    printf '2\nc\nC 0 0 0\nO 1 1 1\n' | gzip >a.xyz.gz
    printf 'junk' >>a.xyz.gz
    expect "xyz.gz with trailing bytes" 1 "follow the end of the compressed data" -- a.xyz.gz $R
fi

# ---- class 7: lenient input
for v in "0 0 0" "0 1 1" "1 1 1 junk" "1e-40 1 1" "nan 1 1"; do
    nhdr sp.nhdr "spacings: $v
" d8
    expect "NRRD spacings '$v'" 1 "sp.nhdr:6: spacings" -- sp.nhdr $R
done
nhdr so.nhdr "space origin: (1,2,3) junk
" d8
expect "NRRD space origin with junk" 1 "so.nhdr:6: space origin" -- so.nhdr $R
nhdr sz.nhdr "" d8
sed -i 's/^sizes: 2 2 2/sizes: 2 -2 2/' sz.nhdr
expect "NRRD negative size" 1 "sz.nhdr:4: sizes" -- sz.nhdr $R
: >empty.xyz
expect "empty XYZ" 1 "empty.xyz: no atoms" -- empty.xyz $R
printf '# only a comment\n\n' >comment.xyz
expect "XYZ of comments only" 1 "comment.xyz: no atoms" -- comment.xyz $R
printf -- '-3\nc\nC 0 0 0\n' >neg.xyz
expect "XYZ negative count" 1 "neg.xyz:1: atom count '-3'" -- neg.xyz $R
printf '2\nc\nC 0 0 0\nO 1 1 1\n' >good.xyz
expect "control: XYZ" 0 "" -- good.xyz $R
expect "--dims with a header file" 2 "--dims does not apply to good.nhdr" -- good.nhdr $R --dims 2,2,2 --type uint8
expect "--raw-particles with a header file" 2 "--raw-particles does not apply to good.xyz" -- good.xyz $R --raw-particles 2 --radius 1
expect "--raw-particles with --dims" 2 "does not apply" -- p.f32 $R --raw-particles 3 --radius 1 --dims 2,2,2

# ---- class 8: messages and exit codes
expect "--dt at its float bound" 0 "" -- good.nhdr $R --dt 1e-30
expect "--dt below its bound" 2 "--dt: 1e-31 is outside" -- good.nhdr $R --dt 1e-31
expect "--fov 179 (lc_camera refuses it)" 2 "--fov: 179 is outside [0.01, 179)" -- good.nhdr $R --fov 179
expect "--dims overflowing a grid" 2 "more than a grid holds" -- d8 $R --dims 2147483647,2,2 --type uint8
expect "--dims not integers" 2 "value 1 is not followed by ','" -- d8 $R --dims 16777217.5,2,2 --type uint8
expect "--dims 16777217 kept exact" 1 "need 67108868" -- d8 $R --dims 16777217,2,2 --type uint8
expect "-o ''" 2 "no output image" -- good.nhdr -o "" --size 8x8 --quiet
expect "eye and at too far apart" 1 "too far apart for float arithmetic" -- good.nhdr $R --eye 3e38,0,0 --at -3e38,0,0
expect "control: a far eye renders" 0 "" -- good.nhdr $R --eye 1e25,1e25,1e25 --at 0,0,0
expect "control: a long up vector" 0 "" -- good.nhdr $R --up 1e30,1e30,0
expect "tiny spacing: default extinction finite" 0 "" -- good.nhdr $R --spacing 1e-30,1e-30,1e-30 --tf heat
nhdr far.nhdr "space origin: (3e38,0,0)
" d8
expect "origin 3e38" 1 "origin 3e+38 and spacing 1 along x" -- far.nhdr $R
if [ $have_json -eq 1 ]; then # JSON parsing needs json-c (-Djson=disabled builds say so instead)
    : >empty.json
    expect "empty TF" 1 "empty.json: empty file" -- good.nhdr $R --tf empty.json
    printf '{"range": [0,1], "color": [[0,1,1' >trunc.json
    expect "truncated TF" 1 "ends at byte 33 inside an array" -- good.nhdr $R --tf trunc.json
else
    echo "skip empty and truncated TF: this build has no json-c"
fi
printf '{"range": [0,1], "opacity": [[0,0],[1,1]]\000}' >nul.json
expect "NUL byte in a TF" 1 "nul.json:1: a NUL byte" -- good.nhdr $R --tf nul.json
printf '2\nc\nC 0 0 0\nO 1 1\0001\n' >nul.xyz
expect "NUL byte in an XYZ line" 1 "nul.xyz:4: a NUL byte at column 6" -- nul.xyz $R
printf 'C 0 0 0%4088s' "" >long.xyz   # 4095 characters, no newline
expect "control: XYZ last line of 4095 characters without a newline" 0 "" -- long.xyz $R
printf 'C 0 0 0%4089s' "" >long2.xyz
expect "XYZ line over the stated limit" 1 "long2.xyz:1: line longer than 4095 characters" -- long2.xyz $R
d=$(printf 'd%.0s' $(seq 200))
mkdir -p "$d/$d/$d"
cp good.xyz "$d/$d/$d/atoms.xyz"
expect "control: a 600+ character particle path keeps its extension" 0 "" -- "$d/$d/$d/atoms.xyz" $R

[ $fail -eq 0 ] && echo "all hardening cases pass"
exit $fail

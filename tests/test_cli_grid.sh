#!/bin/sh
# lanecast render VOLUME: a good volume renders; bad volumes give one line on
# stderr, exit status 1, and no output file. usage: test_cli_grid.sh LANECAST
set -eu
exe=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
# 6x5x4 uint8 ramp
python3 -c "import sys; sys.stdout.buffer.write(bytes((i*7)%256 for i in range(120)))" > "$dir/v.raw"
"$exe" render "$dir/v.raw" --dims 6,5,4 --type uint8 --size 32x32 -o "$dir/ok.png" --quiet || { echo "FAIL good raw volume"; fail=1; }
[ -s "$dir/ok.png" ] || { echo "FAIL no image for the good volume"; fail=1; }
# an orthographic view along z, wider than the grid: missed rays' slab times reach +-1e30,
# which the scalar target once converted to int (UBSan stops the sanitizer build there)
LANECAST_TARGET=scalar "$exe" render "$dir/v.raw" --dims 6,5,4 --type uint8 --eye 2.5,2,30 --at 2.5,2,1.5 \
    --ortho 30 --size 32x32 -o "$dir/ortho.png" --quiet || { echo "FAIL orthographic view along z (scalar)"; fail=1; }
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 6 5 5\nencoding: raw\ndata file: v.raw\n' > "$dir/short.nhdr"
printf 'NRRD0004\ntype: complex\ndimension: 3\nsizes: 6 5 4\nencoding: raw\ndata file: v.raw\n' > "$dir/type.nhdr"
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 65536 65536 65536\nencoding: raw\ndata file: v.raw\n' > "$dir/ovf.nhdr"
head -c 30 "$dir/v.raw" | gzip -c | head -c 20 > "$dir/t.raw.gz"
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 6 5 4\nencoding: gzip\ndata file: t.raw.gz\n' > "$dir/trunc.nhdr"
for b in short type ovf trunc; do
    set +e
    "$exe" render "$dir/$b.nhdr" --size 32x32 -o "$dir/$b.png" 2> "$dir/err" > /dev/null
    rc=$?
    set -e
    lines=$(wc -l < "$dir/err")
    if [ "$rc" -ne 1 ] || [ "$lines" -ne 1 ] || [ -e "$dir/$b.png" ]; then
        echo "FAIL $b: exit $rc, $lines stderr lines, output $( [ -e "$dir/$b.png" ] && echo written || echo absent)"
        cat "$dir/err"
        fail=1
    else
        echo "ok   $b: $(cat "$dir/err")"
    fi
done
exit $fail

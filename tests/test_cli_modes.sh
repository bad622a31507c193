#!/bin/sh
# lanecast render --mode iso|slice: each kind renders in both modes; the
# modes' flags are checked (exit 2, one line on stderr, no image) and a field
# the data lacks fails in the library (exit 1, one line); --help shows an
# example of each. usage: test_cli_modes.sh LANECAST
set -eu
exe=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
python3 "$(dirname "$0")/cli_scenes.py" "$dir" # ball.raw, atoms.xyz, set.rbf
vol="$dir/ball.raw --dims 16,16,16 --type float32"
ok() { # name, args...: renders and writes the image
    name=$1
    shift
    if "$exe" render "$@" --size 24x24 -o "$dir/$name.png" --quiet 2> "$dir/err" && [ -s "$dir/$name.png" ]; then
        echo "ok   $name"
    else
        echo "FAIL $name: $(cat "$dir/err")"
        fail=1
    fi
}
bad() { # name, exit status, words the message must hold, args...
    name=$1 want=$2 words=$3
    shift 3
    set +e
    "$exe" render "$@" --size 24x24 -o "$dir/$name.png" 2> "$dir/err" > /dev/null
    rc=$?
    set -e
    lines=$(wc -l < "$dir/err")
    if [ "$rc" -ne "$want" ] || [ "$lines" -ne 1 ] || [ -e "$dir/$name.png" ] || ! grep -q -- "$words" "$dir/err"; then
        out=absent
        [ -e "$dir/$name.png" ] && out=written
        echo "FAIL $name: exit $rc (want $want), $lines stderr lines, output $out: $(cat "$dir/err")"
        fail=1
    else
        echo "ok   $name: $(cat "$dir/err")"
    fi
}
# shellcheck disable=SC2086
{
ok grid-iso $vol --mode iso --iso 0.5 --shade phong
ok grid-iso-brute $vol --mode iso --iso 0.5 --method brute
ok grid-slice $vol --mode slice --plane 7.5,7.5,7.5,0,0,1 --plane 7.5,7.5,7.5,1,1,0 --tf gray
ok particles-iso "$dir/atoms.xyz" --mode iso --iso 0.5 --fields element --field 1 --shade
ok particles-slice "$dir/atoms.xyz" --mode slice --plane 0,0,0,0,0,1 --method direct
ok rbf-iso "$dir/set.rbf" --mode iso --iso 0.3 --shade phong
ok rbf-slice "$dir/set.rbf" --mode slice --plane 0.2,0,0,1,0,1 --method brute
bad iso-without-value 2 "needs --iso" $vol --mode iso
bad slice-without-plane 2 "needs at least one --plane" $vol --mode slice
bad iso-with-dvr 2 "--iso applies to --mode iso only" $vol --iso 0.5
bad plane-with-mip 2 "--plane applies to --mode slice only" $vol --mode mip --plane 0,0,0,0,0,1
bad field-with-dvr 2 "--field applies to --mode iso or slice only" $vol --field 0
bad zero-normal 2 "normal" $vol --mode slice --plane 1,2,3,0,0,0
bad short-plane 2 "six numbers" $vol --mode slice --plane 1,2,3
bad five-planes 2 "at most 4 planes" $vol --mode slice --plane 0,0,0,0,0,1 --plane 0,0,0,0,0,1 \
    --plane 0,0,0,0,0,1 --plane 0,0,0,0,0,1 --plane 0,0,0,0,0,1
bad iso-nan 2 "not a number" $vol --mode iso --iso nan
bad unknown-mode 2 "dvr, mip, iso, slice" $vol --mode isosurface
bad missing-field 1 "field = 1" $vol --mode iso --iso 0.5 --field 1
}
help=$("$exe" render --help)
for want in "--mode iso --iso" "--mode slice --plane"; do
    if printf '%s\n' "$help" | grep -q -- "lanecast render .*$want"; then
        echo "ok   help: an example with $want"
    else
        echo "FAIL help: no example with $want"
        fail=1
    fi
done
exit $fail

#!/bin/sh
# lanecast render --lighting KA,KD,KS[,P]: the coefficients reach every kind's
# shading. Checks that follow from SPEC.md "Shading" without a stored image:
# SPEC's defaults spelled out give the default image byte for byte; KA 1,
# KD 0, KS 0 gives rgb * 1, i.e. the unshaded image, for diffuse and phong;
# another exponent changes the image. Bad values exit 2 with one line naming
# the flag and write no image. usage: test_cli_lighting.sh LANECAST
set -eu
exe=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
python3 "$(dirname "$0")/cli_scenes.py" "$dir" # ball.raw, atoms.xyz, set.rbf
render() { # out, args...
    out=$1
    shift
    "$exe" render "$@" --size 40x32 -o "$dir/$out.png" --quiet
}
same() { # what, a, b
    if cmp -s "$dir/$2.png" "$dir/$3.png"; then echo "ok   $1"; else echo "FAIL $1: $2 and $3 differ"; fail=1; fi
}
differ() {
    if cmp -s "$dir/$2.png" "$dir/$3.png"; then echo "FAIL $1: $2 and $3 are the same"; fail=1; else echo "ok   $1"; fi
}
vol="$dir/ball.raw --dims 16,16,16 --type float32"
atoms="$dir/atoms.xyz --fields element"
# shellcheck disable=SC2086
for kind in grid particles; do
    if [ $kind = grid ]; then src=$vol; else src=$atoms; fi
    for mode in dvr iso; do
        m="--mode $mode"
        [ $mode = iso ] && m="$m --iso 0.5"
        [ $mode = iso ] && [ $kind = particles ] && m="$m --field 1"
        k=$kind-$mode
        render $k-phong $src $m --shade phong
        render $k-phong-spelled $src $m --shade phong --lighting 0.2,0.8,0.4,16
        render $k-phong-nop $src $m --shade phong --lighting 0.2,0.8,0.4
        render $k-phong-64 $src $m --shade phong --lighting 0.2,0.8,0.4,64
        render $k-none $src $m --shade none
        render $k-diffuse-1 $src $m --shade diffuse --lighting 1,0,0
        render $k-phong-1 $src $m --shade phong --lighting 1,0,0,7
        render $k-diffuse $src $m --shade diffuse
        same "$k: SPEC's defaults spelled out = the default" $k-phong $k-phong-spelled
        same "$k: P omitted = 16" $k-phong $k-phong-nop
        same "$k: diffuse 1,0,0 = unshaded" $k-none $k-diffuse-1
        same "$k: phong 1,0,0,7 = unshaded" $k-none $k-phong-1
        differ "$k: exponent 64 changes phong" $k-phong $k-phong-64
        differ "$k: the shading is visible (diffuse != unshaded)" $k-diffuse $k-none
    done
done
bad() { # value, words the message must hold
    set +e
    "$exe" render $vol --size 8x8 -o "$dir/bad.png" --shade phong --lighting "$1" 2> "$dir/err" > /dev/null
    rc=$?
    set -e
    lines=$(wc -l < "$dir/err")
    if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ] || [ -e "$dir/bad.png" ] || ! grep -q -- "--lighting.*$2" "$dir/err"; then
        echo "FAIL --lighting '$1': exit $rc, $lines stderr lines: $(cat "$dir/err")"
        fail=1
    else
        echo "ok   --lighting '$1': $(cat "$dir/err")"
    fi
}
bad 1,2 "three or four numbers"
bad 1,1,1,1,1 "three or four numbers"
bad a,b,c "three or four numbers"
bad -1,0,0 "KA is -1"
bad 0,0,-0.5 "KS is -0.5"
bad 0.2,0.8,0.4,0.5 "integer from 1 to 256"
bad 0.2,0.8,0.4,257 "integer from 1 to 256"
bad nan,0,0 "three or four numbers"
exit $fail

#!/bin/sh
# lanecast render on bad flags and files: exit status in 1..127, exactly one
# line on stderr naming the flag or file, and no output file. Then a good
# render of 1tii.pdb writes a PNG (skipped with 77 if the data is absent).
# usage: test_particles_cli.sh LANECAST_EXE DATA_DIR
set -u
exe=$1
data=$2
fail=0
tmp=$(mktemp -d)
trap 'chmod -R u+w "$tmp" 2>/dev/null; rm -rf "$tmp"' EXIT
printf 'C 0 0 0\nO 1 0 0\nN 0 1 0\n' >"$tmp/ok.xyz"
printf 'C 0 0 0\nC 1 2\n' >"$tmp/short.xyz"
printf 'C 0 0 0\nC 1 2.y 3\n' >"$tmp/badnum.xyz"
mkdir "$tmp/ro" && chmod a-w "$tmp/ro"

# bad NEEDLE ARGS...: the render must fail cleanly, naming NEEDLE, writing no image
bad() {
    needle=$1; shift
    rm -f "$tmp"/out.* "$tmp"/ro/out.*
    "$exe" render "$@" >"$tmp/stdout" 2>"$tmp/stderr"
    rc=$?
    lines=$(wc -l <"$tmp/stderr")
    leftovers=$(ls "$tmp" "$tmp/ro" | grep -c '^out\.' || true)
    if [ "$rc" -ge 1 ] && [ "$rc" -lt 128 ] && [ "$lines" -eq 1 ] && grep -qF -- "$needle" "$tmp/stderr" && [ "$leftovers" -eq 0 ]; then
        echo "ok   render $* -> exit $rc: $(cat "$tmp/stderr")"
    else
        echo "FAIL render $* -> exit $rc, $lines stderr lines (want 1 naming '$needle'), $leftovers output files:"
        sed 's/^/     /' "$tmp/stderr"
        fail=1
    fi
}
o="$tmp/out.png"
bad --size "$tmp/ok.xyz" -o "$o" --size 0x5
bad --size "$tmp/ok.xyz" -o "$o" --size abc
bad --size "$tmp/ok.xyz" -o "$o" --size 16x
bad --dt "$tmp/ok.xyz" -o "$o" --dt -1
bad --dt "$tmp/ok.xyz" -o "$o" --dt
bad --method "$tmp/ok.xyz" -o "$o" --method foo
bad --target "$tmp/ok.xyz" -o "$o" --target foo
bad "-o" "$tmp/ok.xyz"
bad --frobnicate "$tmp/ok.xyz" -o "$o" --frobnicate
bad --eye "$tmp/ok.xyz" -o "$o" --eye 0,0,10
bad --eye "$tmp/ok.xyz" -o "$o" --eye 0,0
bad --sigma "$tmp/ok.xyz" -o "$o" --sigma x
bad --alpha-stop "$tmp/ok.xyz" -o "$o" --alpha-stop 2
# a read-only folder stops only non-root users; a file as the folder stops everyone
if [ "$(id -u)" -ne 0 ]; then bad "$tmp/ro" "$tmp/ok.xyz" -o "$tmp/ro/out.png" --size 16x16
else echo "skip read-only folder case: running as root"; fi
bad "$tmp/ok.xyz/out.png" "$tmp/ok.xyz" -o "$tmp/ok.xyz/out.png" --size 16x16
bad "$tmp/nodir" "$tmp/ok.xyz" -o "$tmp/nodir/out.png" --size 16x16
bad out.qqq "$tmp/ok.xyz" -o "$tmp/out.qqq" --size 16x16
bad missing.xyz "$tmp/missing.xyz" -o "$o" --size 16x16
bad short.xyz:2 "$tmp/short.xyz" -o "$o" --size 16x16
bad badnum.xyz:2 "$tmp/badnum.xyz" -o "$o" --size 16x16
bad --raw-particles "$tmp/ok.xyz" -o "$o" --raw-particles 0
bad "no input" -o "$o"
bad --kernel "$tmp/ok.xyz" -o "$o" --kernel m7
bad --hsml-is "$tmp/ok.xyz" -o "$o" --hsml-is x
bad hsml_is "$tmp/ok.xyz" -o "$o" --hsml-is h

# an SPH kernel renders and is reported (issue 27)
if "$exe" render "$tmp/ok.xyz" -o "$tmp/sph.png" --size 32x24 --radius 1.5 --kernel wendland-c2 --stats --quiet \
    >"$tmp/stdout" 2>&1 && [ -s "$tmp/sph.png" ] && grep -q '^kernel  *wendland-c2 (radius = support radius H)' "$tmp/stdout"; then
    echo "ok   render --kernel wendland-c2: $(grep '^kernel' "$tmp/stdout")"
else
    echo "FAIL render --kernel wendland-c2"; cat "$tmp/stdout"; fail=1
fi

# a good render of a real molecule
pdb="$data/particles/1tii.pdb"
if [ ! -f "$pdb" ]; then
    echo "skip: $pdb not found (set -Ddata_dir=...)"
    [ $fail -eq 0 ] && exit 77 || exit 1
fi
"$exe" render "$pdb" -o "$tmp/1tii.png" --size 64x48 --shade --fields element --tf demo --quiet 2>"$tmp/stderr"
rc=$?
if [ $rc -eq 0 ] && [ -s "$tmp/1tii.png" ] && [ "$(head -c 4 "$tmp/1tii.png" | od -An -c | tr -d ' ')" = "211PNG" ] && [ ! -s "$tmp/stderr" ]; then
    echo "ok   render 1tii.pdb -> PNG of $(wc -c <"$tmp/1tii.png") bytes"
else
    echo "FAIL render 1tii.pdb -> exit $rc"; cat "$tmp/stderr"; fail=1
fi
[ $fail -eq 0 ] && echo "test_particles_cli: PASS" || echo "test_particles_cli: FAIL"
exit $fail

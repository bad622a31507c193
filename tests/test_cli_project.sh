#!/bin/sh
# lanecast render --mode project (tools/cli_project.c): a CSV of particles
# inside the image projects to a map whose sum (--stats "map sum") is the sum
# of their masses; float maps (.npy + .json, .fits when the build has cfitsio,
# .exr) and a colour image with a colour bar are written; bad flags fail with
# one line naming the flag (exit 2) and a perspective camera with one line
# saying to use --ortho (exit 1), nothing written; without the OpenImageIO
# module a float map is still written, a colour image fails. usage: test_cli_project.sh LANECAST
set -eu
exe=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
# 400 particles on a jittered grid inside [-8, 8]^2, radius 0.05 .. 2, mass 1 + (i mod 7) / 10
awk 'BEGIN { print "x,y,z,radius,mass"; s = 0;
  for (i = 0; i < 400; i++) { x = -7 + 14 * ((i % 20) + 0.3) / 20; y = -7 + 14 * (int(i / 20) + 0.6) / 20;
    r = 0.05 + 1.95 * ((i * 37) % 100) / 100; if (r > 8 - (x < 0 ? -x : x)) r = 1; if (r > 8 - (y < 0 ? -y : y)) r = 1;
    m = 1 + (i % 7) / 10; s += m; printf "%.6f,%.6f,%.3f,%.6f,%.3f\n", x, y, (i % 5) - 2, r, m }
  printf "%.6f\n", s > "/dev/stderr" }' > "$dir/p.csv" 2> "$dir/total"
total=$(cat "$dir/total")
cam="--eye 0,0,50 --at 0,0,0 --ortho 16 --size 128x128"
check() { # name, condition (shell), message
    if eval "$2"; then echo "ok   $1"; else echo "FAIL $1: $3"; fail=1; fi
}
for k in m4 wendland-c2 m6; do
    "$exe" render "$dir/p.csv" --mode project --kernel $k $cam -o "$dir/m_$k.npy" --stats > "$dir/out" 2> "$dir/err" || true
    sum=$(awk '/^map sum/ { print $3 }' "$dir/out")
    check "$k: map sum $sum = total mass $total" \
        "awk -v a=\"$sum\" -v b=\"$total\" 'BEGIN { d = a - b; exit !(a != \"\" && (d < 0 ? -d : d) < 1e-5 * b) }'" \
        "$(cat "$dir/err")"
    check "$k: .npy and .npy.json written" "[ -s \"$dir/m_$k.npy\" ] && grep -q '\"kernel\": \"$k\"' \"$dir/m_$k.npy.json\"" \
        "missing"
done
"$exe" render "$dir/p.csv" --mode project --kernel m4 $cam --sample centre -o "$dir/c.exr" --quiet 2> "$dir/err" &&
    check "centre sampling to .exr" "[ -s \"$dir/c.exr\" ]" "empty" || { echo "FAIL exr: $(cat "$dir/err")"; fail=1; }
"$exe" render "$dir/p.csv" --mode project --kernel m4 $cam --colorbar --colormap inferno -o "$dir/c.png" > "$dir/out" 2> "$dir/err" &&
    check "colour image with a colour bar (log scale)" "[ -s \"$dir/c.png\" ] && grep -q 'log10' \"$dir/out\"" "$(cat "$dir/err")" ||
    { echo "FAIL png: $(cat "$dir/err")"; fail=1; }
if "$exe" formats | grep -q "fits .*yes\|cfitsio.*yes"; then
    "$exe" render "$dir/p.csv" --mode project --kernel m4 $cam -o "$dir/m.fits" --quiet 2> "$dir/err" &&
        check ".fits written" "head -c 2880 \"$dir/m.fits\" | grep -q 'KERNEL' " "no KERNEL keyword" ||
        { echo "FAIL fits: $(cat "$dir/err")"; fail=1; }
else
    echo "skip .fits: this build lacks cfitsio (libcfitsio-dev)"
fi
bad() { # name, exit status, words, args...
    name=$1 want=$2 words=$3
    shift 3
    set +e
    "$exe" render "$dir/p.csv" "$@" -o "$dir/bad.npy" > /dev/null 2> "$dir/err"
    rc=$?
    set -e
    lines=$(wc -l < "$dir/err")
    if [ "$rc" -ne "$want" ] || [ "$lines" -ne 1 ] || [ -e "$dir/bad.npy" ] || ! grep -q -- "$words" "$dir/err"; then
        echo "FAIL $name: exit $rc (want $want), $lines lines: $(cat "$dir/err")"
        fail=1
    else
        echo "ok   $name: $(cat "$dir/err")"
    fi
}
bad "bad --sample" 2 "--sample" --mode project --sample middle
bad "--weight without --mode project" 2 "--weight applies to --mode project" --weight mass
bad "bad --kernel" 2 "--kernel: 'cubic'" --mode project --kernel cubic
bad "bad --depth" 2 "--depth" --mode project --depth -1
bad "perspective" 1 "--ortho" --mode project --kernel m4 --eye 0,0,50 --at 0,0,0
bad "unknown --weight field" 1 "nosuch" --mode project --kernel m4 --weight nosuch
bad "--normalise with a projection" 2 "--normalise applies to the dvr" --mode project --kernel m4 --normalise
# OpenImageIO is a module loaded by the first image write (host/api/image.c): a float map needs none, a
# colour image without it fails before the load with a message naming the module, nothing written
LANECAST_OIIO_MODULE="$dir/none.so" "$exe" render "$dir/p.csv" --mode project --kernel m4 $cam -o "$dir/nm.npy" --quiet \
    2> "$dir/err" && check "no OpenImageIO module: .npy written" "[ -s \"$dir/nm.npy\" ]" "empty" ||
    { echo "FAIL no module, .npy: $(cat "$dir/err")"; fail=1; }
if LANECAST_OIIO_MODULE="$dir/none.so" "$exe" render "$dir/p.csv" --mode project --kernel m4 $cam -o "$dir/nm.png" \
    > /dev/null 2> "$dir/err"; then echo "FAIL no module, .png: exit 0"; fail=1
else check "no OpenImageIO module: .png fails naming it, nothing written" \
    "grep -q 'OpenImageIO module could not be loaded' \"$dir/err\" && [ ! -e \"$dir/nm.png\" ]" "$(cat "$dir/err")"
fi
"$exe" render --help | grep -q "projections (--mode project" && echo "ok   --help has the projections section" ||
    { echo "FAIL --help lacks the projections section"; fail=1; }
exit $fail

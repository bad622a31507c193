#!/bin/sh
# Image output: files appear complete or not at all. A write that fails (a
# full disk, simulated with LANECAST_TEST_WRITE_LIMIT) exits 1 with one line,
# leaves an existing image of that name untouched and no temporary file; the
# temporary file is private (mkstemps), so a name planted next to the target
# is never written through. usage: test_image_write.sh LANECAST
set -u
exe=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail=0
for ext in png exr tif jpg bmp; do
    "$exe" demo --size 48x40 -o "$dir/good.$ext" --quiet || { echo "FAIL $ext: the good render"; fail=1; continue; }
    cp "$dir/good.$ext" "$dir/keep.$ext"
    LANECAST_TEST_WRITE_LIMIT=64 "$exe" demo --size 48x40 -o "$dir/good.$ext" > /dev/null 2> "$dir/err"
    rc=$?
    lines=$(wc -l < "$dir/err")
    if [ "$rc" -ne 1 ] || [ "$lines" -ne 1 ] || ! grep -q "No space left" "$dir/err"; then
        echo "FAIL $ext full disk: exit $rc, $lines lines: $(cat "$dir/err")"; fail=1
    elif ! cmp -s "$dir/good.$ext" "$dir/keep.$ext"; then
        echo "FAIL $ext full disk: the existing image was changed"; fail=1
    else
        echo "ok   $ext full disk: $(cat "$dir/err")"
    fi
done
left=$(ls "$dir" | grep -c lanecast- || true)
[ "$left" -eq 0 ] || { echo "FAIL $left temporary files left: $(ls "$dir")"; fail=1; }
[ "$left" -eq 0 ] && echo "ok   no temporary files left"
# a symlink planted under the old predictable temporary name is not followed
echo precious > "$dir/target"
ln -s "$dir/target" "$dir/out.lanecast-tmp-$$.png"
"$exe" demo --size 32x32 -o "$dir/out.png" --quiet
[ "$(cat "$dir/target")" = precious ] && echo "ok   planted symlink untouched" || { echo "FAIL the symlink target was overwritten"; fail=1; }
[ $fail -eq 0 ] && echo "PASS test_image_write" || echo "FAIL test_image_write"
exit $fail

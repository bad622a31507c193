#!/bin/sh
# lanecast view under an Xvfb of its own (Xvfb -displayfd picks a free
# display, so parallel tests never collide). One case per run:
#   nodisplay   no DISPLAY: the one line, exit 1
#   badfile     a malformed input: the loader's message (as lanecast render
#               gives it), exit 1, no window
#   screenshot  --screenshot equals lanecast render with the same options, bit
#               for bit (PNG bytes; EXR values), for particles, a grid, mip,
#               iso and a target
#   script      after --script orbits/zooms/pans, the printed camera renders
#               the saved frame with lanecast render, and the view did move
#               (the camera is printed exactly, so the images are equal: a
#               stronger check than the issue's PSNR >= 50 dB)
#   xinput      the same after real X input (xdotool: drag, wheel, keys c, s, q)
#   tf          a TF edited by script changes the image; the saved JSON
#               renders the same image through lanecast render --tf
#   switch      mode, shading and target switched live by --script equal
#               lanecast render given the same (mip on sse4, iso on scalar, slice)
#   frames      stepping through a trajectory's frames (loaded in the
#               background) shows what lanecast render --frame N renders; a
#               frame that fails to load leaves the current one, with the error
#   random      1000 random events (drags, wheel, keys, panel values past
#               their bounds, TF points, targets, frame steps) end in bounded
#               time with a refined screenshot, no crash
# usage: test_view.sh LANECAST VIEW_IMGCMP DATA_DIR CASE
# Skips (77) when the build lacks the viewer feature (after checking its
# message) or Xvfb is missing.
set -u
exe=$1 cmpx=$2 data=$3 case=$4
abs() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
exe=$(abs "$exe") cmpx=$(abs "$cmpx") data=$(abs "$data")
supp="$(cd "$(dirname "$0")" && pwd)/view_lsan.supp"
dir=$(mktemp -d)
xpid=""
cleanup() {
    [ -n "$xpid" ] && kill "$xpid" 2> /dev/null
    rm -rf "$dir"
}
trap cleanup EXIT
cd "$dir" || exit 1
fail=0
ok() { echo "ok   $*"; }
bad() { echo "FAIL $*"; fail=1; }

if ! "$exe" formats | grep -q "^  viewer yes"; then
    env -u DISPLAY "$exe" view --demo > out 2> err
    rc=$?
    if [ $rc -eq 1 ] && grep -q "no viewer: install libglfw3-dev libimgui-dev libstb-dev" err; then
        echo "SKIP test_view $case: this build has no viewer ($(cat err))"
        exit 77
    fi
    echo "FAIL test_view: without the viewer, lanecast view exited $rc with: $(cat err)"
    exit 1
fi

if [ "$case" = nodisplay ]; then
    env -u DISPLAY "$exe" view --demo --size 64x64 > out 2> err
    rc=$?
    want="lanecast view: no display (DISPLAY is not set); lanecast render writes images"
    [ $rc -eq 1 ] && [ "$(cat err)" = "$want" ] && ok "no display: exit 1, '$want'" ||
        bad "no display: exit $rc, stderr '$(cat err)'"
    [ -s out ] && bad "no display: wrote to stdout: $(cat out)"
    [ $fail -eq 0 ] && echo "PASS test_view $case" || echo "FAIL test_view $case"
    exit $fail
fi

command -v Xvfb > /dev/null || { echo "SKIP test_view $case: no Xvfb (Debian: xvfb)"; exit 77; }
mkfifo xfd
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3> xfd 2> xvfb.log &
xpid=$!
read -r dnum < xfd || { echo "FAIL test_view: Xvfb did not start: $(cat xvfb.log)"; exit 1; }
export DISPLAY=":$dnum"

# a second target to switch to: sse4 when this build and CPU have it
t2=$("$exe" targets | awk '$1 == "sse4" && $3 == "yes" && $4 == "yes" {print "sse4"}')
t2=${t2:-scalar}
# engine.nhdr's data is gzip-compressed: only with zlib
gz=$("$exe" formats | grep "^  zlib   yes" || true)

# Sanitizer builds: the X11/GLX/Mesa stack keeps some allocations to the end
# (tests/view_lsan.supp); lanecast's own leaks are still reported.
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$supp"

# lanecast view with a time bound: a hang fails the test instead of stalling it.
view() { timeout 120 "$exe" view "$@"; }
# The flags of the first camera line lanecast view printed (in file $1).
camera_of() { grep -m1 -- '^--eye ' "$1"; }

case "$case" in
badfile)
    printf 'NRRD0004\ntype: float\ndimension: 3\nsizes: 4 4\nencoding: raw\n\n' > bad.nrrd
    view bad.nrrd --size 64x64 > out 2> err
    rc=$?
    "$exe" render bad.nrrd --size 64x64 -o r.png > /dev/null 2> rerr
    want=$(sed 's/^lanecast render:/lanecast view:/' rerr)
    [ $rc -eq 1 ] && [ "$(cat err)" = "$want" ] && [ "$(wc -l < err)" -eq 1 ] && ok "bad file: exit 1, '$want'" ||
        bad "bad file: exit $rc, stderr '$(cat err)' (lanecast render says '$(cat rerr)')"
    command -v xdotool > /dev/null && xdotool search --name "lanecast view" > wins 2> /dev/null
    [ -s wins ] 2> /dev/null && bad "bad file: a window is left: $(cat wins)"
    view no-such-file.nhdr > out 2> err
    rc=$?
    [ $rc -eq 1 ] && grep -q "no-such-file.nhdr" err && ok "missing file: exit 1, $(cat err)" ||
        bad "missing file: exit $rc, $(cat err)"
    ;;
screenshot)
    check_same() { # NAME EXT ARGS...: view --screenshot vs render -o
        name=$1 ext=$2
        shift 2
        view "$@" --screenshot "v-$name.$ext" > out 2> err || { bad "$name: view failed: $(cat err)"; return; }
        "$exe" render "$@" -o "r-$name.$ext" --quiet 2> err || { bad "$name: render failed: $(cat err)"; return; }
        if [ "$ext" = png ]; then
            cmp -s "v-$name.$ext" "r-$name.$ext" && ok "$name: the same PNG bytes" || bad "$name: PNG bytes differ"
        else
            "$cmpx" "v-$name.$ext" "r-$name.$ext" exact > cmp.out && ok "$name: $(cat cmp.out)" ||
                bad "$name: $(cat cmp.out)"
        fi
    }
    view --demo --size 200x150 --screenshot v-demo.png > /dev/null 2> err || bad "demo: $(cat err)"
    "$exe" demo --size 200x150 -o r-demo.png --quiet
    cmp -s v-demo.png r-demo.png && ok "demo 200x150: the same PNG bytes" || bad "demo: PNG bytes differ"
    # the comparer must see a different view as different
    "$exe" demo --size 200x150 --view 40,25 -o r-demo2.png --quiet
    "$cmpx" v-demo.png r-demo2.png exact > cmp.out && bad "a different view compares equal: $(cat cmp.out)" ||
        ok "a different view differs ($(cat cmp.out))"
    if [ -f "$data/volumes/engine.nhdr" ] && [ -n "$gz" ]; then
        check_same engine exr "$data/volumes/engine.nhdr" --size 160x128 --shade phong
        check_same "engine-iso-$t2" exr "$data/volumes/engine.nhdr" --size 128x128 --mode iso --iso 150 --shade \
            --target "$t2"
    else
        echo "skip engine cases: no $data/volumes/engine.nhdr, or no gzip input in this build (zlib1g-dev)"
    fi
    if [ -f "$data/particles/1tii.pdb" ]; then
        check_same 1tii png "$data/particles/1tii.pdb" --size 128x96 --shade --eye 60,40,90 --at 0,0,0 --fov 35
    else
        echo "skip 1tii: no $data/particles/1tii.pdb"
    fi
    ;;
script)
    printf 'orbit 60 -30\nzoom 2\npan 12 -7\norbit -15 40\nwait\ncamera\nscreenshot moved.exr\nquit\n' > s.txt
    view --demo --size 192x160 --script s.txt > out 2> err
    rc=$?
    cam=$(camera_of out)
    [ $rc -eq 0 ] && [ -n "$cam" ] && [ -f moved.exr ] || bad "script: exit $rc, camera '$cam', $(cat err)"
    # shellcheck disable=SC2086
    "$exe" demo --size 192x160 $cam -o again.exr --quiet || bad "render with '$cam' failed"
    "$cmpx" moved.exr again.exr exact > cmp.out && ok "script: lanecast render $cam: $(cat cmp.out)" ||
        bad "script: $(cat cmp.out)"
    "$exe" demo --size 192x160 -o home.exr --quiet
    "$cmpx" moved.exr home.exr 50 > cmp.out && bad "script: the view did not move ($(cat cmp.out))" ||
        ok "script: the view moved"
    # key r goes back to the first view
    printf 'orbit 80 20\nzoom -3\nwait\nkey r\nwait\nscreenshot reset.exr\nquit\n' > r.txt
    view --demo --size 192x160 --script r.txt > out 2> err || bad "script r: $(cat err)"
    "$cmpx" reset.exr home.exr exact > cmp.out && ok "script: key r: the first view again" ||
        bad "script: key r: $(cat cmp.out)"
    # adaptive navigation quality: after a navigation frame of ms at scale 2, far over --target-ms 1,
    # the next one jumps to ceil(2 sqrt(ms / 1)) (at least 3, at most 16: viewer/view_action.c)
    printf 'down 192 192\nmove 200 196\nwait-frame\nstats\nmove 208 200\nwait-frame\nstats\nup\nquit\n' > a.txt
    view --demo --size 384x384 --target-ms 1 --script a.txt > out 2> err || bad "adaptive: $(cat err)"
    got=$(awk '/^stats nav 1/ {printf "%s %s ", $5, $11}' out)
    echo "$got" | awk '{ms = $2; want = int(2 * sqrt(ms)); if (want < 2 * sqrt(ms)) want++; if (want < 3) want = 3;
        if (want > 16) want = 16; exit !($1 == 2 && $3 == want)}' && ok "adaptive: scale, ms: $got" ||
        bad "adaptive: scale, ms of two navigation frames: '$got' (the second scale should be ceil(2 sqrt(ms)))"
    ;;
xinput)
    command -v xdotool > /dev/null || { echo "SKIP test_view xinput: no xdotool (Debian: xdotool)"; exit 77; }
    timeout 120 "$exe" view --demo --size 256x256 > out 2> err &
    vpid=$!
    wid=$(timeout 30 xdotool search --sync --name "lanecast view" | head -n1)
    [ -n "$wid" ] || { bad "xinput: no window"; kill $vpid; wait; exit 1; }
    xdotool windowfocus --sync "$wid" 2> /dev/null
    sleep 0.5
    xdotool mousemove --window "$wid" 128 140 mousedown 1
    for x in 140 152 164 176 188; do xdotool mousemove --window "$wid" "$x" $((x / 2 + 60)); sleep 0.05; done
    xdotool mouseup 1
    xdotool mousemove --window "$wid" 128 200 mousedown 2 mousemove --window "$wid" 120 190 mouseup 2
    xdotool click 4 click 4 click 5 click 4
    sleep 0.5
    xdotool key --window "$wid" c s q
    wait $vpid
    rc=$?
    cam=$(camera_of out)
    shot=lanecast-view-000.png
    [ $rc -eq 0 ] && [ -n "$cam" ] && [ -f $shot ] || bad "xinput: exit $rc, camera '$cam', files $(ls), $(cat err)"
    # shellcheck disable=SC2086
    "$exe" demo --size 256x256 $cam -o again.png --quiet || bad "render with '$cam' failed"
    "$cmpx" $shot again.png exact > cmp.out && ok "xinput: lanecast render $cam: $(cat cmp.out)" ||
        bad "xinput: $(cat cmp.out)"
    "$exe" demo --size 256x256 -o home.png --quiet
    "$cmpx" $shot home.png 50 > cmp.out && bad "xinput: the view did not move ($(cat cmp.out))" ||
        ok "xinput: the drags and the wheel moved the view"
    ;;
tf)
    printf 'tf 0 1 0.5 0.9\ntf 1 0 0.3 0.2\nset colormap inferno\nset opacity_scale 1.5\nwait\nscreenshot edited.png\nsave-tf t.json\nquit\n' > s.txt
    view --demo --size 160x160 --script s.txt > out 2> err
    rc=$?
    [ $rc -eq 0 ] && [ -f edited.png ] && [ -f t.json ] || bad "tf: exit $rc, $(cat err)"
    "$exe" demo --size 160x160 -o home.png --quiet
    cmp -s edited.png home.png && bad "tf: the edit did not change the image" || ok "tf: the edit changed the image"
    if "$exe" formats | grep -q "^  json   yes"; then
        "$exe" demo --size 160x160 --tf t.json -o cli.png --quiet 2> err || bad "tf: lanecast render --tf t.json: $(cat err)"
        cmp -s edited.png cli.png && ok "tf: the saved TF renders the same PNG through lanecast render --tf" ||
            bad "tf: lanecast render --tf t.json differs ($("$cmpx" edited.png cli.png 50))"
    else
        echo "skip reading the saved TF back: this build has no JSON transfer functions (libjson-c-dev)"
    fi
    ;;
random)
    awk -v seed=24 'BEGIN {
        srand(seed)
        split("alpha_stop sigma kappa ka kd ks phong_exp threads nav_scale nav_step target_ms adaptive opacity_scale plane_axis plane_pos box iso dt range_lo range_hi field refine_delay", num, " ")
        split("mode:dvr mode:mip mode:iso mode:slice shading:none shading:diffuse shading:phong method:default method:coherent method:direct method:bvh method:brute target:scalar target:sse4 target:avx2 target:avx512 target:auto colormap:viridis colormap:gray", word, " ")
        split("r h b c", keys, " ")
        for (i = 0; i < 1000; i++) {
            e = int(rand() * 9)
            if (e == 0) printf "orbit %d %d\n", int(rand() * 600) - 300, int(rand() * 600) - 300
            else if (e == 1) printf "pan %d %d\n", int(rand() * 600) - 300, int(rand() * 600) - 300
            else if (e == 2) printf "zoom %d\n", int(rand() * 11) - 5
            else if (e == 3) printf "key %s\n", keys[1 + int(rand() * 4)]
            else if (e == 4) { b = rand(); printf "set %s %s\n", num[1 + int(rand() * 22)], b < 0.4 ? "-1e30" : b < 0.8 ? "1e30" : rand() }
            else if (e == 5) { w = word[1 + int(rand() * 19)]; sub(":", " ", w); printf "set %s\n", w }
            else if (e == 6) printf "tf %d %d %g %g\n", int(rand() * 3) - 1, int(rand() * 6) - 1, rand() * 1.4 - 0.2, rand() * 3 - 1
            else if (e == 7) printf "tf-delete %d %d\n", int(rand() * 3), int(rand() * 4)
            else printf "step %d\n", int(rand() * 5) - 2
        }
        print "set target auto"; print "set sigma 2"; print "set threads 0"; print "set method default"
        print "wait"; print "screenshot last.png"; print "quit"
    }' > s.txt
    start=$(date +%s)
    view --demo --size 64x64 --script s.txt > out 2> err
    rc=$?
    t=$(($(date +%s) - start))
    [ $rc -eq 0 ] && [ -f last.png ] && ok "random: 1000 events in ${t}s, exit 0, a refined screenshot" ||
        bad "random: exit $rc after ${t}s: $(tail -n3 err)"
    ;;
switch)
    # mode, shading and target switched live by script equal lanecast render given them
    if [ -f "$data/volumes/engine.nhdr" ] && [ -n "$gz" ]; then
        in="$data/volumes/engine.nhdr" sz="--size 128x112" iso=150
    else
        in="" sz="--size 128x112" iso=0.5
        echo "(no engine.nhdr or no gzip input: the demo scene)"
    fi
    run_view() { if [ -n "$in" ]; then view "$in" "$@"; else view --demo "$@"; fi; }
    run_render() { if [ -n "$in" ]; then "$exe" render "$in" "$@"; else "$exe" demo "$@"; fi; }
    printf '%s\n' 'set mode mip' "set target $t2" 'wait' 'screenshot mip.png' "mode iso $iso" 'set shading phong' \
        'set target scalar' 'wait' 'screenshot iso.png' 'set mode slice' 'set plane_axis 0' 'set plane_pos 0.25' \
        'set target auto' 'wait' 'screenshot slice.png' 'quit' > s.txt
    # shellcheck disable=SC2086
    run_view $sz --script s.txt > out 2> err || bad "switch: view: $(cat err)"
    # shellcheck disable=SC2086
    run_render $sz --mode mip --target "$t2" -o r-mip.png --quiet
    # shellcheck disable=SC2086
    run_render $sz --mode iso --iso $iso --shade phong --target scalar -o r-iso.png --quiet
    # the slice plane: the box's centre, a quarter across in x (the info's bounds)
    plane=$(if [ -n "$in" ]; then "$exe" info "$in"; else echo "bounds -1 -1 -1 .. 1 1 1"; fi |
        awk '/^bounds/ {printf "%.9g,%.9g,%.9g,1,0,0", $2 + 0.25 * ($6 - $2), ($3 + $7) / 2, ($4 + $8) / 2}')
    [ -n "$in" ] && run_render $sz --mode slice --plane "$plane" -o r-slice.png --quiet
    for m in mip iso slice; do
        [ $m = slice ] && [ -z "$in" ] && continue
        cmp -s $m.png r-$m.png && ok "switch: $m equals lanecast render's" || bad "switch: $m differs: $("$cmpx" $m.png r-$m.png 50)"
    done
    cmp -s mip.png iso.png && bad "switch: mip and iso look the same"
    ;;
frames)
    # a frame that fails to load in the background: the current frame stays, the error is said
    printf '%s\n' 'MODEL        1' \
        'ATOM      1  CA  ALA A   1       0.000   0.000   0.000  1.00  0.00           C' \
        'ATOM      2  CA  ALA A   2       3.800   0.000   0.000  1.00  0.00           C' \
        'ATOM      3  CA  ALA A   3       3.800   3.800   0.000  1.00  0.00           C' \
        'ENDMDL' 'MODEL        2' \
        'ATOM      1  CA  ALA A   1       0.000   0.000   0.000  1.00  0.00           C' \
        'ATOM      2  CA  ALA A   2       3.800   xx.xxx  0.000  1.00  0.00           C' \
        'ENDMDL' 'END' > two.pdb
    printf 'step 1\nwait\nscreenshot after.png\nquit\n' > s.txt
    view two.pdb --size 96x96 --script s.txt > out 2> err
    rc=$?
    "$exe" render two.pdb --size 96x96 -o f0.png --quiet
    [ $rc -eq 0 ] && grep -q "frame 1: two.pdb:8: ATOM record" err && cmp -s after.png f0.png &&
        ok "a frame failing to load: $(grep 'frame 1' err); frame 0 stays" ||
        bad "a frame failing to load: exit $rc, $(cat err)"
    if [ -f "$data/particles/adk.dcd" ]; then
        cam="--eye 60,30,90 --at 0,0,0 --size 128x128"
        printf 'step 3\nwait\nscreenshot f3.png\nstep -1\nwait\nscreenshot f2.png\nquit\n' > s.txt
        # shellcheck disable=SC2086
        view "$data/particles/adk.dcd" $cam --script s.txt > out 2> err || bad "adk frames: $(cat err)"
        for f in 2 3; do
            # shellcheck disable=SC2086
            "$exe" render "$data/particles/adk.dcd" $cam --frame $f -o r$f.png --quiet
            cmp -s f$f.png r$f.png && ok "adk.dcd: frame $f stepped to in the view == lanecast render --frame $f" ||
                bad "adk.dcd frame $f differs: $("$cmpx" f$f.png r$f.png 50)"
        done
        cmp -s f2.png f3.png && bad "adk.dcd: frames 2 and 3 look the same"
    else
        echo "skip adk.dcd: no $data/particles/adk.dcd"
    fi
    ;;
*)
    echo "test_view.sh: unknown case '$case'"
    exit 2
    ;;
esac
[ $fail -eq 0 ] && echo "PASS test_view $case" || echo "FAIL test_view $case"
exit $fail

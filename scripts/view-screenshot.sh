#!/bin/sh
# The README's picture of lanecast view: the window (image, overlay and
# panels) on an Xvfb screen, dumped from Xvfb's frame buffer file and
# cropped to the window. usage: scripts/view-screenshot.sh [OUT.png]
# (default docs/images/view.png; needs a built ./build/tools/lanecast, Xvfb
# and python3; uses the engine CT of ../shared/data, else the demo scene).
set -eu
cd "$(dirname "$0")/.."
out=${1:-docs/images/view.png}
exe=$PWD/build/tools/lanecast
data=${LANECAST_DATA:-$PWD/../shared/data}
W=760 H=520
tmp=$(mktemp -d)
xpid="" vpid=""
trap '[ -n "$vpid" ] && kill $vpid 2> /dev/null; [ -n "$xpid" ] && kill $xpid 2> /dev/null; rm -rf "$tmp"' EXIT
mkfifo "$tmp/xfd"
Xvfb -displayfd 3 -screen 0 1024x768x24 -fbdir "$tmp" -nolisten tcp 3> "$tmp/xfd" 2> "$tmp/xvfb.log" &
xpid=$!
read -r dnum < "$tmp/xfd"
if [ -f "$data/volumes/engine.nhdr" ]; then
    set -- "$data/volumes/engine.nhdr" --shade phong --colormap inferno
else
    set -- --demo
fi
# orbit a little, open the panels, refine, say so on stdout, hold the frame (killed when dumped)
printf 'orbit 50 -20\nset panels 1\nset box 1\nwait\ncamera\nsleep 60\nquit\n' > "$tmp/s.txt"
DISPLAY=":$dnum" "$exe" view "$@" --size ${W}x${H} --script "$tmp/s.txt" > "$tmp/out" &
vpid=$!
i=0
until grep -q -- '^--eye' "$tmp/out"; do
    i=$((i + 1))
    [ $i -lt 600 ] || { echo "view-screenshot: lanecast view did not refine its frame" >&2; exit 1; }
    sleep 0.1
done
command -v xdotool > /dev/null && DISPLAY=":$dnum" xdotool mousemove 1020 760 # the pointer out of the picture
sleep 1 # a few UI frames with the refined image
mkdir -p "$(dirname "$out")"
cp "$tmp/Xvfb_screen0" "$tmp/screen.xwd" # the screen now (the file follows the screen)
python3 scripts/xwd2png.py "$tmp/screen.xwd" "$out" 0,0,$W,$H
echo "wrote $out (${W}x${H}, $(wc -c < "$out") bytes)"

#!/bin/sh
# Makes docs/images/first-*.png: each shared data set with the defaults of
# before issue 11 ("before": heat preset, looking down -z, which the current
# lanecast reproduces exactly with --tf heat --view 0,0; molecules loaded
# with one field) and with the current defaults ("after": no flags at all).
# usage: scripts/first_image.sh [LANECAST] [DATA_DIR]   (from the source root)
set -eu
exe=${1:-build/tools/lanecast}
data=${2:-../shared/data}
out=docs/images
size=${SIZE:-256x256}
mkdir -p "$out"
for f in volumes/HeadMRVolume.mhd volumes/engine.nhdr volumes/headsq.nhdr volumes/neghip.nhdr \
         volumes/embryo.nhdr particles/1tw7_solvated.pdb particles/1tii.pdb; do
    name=$(basename "$f"); name=${name%%.*}
    "$exe" render "$data/$f" -o "$out/first-$name-before.png" --size "$size" --tf heat --view 0,0 --quiet
    "$exe" render "$data/$f" -o "$out/first-$name-after.png" --size "$size" --quiet
    echo "$name"
done

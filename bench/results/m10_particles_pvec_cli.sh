#!/bin/bash
# usage: run.sh NEWBIN ; compares against /tmp/s10_now_lanecast
NEW=$1; OLD=${OLD:-/tmp/s10_now_lanecast}; D=${DATA:-/work/shared/data}/particles; O=$(mktemp -d)
n=0; bad=0
h() { perl -0777 -pe 's/\d{4}:\d\d:\d\d \d\d:\d\d:\d\d/DATE/g' "$1" | md5sum | cut -d' ' -f1; }
while IFS='|' read -r f args; do
  [ -z "$f" ] && continue
  for t in scalar avx2 avx512 avx512_8; do
    $OLD render $D/$f -o $O/a.tiff --target $t $args 2>/dev/null || { echo "old fail $f $args $t"; continue; }
    $NEW render $D/$f -o $O/b.tiff --target $t $args 2>/dev/null || { echo "new fail $f $args $t"; bad=$((bad+1)); continue; }
    n=$((n+1))
    if [ "$(h $O/a.tiff)" != "$(h $O/b.tiff)" ]; then echo "DIFF $f $args $t"; bad=$((bad+1)); fi
  done
done <<'L'
1tw7_solvated.pdb|--size 203x157
1tw7_solvated.pdb|--size 203x157 --shade phong
1tw7_solvated.pdb|--size 203x157 --mode mip
1tw7_solvated.pdb|--size 203x157 --packet 8
1tw7_solvated.pdb|--size 203x157 --packet 1
1tw7_solvated.pdb|--size 203x157 --eye 5,3,2 --at 0,0,0 --fov 70
1tw7_solvated.pdb|--size 203x157 --eye 5,3,2 --at 0,0,0 --fov 70 --shade
1tw7_solvated.pdb|--size 160x120 --view 10,70 --fov 10
1tw7_solvated.pdb|--size 150x130 --ortho 0
1tw7_solvated.pdb|--size 150x130 --mode iso --iso 0.5 --shade
1tii.pdb|--size 191x173 --shade --fields element --tf demo
gadget_galaxy.dat|--size 211x149
gadget_galaxy.dat|--size 211x149 --shade phong --threads 3
L
echo "renders $n, differing $bad"

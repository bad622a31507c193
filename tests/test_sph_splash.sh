#!/bin/sh
# lanecast's column-density maps against SPLASH's (tests/sph_splash.py): the
# centre-sampled map against SPLASH's default projection and the exact map
# against SPLASH's exact rendering, to 1e-4; a 1% mass change in lanecast's
# input must fail. Skips (77) without Debian's splash.
# usage: test_sph_splash.sh LANECAST SOURCE_ROOT WORK_DIR
set -u
exe=$1 src=$2 work=$3
py=/usr/bin/python3
[ -x "$py" ] || { echo "skip: no /usr/bin/python3"; exit 77; }
"$py" -c 'import numpy, scipy, matplotlib' 2>/dev/null || { echo "skip: NumPy, SciPy or Matplotlib missing"; exit 77; }
rm -rf "$work"
"$py" "$src/tests/sph_splash.py" "$exe" "$work"
rc=$?
[ $rc -eq 0 ] || exit $rc
"$py" "$src/tests/sph_splash.py" "$exe" "$work/broken" --break
rc=$?
if [ $rc -ne 1 ]; then
    echo "FAIL: a 1% mass change in lanecast's snapshot was not caught (exit $rc)"
    exit 1
fi
echo "ok: the 1% mass change is caught"
exit 0

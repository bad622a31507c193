#!/bin/sh
# lanecast against its peers, side by side in the same run: VTK 9
# (vtkFixedPointVolumeRayCastMapper, under Xvfb) on the same volume, TF,
# camera, sample distance and image size (bench/peers_vtk.py); for particles
# the proxy path VTK users take (Gaussian interpolation onto a grid, then the
# ray caster). Records go to
# bench/results/bench_peers.jsonl, composite PNGs (lanecast | VTK | diff) to
# docs/bench/; bench/report.py puts both into docs/BENCHMARKS.md.
# And SPLASH (Debian `splash`, opacity rendering) on the LCDM gas particles,
# from a GADGET snapshot with SPH densities and smoothing lengths that
# bench/peers_splash.py writes first (the shared initial conditions lack
# them), against lanecast on the same particles (bench/peers_splash.py).
# usage: bench/peers.sh [--install] BUILD_DIR [name ...]   (from the source root; names: .nhdr volumes
#        and .pdb particle files under ../shared/data, default engine neghip 1tii)
#   --install   apt-get install python3-vtk9 xvfb xauth splash python3-matplotlib
#               python3-scipy first (root)
set -eu
if [ "${1:-}" = "--install" ]; then
    shift
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends python3-vtk9 xvfb xauth splash \
        python3-matplotlib python3-scipy
fi
build=${1:-build}
[ $# -gt 0 ] && shift
exe=$build/tools/lanecast
data=${LANECAST_DATA:-../shared/data}
[ -x "$exe" ] || { echo "peers.sh: $exe not found (build first, or give the build folder)" >&2; exit 2; }
/usr/bin/python3 -c 'import vtk' 2>/dev/null || {
    echo "peers.sh: VTK's Python module is missing: bench/peers.sh --install (apt-get install python3-vtk9 xvfb xauth)" >&2
    exit 1
}
command -v xvfb-run >/dev/null || { echo "peers.sh: xvfb-run is missing: apt-get install xvfb xauth" >&2; exit 1; }
xvfb-run -a -s "-screen 0 1024x768x24" /usr/bin/python3 bench/peers_vtk.py "$exe" "$data" docs/bench \
    bench/results/bench_peers.jsonl "$@"
if command -v splash >/dev/null; then
    /usr/bin/python3 bench/peers_splash.py "$exe" "$data" docs/bench bench/results/bench_peers.jsonl "${SPLASH_SPLIT:-1}"
else
    echo "peers.sh: splash is missing (apt-get install splash): SPLASH skipped" >&2
fi

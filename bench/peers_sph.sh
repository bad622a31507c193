#!/bin/sh
# Column-density projections against SPLASH and yt on the same GADGET
# snapshots (bench/peers_sph.py; docs/bench/sph.md has the figures).
# usage: bench/peers_sph.sh [--install] BUILD_DIR [N_GENERATED [SIZES]]
#   --install   apt-get install splash python3-yt python3-scipy first (root)
set -eu
if [ "${1:-}" = "--install" ]; then
    shift
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends splash python3-yt python3-scipy
fi
build=${1:-build}
[ $# -gt 0 ] && shift
exe=$build/tools/lanecast
[ -x "$exe" ] || { echo "peers_sph.sh: $exe not found (build first, or give the build folder)" >&2; exit 2; }
/usr/bin/python3 bench/peers_sph.py "$exe" "${LANECAST_DATA:-../shared/data}" bench/results/bench_peers_sph.jsonl "$@"

#!/bin/sh
# Installs what is missing, configures (once) and builds lanecast in ./build.
# Warnings are errors here, as in CI. Extra arguments go to `meson setup`.
set -eu
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
if [ ! -f build/build.ninja ]; then
    meson setup build --buildtype=release -Dwerror=true "$@" >/dev/null
fi
ninja -C build >/dev/null
echo "lanecast: built in ./build" >&2

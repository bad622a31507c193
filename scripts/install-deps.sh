#!/bin/sh
# Installs lanecast's build and test dependencies from Debian's packages.
# Idempotent: when everything is present it only runs dpkg-query and exits.
set -eu
PKGS="meson ninja-build pkg-config cmake gcc g++ libembree-dev libopenimageio-dev libcglm-dev libjson-c-dev zlib1g-dev liblapacke-dev libnifti2-dev libhdf5-dev openmpi-bin libopenmpi-dev libnetcdf-dev"
# FITS float maps of projections (the fits feature)
PKGS="$PKGS libcfitsio-dev"
# Python bindings (python/) and their tests and adapters
PKGS="$PKGS python3-dev python3-numpy python3-pytest python3-yt python3-mdanalysis"
# DICOM series through GDCM (the dicom feature); its tests write files with pydicom and gdcmconv
PKGS="$PKGS libgdcm-dev libgdcm-tools python3-pydicom"
# lanecast view (the viewer feature) and its tests under Xvfb
PKGS="$PKGS libglfw3-dev libimgui-dev libstb-dev xvfb xauth xdotool"
# SPLASH, which test sph_splash compares the projections with (skipped without it)
PKGS="$PKGS splash"
missing=""
for p in $PKGS; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
        missing="$missing $p"
    fi
done
if [ -z "$missing" ]; then
    exit 0
fi
echo "lanecast: installing$missing" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq || echo "lanecast: apt-get update failed; trying the cached package lists" >&2
$SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null

"""Shared helpers of the lanecast Python tests (run by meson test: PYTHONPATH points at
build/python, LANECAST_CLI at the build's lanecast binary, LANECAST_DATA at the shared data)."""

import os
import subprocess

import numpy as np
import pytest

import lanecast as lc

CLI = os.environ.get("LANECAST_CLI", "")
DATA = os.environ.get("LANECAST_DATA", "")


def feature(name):
    return any(f["name"] == name and f["available"] for f in lc.features())


@pytest.fixture(scope="module")
def dev():
    return lc.Device()


def data_file(*parts):
    path = os.path.join(DATA, *parts)
    if not DATA or not os.path.exists(path):
        pytest.skip(f"shared data file {os.path.join(*parts)} is absent (LANECAST_DATA={DATA!r})")
    return path


def read_fits_rgb(path):
    """The RGB pixels of a float FITS image as OpenImageIO writes them (BITPIX -32, NAXIS1 = 3
    channels, NAXIS2 = width, NAXIS3 = height, big-endian, the bottom row first), row 0 at
    the top. The data are the file's last width * height * 12 bytes: the tests pick sizes whose
    data fill whole 2880-byte FITS blocks, so nothing pads the data."""
    b = open(path, "rb").read()
    assert b.startswith(b"SIMPLE  =")
    cards = {}
    for i in range(0, b.index(b"END     ") , 80):
        card = b[i:i + 80].decode("ascii")
        if "=" in card:
            k, v = card.split("=", 1)
            cards[k.strip()] = v.split("/")[0].strip()
    assert cards["BITPIX"] == "-32" and cards["NAXIS"] == "3" and cards["NAXIS1"] == "3"
    w, h = int(cards["NAXIS2"]), int(cards["NAXIS3"])
    n = w * h * 3 * 4
    assert n % 2880 == 0, "pick an image size whose data fill whole FITS blocks"
    return np.frombuffer(b[len(b) - n:], dtype=">f4").reshape(h, w, 3)[::-1].astype(np.float32)


def cli_render(tmp_path, args, name="cli.fits"):
    """Runs `lanecast render ARGS -o tmp/cli.fits --quiet` and returns its RGB pixels."""
    if not CLI or not os.path.exists(CLI):
        pytest.skip("LANECAST_CLI is not set: run the tests through meson test")
    out = str(tmp_path / name)
    r = subprocess.run([CLI, "render", *[str(a) for a in args], "-o", out, "--quiet"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return read_fits_rgb(out)

"""lanecast.render gives the same pixels as `lanecast render` with the same options: particles,
grids and RBF sets made from NumPy arrays against the CLI reading the same data from files,
in every mode; lanecast.load against the CLI on the same file; the default TF and view."""

import numpy as np
import pytest

import lanecast as lc
from conftest import cli_render, data_file

W, H = 96, 80  # W * H * 12 bytes fill whole FITS blocks (conftest.read_fits_rgb)
rng = np.random.default_rng(7)
POS = (rng.normal(size=(1500, 3)) * [6.0, 4.0, 3.0]).astype(np.float32)
z, y, x = np.mgrid[0:16, 0:20, 0:24].astype(np.float32)
GRID = (np.exp(-((x - 11) ** 2 / 40 + (y - 9) ** 2 / 25 + (z - 8) ** 2 / 16)) +
        0.3 * np.sin(x / 3.0) * np.cos(y / 4.0)).astype(np.float32)  # (z, y, x): x fastest
CENTRES = (rng.normal(size=(20, 3)) * 2.0).astype(np.float32)
WIDTHS = rng.uniform(0.6, 1.4, size=20).astype(np.float32)
WEIGHTS = rng.uniform(-0.4, 1.0, size=20).astype(np.float32)

MODES = {
    "particles": {"dvr": (["--shade", "phong"], dict(shade="phong")),
                  "mip": (["--mode", "mip"], dict(mode="mip")),
                  "iso": (["--mode", "iso", "--iso", "0.5", "--shade", "diffuse"], dict(mode="iso", iso=0.5, shade="diffuse")),
                  "slice": (["--mode", "slice", "--plane", "0,0,0,0,0.2,1"], dict(mode="slice", planes=[((0, 0, 0), (0, 0.2, 1))]))},
    "grid": {"dvr": (["--shade", "diffuse"], dict(shade="diffuse")),
             "mip": (["--mode", "mip"], dict(mode="mip")),
             "iso": (["--mode", "iso", "--iso", "0.6", "--shade", "phong"], dict(mode="iso", iso=0.6, shade="phong")),
             "slice": (["--mode", "slice", "--plane", "11.5,9.5,7.5,1,0.3,0.2", "--plane", "11.5,9.5,7.5,0,0,1"],
                       dict(mode="slice", planes=[((11.5, 9.5, 7.5), (1, 0.3, 0.2)), ((11.5, 9.5, 7.5), (0, 0, 1))]))},
    "rbf": {"dvr": ([], {}),
            "mip": (["--mode", "mip"], dict(mode="mip")),
            "iso": (["--mode", "iso", "--iso", "0.3"], dict(mode="iso", iso=0.3)),
            "slice": (["--mode", "slice", "--plane", "0,0,0,1,1,1"], dict(mode="slice", planes=[((0, 0, 0), (1, 1, 1))]))},
}


def scene(kind, dev, tmp_path):
    """The volume from arrays, the same data as a file, and the CLI flags reading it."""
    if kind == "particles":
        f = tmp_path / "p.f32"
        POS.astype("<f4").tofile(f)
        return (lc.Particles(dev, POS, radii=0.8), lc.TransferFunction.preset("heat", 1, 1.25),
                [f, "--raw-particles", len(POS), "--radius", "0.8", "--tf", "heat", "--tau", "1.25"])
    if kind == "grid":
        f = tmp_path / "g.raw"
        GRID.astype("<f4").tofile(f)
        return (lc.Grid(dev, GRID), lc.TransferFunction.preset("gray", 1, 0.3),
                [f, "--dims", "24,20,16", "--type", "float32", "--tf", "gray", "--tau", "0.3"])
    f = tmp_path / "s.rbf"  # docs/FORMATS-rbf.md, text version 1
    lines = ["lanecast-rbf 1", "bias 0", f"count {len(WIDTHS)}"]
    lines += [f"{c[0]:.9g} {c[1]:.9g} {c[2]:.9g} {s:.9g} {w:.9g}" for c, s, w in zip(CENTRES, WIDTHS, WEIGHTS)]
    f.write_text("\n".join(lines) + "\n")
    return (lc.RBFSet(dev, CENTRES, WIDTHS, WEIGHTS, 0.0), lc.TransferFunction.preset("heat", 1, 0.5),
            [f, "--tf", "heat", "--tau", "0.5"])


@pytest.mark.parametrize("kind,mode", [(k, m) for k in MODES for m in MODES[k]])
def test_same_pixels_as_cli(kind, mode, dev, tmp_path):
    vol, tf, args = scene(kind, dev, tmp_path)
    flags, kw = MODES[kind][mode]
    cli = cli_render(tmp_path, args + ["--size", f"{W}x{H}", "--view", "20,30"] + flags)
    img = lc.render(vol, tf, W, H, view=(20, 30), **kw)
    assert img.shape == (H, W, 4)
    assert img[..., 3].max() > 0.05, "the scene must show something for the comparison to mean anything"
    np.testing.assert_array_equal(np.asarray(img)[..., :3], cli)


def test_explicit_camera_and_range_as_cli(dev, tmp_path):
    vol, tf, args = scene("grid", dev, tmp_path)
    cli = cli_render(tmp_path, args + ["--size", f"{W}x{H}", "--eye", "40,30,50", "--at", "11,9,7", "--up", "0,1,0.2",
                                       "--fov", "30", "--range", "0.1,0.9", "--dt", "0.3"])
    img = lc.render(vol, tf, W, H, eye=(40, 30, 50), at=(11, 9, 7), up=(0, 1, 0.2), fov=30, range=(0.1, 0.9), dt=0.3)
    np.testing.assert_array_equal(np.asarray(img)[..., :3], cli)
    ortho = cli_render(tmp_path, args + ["--size", f"{W}x{H}", "--eye", "11,9,60", "--at", "11,9,7", "--ortho", "30"],
                       name="ortho.fits")
    img = lc.render(vol, tf, W, H, eye=(11, 9, 60), at=(11, 9, 7), ortho=30)
    np.testing.assert_array_equal(np.asarray(img)[..., :3], ortho)


def test_defaults_as_cli(dev, tmp_path):
    """No TF and no camera: the histogram TF (lc_tf_auto) and the default three-quarter view."""
    f = tmp_path / "g.raw"
    GRID.astype("<f4").tofile(f)
    cli = cli_render(tmp_path, [f, "--dims", "24,20,16", "--type", "float32", "--size", f"{W}x{H}"])
    img = lc.render(lc.Grid(dev, GRID), width=W, height=H)
    np.testing.assert_array_equal(np.asarray(img)[..., :3], cli)


def test_load_as_cli(dev, tmp_path):
    f = tmp_path / "p.f32"
    POS.astype("<f4").tofile(f)
    vol = lc.load(dev, f, format="raw-particles", count=len(POS), radius=0.8)
    vol.set_params(sigma=2.5, kappa=0.7)
    cli = cli_render(tmp_path, [f, "--raw-particles", len(POS), "--radius", "0.8", "--tf", "cool", "--tau", "1",
                                "--sigma", "2.5", "--kappa", "0.7", "--size", f"{W}x{H}"])
    img = lc.render(vol, lc.TransferFunction.preset("cool", 1, 1.0), W, H)
    np.testing.assert_array_equal(np.asarray(img)[..., :3], cli)


def test_shared_molecule_as_cli(dev, tmp_path):
    path = data_file("particles", "1tii.pdb")
    vol = lc.load(dev, path, fields="element")
    n = vol.info["nfields"]
    cli = cli_render(tmp_path, [path, "--fields", "element", "--tf", "demo", "--tau", "1", "--shade",
                                "--size", f"{W}x{H}"])
    img = lc.render(vol, lc.TransferFunction.preset("demo", n, 1.0), W, H, shade="diffuse")
    np.testing.assert_array_equal(np.asarray(img)[..., :3], cli)

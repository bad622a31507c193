"""The API around the arrays: devices, exceptions per lc_status, images, cameras, TFs,
modes and their errors, info and set_params, the build queries."""

import os
import subprocess

import numpy as np
import pytest

import lanecast as lc
from conftest import CLI, feature

rng = np.random.default_rng(5)
POS = (rng.normal(size=(600, 3)) * 3).astype(np.float32)


def test_exception_hierarchy():
    pairs = [(lc.InvalidArgumentError, ValueError), (lc.UnsupportedError, NotImplementedError),
             (lc.OutOfMemoryError, MemoryError), (lc.FileError, OSError), (lc.FormatError, ValueError),
             (lc.InternalError, RuntimeError), (lc.TimeoutError, TimeoutError)]
    for cls, builtin in pairs:
        assert issubclass(cls, lc.Error) and issubclass(cls, builtin)
    assert issubclass(lc.CancelledError, lc.Error)


def test_errors_carry_the_library_message(dev, tmp_path):
    with pytest.raises(lc.FileError, match="nope.xyz") as e:
        lc.load(dev, tmp_path / "nope.xyz")
    assert e.value.status == -4
    bad = tmp_path / "bad.xyz"
    bad.write_text("2\ncomment\nC 0 0 0\nC 1 x 0\n")
    with pytest.raises(lc.FormatError, match="bad.xyz:4") as e:
        lc.load(dev, bad)
    assert e.value.status == -5
    with pytest.raises(lc.InvalidArgumentError, match="option 'no_such_option' does not apply"):
        lc.load(dev, bad, no_such_option=1)
    with pytest.raises(lc.InvalidArgumentError, match="select"):
        lc.select_check("protein and (")
    with pytest.raises(lc.InvalidArgumentError):
        lc.Device(target="bogus")
    with pytest.raises(ValueError, match="threads"):
        lc.Device(threads=0)


def test_device():
    d = lc.Device(threads=1, target="scalar")
    assert d.target == "scalar" and d.threads == 1 and d.lanes == 1
    assert lc.Device().target in [t["name"] for t in lc.targets() if t["supported"]]


def test_build_queries():
    t = {x["name"]: x for x in lc.targets()}
    assert t["scalar"]["compiled"] and t["scalar"]["supported"] and t["avx2"]["lanes"] == 8
    names = {f["name"] for f in lc.formats()}
    assert {"pdb", "nrrd", "rbf", "raw-particles", "raw-volume"} <= names
    assert {f["name"] for f in lc.features()} >= {"zlib", "json", "lapacke", "nifti", "hdf5"}
    assert "viridis" in lc.presets() and "heat" in lc.presets()
    if CLI:  # the same list as `lanecast formats` prints
        out = subprocess.run([CLI, "formats"], capture_output=True, text=True).stdout
        for f in lc.formats():
            assert f["name"] in out


def test_render_image_and_stats(dev, tmp_path):
    vol = lc.Particles(dev, POS, radii=0.7)
    img = lc.render(vol, width=64, height=32)
    assert isinstance(img, lc.Image) and isinstance(img, np.ndarray)
    assert img.shape == (32, 64, 4) and img.dtype == np.float32
    a = np.asarray(img)[..., 3]
    assert 0.0 < a.max() <= 1.0 and a.min() == 0.0  # the corners are empty
    assert np.all(np.asarray(img)[..., :3] <= a[..., None] + 1e-6)  # premultiplied
    s = img.stats
    assert s["rays"] > 0 and s["samples"] > 0 and s["seconds"] > 0 and s["target"] == dev.target
    png = img._repr_png_()
    assert png.startswith(b"\x89PNG\r\n\x1a\n")
    img.save(tmp_path / "a.png")
    assert (tmp_path / "a.png").read_bytes()[:8] == png[:8]
    with pytest.raises(lc.UnsupportedError, match="cannot write"):
        img.save(tmp_path / "a.nosuchformat")
    with pytest.raises(ValueError, match=r"image: expected an array of shape \(H, W, 4\)"):
        img[..., :3].copy().view(lc.Image).save(tmp_path / "b.png")


def test_default_view_is_camera_frame(dev):
    vol = lc.Particles(dev, POS, radii=0.7)
    tf = lc.TransferFunction.preset("heat", 1, 1.0)
    a = lc.render(vol, tf, 40, 40)
    b = lc.render(vol, tf, 40, 40, camera=lc.Camera.frame(vol, 35, 25))
    c = lc.render(vol, tf, 40, 40, view=(35, 25))
    d = lc.render(vol, tf, 40, 40, view=(80, 25))
    np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(a, c)
    assert not np.array_equal(a, d)
    cam = lc.Camera.frame(((0, 0, 0), (2, 2, 2)), azimuth=0, elevation=0)
    assert cam.at == (1, 1, 1) and cam.eye[0] == pytest.approx(1) and cam.eye[2] > 2


def test_modes_and_their_errors(dev):
    vol = lc.Particles(dev, POS, radii=0.7, fields=(np.arange(600) % 2))
    tf = lc.TransferFunction.preset("demo", 2, 1.0)
    imgs = {m: np.asarray(lc.render(vol, tf, 32, 32, mode=m, iso=0.4 if m == "iso" else None,
                                    planes=[((0, 0, 0), (0, 0, 1))] if m == "slice" else None)) for m in
            ["dvr", "mip", "iso", "slice"]}
    for m in ["mip", "iso", "slice"]:
        assert not np.array_equal(imgs[m], imgs["dvr"])
    assert np.isin(imgs["iso"][..., 3], [0.0, 1.0]).all()  # opaque surfaces
    with pytest.raises(ValueError, match="mode: 'volume'"):
        lc.render(vol, tf, 8, 8, mode="volume")
    with pytest.raises(ValueError, match="iso"):
        lc.render(vol, tf, 8, 8, mode="iso")
    with pytest.raises(ValueError, match="planes"):
        lc.render(vol, tf, 8, 8, mode="slice")
    with pytest.raises(lc.InvalidArgumentError, match="field"):
        lc.render(vol, tf, 8, 8, mode="iso", iso=0.5, field=5)
    with pytest.raises(ValueError, match="width, height"):
        lc.render(vol, tf, 0, 8)
    with pytest.raises(TypeError, match="both eye and at"):
        lc.render(vol, tf, 8, 8, eye=(1, 2, 3))
    with pytest.raises(TypeError, match="volume"):
        lc.render(POS)
    with pytest.raises(ValueError, match="planes: normal"):
        lc.render(vol, tf, 8, 8, mode="slice", planes=[((0, 0, 0), (0, np.nan, 1))])
    lit = lc.render(vol, tf, 32, 32, shade="phong", lighting=(0.1, 0.5, 0.9, 32))
    assert not np.array_equal(np.asarray(lit), imgs["dvr"])


def test_info_and_set_params(dev):
    vol = lc.Particles(dev, POS, radii=0.7)
    info = vol.info
    assert info["kind"] == "particles" and info["count"] == 600 and info["nfields"] == 1
    assert info["params"]["sigma"] == 2.0 and info["radius"] == (pytest.approx(0.7), pytest.approx(0.7))
    tf = lc.TransferFunction.preset("heat", 1, 1.0)
    before = np.asarray(lc.render(vol, tf, 32, 32, range=(0, 1)))
    vol.set_params(kappa=0.5)
    assert vol.info["params"]["kappa"] == 0.5 and vol.info["params"]["sigma"] == 2.0
    after = np.asarray(lc.render(vol, tf, 32, 32, range=(0, 1)))
    assert after[..., 3].sum() < before[..., 3].sum()
    with pytest.raises(lc.InvalidArgumentError):
        vol.set_params(sigma=-1)
    g = lc.Grid(dev, rng.random((8, 9, 10)).astype(np.float32), spacing=(1, 2, 3))
    assert g.info["size"] == (10, 9, 8) and g.info["spacing"] == (1, 2, 3)
    g.set_params(preintegrated=True)
    assert g.info["params"]["preintegrated"] is True
    assert g.histogram(16).sum() == 8 * 9 * 10
    vol.close()
    with pytest.raises(ValueError, match="closed"):
        vol.info


def test_transfer_functions(dev, tmp_path):
    tf = lc.TransferFunction(color=[(0, 0, 0, 1), (1, 1, 0, 0)], opacity=[(0, 0), (1, 2)], range=(0, 3))
    f = tf.fields()[0]
    np.testing.assert_array_equal(f["opacity"], [[0, 0], [1, 2]])
    assert f["range"] == (0, 3) and tf.nfields == 1
    cm = lc.TransferFunction.from_colormap("viridis", range=(1, 2), opacity=[(0, 0), (1, 0.5)])
    f = cm.fields()[0]
    assert f["range"] == (1, 2) and f["opacity"].tolist() == [[0, 0], [1, 0.5]] and len(f["color"]) > 10
    with pytest.raises(lc.InvalidArgumentError, match="decreases"):
        lc.TransferFunction(color=[(0.5, 0, 0, 1), (0.2, 1, 0, 0)], opacity=[(0, 0), (1, 2)])
    with pytest.raises(lc.InvalidArgumentError):
        lc.TransferFunction.preset("no-such-map")
    j = tmp_path / "tf.json"
    j.write_text('{"color": [[0, 0, 0, 0], [1, 1, 1, 1]], "opacity": [[0, 0], [1, 4]], "range": [0, 1]}')
    if not feature("json"):
        with pytest.raises(lc.UnsupportedError, match="libjson-c-dev"):
            lc.TransferFunction.load(j)
        pytest.skip("this build has no json-c: JSON transfer functions are compiled out")
    t = lc.TransferFunction.load(j)
    assert t.fields()[0]["opacity"].tolist() == [[0, 0], [1, 4]]
    vol = lc.Particles(dev, POS, radii=0.7)
    np.testing.assert_array_equal(lc.render(vol, str(j), 16, 16), lc.render(vol, t, 16, 16))
    with pytest.raises(lc.FormatError, match="tf2.json"):
        (tmp_path / "tf2.json").write_text("{")
        lc.TransferFunction.load(tmp_path / "tf2.json")


def test_warnings_become_python_warnings(dev, tmp_path):
    """A loader's warning (here: a PDB whose 9th distinct chain shares field 7) reaches Python."""
    lines = [f"ATOM  {i + 1:5d}  CA  ALA {chr(65 + i)}{i + 1:4d}    {i:8.3f}{0:8.3f}{0:8.3f}  1.00  0.00           C"
             for i in range(10)]
    p = tmp_path / "chains.pdb"
    p.write_text("\n".join(lines) + "\nEND\n")
    with pytest.warns(lc.Warning):
        v = lc.load(dev, p, fields="chain")
    assert v.info["nfields"] == 8

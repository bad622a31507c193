"""RBF sets and encoding with progress, saving sets, probing and loading with progress,
trajectory frames through load."""

import numpy as np
import pytest

import lanecast as lc
from conftest import data_file, feature

rng = np.random.default_rng(13)


def gaussians(points):
    """The field the encoder should recover: two Gaussians (written from SPEC.md's RBF form)."""
    c = np.array([[0.0, 0.0, 0.0], [1.5, 0.5, -0.5]])
    s = np.array([0.8, 0.5])
    w = np.array([1.0, 0.6])
    d2 = ((points[:, None, :] - c[None]) ** 2).sum(-1)
    return (w * np.exp(-d2 / (2 * s ** 2))).sum(-1)


def test_encode_with_progress(dev):
    pts = rng.uniform(-2.5, 2.5, size=(3000, 3))
    vals = gaussians(pts)
    if not feature("lapacke"):
        with pytest.raises(lc.UnsupportedError, match="liblapacke-dev"):
            lc.encode(dev, pts, vals)
        pytest.skip("this build has no LAPACKE: RBF encoding is compiled out")
    seen = []
    rbf = lc.encode(dev, pts, vals, max_error=0.01, max_rbfs=16, progress=seen.append)
    assert isinstance(rbf, lc.RBFSet)
    r = rbf.report
    assert r["rbfs"] == rbf.info["count"] and r["samples"] == 3000 and r["rms"] <= 0.01 and r["reached"]
    assert seen and [p["iteration"] for p in seen] == sorted(p["iteration"] for p in seen)
    assert seen[-1]["rbfs"] == r["rbfs"] and all(p["target"] == pytest.approx(0.01) for p in seen)
    test = rng.uniform(-2, 2, size=(200, 3)).astype(np.float32)
    err = np.abs(rbf.sample(test)[:, 0] - gaussians(test.astype(np.float64)))
    assert err.max() < 0.05  # the fit, not the samples, checked against the formula
    with pytest.raises(ZeroDivisionError):
        lc.encode(dev, pts, vals, max_rbfs=4, progress=lambda p: 1 / 0)


def test_encode_a_grid(dev):
    if not feature("lapacke"):
        pytest.skip("this build has no LAPACKE: RBF encoding is compiled out")
    z, y, x = np.mgrid[0:12, 0:12, 0:12].astype(np.float32)
    vol = np.exp(-((x - 7) ** 2 + (y - 4) ** 2 + (z - 5) ** 2) / 6)  # C order: the peak at x 7, y 4, z 5
    rbf = lc.encode(dev, grid=vol, max_error=0.02, max_rbfs=8)
    assert rbf.report["samples"] == 12 ** 3 and rbf.report["rms"] <= 0.02
    v = rbf.sample(np.array([[7, 4, 5], [5, 4, 7], [4, 7, 5]], np.float32))[:, 0]
    assert v[0] > 0.85 and v[1] == pytest.approx(np.exp(-8 / 6), abs=0.1) and v[2] < 0.1


def test_rbf_set_save_and_load(dev, tmp_path):
    c = rng.normal(size=(25, 3)).astype(np.float32)
    s = rng.uniform(0.5, 1.0, 25).astype(np.float32)
    w = rng.uniform(-1, 1, 25).astype(np.float32)
    rbf = lc.RBFSet(dev, c, s, w, 0.1, accel="octree")
    assert rbf.info["accel"] == "octree" and rbf.info["bias"] == pytest.approx(0.1)
    tf = lc.TransferFunction.preset("cool-warm", 1, 1.0)
    for text in (False, True):
        p = tmp_path / f"s{int(text)}.rbf"
        rbf.save(p, text=text)
        again = lc.load(dev, p, accel="octree")
        assert again.info["count"] == 25
        np.testing.assert_array_equal(lc.render(again, tf, 24, 24), lc.render(rbf, tf, 24, 24))
        with pytest.raises(ValueError, match="read from a file"):
            again.save(tmp_path / "x.rbf")
    with pytest.raises(ValueError, match="accel: 'fast'"):
        lc.RBFSet(dev, c, s, w, accel="fast")


def test_probe_and_load_progress(dev, tmp_path):
    f = tmp_path / "a.xyz"
    f.write_text("3\nx\nC 0 0 0\nO 1.2 0 0\nN 0 1.3 0\n")
    assert lc.probe(f) == {"format": "xyz", "kind": "particles", "frames": 1, "gzip": False}
    seen = []
    v = lc.load(dev, f, progress=seen.append, radius=1.0)
    assert v.info["count"] == 3 and v.info["radius"] == (1.0, 1.0)
    assert seen and seen[-1] == 1.0
    with pytest.raises(ZeroDivisionError):
        lc.load(dev, f, progress=lambda x: 1 / 0)


def test_trajectory_frames(dev):
    path = data_file("particles", "adk.dcd")
    n = lc.probe(path)["frames"]
    assert n > 1
    a = lc.load(dev, path, frame=0)
    b = lc.load(dev, path, frame=n - 1)
    assert a.info["count"] == b.info["count"] and a.info["centre_bounds"] != b.info["centre_bounds"]

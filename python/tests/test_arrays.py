"""The array rules: zero-copy where the C API allows it, conversions (float64, Fortran order,
negative strides, read-only, big-endian, sequences) giving the same pixels, copy=False/True,
bad shapes/dtypes/values naming the argument, borrowed arrays kept alive, axis order."""

import gc

import numpy as np
import pytest

import lanecast as lc

rng = np.random.default_rng(3)
POS = (rng.normal(size=(800, 3)) * 4).astype(np.float32)
RAD = rng.uniform(0.5, 1.0, size=800).astype(np.float32)
VOX = rng.random((10, 12, 14)).astype(np.float32)  # (z, y, x)


def pimg(dev, pos, **kw):
    return np.asarray(lc.render(lc.Particles(dev, pos, **kw), lc.TransferFunction.preset("heat", 1, 1.0), 48, 40,
                                view=(30, 20)))


def gimg(vol):
    return np.asarray(lc.render(vol, lc.TransferFunction.preset("gray", 1, 0.5), 48, 40, view=(30, 20)))


@pytest.mark.parametrize("variant", ["float64", "fortran", "negative", "readonly", "bigendian", "list", "int"])
def test_particle_conversions_same_pixels(dev, variant):
    pos = np.round(POS) if variant == "int" else POS  # integer-valued for the int case
    ref = pimg(dev, pos.astype(np.float32), radii=RAD)
    if variant == "float64":
        p = pos.astype(np.float64)
    elif variant == "fortran":
        p = np.asfortranarray(pos)
    elif variant == "negative":
        p = pos[::-1].copy()[::-1]  # a view with a negative row stride, same rows
        assert p.strides[0] < 0
    elif variant == "readonly":
        p = pos.copy()
        p.flags.writeable = False
    elif variant == "bigendian":
        p = pos.astype(">f4")
    elif variant == "list":
        p = pos.tolist()
    else:
        p = pos.astype(np.int32)
    np.testing.assert_array_equal(pimg(dev, p, radii=RAD), ref)


def test_copy_false(dev):
    lc.Particles(dev, POS, radii=RAD, copy=False)  # C-contiguous float32: used in place
    ro = POS.copy()
    ro.flags.writeable = False
    lc.Particles(dev, ro, copy=False)
    for bad, why in [(POS.astype(np.float64), "dtype"), (np.asfortranarray(POS), "C-contiguous"),
                     (POS[::-1], "C-contiguous"), (POS.astype(">f4"), "byte order"), (POS.tolist(), "NumPy")]:
        with pytest.raises(ValueError, match=f"positions: copy=False.*{why}"):
            lc.Particles(dev, bad, copy=False)
    with pytest.raises(ValueError, match="radii: copy=False"):
        lc.Particles(dev, POS, radii=RAD.astype(np.float64), copy=False)
    with pytest.raises(TypeError, match="copy"):
        lc.Particles(dev, POS, copy="yes")


def test_bad_particle_input(dev):
    with pytest.raises(ValueError, match=r"positions: expected an array of shape \(N, 3\), got shape \(800, 2\)"):
        lc.Particles(dev, POS[:, :2])
    with pytest.raises(ValueError, match=r"positions: .*got shape \(2400,\)"):
        lc.Particles(dev, POS.ravel())
    with pytest.raises(ValueError, match="positions: no particles"):
        lc.Particles(dev, np.zeros((0, 3), np.float32))
    with pytest.raises(TypeError, match="positions: expected numbers.*complex"):
        lc.Particles(dev, POS.astype(np.complex64))
    with pytest.raises(TypeError, match="positions"):
        lc.Particles(dev, [["a", "b", "c"]])
    with pytest.raises(TypeError, match="positions"):
        lc.Particles(dev, np.ones((3, 3), dtype=bool))
    for name, kw in [("positions", {}), ("radii", {}), ("values", {})]:
        pos, rad, val = POS.copy(), RAD.copy(), np.ones(800, np.float32)
        {"positions": pos, "radii": rad, "values": val}[name][17] = np.nan if name != "radii" else np.inf
        with pytest.raises(lc.InvalidArgumentError, match=f"^{name}: .*particle 17"):
            lc.Particles(dev, pos, radii=rad, values=val)
    with pytest.raises(ValueError, match="radii: expected 800 values"):
        lc.Particles(dev, POS, radii=RAD[:10])
    with pytest.raises(ValueError, match="radii: expected a radius > 0"):
        lc.Particles(dev, POS, radii=-1.0)
    with pytest.raises(ValueError, match="fields: id 9 at index 3"):
        lc.Particles(dev, POS[:5], fields=[0, 1, 0, 9, 0])
    with pytest.raises(TypeError, match="fields: expected integers"):
        lc.Particles(dev, POS[:5], fields=[0.0, 1, 0, 1, 0])
    with pytest.raises(ValueError, match="fields: expected 800 field ids"):
        lc.Particles(dev, POS, fields=[0, 1])
    assert lc.Particles(dev, POS[:5], fields=np.array([0, 1, 0, 2, 0], np.int64)).info["nfields"] == 3


def test_grid_zero_copy_and_copies(dev):
    g = lc.Grid(dev, VOX)
    assert g.info["borrowed"] and np.shares_memory(g.borrowed[0], VOX)
    g2 = lc.Grid(dev, VOX, copy=True)
    assert not g2.info["borrowed"] and g2.borrowed == ()
    np.testing.assert_array_equal(gimg(g), gimg(g2))
    for v in [VOX.astype(np.float64), np.asfortranarray(VOX), VOX.astype(">f4"), VOX[:, ::-1].copy()[:, ::-1]]:
        with pytest.raises(ValueError, match="data: copy=False"):
            lc.Grid(dev, v, copy=False)
        c = lc.Grid(dev, v)
        assert not c.info["borrowed"]  # converted once, owned by the library
        np.testing.assert_array_equal(gimg(c), gimg(g))
    ro = VOX.copy()
    ro.flags.writeable = False
    assert lc.Grid(dev, ro, copy=False).info["borrowed"]
    np.testing.assert_array_equal(gimg(lc.Grid(dev, VOX.tolist())), gimg(g))


def test_grid_types(dev):
    u8 = (VOX * 255).astype(np.uint8)
    assert lc.Grid(dev, u8).info["type"] == "uint8"
    assert lc.Grid(dev, u8.astype(np.uint16)).info["type"] == "uint16"
    assert lc.Grid(dev, u8.astype(np.int16)).info["type"] == "int16"
    assert lc.Grid(dev, u8.astype(np.int32)).info["type"] == "float32"
    assert lc.Grid(dev, u8.astype(np.float64)).info["type"] == "float32"
    # the same values as uint8 and as float32 give the same field
    pts = np.array([[3.3, 4.1, 5.7], [10.0, 2.5, 1.2]], np.float32)
    np.testing.assert_allclose(lc.Grid(dev, u8).sample(pts), lc.Grid(dev, u8.astype(np.float32)).sample(pts),
                               rtol=1e-6)


def test_bad_grid_input(dev):
    with pytest.raises(ValueError, match=r"data: expected a 3-D array, got shape \(12, 14\)"):
        lc.Grid(dev, VOX[0])
    with pytest.raises(ValueError, match="data: the x axis has 1 nodes"):
        lc.Grid(dev, VOX[:, :, :1])
    with pytest.raises(TypeError, match="data: expected numbers"):
        lc.Grid(dev, VOX.astype(np.complex64))
    bad = VOX.copy()
    bad[2, 3, 4] = np.nan
    with pytest.raises(lc.InvalidArgumentError, match="^data: "):
        lc.Grid(dev, bad)
    with pytest.raises(ValueError, match="order: expected"):
        lc.Grid(dev, VOX, order="zyy")
    with pytest.raises(ValueError, match="spacing"):
        lc.Grid(dev, VOX, spacing=(1, 0, 1))
    with pytest.raises(ValueError, match="origin: expected three finite"):
        lc.Grid(dev, VOX, origin=(0, np.inf, 0))


def test_borrowed_array_outlives_the_caller(dev):
    arr = rng.random((10, 12, 14)).astype(np.float32)
    ref = gimg(lc.Grid(dev, arr.copy(), copy=True))
    g = lc.Grid(dev, arr)
    assert g.info["borrowed"]
    del arr
    gc.collect()
    junk = [np.full((10, 12, 14), 7.0, np.float32) for _ in range(50)]  # reuse freed memory, if it were freed
    np.testing.assert_array_equal(gimg(g), ref)
    del junk


def test_c_and_fortran_order_render_the_same(dev):
    c = np.ascontiguousarray(VOX)
    f = np.asfortranarray(VOX)
    assert f.flags.f_contiguous and not f.flags.c_contiguous
    np.testing.assert_array_equal(gimg(lc.Grid(dev, c)), gimg(lc.Grid(dev, f)))
    # the same data given as data[i, j, k] (order "xyz") in Fortran order is borrowed in place
    x = np.asfortranarray(VOX.transpose(2, 1, 0))
    gx = lc.Grid(dev, x, order="xyz", copy=False)
    assert gx.info["size"] == (14, 12, 10)
    np.testing.assert_array_equal(gimg(gx), gimg(lc.Grid(dev, c)))


def test_marked_voxel_lands_where_the_docs_say(dev):
    """docs/PYTHON.md "Axis order": data[k, j, i] is the node at origin + (i sx, j sy, k sz);
    x runs to the right of the image and y up when looking down -z."""
    nz, ny, nx = 6, 10, 16
    a = np.zeros((nz, ny, nx), np.float32)
    k, j, i = 4, 7, 3
    a[k, j, i] = 1.0
    sp, org = (2.0, 1.0, 0.5), (10.0, -3.0, 1.0)
    g = lc.Grid(dev, a, spacing=sp, origin=org)
    p = [org[0] + i * sp[0], org[1] + j * sp[1], org[2] + k * sp[2]]
    v = g.sample(np.array([p, [p[0] + sp[0], p[1], p[2]], [p[0], p[1] + sp[1], p[2]]], np.float32))
    np.testing.assert_allclose(v[:, 0], [1.0, 0.0, 0.0], atol=1e-6)
    assert g.info["bounds"] == ((10.0, -3.0, 1.0), (10.0 + 15 * 2.0, -3.0 + 9.0, 1.0 + 5 * 0.5))
    # MIP seen from +z, orthographic: image column grows with x, row 0 is the top (largest y)
    lo, hi = g.info["bounds"]
    c = [(lo[d] + hi[d]) / 2 for d in range(3)]
    Wd, Hd, h = 160, 80, 20.0  # 0.25 world units per pixel
    img = lc.render(g, lc.TransferFunction.preset("gray", 1, 1.0), Wd, Hd, eye=(c[0], c[1], 50), at=c, ortho=h,
                    mode="mip", range=(0, 1))
    row, col = np.unravel_index(np.argmax(np.asarray(img)[..., 0]), (Hd, Wd))
    px = h / Hd
    assert abs((col + 0.5) - (Wd / 2 + (p[0] - c[0]) / px)) <= 1.0
    assert abs((row + 0.5) - (Hd / 2 - (p[1] - c[1]) / px)) <= 1.0
    # the same voxel given with order "xyz" lands on the same pixel
    gx = lc.Grid(dev, a.transpose(2, 1, 0), spacing=sp, origin=org, order="xyz")
    np.testing.assert_array_equal(np.asarray(lc.render(gx, lc.TransferFunction.preset("gray", 1, 1.0), Wd, Hd,
                                                       eye=(c[0], c[1], 50), at=c, ortho=h, mode="mip",
                                                       range=(0, 1))), np.asarray(img))


def test_rbf_arrays(dev):
    c = rng.normal(size=(10, 3)).astype(np.float32)
    with pytest.raises(ValueError, match="widths: expected 10 values"):
        lc.RBFSet(dev, c, np.ones(9), np.ones(10))
    w = np.ones(10)
    w[4] = np.nan
    with pytest.raises(lc.InvalidArgumentError, match="^widths: "):
        lc.RBFSet(dev, c, w, np.ones(10))
    assert lc.RBFSet(dev, c.astype(np.float64).tolist(), [1.0] * 10, np.ones(10, np.int32)).info["count"] == 10

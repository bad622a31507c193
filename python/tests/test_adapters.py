"""lanecast.yt and lanecast.mdanalysis on in-memory data (no downloads) and on the project's
PDB/DCD files read by MDAnalysis itself."""

import warnings

import numpy as np
import pytest

import lanecast as lc
from conftest import data_file

yt = pytest.importorskip("yt", reason="yt is absent (Debian: python3-yt); lanecast.yt is not tested")
mda = pytest.importorskip("MDAnalysis", reason="MDAnalysis is absent (Debian: python3-mdanalysis)")
import lanecast.mdanalysis as lcmda  # noqa: E402
import lanecast.yt as lcyt  # noqa: E402
from yt.testing import fake_random_ds, fake_sph_orientation_ds  # noqa: E402

yt.set_log_level(40)


def test_yt_uniform_grid(dev):
    ds = fake_random_ds(16, fields=("density",), units=("g/cm**3",), nprocs=1)
    vol = lcyt.volume(ds, ("gas", "density"), dev)
    info = vol.info
    assert vol.kind == "grid" and info["size"] == (16, 16, 16)
    assert info["spacing"] == pytest.approx((1 / 16,) * 3) and info["origin"] == pytest.approx((1 / 32,) * 3)
    cg = ds.covering_grid(0, ds.domain_left_edge, ds.domain_dimensions)[("gas", "density")].d
    ijk = [(3, 9, 12), (12, 3, 9), (0, 15, 7)]
    pts = np.array([[(i + 0.5) / 16, (j + 0.5) / 16, (k + 0.5) / 16] for i, j, k in ijk], np.float32)
    np.testing.assert_allclose(vol.sample(pts)[:, 0], [cg[i, j, k] for i, j, k in ijk], rtol=1e-6)
    img = lcyt.render(ds, ("gas", "density"), width=32)
    assert img.shape == (32, 32, 4) and img[..., 3].max() > 0


def test_yt_load_uniform_grid(dev):
    a = np.zeros((8, 6, 4))
    a[5, 1, 2] = 3.0
    ds = yt.load_uniform_grid({"density": (a, "g/cm**3")}, a.shape, bbox=np.array([[0, 8], [0, 6], [0, 4]]))
    vol = lcyt.volume(ds, ("stream", "density"), dev)
    assert vol.info["size"] == (8, 6, 4)
    np.testing.assert_allclose(vol.sample(np.array([[5.5, 1.5, 2.5], [2.5, 1.5, 5.5]], np.float32))[:, 0], [3, 0])


def test_yt_sph_particles(dev):
    ds = fake_sph_orientation_ds()
    ad = ds.all_data()
    vol = lcyt.volume(ds, ("io", "density"), dev)
    pos = ad["io", "particle_position"].to("code_length").d
    h = ad["io", "smoothing_length"].to("code_length").d
    info = vol.info
    assert vol.kind == "particles" and info["count"] == len(pos)
    assert info["radius"] == (pytest.approx(h.min() / 2), pytest.approx(h.max() / 2))
    assert info["centre_bounds"] == (tuple(pytest.approx(x) for x in pos.min(0)),
                                     tuple(pytest.approx(x) for x in pos.max(0)))
    # at a particle's centre the field is its own weight (the others are beyond sigma r)
    np.testing.assert_allclose(vol.sample(pos[1:2].astype(np.float32))[0, 0], ad["io", "density"].d[1], rtol=1e-6)


def test_yt_load_particles_without_smoothing_lengths(dev):
    rng = np.random.default_rng(2)
    n = 500
    data = {("io", "particle_position_" + c): rng.uniform(0, 1, n) for c in "xyz"}
    data["io", "particle_mass"] = np.ones(n)
    ds = yt.load_particles(data, length_unit=3.0, bbox=np.array([[0, 1], [0, 1], [0, 1]]))
    vol = lcyt.volume(ds, ("io", "particle_mass"), dev)
    assert vol.info["count"] == n
    assert vol.info["radius"][0] == pytest.approx((1.0 / n) ** (1 / 3) * 0.5)  # code units: the box is 1


def water_universe(nres=3):
    u = mda.Universe.empty(3 * nres, n_residues=nres, atom_resindex=np.repeat(np.arange(nres), 3),
                           trajectory=True)
    u.add_TopologyAttr("name", ["OW", "HW1", "HW2"] * nres)
    u.add_TopologyAttr("elements", ["O", "H", "H"] * nres)
    u.add_TopologyAttr("resname", ["SOL"] * nres)
    u.add_TopologyAttr("charges", [-0.8, 0.4, 0.4] * nres)
    u.atoms.positions = np.array([[3 * r, 0, 0] for r in range(nres)] * 3, np.float32).reshape(3, nres, 3) \
        .transpose(1, 0, 2).reshape(-1, 3) + np.tile([[0, 0, 0], [0.96, 0, 0], [-0.24, 0.93, 0]], (nres, 1))
    return u


def test_mdanalysis_in_memory(dev):
    from MDAnalysis.topology.tables import vdwradii
    u = water_universe()
    vol = lcmda.volume(u, dev, fields="element", values="charges")
    info = vol.info
    assert info["count"] == 9 and info["nfields"] == 2
    assert info["radius"] == (pytest.approx(vdwradii["H"] * 0.5), pytest.approx(vdwradii["O"] * 0.5))
    o = u.atoms.positions[0:1]
    assert vol.sample(o)[0, 0] == pytest.approx(-0.8, abs=1e-6)  # field 0 (O) at the oxygen: its charge
    hs = lcmda.volume(u.select_atoms("name HW1 HW2"), dev)
    assert hs.info["count"] == 6
    assert lcmda.volume(u, dev, select="element O").info["count"] == 3
    with pytest.raises(ValueError, match="no atom"):
        lcmda.volume(u, dev, select="name CA")
    img = lcmda.render(u, dev, fields="element", width=32)
    assert img[..., 3].max() > 0


def test_mdanalysis_trajectory_against_lanecast(dev):
    psf, dcd = data_file("particles", "adk.psf"), data_file("particles", "adk.dcd")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(psf, dcd)
    for frame in (0, 5):
        vol = lcmda.volume(u, dev, frame=frame)
        ref = lc.load(dev, dcd, topology=psf, frame=frame)  # lanecast's own reader of the same frame
        assert vol.info["count"] == ref.info["count"] == len(u.atoms)
        for a, b in zip(vol.info["centre_bounds"], ref.info["centre_bounds"]):
            assert a == pytest.approx(b, abs=1e-4)
    ca = lcmda.volume(u, dev, select="name CA")
    assert ca.info["count"] == len(u.select_atoms("name CA"))


def test_mdanalysis_pdb(dev):
    path = data_file("particles", "1tii.pdb")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(path)
    vol = lcmda.volume(u, dev, select="protein and not element H")
    pos = u.select_atoms("protein and not element H").positions
    lo, hi = vol.info["centre_bounds"]
    np.testing.assert_allclose(lo, pos.min(0), atol=1e-4)
    np.testing.assert_allclose(hi, pos.max(0), atol=1e-4)

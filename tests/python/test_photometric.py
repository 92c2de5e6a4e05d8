"""Photometric files against `lumis info FILE --json`, candela on a grid, sampling."""
import glob
import json
import os

import numpy as np
import pytest

import lumis

HERE = os.path.dirname(os.path.abspath(__file__))
FILES = sorted(glob.glob(os.path.join(HERE, "..", "data", "photometric", "*.ies")) +
               glob.glob(os.path.join(HERE, "..", "data", "photometric", "*.ldt")))


@pytest.mark.parametrize("path", FILES, ids=os.path.basename)
def test_info_matches_the_tool(cli, path):
    want = json.loads(cli("info", path, "--json"))
    with lumis.read_photometric(path) as f:
        got = f.info()
        assert f.format == want["format"] and f.standard == want["standard"]
        assert f.manufacturer == want["manufacturer"]
    assert got["type"] == want["type"] and got["symmetry"] == want["symmetry"]
    assert got["shape"] == want["shape"]
    assert (got["nv"], got["nh"]) == (want["vertical_angles"], want["horizontal_angles"])
    for k in ("flux", "max_candela", "downward_fraction"):
        assert got[k] == pytest.approx(want[k], rel=1e-14, abs=0), k
    assert got["beam_deg"] == pytest.approx(want["beam_deg"], rel=1e-14, abs=0)


def test_candela_grid_and_sampling():
    path = os.path.join(HERE, "..", "data", "photometric", "luxcore_asa_15m_r2.ies")
    with lumis.read_photometric(path) as f:
        info = f.info()
        grid = f.candela(np.arange(0, 360, 5.0), np.arange(0, 181, 2.5))
        assert grid.shape == (72, 73)
        assert grid.max() == pytest.approx(info["max_candela"], rel=1e-12)
        d, p = f.sample(lumis.uniform(20000, 4))
        assert np.allclose(np.linalg.norm(d, axis=1), 1, atol=1e-6)
        # the pdf is the intensity over the flux: its samples estimate the flux back
        i = f.intensity(d)
        assert np.allclose(p, i / info["flux"], rtol=1e-4)
        assert np.allclose(f.pdf(d), p, rtol=1e-4)  # d rounded to float
        assert np.mean(i / p) == pytest.approx(info["flux"], rel=1e-4)
        assert np.all(d[:, 2] < 1e-6)  # a full cut-off: nothing upwards (+z is away from the aim)


def test_orient_is_the_documented_frame():
    """photometric_orient (the Blender add-on aims fixtures with it): docs/photometric.md's
    hanging pose and yoke, the aim at -z, the roll, and the refusals."""
    hang = lumis.photometric_orient("C", (0, -1, 0))
    assert hang == pytest.approx(np.array([[1, 0, 0], [0, 0, 1], [0, -1, 0]]), abs=1e-12)
    a = np.array([0.3, -1.0, 0.5])
    a /= np.linalg.norm(a)
    for t in ("C", "B", "A"):
        R = lumis.photometric_orient(t, a, roll_deg=30)
        assert R @ R.T == pytest.approx(np.eye(3), abs=1e-9)
        assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-9)
        assert R @ (0, 0, -1) == pytest.approx(a, abs=1e-6)  # lumis_vec3 is float
    # C0 of a type C fixture tilted by the documented formula, before the roll
    c0 = np.array([1 - a[0] ** 2 / (1 - a[1]), a[0], -a[0] * a[2] / (1 - a[1])])
    R = lumis.photometric_orient("C", a)
    assert R[:, 0] == pytest.approx(c0 / np.linalg.norm(c0), abs=1e-6)
    # a yoke's lateral axis (local +y) is horizontal
    assert lumis.photometric_orient("B", a)[1, 1] == pytest.approx(0.0, abs=1e-9)
    with lumis.read_photometric(FILES[0]) as f:
        assert f.orient(a) == pytest.approx(lumis.photometric_orient(f.type, a), abs=0)
    for bad in (dict(aim=(0, 0, 0)), dict(aim=(0, -1, 0), up=(0, 2, 0)),
                dict(aim=(0, -1, 0), roll_deg=float("nan"))):
        with pytest.raises(lumis.InvalidArgumentError):
            lumis.photometric_orient("C", **bad)
    with pytest.raises(lumis.InvalidArgumentError, match="type"):
        lumis.photometric_orient("D", (0, -1, 0))


@pytest.mark.parametrize("name", ["luxcore_asa_15m_r2.ies", "mdl_type_b_test.ies",
                                  "pv_no_symmetry.ldt"])
def test_batches_are_the_single_calls(name):
    """candela, intensity, pdf and sample make one batched C call each: their numbers are the
    scalar C calls' (bit for bit), called here one by one through the same library."""
    from lumis._lib import ffi, lib
    path = os.path.join(HERE, "..", "data", "photometric", name)
    rng = np.random.default_rng(40)
    d = rng.normal(size=(500, 3))
    d = (d / np.linalg.norm(d, axis=1)[:, None]).astype(np.float32)
    u = lumis.uniform(500, 7)
    h, v = np.linspace(-200, 360, 29), np.linspace(-190, 190, 31)
    with lumis.read_photometric(path) as f:
        m = f.ptr.model
        vec = [ffi.new("lumis_vec3 *", tuple(map(float, x)))[0] for x in d]
        assert f.intensity(d).tolist() == [lib.lumis_photometric_intensity(m, x) for x in vec]
        assert f.pdf(d).tolist() == [lib.lumis_photometric_pdf(m, x) for x in vec]
        assert f.candela(h, v).tolist() == [[lib.lumis_photometric_intensity_at(m, a, b)
                                             for b in v.tolist()] for a in h.tolist()]
        dirs, pdf = f.sample(u)
        dp, pp = ffi.new("lumis_vec3 *"), ffi.new("double *")
        for k, (a, b) in enumerate(u.tolist()):
            assert lib.lumis_photometric_sample(m, a, b, dp, pp) == lib.LUMIS_OK
            assert (dp.x, dp.y, dp.z) == tuple(dirs[k].tolist()) and pp[0] == pdf[k]
        # empty batches are empty arrays
        assert f.intensity(np.zeros((0, 3))).shape == (0,)
        assert f.sample(np.zeros((0, 2)))[0].shape == (0, 3)
        assert f.candela([], [0.0]).shape == (0, 1)

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

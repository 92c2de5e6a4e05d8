"""Maps: specs and files against `lumis info --json`, numpy in and out, the orientation."""
import json

import numpy as np
import pytest

import lumis


@pytest.mark.parametrize("spec", ["sky:64x32", "studio:48x24"])
def test_info_matches_the_tool(cli, spec):
    want = json.loads(cli("info", spec, "--json"))
    with lumis.read_map(spec) as m:
        got = m.info()
        assert (m.width, m.height) == (want["width"], want["height"])
    for k in ("min_luminance", "avg_luminance", "max_luminance", "dynamic_range", "power",
              "top1_share", "top01_share"):
        # the same C call; cJSON prints 15 significant digits
        assert got[k] == pytest.approx(want[k], rel=1e-14, abs=0), k
    assert got["power_rgb"] == pytest.approx(want["power_rgb"], rel=1e-14, abs=0)


def test_real_file_matches_the_tool(cli, real_map):
    want = json.loads(cli("info", real_map, "--json"))
    with lumis.read_map(real_map) as m:
        got = m.info()
        assert m.read_info["format"] == "exr"
        assert m.replaced["nan"] + m.replaced["inf"] + m.replaced["negative"] == want["replaced"]
    assert (got["width"], got["height"]) == (want["width"], want["height"])
    assert got["power"] == pytest.approx(want["power"], rel=1e-14, abs=0)


def test_array_round_trip_and_file_round_trip(tmp_path, cli):
    rng = np.random.default_rng(3)
    a = rng.random((5, 8, 3), dtype=np.float32) * 10
    a[0, 0, 0] = np.nan
    a[1, 2, 1] = -4.0
    with lumis.Map(a) as m:
        assert m.shape == (5, 8, 3)
        b = m.to_array()
        assert m.replaced["nan"] == 1 and m.replaced["negative"] == 1
    want = np.nan_to_num(a, nan=0.0)
    want[want < 0] = 0
    assert b.dtype == np.float32 and np.array_equal(b, want)
    p = tmp_path / "x.pfm"
    lumis.write_image(str(p), b)
    assert np.array_equal(lumis.read_image(str(p)), b)
    # the tool reads what the package wrote, as the same map
    info = json.loads(cli("info", p, "--json"))
    assert (info["width"], info["height"]) == (8, 5)
    assert info["power"] == lumis.Map(b).info()["power"]


def test_row_zero_is_the_zenith():
    a = np.zeros((16, 32, 3), dtype=np.float32)
    a[0, :, :] = 1.0  # only the top row shines
    with lumis.Map(a) as m, lumis.Sampler(m, "inversion") as s:
        d, p = s.sample(lumis.uniform(100, 5))
    assert np.all(d[:, 1] > np.cos(np.pi / 16) - 1e-6)  # within the first row's cap about +y
    b = np.zeros((16, 32, 3), dtype=np.float32)
    b[8, 0, :] = 1.0  # row 8 (the horizon's lower side), column 0: u = 0 looks along +x
    with lumis.Map(b) as m, lumis.Sampler(m, "inversion") as s:
        d, _ = s.sample(lumis.uniform(100, 5))
    assert np.all(d[:, 0] > 0.95) and np.all(d[:, 1] <= 0) and np.all(d[:, 2] >= 0)


def test_rotation_and_scale():
    with lumis.read_map("sky:32x16", rotation_deg=90.0, scale=2.0) as m:
        assert m.rotation_deg == 90.0 and m.scale == 2.0
        with lumis.read_map("sky:32x16") as m1:
            assert m.info()["power"] == pytest.approx(2 * m1.info()["power"], rel=1e-12)
            assert np.array_equal(m.to_array(), m1.to_array())  # unscaled, unrotated pixels

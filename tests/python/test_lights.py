"""Light sets: every method against `lumis lights --json`, the exports read back."""
import json

import numpy as np
import pytest

import lumis

MAP = "sky:64x32"


def test_every_method_is_known():
    assert set(lumis.light_methods()) >= {"median-cut", "variance-min", "fhis", "tmms", "wu",
                                          "wu-is", "wu-is-mask", "wu-is-kmeans", "wu-original-cut"}


@pytest.mark.parametrize("method", lumis.light_methods())
def test_lights_match_the_tool(cli, tmp_path, method):
    params = "seed=5,jitter=0.2" + (",lambda=2" if method.startswith("wu") else "")
    out = tmp_path / "cli.json"
    cli("lights", MAP, "--method", method, "-k", 12, "--sets", 2, "--param", params,
        "--frame", "lumis", "--json", out)
    want = json.loads(out.read_text())
    with lumis.read_map(MAP) as m, lumis.lights(m, method, 12, 2, params) as L:
        got = L.lights()
        assert L.sets == 2 and L.count == len(want["lights"]) == len(got)
        for g, w in zip(got, want["lights"]):
            assert np.array_equal(g["direction"], np.float32(w["dir"]))
            # cJSON prints doubles with 15 significant digits
            assert np.allclose(g["power"], w["power"], rtol=1e-14, atol=0)
        # the package's own export is the tool's file
        mine = tmp_path / "py.json"
        L.write_json(str(mine), frame="lumis", source=MAP)
        assert json.loads(mine.read_text()) == want
        # the power of the map, conserved
        assert got["power"].sum(0) == pytest.approx(m.info()["power_rgb"], rel=1e-9)
        assert L.labels().shape == (32, 64)
        assert L.labels().max() == L.count - 1


def test_params_as_a_dict_and_refused_ones(tmp_path):
    with lumis.read_map(MAP) as m:
        with lumis.lights(m, "wu", 8, params={"seed": 3, "percentile": 95}) as L:
            assert L.params == "percentile=95,seed=3" or "percentile=95" in L.params
            assert L.info()["direct"] + L.info()["indirect"] == L.count
        with pytest.raises(lumis.InvalidArgumentError, match="percentile"):
            lumis.lights(m, "median-cut", 8, params="percentile=95")  # a Wu parameter
        with pytest.raises(lumis.InvalidArgumentError, match="bogus"):
            lumis.lights(m, "wu", 8, params="bogus=1")
        with pytest.raises(lumis.InvalidArgumentError, match="no-such-method"):
            lumis.lights(m, "no-such-method", 8)


def test_gltf_export(tmp_path):
    with lumis.read_map(MAP) as m, lumis.lights(m, "median-cut", 16) as L:
        L.write_gltf(str(tmp_path / "l.gltf"))
        g = json.loads((tmp_path / "l.gltf").read_text())
        assert len(g["extensions"]["KHR_lights_punctual"]["lights"]) == 16
        L.write_gltf(str(tmp_path / "l.glb"))
        assert (tmp_path / "l.glb").read_bytes()[:4] == b"glTF"
        with pytest.raises(lumis.UnknownFormatError):
            L.write_gltf(str(tmp_path / "l.txt"))


def test_fold_below_keeps_the_power():
    with lumis.read_map(MAP) as m, lumis.lights(m, "median-cut", 16) as L:
        before = L.power.sum(0)
        rep = L.fold_below()
        assert rep["kept"] == L.count and rep["folded"] > 0
        assert np.all(L.directions[:, 1] > 0)
        assert L.power.sum(0) == pytest.approx(before, rel=1e-12)
        set_e, map_e = L.irradiance((0, 1, 0))
        assert set_e > 0 and map_e > 0

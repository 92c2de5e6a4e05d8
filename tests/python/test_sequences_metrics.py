"""Sequences (every public one) and metrics against `lumis compare --json`."""
import json

import numpy as np
import pytest

import lumis


def test_pcg_is_the_tools_random_numbers(cli):
    # `lumis sample --method uniform` turns u into directions through a known warp; the
    # uniform sampler's directions from lumis.uniform equal the tool's, so its u are the same
    want = np.array(cli("sample", "sky:8x4", "--method", "uniform", "-n", 50, "--seed", 9).split(),
                    dtype=np.float64).reshape(-1, 7).astype(np.float32)
    with lumis.read_map("sky:8x4") as m, lumis.Sampler(m, "uniform") as s:
        d, _ = s.sample(lumis.sequence("pcg", 50, 9))
    assert np.array_equal(d, want[:, :3])


def is_02_net(u, m):
    """Each of the m + 1 grids of 2^m elementary intervals holds exactly one point."""
    n = 1 << m
    for a in range(m + 1):
        cx, cy = 1 << a, 1 << (m - a)
        cells = (np.floor(u[:, 0] * cx) * cy + np.floor(u[:, 1] * cy)).astype(int)
        if len(np.unique(cells)) != n:
            return False
    return True


@pytest.mark.parametrize("name", ["sobol", "pmj02"])
def test_02_sequences_are_nets(name):
    u = lumis.sequence(name, 256, seed=12)
    assert u.shape == (256, 2) and np.all((u >= 0) & (u < 1))
    assert all(is_02_net(u[: 1 << m], m) for m in range(9))
    assert not np.array_equal(u, lumis.sequence(name, 256, seed=13))


def test_halton_and_the_render_only_sequences():
    u = lumis.sequence("halton", 4)
    assert np.allclose(u, [[0, 0], [1 / 2, 1 / 3], [1 / 4, 2 / 3], [3 / 4, 1 / 9]])
    for name in ("stratified", "zsobol"):
        with pytest.raises(lumis.InvalidArgumentError, match="renderer"):
            lumis.sequence(name, 4)


def test_compare_matches_the_tool(cli, tmp_path):
    ref = lumis.read_map("sky:64x32").to_array()
    test = ref * np.float32(1.1) + np.float32(0.05)
    lumis.write_image(str(tmp_path / "r.exr"), ref)
    lumis.write_image(str(tmp_path / "t.exr"), test)
    want = json.loads(cli("compare", tmp_path / "r.exr", tmp_path / "t.exr", "--json",
                          "--exposure", -3))
    got = lumis.compare(ref, test, exposure_ev=-3)
    for k in ("rmse", "mse", "relmse", "psnr", "lab_delta_e", "flip_ldr", "flip_hdr"):
        assert got[k] == pytest.approx(want[k], rel=1e-12, abs=0), k
    assert lumis.errors(ref, ref)["psnr"] == float("inf")
    mean, emap = lumis.flip(ref, test, map=True)
    assert emap.shape == (32, 64) and emap.mean() == pytest.approx(mean, rel=1e-5)

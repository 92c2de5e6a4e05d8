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


@pytest.mark.parametrize("name", ["stratified", "zsobol"])
def test_the_renderers_own_sequences(name):
    """stratified and zsobol exist only per pixel (lumis_sequence_fill): sequence(name, n)
    is pixel (0, 0)'s camera jitter planned for n samples, stratified as each promises."""
    u = lumis.sequence(name, 64, seed=3)
    assert u.shape == (64, 2) and np.all((u >= 0) & (u < 1))
    assert np.array_equal(u, lumis.render_sequence(name, 64, seed=3, spp=64))
    if name == "zsobol":
        assert is_02_net(u, 6)
    else:  # 2^6 strata: an 8 x 8 grid, one point in each cell
        assert len(np.unique(np.floor(u[:, 0] * 8) * 8 + np.floor(u[:, 1] * 8))) == 64
    assert not np.array_equal(u, lumis.sequence(name, 64, seed=4))
    other = lumis.render_sequence(name, 64, seed=3, spp=64, width=4, pixel=(1, 0))
    assert not np.array_equal(u, other)


def test_render_sequence_is_the_renderers():
    """sobol and pmj02 as the renderer draws them are the public (0,2) points scrambled per
    pixel and dimension: prefixes of 2^m stay nets at any pixel and dimension; the camera
    samples from first_sample on are the whole run's tail; per_sample points come sample
    after sample; pcg's dimension d is its stream's pairs from d on."""
    for name in ("sobol", "pmj02", "default"):
        u = lumis.render_sequence(name, 256, seed=12, spp=256, width=5, pixel=(3, 2), dimension=4)
        assert all(is_02_net(u[: 1 << m], m) for m in range(9)), name
        tail = lumis.render_sequence(name, 100, seed=12, spp=256, width=5, pixel=(3, 2),
                                     dimension=4, first_sample=156)
        assert np.array_equal(tail, u[156:]), name
    assert np.array_equal(lumis.render_sequence("default", 8), lumis.render_sequence("sobol", 8))
    three = lumis.render_sequence("sobol", 16, spp=16, per_sample=3, dimension=2)
    assert three.shape == (48, 2)
    assert all(is_02_net(three[: 1 << m], m) for m in range(6))
    pcg = lumis.render_sequence("pcg", 4, dimension=0)
    pcg2 = lumis.render_sequence("pcg", 4, dimension=2)
    assert not np.array_equal(pcg, pcg2)
    for bad in (dict(pixel=(5, 0)), dict(dimension=-1), dict(per_sample=-1), dict(spp=-2),
                dict(first_sample=-1)):
        with pytest.raises(lumis.InvalidArgumentError):
            lumis.render_sequence("sobol", 4, width=5, **bad)
    with pytest.raises(lumis.InvalidArgumentError, match="nosuch"):
        lumis.render_sequence("nosuch", 4)


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

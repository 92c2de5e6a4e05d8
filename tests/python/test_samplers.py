"""Samplers: bit for bit the tool's `lumis sample` and `lumis pdf`, invert, and the
statistics redone from Python (chi-square against the pdf, the pdf integrating to one)."""
import math

import numpy as np
import pytest

import lumis

MAP = "sky:64x32"
CONFIGS = [(m, c) for m in lumis.sampler_methods() for c in (False, True)]


def parse(text, cols):
    a = np.array(text.split(), dtype=np.float64).reshape(-1, cols)
    return a.astype(np.float32)  # %.9g reads back every float exactly


@pytest.mark.parametrize("method,compensate", CONFIGS)
def test_sample_and_pdf_match_the_tool_bit_for_bit(cli, method, compensate):
    args = ["--method", method] + (["--compensate"] if compensate else [])
    want = parse(cli("sample", MAP, "-n", 500, "--seed", 7, *args), 7)
    with lumis.read_map(MAP) as m, lumis.Sampler(m, method, compensate=compensate) as s:
        d, p, rad = s.sample(lumis.uniform(500, 7), radiance=True)
        assert s.method == method
        assert np.array_equal(d, want[:, 0:3]) and np.array_equal(p, want[:, 3])
        assert np.array_equal(rad, want[:, 4:7])
        # pdf of other directions than the samples too
        q = np.random.default_rng(1).normal(size=(300, 3)).astype(np.float32)
        lines = "".join("%.9g %.9g %.9g\n" % tuple(x) for x in q.tolist())
        want_pdf = parse(cli("pdf", MAP, *args, stdin=lines), 4)
        got, got_rad = s.pdf(q, radiance=True)
        assert np.array_equal(got, want_pdf[:, 0]) and np.array_equal(got_rad, want_pdf[:, 1:4])
        assert np.array_equal(s.pdf(d), p)  # pdf(sample(u).dir) == sample(u).pdf


def test_importance_and_kdtree_options_reach_the_sampler(cli):
    for args, kw in [(["--importance", "max-channel"], {"importance": "max-channel"}),
                     (["--method", "kdtree", "--blocks", "64", "--kdtree-uniform-angles"],
                      {"method": "kdtree", "kdtree_blocks": 64, "kdtree_uniform_angles": True})]:
        want = parse(cli("sample", MAP, "-n", 200, "--seed", 3, *args), 7)
        with lumis.read_map(MAP) as m, lumis.Sampler(m, **kw) as s:
            d, p = s.sample(lumis.uniform(200, 3))
        assert np.array_equal(d, want[:, 0:3]) and np.array_equal(p, want[:, 3])


@pytest.mark.parametrize("method", ["inversion", "inversion-guided", "hierarchical", "uniform"])
def test_invert_round_trips(method):
    u = lumis.uniform(2000, 11)
    with lumis.read_map(MAP) as m, lumis.Sampler(m, method) as s:
        d, _ = s.sample(u)
        assert np.allclose(s.invert(d), u, atol=2e-5)


def test_invert_refuses_what_it_cannot():
    with lumis.read_map(MAP) as m, lumis.Sampler(m, "alias") as s:
        with pytest.raises(lumis.UnsupportedError):
            s.invert(np.array([[0, 1, 0]], dtype=np.float32))
    with lumis.read_map(MAP) as m, lumis.Sampler(m, "inversion") as s:
        with pytest.raises(lumis.InvalidArgumentError, match="direction 1"):
            s.invert(np.array([[0, 1, 0], [0, 0, 0]], dtype=np.float32))


# ---- statistics --------------------------------------------------------------------------

def pixel_centres(w, h):
    i, j = np.meshgrid(np.arange(w), np.arange(h))
    phi, theta = 2 * np.pi * (i + 0.5) / w, np.pi * (j + 0.5) / h
    d = np.stack([np.sin(theta) * np.cos(phi), np.cos(theta), np.sin(theta) * np.sin(phi)], -1)
    cos_edges = np.cos(np.pi * np.arange(h + 1) / h)
    omega = (2 * np.pi / w) * (cos_edges[:-1] - cos_edges[1:])
    return d.reshape(-1, 3).astype(np.float32), np.repeat(omega, w)


def pixel_of(d, w, h):
    phi = np.arctan2(d[:, 2], d[:, 0]) / (2 * np.pi)
    phi[phi < 0] += 1
    theta = np.arccos(np.clip(d[:, 1], -1, 1)) / np.pi
    i = np.minimum((phi * w).astype(int), w - 1)
    j = np.minimum((theta * h).astype(int), h - 1)
    return j * w + i


def chi2_p_value(x, k):
    """Upper tail of chi-square with k degrees of freedom (Wilson-Hilferty)."""
    z = ((x / k) ** (1 / 3) - (1 - 2 / (9 * k))) / math.sqrt(2 / (9 * k))
    return 0.5 * math.erfc(z / math.sqrt(2))


# Exact per-pixel samplers: the pdf is constant over a pixel, so pdf(centre) x solid angle is
# the pixel's probability.
@pytest.mark.parametrize("method", ["alias", "hierarchical"])
def test_pdf_integrates_to_one_and_samples_follow_it(method):
    w, h, n = 32, 16, 400_000
    with lumis.read_map("studio:%dx%d" % (w, h)) as m, lumis.Sampler(m, method) as s:
        centres, omega = pixel_centres(w, h)
        prob = s.pdf(centres).astype(np.float64) * omega
        assert prob.sum() == pytest.approx(1.0, abs=1e-5)
        d, p = s.sample(lumis.uniform(n, 2024))
    counts = np.bincount(pixel_of(d.astype(np.float64), w, h), minlength=w * h)
    expected = prob * n
    # Monte Carlo: the mean of 1 / pdf over the samples is the sphere's 4 pi
    assert np.mean(1.0 / p.astype(np.float64)) == pytest.approx(4 * np.pi, rel=0.02)
    assert counts[expected == 0].sum() == 0  # nothing where the pdf is 0
    order = np.argsort(expected)
    e, c = expected[order], counts[order].astype(np.float64)
    keep = e >= 5
    x = np.sum((c[keep] - e[keep]) ** 2 / e[keep])
    rest_e, rest_c = e[~keep].sum(), c[~keep].sum()
    k = int(keep.sum()) - 1
    if rest_e > 0:
        x += (rest_c - rest_e) ** 2 / rest_e
        k += 1
    assert chi2_p_value(x, k) > 1e-4, (x, k)

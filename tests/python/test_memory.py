"""10,000 create/destroy cycles do not grow the process (every handle freed)."""
import gc

import numpy as np

import lumis


def rss_kib():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 // 1024


def cycle(u, pixels):
    with lumis.Map(pixels) as m, lumis.Sampler(m, "alias") as s:
        s.sample(u)
        with lumis.lights(m, "median-cut", 4, 1) as L:
            L.lights()
    # and through the finalizer, without close()
    lumis.Sampler(lumis.read_map("studio:16x8"), "kdtree", kdtree_blocks=16).pdf(u[:, :1].repeat(3, 1))


def test_no_growth_over_10000_cycles():
    u = lumis.uniform(64, 1)
    pixels = np.random.default_rng(0).random((16, 32, 3), dtype=np.float32)
    for _ in range(1000):  # warm up: allocator pools, cffi's caches
        cycle(u, pixels)
    gc.collect()
    before = rss_kib()
    for _ in range(10_000):
        cycle(u, pixels)
    gc.collect()
    grown = rss_kib() - before
    # a leaked map, sampler or light set per cycle would be > 20 KiB each: > 200 MB in all
    assert grown < 4096, "RSS grew by %d KiB over 10,000 cycles" % grown

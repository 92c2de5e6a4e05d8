#!/usr/bin/env python3
"""Sampling 10^6 directions from Python against the C batch path (issue 40: within 1.2x).

Per method and run, back to back so that a loaded machine slows both alike: the C batch path
alone (lumis_sampler_sample_n into a buffer written before, the call `lumis bench-samplers`
times, made directly), lumis.Sampler.sample(u, out=buf) (the package's path with a reused
buffer: argument checks, the call, the views) and lumis.Sampler.sample(u) (new arrays:
the kernel maps and zeroes 28 MB of fresh pages).  Reports median samples per second and the
median of the per-run ratios; `lumis bench-samplers --json`'s batch figure is printed beside
them when --cli is given.  Exits 1 when the package with out= costs more than --limit (1.2)
times the C call.

    PYTHONPATH=python python3 bench/python_sampling.py [MAP] [--methods ...] [--cli build/lumis]
"""
import argparse
import json
import statistics
import subprocess
import sys
import time

import numpy as np

import lumis
from lumis import ffi, lib

ap = argparse.ArgumentParser()
ap.add_argument("map", nargs="?", default="sky:2048x1024")
ap.add_argument("--cli", default=None)
ap.add_argument("--methods", default="inversion-guided,alias,kdtree")
ap.add_argument("--samples", type=int, default=1_000_000)
ap.add_argument("--runs", type=int, default=9)
ap.add_argument("--limit", type=float, default=1.2)
a = ap.parse_args()

cli = {}
if a.cli:
    rows = json.loads(subprocess.run([a.cli, "bench-samplers", a.map, "--methods", a.methods,
                                      "--samples", str(a.samples), "--runs", "5", "--json"],
                                     check=True, capture_output=True, text=True).stdout)
    cli = {r["method"]: r["batch_samples_per_second"] for r in rows if not r.get("variant")}

n = a.samples
u = lumis.uniform(n, 1)
cu = ffi.cast("double *", ffi.from_buffer(u))
cout = ffi.new("lumis_env_sample[]", n)
buf = np.empty((n, 7), dtype=np.float32)
worst = 0.0
print("map %s, %d samples a call, %d runs (medians)" % (a.map, n, a.runs))
print("%-17s %12s %12s %6s %12s %6s %14s" % ("method", "C calls/s", "Py out= /s", "Py/C",
                                             "Py new /s", "Py/C", "bench-samplers"))
with lumis.read_map(a.map) as m:
    for method in a.methods.split(","):
        with lumis.Sampler(m, method) as s:
            lib.lumis_sampler_sample_n(s.ptr, cu, n, cout)
            s.sample(u, out=buf)
            tc, to, tn = [], [], []
            for _ in range(a.runs):
                t0 = time.perf_counter()
                lib.lumis_sampler_sample_n(s.ptr, cu, n, cout)
                t1 = time.perf_counter()
                s.sample(u, out=buf)
                t2 = time.perf_counter()
                s.sample(u)
                t3 = time.perf_counter()
                tc.append(t1 - t0)
                to.append(t2 - t1)
                tn.append(t3 - t2)
        r_out = statistics.median(o / c for o, c in zip(to, tc))
        r_new = statistics.median(x / c for x, c in zip(tn, tc))
        worst = max(worst, r_out)
        med = lambda t: n / statistics.median(t)  # noqa: E731
        print("%-17s %12.4g %12.4g %6.3f %12.4g %6.3f %14s" % (
            method, med(tc), med(to), r_out, med(tn), r_new,
            "%.4g" % cli[method] if method in cli else "-"))
sys.exit(0 if worst <= a.limit else 1)

#!/usr/bin/env python3
"""lumis against Cycles at equal error: per map, the samples per pixel each renderer needs
to reach relMSE 0.01 and 0.001 (each against its own reference; log-log interpolation
between the measured powers of two, as analyze.py), the cost of a sample of lumis relative
to Cycles' (cost.txt: the median of pairs of 1024-spp renders in turn on one core, each
renderer's own sampling time), and their product: lumis's render time to the target
relative to Cycles'.

    python3 bench/cycles/compare.py [SEQUENCE]   (default sobol; reads cycles.csv,
                                                 lumis.csv and cost.txt beside it)
"""
import csv
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def rows_of(path, renderer_prefix, sequence):
    out = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            if r["renderer"].startswith(renderer_prefix) and r["sequence"] == sequence:
                out.setdefault(r["map"], []).append((int(r["spp"]), float(r["relmse"])))
    for m in out:
        out[m].sort()
    return out


def spp_at(rows, target):
    for (n0, e0), (n1, e1) in zip(rows, rows[1:]):
        if e0 >= target >= e1 and e0 > e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(n0) + f * (math.log(n1) - math.log(n0)))
    return float("nan")


def main():
    seq = sys.argv[1] if len(sys.argv) > 1 else "sobol"
    lumis = rows_of(os.path.join(HERE, "lumis.csv"), "lumis", seq)
    cycles = rows_of(os.path.join(HERE, "cycles.csv"), "cycles", "pmj")
    cost = {}
    with open(os.path.join(HERE, "cost.txt")) as f:
        for line in f:
            m = re.match(r"(\S+): lumis \((\S+)\) / Cycles .* median ([0-9.]+)", line)
            if m and m.group(2) == seq:
                cost[m.group(1)] = float(m.group(3))
    print("| map | target | lumis spp | Cycles spp | spp ratio | cost of a sample, lumis / Cycles "
          "| render time, lumis / Cycles |")
    print("|---|---|---|---|---|---|---|")
    for m in cycles:
        if m not in lumis or m not in cost:
            continue
        for t in (0.01, 0.001):
            a, b = spp_at(lumis[m], t), spp_at(cycles[m], t)
            print("| %s | %g | %.1f | %.1f | %.3f | %.3f | %.3f |" % (
                m, t, a, b, a / b, cost[m], a / b * cost[m]))


main()

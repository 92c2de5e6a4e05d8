#!/usr/bin/env python3
"""Summarises bench/cycles/cycles.csv (map,renderer,sequence,spp,seconds,relmse) per map:
the least-squares slope of log relMSE against log spp over spp 4..1024, samples per
second, and the spp and seconds at which relMSE reaches 0.01 and 0.001 (linear
interpolation in log-log between the two measured points that bracket the target; past
the last point, extrapolated along the fitted slope and marked with '*').

The measured relMSE against a reference of R spp is the test's own error plus the
reference's.  With --ref-spp R the last column also gives the slope after subtracting an
estimate of the reference's share, r = m(N) (N/R) / (1 + N/R) at the largest N measured
(its error taken as falling like 1/spp between N and R).

    python3 bench/cycles/analyze.py [bench/cycles/cycles.csv] [--pixels 19200] [--ref-spp R]
"""
import csv
import math
import sys


def fit(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    b = sxy / sxx
    return b, my - b * mx


def crossing(rows, target, slope):
    """(spp, seconds, extrapolated) where relMSE first falls to target."""
    for a, b in zip(rows, rows[1:]):
        if a["relmse"] >= target >= b["relmse"] and a["relmse"] > b["relmse"]:
            f = (math.log(target) - math.log(a["relmse"])) / (
                math.log(b["relmse"]) - math.log(a["relmse"]))
            spp = math.exp(math.log(a["spp"]) + f * (math.log(b["spp"]) - math.log(a["spp"])))
            sec = math.exp(math.log(a["seconds"]) + f *
                           (math.log(b["seconds"]) - math.log(a["seconds"])))
            return spp, sec, False
    if rows[0]["relmse"] <= target:
        return rows[0]["spp"], rows[0]["seconds"], False
    last = rows[-1]  # extrapolate along the fitted slope, time proportional to spp
    spp = last["spp"] * (target / last["relmse"]) ** (1.0 / slope)
    return spp, last["seconds"] * spp / last["spp"], True


def main():
    args = sys.argv[1:]
    pixels = 160 * 120
    ref_spp = None
    if "--ref-spp" in args:
        k = args.index("--ref-spp")
        ref_spp = int(args[k + 1])
        del args[k : k + 2]
    if "--pixels" in args:
        k = args.index("--pixels")
        pixels = int(args[k + 1])
        del args[k : k + 2]
    path = args[0] if args else "bench/cycles/cycles.csv"
    groups = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            key = (r["map"], r["renderer"], r["sequence"])
            groups.setdefault(key, []).append(
                {"spp": int(r["spp"]), "seconds": float(r["seconds"]),
                 "relmse": float(r["relmse"])})
    print("| map | renderer | sequence | slope (spp 4-1024) | spp/s (at 1024 spp) | "
          "samples/s | spp @ 0.01 | s @ 0.01 | spp @ 0.001 | s @ 0.001 |"
          + (" ref share r | slope, r removed |" if ref_spp else ""))
    print("|---|---|---|---|---|---|---|---|---|---|" + ("---|---|" if ref_spp else ""))
    for (m, ren, seq), rows in groups.items():
        rows.sort(key=lambda r: r["spp"])
        sel = [r for r in rows if 4 <= r["spp"] <= 1024]
        slope, _ = fit([math.log(r["spp"]) for r in sel], [math.log(r["relmse"]) for r in sel])
        top = rows[-1]
        sps = top["spp"] / top["seconds"]
        cells = []
        for t in (0.01, 0.001):
            spp, sec, ext = crossing(rows, t, slope)
            star = "*" if ext else ""
            cells += ["%.0f%s" % (spp, star), "%.3g%s" % (sec, star)]
        extra = ""
        if ref_spp:
            q = top["spp"] / ref_spp
            r = top["relmse"] * q / (1.0 + q)
            sc, _ = fit([math.log(x["spp"]) for x in sel],
                        [math.log(x["relmse"] - r) for x in sel])
            extra = " %.3g | %.3f |" % (r, sc)
        print("| %s | %s | %s | %.3f | %.0f | %.3g | %s |%s" % (
            m, ren, seq, slope, sps, sps * pixels, " | ".join(cells), extra))


main()

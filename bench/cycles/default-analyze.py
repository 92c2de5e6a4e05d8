#!/usr/bin/env python3
"""lumis's default (the automatic estimator) against Cycles from default.sh's side-by-side
run: per map, the spp and seconds at which relMSE reaches 0.01 and 0.001 (log-log
interpolation between the two measured powers of two that bracket the target, as
analyze.py; '*' where the first point is already below it: its time is then an upper
bound), and lumis's time over Cycles'.  The default's relMSE need not fall monotonically
with spp (it may choose another estimator at another spp): the crossing is the first
bracket's, and the last column gives the fastest measured lumis render that is at or below
the target, without interpolation.

- lumis: the series' relmse (against lumis's reference) and seconds (render_seconds + the
  automatic estimator's own seconds: pilots and regions).
- Cycles: the relMSE recorded in cycles.csv (against Cycles' reference; same seed, same
  settings, same image) with the seconds measured now beside lumis (cycles_seconds), and
  for comparison the seconds recorded in cycles.csv (another day's load).

    python3 bench/cycles/default-analyze.py [lumis-default.csv] [cycles.csv]
"""
import csv
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def crossing(pts, target):
    """pts: [(spp, relmse, seconds)] sorted by spp -> (spp, seconds, flag)."""
    if pts[0][1] <= target:
        return pts[0][0], pts[0][2], "*"
    for (n0, e0, s0), (n1, e1, s1) in zip(pts, pts[1:]):
        if e0 >= target >= e1 and e0 > e1:
            f = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return (math.exp(math.log(n0) + f * (math.log(n1) - math.log(n0))),
                    math.exp(math.log(s0) + f * (math.log(s1) - math.log(s0))), "")
    return float("nan"), float("nan"), "?"


def main():
    lpath = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "lumis-default.csv")
    cpath = sys.argv[2] if len(sys.argv) > 2 else os.path.join(HERE, "cycles.csv")
    cyc = {}
    with open(cpath) as f:
        for r in csv.DictReader(f):
            if r["renderer"].startswith("cycles"):
                cyc[(r["map"], int(r["spp"]))] = (float(r["relmse"]), float(r["seconds"]))
    runs = {}
    with open(lpath) as f:
        for r in csv.DictReader(f):
            runs.setdefault(r["map"], []).append(r)
    print("### What the default chose (spp: estimator)\n")
    for m, rows in runs.items():
        rows.sort(key=lambda r: int(r["spp"]))
        print("- %s: %s" % (m, ", ".join("%s: %s" % (r["spp"], r["estimator"]) for r in rows)))
    print("\n### Time to the target\n")
    print("| map | target | lumis default spp | lumis s | Cycles spp | Cycles s (now) "
          "| lumis / Cycles (now) | Cycles s (cycles.csv) | lumis / Cycles (cycles.csv) "
          "| Cycles spp vs lumis's ref | lumis's fastest render at or below the target (spp, s) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for m, rows in runs.items():
        lum = [(int(r["spp"]), float(r["relmse"]), float(r["seconds"])) for r in rows]
        have = [r for r in rows if r["cycles_seconds"] not in ("", "NA")
                and (m, int(r["spp"])) in cyc]
        now = [(int(r["spp"]), cyc[(m, int(r["spp"]))][0], float(r["cycles_seconds"]))
               for r in have]
        old = [(n, e, s) for (mm, n), (e, s) in sorted(cyc.items()) if mm == m]
        chk = [(int(r["spp"]), float(r["cycles_relmse_vs_lumis_ref"]), float(r["cycles_seconds"]))
               for r in have]
        for t in (0.01, 0.001):
            ln, ls, lf = crossing(lum, t)
            cells = ["%s" % m, "%g" % t, "%.1f%s" % (ln, lf), "%.3g%s" % (ls, lf)]
            if now:
                cn, cs, cf = crossing(now, t)
                cells += ["%.1f%s" % (cn, cf), "%.3g" % cs, "**%.3f**%s" % (ls / cs, lf)]
            else:
                cells += ["", "", ""]
            on, os_, of = crossing(old, t) if old else (float("nan"),) * 2 + ("?",)
            cells += ["%.3g" % os_, "%.3f%s" % (ls / os_, lf)]
            cells += ["%.1f" % crossing(chk, t)[0] if chk else ""]
            ok = sorted((sec, n) for n, e, sec in lum if e <= t)
            cells += ["%d, %.3g" % (ok[0][1], ok[0][0]) if ok else "none"]
            print("| " + " | ".join(cells) + " |")
    print("\n'*': lumis is below the target at its first point (1 spp): the time is that "
          "render's, an upper bound.")


main()

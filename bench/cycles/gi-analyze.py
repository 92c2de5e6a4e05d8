"""Slopes and times to relMSE 0.01 and 0.001 of the global-illumination series
(run-gi.sh series; README.md, "Global illumination (issue 39)").

    python3 bench/cycles/gi-analyze.py bench/cycles/gi.csv [--ref-spp 4096] [--min-spp 4]

Per scene and renderer/estimator: the least-squares slope of log relMSE on log seconds
(and on log spp) over spp >= --min-spp; the spp and seconds where relMSE crosses 0.01 and
0.001, by linear interpolation in log-log between the two measured spp that bracket it,
or, past the last point, extrapolated along the slope of the last three points (marked
"~").  "s (pooled)": the spp crossing times the series' seconds per spp pooled over
spp >= 16 (the machine was shared: single timings swing).  "corr." columns first remove the reference's own share of every relMSE,
m_ref = m(N) (N/R) / (1 + N/R) at the largest N of the estimator that made the reference
(lumis: inversion-guided + MIS; R the reference's spp: each estimate against an
independent reference measures m(N) + m(R), and m_ref is m(R) for an error falling as
1/N).  Then the ratio of lumis's time to Cycles' per target.
Prints a Markdown table.
"""
import csv
import math
import sys
from collections import defaultdict


def fit(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx > 0 else float("nan")


def crossing(pts, target):
    """pts: (spp, seconds, relmse) sorted by spp -> (spp, seconds, extrapolated?)."""
    for a, b in zip(pts, pts[1:]):
        if a[2] >= target > b[2] or (a[2] > target >= b[2]):
            f = (math.log(target) - math.log(a[2])) / (math.log(b[2]) - math.log(a[2]))
            lerp = lambda u, v: math.exp(math.log(u) + f * (math.log(v) - math.log(u)))
            return lerp(a[0], b[0]), lerp(a[1], b[1]), False
    if pts and pts[0][2] < target:
        return pts[0][0], pts[0][1], False  # already below at the first point
    tail = pts[-3:]
    if len(tail) < 2 or tail[-1][2] <= 0:
        return float("nan"), float("nan"), True
    s_spp = fit([math.log(p[0]) for p in tail], [math.log(p[2]) for p in tail])
    s_sec = fit([math.log(p[1]) for p in tail], [math.log(p[2]) for p in tail])
    last = tail[-1]
    if not (s_spp < 0 and s_sec < 0):
        return float("nan"), float("nan"), True
    return (last[0] * (target / last[2]) ** (1 / s_spp),
            last[1] * (target / last[2]) ** (1 / s_sec), True)


def main():
    args = sys.argv[1:]
    ref_spp, min_spp = 4096, 4
    if "--ref-spp" in args:
        k = args.index("--ref-spp")
        ref_spp = int(args[k + 1])
        del args[k : k + 2]
    if "--min-spp" in args:
        k = args.index("--min-spp")
        min_spp = int(args[k + 1])
        del args[k : k + 2]
    series = defaultdict(list)
    for path in args:
        with open(path) as f:
            for r in csv.DictReader(f):
                key = (r["scene"], r["map"], r["renderer"], r["estimator"])
                series[key].append((int(r["spp"]), float(r["seconds"]), float(r["relmse"])))
    rows, times = [], {}

    def ref_share(key):
        """The reference's own relMSE: from the series of the estimator that made it
        (lumis's reference is an inversion-guided + MIS render; Cycles' its own)."""
        ref_key = key if key[2].startswith("cycles") else key[:3] + ("inversion-mis",)
        pts = sorted(series.get(ref_key, series[key]))
        n_max, m_max = pts[-1][0], pts[-1][2]
        return m_max * (n_max / ref_spp) / (1 + n_max / ref_spp)

    for key in sorted(series):
        pts = sorted(series[key])
        use = [p for p in pts if p[0] >= min_spp and p[2] > 0]
        m_ref = ref_share(key)
        corr = [(p[0], p[1], p[2] - m_ref) for p in pts if p[2] - m_ref > 0]
        # seconds per spp pooled over spp >= 16 (the runs alternate between the renderers,
        # so a busy machine slows all alike; pooling smooths its swings)
        big = [p for p in pts if p[0] >= 16]
        cost = sum(p[1] for p in big) / sum(p[0] for p in big)
        sl_t = fit([math.log(p[1]) for p in use], [math.log(p[2]) for p in use])
        sl_n = fit([math.log(p[0]) for p in use], [math.log(p[2]) for p in use])
        cells = []
        for target in (0.01, 0.001):
            n, t, ex = crossing(pts, target)
            nc, tc, exc = crossing(corr, target)
            times[key + (target,)] = (t, tc, ex, exc, n * cost, nc * cost)
            mark = "~" if ex else ""
            markc = "~" if exc else ""
            cells += ["%s%.0f" % (mark, n), "%s%.2f" % (mark, t), "%s%.2f" % (mark, n * cost),
                      "%s%.0f" % (markc, nc), "%s%.2f" % (markc, nc * cost)]
        rows.append("| %s | %s | %s | %.3f | %.3f | %.2g | %.4f | %s |" % (
            key[0], key[2], key[3], sl_t, sl_n, m_ref, cost, " | ".join(cells)))
    print("| scene | renderer | estimator | slope vs s | slope vs spp | ref. share | s/spp "
          "| spp to 0.01 | s to 0.01 | s (pooled) | spp corr. | s corr. (pooled) "
          "| spp to 0.001 | s to 0.001 | s (pooled) | spp corr. | s corr. (pooled) |")
    print("|" + "---|" * 17)
    print("\n".join(rows))
    print()
    print("lumis's time / Cycles' time to the target: measured seconds; pooled s/spp; "
          "pooled, reference share removed")
    print()
    print("| scene | estimator | to 0.01 | pooled | pooled corr. | to 0.001 | pooled "
          "| pooled corr. |")
    print("|---|---|---|---|---|---|---|---|")
    for key in sorted(series):
        if key[2].startswith("cycles"):
            continue
        cyc = [k for k in series if k[0] == key[0] and k[1] == key[1] and k[2].startswith("cycles")]
        if not cyc:
            continue
        cells = []
        for target in (0.01, 0.001):
            a, b = times[key + (target,)], times[cyc[0] + (target,)]
            ex = "~" if (a[2] or b[2]) else ""
            exc = "~" if (a[3] or b[3]) else ""
            cells += ["%s%.2f" % (ex, a[0] / b[0]), "%s%.2f" % (ex, a[4] / b[4]),
                      "%s%.2f" % (exc, a[5] / b[5])]
        print("| %s | %s | %s |" % (key[0], key[3], " | ".join(cells)))


main()

#!/usr/bin/env python3
"""The default suite's tables (bench/suites/default.json, default-scenes.json): per budget the
geometric mean over the (map, scene) pairs of relMSE ratios between methods, how many pairs
each is worse than MIS on, the pairs where it is, and what the default chose.

    python3 docs/results/default/analyze.py OUT/results.csv [--pairs]
"""
import collections
import csv
import math
import sys


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    show_pairs = "--pairs" in sys.argv
    by = collections.defaultdict(dict)  # (budget, map, scene) -> method -> row
    for r in rows:
        by[(r["budget"], r["map"], r["scene"])][r["method"]] = r
    budgets = sorted({k[0] for k in by}, key=lambda b: float(b.strip("ts")))
    methods = sorted({m for v in by.values() for m in v})
    others = [m for m in methods if m != "mis"]
    print("| ratio | " + " | ".join(budgets) + " |")
    print("|---|" + "---|" * len(budgets))
    pairs = [(a, "mis") for a in others]
    if "default" in methods and "strat32" in methods:
        pairs.append(("default", "strat32"))
    for a, b in pairs:
        cells = []
        for bu in budgets:
            logs = [math.log(float(v[a]["relmse"]) / float(v[b]["relmse"]))
                    for k, v in by.items() if k[0] == bu and a in v and b in v]
            cells.append("%.3f" % math.exp(sum(logs) / len(logs)) if logs else "–")
        print("| %s / %s | %s |" % (a, b, " | ".join(cells)))
    print()
    print("| budget | " + " | ".join("%s worse than mis" % m for m in others) +
          " | default chose | cpu_share (median) |")
    print("|---|" + "---|" * (len(others) + 2))
    for bu in budgets:
        cells = []
        for m in others:
            worse = [k for k, v in by.items() if k[0] == bu and m in v and "mis" in v and
                     float(v[m]["relmse"]) > float(v["mis"]["relmse"])]
            cells.append("%d of %d" % (len(worse), sum(1 for k in by if k[0] == bu)))
        chose = collections.Counter(v["default"].get("auto_chosen", "") for k, v in by.items()
                                    if k[0] == bu and "default" in v)
        shares = sorted(float(v[m]["cpu_share"]) for k, v in by.items() if k[0] == bu
                        for m in v if v[m].get("cpu_share"))
        med = shares[len(shares) // 2] if shares else float("nan")
        print("| %s | %s | %s | %.2f |" % (bu, " | ".join(cells),
                                          ", ".join("%s %d" % c for c in chose.most_common()),
                                          med))
    if show_pairs:
        print()
        print("| budget | map | scene | " + " | ".join("%s / mis" % m for m in others) + " |")
        print("|---|---|---|" + "---|" * len(others))
        for k in sorted(by, key=lambda k: (float(k[0].strip("ts")), k[1], k[2])):
            v = by[k]
            print("| %s | %s | %s | %s |" % (k[0], k[1], k[2], " | ".join(
                "%.3f" % (float(v[m]["relmse"]) / float(v["mis"]["relmse"]))
                if m in v and "mis" in v else "–" for m in others)))


if __name__ == "__main__":
    main()

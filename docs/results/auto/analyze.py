#!/usr/bin/env python3
"""What docs/results/auto/README.md says about the auto suite, from its results.csv.

    python3 docs/results/auto/analyze.py docs/results/auto/results.csv

Per budget, and per scene over the budgets: the geometric mean of auto's relMSE over the
best fixed method's (every other method of the suite) and over the better of its own two
candidates rendered as fixed methods (mis: inversion + MIS; mc-strat-32: the median-cut
strata at K = 32), the cases beyond 1.10x, how often auto chose the candidate that the
full renders found better, and the share of the budget auto spent before its first
sample (pilots and regions).  Then every miss, with the reason it is most likely one of:
"choice" (auto chose the candidate that rendered worse), "candidate" (auto chose the better
of its candidates, but a method it cannot choose was better by more than 10 %),
"overhead" (neither: its pilots cost it the rest).
"""
import csv
import math
import sys
from collections import defaultdict

MISS = 1.10
CANDIDATE = {"mis": "mis", "stratified": "mc-strat-32"}


def main(path):
    rows = list(csv.DictReader(open(path)))
    by = defaultdict(dict)
    for r in rows:
        by[(r["map"], r["scene"], r["budget"])][r["method"]] = r
    budgets = sorted({k[2] for k in by}, key=lambda b: float(b[1:-1]))
    cases = []
    for (m, sc, b), meth in sorted(by.items()):
        a = meth.get("auto")
        if not a:
            continue
        rel = float(a["relmse"])
        fixed = {k: float(v["relmse"]) for k, v in meth.items() if k != "auto"}
        best = min(fixed, key=fixed.get)
        cands = {k: fixed[k] for k in ("mis", "mc-strat-32") if k in fixed}
        better = min(cands, key=cands.get)
        chosen = a["auto_chosen"]
        right = CANDIDATE.get(chosen) == better
        ratio = rel / fixed[best]
        why = ""
        if ratio > MISS:
            if not right:
                why = "choice"
            elif fixed[better] > MISS * fixed[best]:
                why = "candidate"
            else:
                why = "overhead"
        cases.append(dict(map=m, scene=sc, budget=b, chosen=chosen, best=best,
                          ratio=ratio, cand_ratio=rel / cands[better], right=right,
                          better=better, prep=float(a["prep_seconds"]) / float(b[1:-1]),
                          why=why, cand_gap=cands[max(cands, key=cands.get)] / cands[better]))

    def gm(xs):
        return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")

    def row(label, cs):
        n = len(cs)
        return "| %s | %d | %.3f | %d | %.3f | %d of %d | %.0f %% |" % (
            label, n, gm([c["ratio"] for c in cs]), sum(c["ratio"] > MISS for c in cs),
            gm([c["cand_ratio"] for c in cs]), sum(c["right"] for c in cs), n,
            100 * sum(c["prep"] for c in cs) / n)

    head = ("| %s | cases | auto / best fixed | beyond 1.10× | auto / better candidate "
            "| chose the better candidate | budget spent before the first sample |\n"
            "|---|---|---|---|---|---|---|")
    print(head % "budget")
    for b in budgets:
        print(row(b, [c for c in cases if c["budget"] == b]))
    print(row("all", cases))
    print()
    print(head % "scene")
    for sc in sorted({c["scene"] for c in cases}):
        print(row(sc, [c for c in cases if c["scene"] == sc]))
    print()
    print("| map | scene | budget | chosen | better candidate (gap) | best fixed "
          "| auto / best | why |\n|---|---|---|---|---|---|---|---|")
    for c in cases:
        if c["ratio"] > MISS:
            print("| %s | %s | %s | %s | %s (%.2f×) | %s | %.2f | %s |" % (
                c["map"], c["scene"], c["budget"], c["chosen"], c["better"], c["cand_gap"],
                c["best"], c["ratio"], c["why"]))
    print()
    for w in ("choice", "candidate", "overhead"):
        print("%s: %d" % (w, sum(c["why"] == w for c in cases)))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results/auto/results.csv")

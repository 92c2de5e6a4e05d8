#!/usr/bin/env python3
"""Checks that two `lumis bench` folders of one suite report the same thing: one run on a
single machine, one as Slurm job arrays (CI's cluster stage, docs/cluster.md).

    scripts/bench-equal.py SINGLE_DIR CLUSTER_DIR [--rel-tol 1e-5]

- Both are complete (items_done == items) and hold the same items.
- Equal-sample items are deterministic: their renders are the same bytes, and their
  metrics agree to --rel-tol. (Not exactly: a reference split by passes and merged equals
  the single render up to float rounding, a few 1e-8 relative in the metrics.)
- Rankings (every rank_* of results.json's summary, per budget) are identical, equal-time
  budgets included: a suite for this check has methods far enough apart that the noise of
  equal time cannot swap them.
Exit 0 when equal; 1 with every difference listed.
"""
import csv
import json
import math
import os
import sys

METRICS = ["rmse", "relmse", "psnr", "lab_delta_e", "flip_ldr", "flip_hdr"]


def load(d):
    with open(os.path.join(d, "results.json")) as f:
        j = json.load(f)
    with open(os.path.join(d, "results.csv")) as f:
        rows = {(r["map"], r["scene"], r["method"], r["budget"]): r for r in csv.DictReader(f)}
    return j, rows


def close(a, b, tol):
    if a == b:
        return True
    if a is None or b is None:
        return False
    a, b = float(a), float(b)
    if math.isnan(a) and math.isnan(b):
        return True
    return abs(a - b) <= tol * max(abs(a), abs(b))


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    tol = 1e-5
    if "--rel-tol" in sys.argv:
        tol = float(sys.argv[sys.argv.index("--rel-tol") + 1])
        args = [a for a in args if a != sys.argv[sys.argv.index("--rel-tol") + 1]]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    a_dir, b_dir = args
    (ja, ra), (jb, rb) = load(a_dir), load(b_dir)
    bad = []
    for name, j in (("single", ja), ("cluster", jb)):
        if j["items_done"] != j["items"]:
            bad.append(f"{name}: {j['items_done']} of {j['items']} items done")
    if set(ra) != set(rb):
        bad.append(f"the items differ: {sorted(set(ra) ^ set(rb))}")
    spp_budgets = {b for (_, _, _, b), r in ra.items() if b.startswith("spp")}
    compared = 0
    for key in sorted(set(ra) & set(rb)):
        if key[3] not in spp_budgets:
            continue
        x, y = ra[key], rb[key]
        if x["spp"] != y["spp"]:
            bad.append(f"{key}: {x['spp']} spp against {y['spp']}")
        for m in METRICS:
            if not close(x[m] or None, y[m] or None, tol):
                bad.append(f"{key}: {m} {x[m]} against {y[m]}")
        ida = "__".join(key)
        with open(os.path.join(a_dir, "renders", ida + ".exr"), "rb") as f:
            pa = f.read()
        with open(os.path.join(b_dir, "renders", ida + ".exr"), "rb") as f:
            pb = f.read()
        if pa != pb:
            bad.append(f"{key}: the renders differ")
        compared += 1
    sa = {(s["budget"], s["method"]): s for s in ja["summary"]}
    sb = {(s["budget"], s["method"]): s for s in jb["summary"]}
    ranks = 0
    for k in sorted(set(sa) | set(sb)):
        if k not in sa or k not in sb:
            bad.append(f"summary {k}: in one run only")
            continue
        for f in sa[k]:
            if f.startswith("rank_"):
                ranks += 1
                if sa[k][f] != sb[k].get(f):
                    bad.append(f"summary {k}: {f} {sa[k][f]} against {sb[k].get(f)}")
            elif f.startswith("mean_") and k[0] in spp_budgets and f[5:] in METRICS:
                if not close(sa[k][f], sb[k].get(f), tol):
                    bad.append(f"summary {k}: {f} {sa[k][f]} against {sb[k].get(f)}")
    if bad:
        print("bench-equal: the runs differ:", file=sys.stderr)
        for b in bad:
            print("  " + b, file=sys.stderr)
        return 1
    print(f"bench-equal: {len(ra)} items in each; {compared} equal-sample items with the same "
          f"renders and metrics within {tol:g}; {ranks} ranks identical")
    return 0


if __name__ == "__main__":
    sys.exit(main())

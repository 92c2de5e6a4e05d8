#!/usr/bin/env python3
"""make coverage, after gcovr: the files of src/ with the lowest branch coverage, and every
public function (declared in include/lumis/*.h) that no test ever called.

    scripts/coverage-check.py COVERAGE.json [--min-branch PERCENT]

Exit 1 if a public function was never called or if the branch coverage of src/ is below
--min-branch (default: 0, report only)."""
import argparse
import glob
import json
import os
import re
import sys


def public_names(root):
    names = set()
    for h in glob.glob(os.path.join(root, "include", "lumis", "*.h")):
        with open(h, encoding="utf-8") as f:
            text = f.read()
        # a declaration: "type lumis_name(" at the start of a statement (not a call in a
        # comment's example, which is indented or follows '=')
        for m in re.finditer(r"^[A-Za-z_][\w \*]*?\b(lumis_\w+)\s*\(", text, re.M):
            names.add(m.group(1))
    return names


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("json")
    ap.add_argument("--min-branch", type=float, default=0.0)
    a = ap.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    with open(a.json, encoding="utf-8") as f:
        data = json.load(f)
    public = public_names(root)
    rows, never = [], []
    tot_b = tot_bc = 0
    for fe in data["files"]:
        b = bc = 0
        for ln in fe["lines"]:
            for br in ln.get("branches", []):
                b += 1
                bc += br["count"] > 0
        tot_b += b
        tot_bc += bc
        if b:
            rows.append((100.0 * bc / b, b - bc, fe["file"]))
        for fn in fe.get("functions", []):
            name = fn["name"].split("(")[0]
            if name in public and fn["execution_count"] == 0:
                never.append(f'{fe["file"]}:{fn["lineno"]}: {name}')
    rows.sort()
    print("coverage: lowest branch coverage (percent, branches never taken, file)")
    for pct, missed, name in rows[:8]:
        print(f"  {pct:5.1f} %  {missed:4d}  {name}")
    total = 100.0 * tot_bc / tot_b if tot_b else 100.0
    print(f"coverage: branches of src/ taken: {tot_bc} of {tot_b} ({total:.1f} %)")
    status = 0
    if never:
        print(f"coverage: {len(never)} public function(s) no test calls:")
        for n in sorted(never):
            print("  " + n)
        status = 1
    else:
        print(f"coverage: every public function of include/lumis/ that src/ defines is called")
    if total < a.min_branch:
        print(f"coverage: branch coverage {total:.1f} % is below the floor {a.min_branch:.1f} %")
        status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())

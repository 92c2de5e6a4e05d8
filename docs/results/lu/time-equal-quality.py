#!/usr/bin/env python3
"""Equal-quality render time, restricted against global sampling (Fig. 11 of
docs/results/lu/README.md), with medians instead of run.py's single timings.

    taskset -c 1 docs/results/lu/time-equal-quality.py [--out bench-out/lu] [--runs 5]

Reads run.py's OUT/results.json.  For each scene and each equal-quality row there (a
restricted configuration on its best-time front), it times, on one thread, alternating,
--runs times: the restricted configuration and the two global configurations of the
global front that bracket its mean Lab.  The global time at the restricted mean Lab is
then interpolated log-log between the brackets' median times, at the brackets' mean Lab
from run.py.  Of the rows whose global brackets took at most --max-global-seconds in
run.py, the two at the ends of the mean Lab range are timed.  Prints one line per timed render and a markdown table.  Standard library
only.
"""
import argparse
import json
import math
import os
import statistics
import subprocess

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("--lumis", default="./build/lumis")
ap.add_argument("--out", default="bench-out/lu")
ap.add_argument("--size", default="256x160")
ap.add_argument("--runs", type=int, default=5)
ap.add_argument("--max-global-seconds", type=float, default=20.0,
                help="skip rows whose slower global bracket took longer in run.py")
args = ap.parse_args()
with open(os.path.join(args.out, "results.json")) as f:
    results = json.load(f)
tmp = os.path.join(args.out, "timing")
os.makedirs(tmp, exist_ok=True)


def seconds(scene, opts):
    exr = os.path.join(tmp, f"{scene}.exr")
    subprocess.run([args.lumis, "render", "--scene", scene, "--size", args.size, "--threads", "1",
                    "--quiet", "-o", exr] + opts, check=True)
    with open(exr[:-4] + ".json") as f:
        return json.load(f)["timings"]["render_seconds"]


rows = []
for scene, R in results.items():
    runs = R["fig11"]["global"]["runs"]
    front = R["fig11"]["global"]["time"]
    todo = []
    for e in R["equal_quality"]:
        # The global front's bracketing points, and the runs they come from.
        pair = next(((a, b) for a, b in zip(front, front[1:]) if a[1] >= e["lab"] >= b[1]), None)
        if pair is not None and pair[1][0] <= args.max_global_seconds:
            todo.append((e, [next(r for r in runs if (r["seconds"], r["lab"]) == tuple(p))
                             for p in pair]))
    todo.sort(key=lambda t: t[0]["lab"])
    for e, g in todo[:1] + todo[-1:] if len(todo) > 1 else todo:
        configs = [e["restricted"].split()] + [r["options"].split() for r in g]
        times = [[] for _ in configs]
        for _ in range(args.runs):
            for i, opts in enumerate(configs):
                times[i].append(seconds(scene, opts))
                print(scene, " ".join(opts), f"{times[i][-1]:.4f}", flush=True)
        med = [statistics.median(t) for t in times]
        (l0, l1), (t0, t1) = (g[0]["lab"], g[1]["lab"]), (med[1], med[2])
        w = math.log(l0 / e["lab"]) / math.log(l0 / l1)
        tg = math.exp(math.log(t0) + w * (math.log(t1) - math.log(t0)))
        rows.append((scene, e["restricted"], e["lab"], med[0], " / ".join(r["options"] for r in g),
                     f"{t0:.2f} / {t1:.2f}", tg, tg / med[0]))

print("\n| scene | restricted | mean Lab | s (median) | global brackets | their s (median) | "
      "global s at that Lab | time ratio |\n|---|---|---|---|---|---|---|---|")
for r in rows:
    print(f"| {r[0]} | {r[1]} | {r[2]:.3g} | {r[3]:.3f} | {r[4]} | {r[5]} | {r[6]:.2f} | {r[7]:.1f}x |")

#!/usr/bin/env python3
"""Reproduces the numbers of docs/results/lu/README.md: Lu, Pacanowski and Granier's
experiments (Fig. 5, 7, 8, 9, 11, 12) on lumis' synthetic car headlight, with the built-in
scenes headlight and headlight-close, against a reference rendered at a high sample count.

    docs/results/lu/run.py [--out bench-out/lu] [--size 256x160] [--ref-spp 256]

Every image is rendered by `lumis render` and judged by `lumis compare` (mean CIELAB Delta E,
as the paper, and RMSE).  Renders are kept in --out and reused when their sidecar exists
(delete the folder to start again).  Prints the tables as markdown and writes them, with
every measurement, to OUT/tables.md and OUT/results.json.  Standard library only.
"""
import argparse
import json
import math
import os
import subprocess
import sys

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("--lumis", default="./build/lumis")
ap.add_argument("--out", default="bench-out/lu")
ap.add_argument("--size", default="256x160")
ap.add_argument("--ref-spp", type=int, default=256, help="camera samples of the reference (K = 64 each)")
ap.add_argument("--scenes", default="headlight,headlight-close")
ap.add_argument("--threads", type=int, default=0, help="0: all cores")
args = ap.parse_args()
os.makedirs(args.out, exist_ok=True)
PIXELS = math.prod(int(v) for v in args.size.split("x"))


def render(scene, name, opts, seed=1, threads=None):
    """Renders once (or reuses the render); returns (exr path, sidecar dict)."""
    exr = os.path.join(args.out, f"{scene}-{name}.exr")
    side = exr[:-4] + ".json"
    if not os.path.exists(side):
        cmd = [args.lumis, "render", "--scene", scene, "--size", args.size, "--seed", str(seed),
               "--quiet", "-o", exr] + opts
        threads = args.threads if threads is None else threads
        if threads:
            cmd += ["--threads", str(threads)]
        print("  " + " ".join(cmd[1:]), file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True)
    with open(side) as f:
        return exr, json.load(f)


def judge(scene, ref, name, opts, threads=None):
    exr, side = render(scene, name, opts, threads=threads)
    out = subprocess.run([args.lumis, "compare", ref, exr, "--json", "--no-hdr-flip"],
                         check=True, capture_output=True, text=True).stdout
    m = json.loads(out)
    return {"name": name, "options": " ".join(opts), "lab": m["lab_delta_e"], "rmse": m["rmse"],
            "seconds": side["timings"]["render_seconds"], "shadow_rays": side["rays"]["shadow"],
            "spp": side["spp"], "samples": side["luminaires"]["samples_per_pixel"]}


def loglog_at(points, lab):
    """The x where the log-log line through the bracketing (x, lab) points reaches lab
    (points sorted by x, lab falling); None if no pair brackets it."""
    for (x0, e0), (x1, e1) in zip(points, points[1:]):
        if e0 >= lab >= e1 and e0 > e1 > 0:
            t = math.log(e0 / lab) / math.log(e0 / e1)
            return math.exp(math.log(x0) + t * (math.log(x1) - math.log(x0)))
    return None


def envelope(points):
    """The lower envelope of (cost, lab) points: sorted by cost, each with a lower lab than
    every cheaper one (the best quality reachable at that cost)."""
    front = []
    for c, e in sorted(points):
        if not front or e < front[-1][1]:
            front.append((c, e))
    return front


def table(head, rows):
    s = "| " + " | ".join(head) + " |\n|" + "---|" * len(head) + "\n"
    for r in rows:
        s += "| " + " | ".join(r) + " |\n"
    return s


results, md = {}, []
for scene in args.scenes.split(","):
    print(f"== {scene}", file=sys.stderr)
    ref, ref_side = render(scene, f"ref{args.ref_spp}", ["--lum-budget", "64", "--spp", str(args.ref_spp)], seed=999)
    R = {"reference": {"spp": ref_side["spp"], "budget": 64,
                       "seconds": ref_side["timings"]["render_seconds"]}}
    md.append(f"### {scene} ({args.size}; reference: restricted, K = 64, {args.ref_spp} spp, "
              f"{R['reference']['seconds']:.0f} s)\n")
    f = lambda x: f"{x:.3g}"

    # Fig. 12 (and the K = 32 rows of Fig. 11): every strategy at K = 32 per camera sample.
    runs = {}
    for strat, spps in (("restricted", (1, 2, 4, 16)), ("uniform", (1, 2, 4, 8, 16, 32)),
                        ("global", (1, 4, 16, 64, 256))):
        runs[strat] = [judge(scene, ref, f"{strat}-k32-spp{n}",
                             ["--lum-strategy", strat, "--lum-budget", "32", "--spp", str(n)])
                       for n in spps]
    R["strategies"] = runs
    rows = [[s, str(r["spp"]), f"{r['samples']:.1f}", f(r["lab"]), f(r["rmse"]), f"{r['seconds']:.3f}"]
            for s in runs for r in runs[s]]
    md.append("Strategies at K = 32 per camera sample (samples: evaluated per pixel, sidecar):\n\n" +
              table(["strategy", "spp", "samples/pixel", "mean Lab", "RMSE", "render s"], rows))
    base = runs["restricted"][0]
    pts = [(r["samples"], r["lab"]) for r in runs["uniform"]]
    uni = loglog_at(pts, base["lab"])
    same = {n: runs["uniform"][[r["spp"] for r in runs["uniform"]].index(n)]["lab"] /
            runs["restricted"][[r["spp"] for r in runs["restricted"]].index(n)]["lab"]
            for n in (1, 2, 4, 16)}
    R["uniform_over_restricted_equal_samples"] = same
    R["uniform_equal_quality_samples"] = uni
    md.append(f"\nUniform at the mean Lab of restricted at 1 spp ({base['lab']:.3g}, "
              f"{base['samples']:.1f} samples/pixel): "
              + (f"{uni:.1f} samples/pixel" if uni else "beyond the renders") + ".  Uniform over "
              "restricted Lab error at equal samples: "
              + ", ".join(f"{v:.2f}x at {n} spp" for n, v in same.items()) + ".\n")

    # Fig. 11: restricted against global sampling at equal quality.  Each strategy over a
    # grid of K (samples per camera sample) and spp, then the best of each at equal mean
    # Lab: the lower envelope of (render time, Lab) and of (samples, Lab).  The global
    # strategy's best K is large (its draws are shared by every pixel, and most cost no
    # ray), so a comparison at one K would flatter restricted sampling.
    # The long global renders (K = 4096 beyond 16 spp, minutes on one thread) run on every
    # core and are timed by scaling the 16 spp render's time linearly in spp (render time
    # is linear in spp at fixed K: the 1-16 spp rows show it).
    grid = {"restricted": [(k, n) for k in (32, 64, 128, 256) for n in (1, 2, 4)] +
                          [(256, 8), (512, 4), (512, 8)],
            "global": [(k, n) for k in (64, 256, 1024, 4096) for n in (1, 2, 4, 8, 16)] +
                      [(4096, 32), (4096, 64)]}
    fronts = {}
    for strat, cfgs in grid.items():
        rs = []
        for k, n in cfgs:
            long = strat == "global" and n > 16
            r = judge(scene, ref, f"fig11-{strat}-k{k}-spp{n}",
                      ["--lum-strategy", strat, "--lum-budget", str(k), "--spp", str(n)],
                      threads=0 if long else None)
            if long:
                r16 = next(x for x in rs if x["options"].split()[3] == str(k) and x["spp"] == 16)
                r["seconds"], r["scaled"] = r16["seconds"] * n / 16, True
            rs.append(r)
        fronts[strat] = {"runs": rs, "time": envelope([(r["seconds"], r["lab"]) for r in rs]),
                         "samples": envelope([(r["samples"], r["lab"]) for r in rs])}
    R["fig11"] = fronts
    md.append("\nFig. 11 grid (one thread; samples evaluated per pixel):\n\n" + table(
        ["strategy", "K", "spp", "samples/pixel", "mean Lab", "render s"],
        [[s, r["options"].split()[3], str(r["spp"]), f"{r['samples']:.0f}", f(r["lab"]),
          f"{r['seconds']:.3f}" + (" (scaled)" if r.get("scaled") else "")]
         for s in fronts for r in fronts[s]["runs"]]))
    eq = []
    for r in fronts["restricted"]["runs"]:
        if (r["seconds"], r["lab"]) not in fronts["restricted"]["time"]:
            continue  # not on restricted's own best-time front
        gt = loglog_at(fronts["global"]["time"], r["lab"])
        gs = loglog_at(fronts["global"]["samples"], r["lab"])
        if gt is None or gs is None:
            continue  # outside the global grid's range: no interpolation
        eq.append({"restricted": r["options"], "lab": r["lab"], "seconds": r["seconds"],
                   "samples": r["samples"], "global_seconds": gt, "global_samples": gs,
                   "time_ratio": gt / r["seconds"], "sample_ratio": gs / r["samples"]})
    R["equal_quality"] = eq
    md.append("\nEqual quality, each strategy at its best (global interpolated log-log on its "
              "fronts):\n\n" + table(
                  ["restricted", "mean Lab", "samples/pixel", "s", "global samples/pixel",
                   "global s", "sample ratio", "time ratio"],
                  [[e["restricted"], f(e["lab"]), f"{e['samples']:.0f}", f"{e['seconds']:.3f}",
                    f"{e['global_samples']:.0f}", f"{e['global_seconds']:.2f}",
                    f"{e['sample_ratio']:.0f}x", f"{e['time_ratio']:.1f}x"] for e in eq]))

    # Fig. 9: K_max at K = 64.
    kmax = [judge(scene, ref, f"kmax{k}-k64", ["--lum-budget", "64", "--spp", "2"] +
                  (["--lum-kmax", str(k)] if k else [])) for k in (1, 2, 4, 8, 16, 0)]
    R["k_max"] = kmax
    md.append("\nK_max at K = 64, 2 spp:\n\n" + table(
        ["K_max", "shadow rays/pixel", "mean Lab", "RMSE", "render s"],
        [[r["name"].split("-")[0][4:] or "none", f"{r['shadow_rays'] / PIXELS:.1f}",
          f(r["lab"]), f(r["rmse"]), f"{r['seconds']:.3f}"] for r in kmax]))

    # Fig. 5: secant against binary search at equal depth.
    depth = {}
    for s in ("secant", "binary"):
        depth[s] = [judge(scene, ref, f"{s}-depth{d}", ["--lum-budget", "32", "--spp", "4",
                                                          "--lum-search", s, "--lum-depth", str(d)])
                    for d in (1, 2, 3, 4, 6, 8, 0)]
    R["search_depth"] = depth
    md.append("\nSearch depth (K = 32, 4 spp; depth 0 = exact):\n\n" + table(
        ["depth"] + [f"{s} Lab" for s in depth] + [f"{s} s" for s in depth],
        [[str(d)] + [f(depth[s][i]["lab"]) for s in depth] + [f"{depth[s][i]['seconds']:.3f}" for s in depth]
         for i, d in enumerate((1, 2, 3, 4, 6, 8, 0))]))

    # Fig. 8: Halton against PCG.
    seq = {q: [judge(scene, ref, f"{q}-spp{n}", ["--lum-budget", "32", "--spp", str(n), "--sequence", q])
               for n in (1, 4, 16)] for q in ("pcg", "halton")}
    R["sequence"] = seq
    md.append("\nRandom numbers (K = 32):\n\n" + table(
        ["spp", "PCG32 Lab", "Halton Lab", "PCG32 RMSE", "Halton RMSE"],
        [[str(n), f(seq["pcg"][i]["lab"]), f(seq["halton"][i]["lab"]), f(seq["pcg"][i]["rmse"]),
          f(seq["halton"][i]["rmse"])] for i, n in enumerate((1, 4, 16))]))

    # Fig. 7: approximate against exact visibility.
    vis = [judge(scene, ref, f"vis-{v}", ["--lum-budget", "32", "--spp", "64", "--visibility", v])
           for v in ("exact", "approx", "shadowmap", "none")]
    R["visibility"] = vis
    md.append("\nVisibility (K = 32, 64 spp) against the exact reference:\n\n" + table(
        ["visibility", "mean Lab", "RMSE", "shadow rays", "render s"],
        [[r["name"][4:], f(r["lab"]), f(r["rmse"]), f(r["shadow_rays"]), f"{r['seconds']:.2f}"] for r in vis]))
    md.append("\n")
    results[scene] = R

with open(os.path.join(args.out, "results.json"), "w") as fo:
    json.dump(results, fo, indent=1)
with open(os.path.join(args.out, "tables.md"), "w") as fo:
    fo.write("\n".join(md))
print("\n".join(md))

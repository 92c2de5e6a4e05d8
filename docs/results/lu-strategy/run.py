#!/usr/bin/env python3
"""Checks lumis_luminaire_predict against measurement, and `--lum-strategy auto` against
the best fixed strategy: docs/results/lu-strategy/README.md.

    docs/results/lu-strategy/run.py [--out bench-out/lu-strategy] [--size 192x120]

For every case (the car and bike presets in the headlight scenes; light fields made from
photometric files by `lumis luminaire create --from`, above a floor at several heights)
and every sequence (pcg, sobol), each strategy (restricted and uniform at K = --budget,
global at K = --global-budget, auto at K = --budget) renders --seeds times with different
seeds on one thread.  Its variance is half the MSE between two seeds' images (`lumis
compare`: no reference needed, and all four are unbiased); its time is render plus
preparation seconds (auto's prediction included), the mean over the seeds.  Then

    work = variance x time        (proportional to the time for a given MSE)
    measured time ratio of S = work(global) / work(S)

against the prediction auto made from the same scene (the sidecar's
luminaires.prediction).  Writes OUT/results.json and OUT/tables.md and prints the tables.
Standard library only.
"""
import argparse
import json
import math
import os
import subprocess
import sys

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("--lumis", default="./build/lumis")
ap.add_argument("--out", default="bench-out/lu-strategy")
ap.add_argument("--size", default="192x120")
ap.add_argument("--spp", type=int, default=4)
ap.add_argument("--budget", type=int, default=32)
ap.add_argument("--global-budget", type=int, default=1024)
ap.add_argument("--seeds", type=int, default=2)
ap.add_argument("--sequences", default="pcg,sobol")
ap.add_argument("--fixtures", default="narrow-spot,wide-flood,batwing-street,linear")
ap.add_argument("--heights", default="1.5,5,15,50", help="in units of the fixture's size")
ap.add_argument("--only", default="", help="run only the cases whose name contains one of "
                "these (comma-separated)")
args = ap.parse_args()
HERE = os.path.dirname(os.path.abspath(__file__))
FIXTURES = os.path.join(HERE, "..", "photometric", "fixtures")
# the largest dimension of each opening (m) and its field angle (deg, C0-C180), from
# docs/results/photometric/README.md
SIZE = {"narrow-spot": 0.1, "wide-flood": 0.6, "batwing-street": 0.5, "linear": 1.2,
        "linear-cusp": 1.2}
FIELD = {"narrow-spot": 34.5, "wide-flood": 168.5, "batwing-street": 175.0, "linear": 168.5,
         "linear-cusp": 172.0}
os.makedirs(os.path.join(args.out, "lf"), exist_ok=True)
os.makedirs(os.path.join(args.out, "scenes"), exist_ok=True)
os.makedirs(os.path.join(args.out, "renders"), exist_ok=True)


def run(cmd):
    print("  " + " ".join(cmd[1:]), file=sys.stderr, flush=True)
    subprocess.run(cmd, check=True)


def floor_scene(fixture, c):
    """A floor c sizes below the fixture's light field, aimed down; the camera frames the
    floor its field lights (up to 60 degrees off the aim)."""
    lf = os.path.join(args.out, "lf", fixture + ".json")
    if not os.path.exists(lf):
        run([args.lumis, "luminaire", "create", lf, "--from",
             os.path.join(FIXTURES, fixture + ".ies")])
    h = c * SIZE[fixture]
    r = h * math.tan(math.radians(min(FIELD[fixture] / 2, 60.0)))
    d = 2.2 * r + 0.5 * h
    scene = {"camera": {"eye": [0.6 * d, 0.8 * d, 0.0], "look_at": [0, 0, 0], "up": [0, 1, 0],
                        "fov_deg": 55, "width": 192, "height": 120},
             "objects": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0],
                          "size": 400 * h, "material": {"type": "lambert", "albedo": [0.7, 0.7, 0.7]}}],
             "luminaires": [{"file": os.path.join("..", "lf", fixture + ".json"),
                             "transform": {"translate": [0, h, 0], "rotate_deg": [90, 0, 0], "scale": 1},
                             "intensity": 1}]}
    path = os.path.join(args.out, "scenes", f"{fixture}-h{c:g}.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def plate_scene(fixture):
    """The fixture's light field aimed down at a plate 1.5 sizes below it, half in the beam,
    and a floor 50 sizes below: two distances in one view, for the bands of auto."""
    lf = os.path.join(args.out, "lf", fixture + ".json")
    if not os.path.exists(lf):
        run([args.lumis, "luminaire", "create", lf, "--from",
             os.path.join(FIXTURES, fixture + ".ies")])
    z = SIZE[fixture]
    lam = {"type": "lambert", "albedo": [0.7, 0.7, 0.7]}
    scene = {"camera": {"eye": [20 * z, 15 * z, 25 * z], "look_at": [0, -20 * z, 0], "up": [0, 1, 0],
                        "fov_deg": 70, "width": 192, "height": 120},
             "objects": [{"type": "plane", "point": [3 * z, -1.5 * z, 0], "normal": [0, 1, 0],
                          "size": 6 * z, "material": lam},
                         {"type": "plane", "point": [0, -50 * z, 0], "normal": [0, 1, 0],
                          "size": 400 * z, "material": lam}],
             "luminaires": [{"file": os.path.join("..", "lf", fixture + ".json"),
                             "transform": {"rotate_deg": [90, 0, 0]}}]}
    path = os.path.join(args.out, "scenes", f"{fixture}-plate.json")
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


cases = [("car / headlight", ["--scene", "headlight"]),
         ("car / headlight-close", ["--scene", "headlight-close"]),
         ("bike / headlight", ["--scene", "headlight", "--luminaire", "preset:bike"]),
         ("bike / headlight-close", ["--scene", "headlight-close", "--luminaire", "preset:bike"])]
for fx in args.fixtures.split(","):
    for c in (float(v) for v in args.heights.split(",")):
        cases.append((f"{fx} / {c:g} sizes", [floor_scene(fx, c)]))
BANDS = [f"{fx} / plate and floor" for fx in ("narrow-spot", "wide-flood")]
for fx in ("narrow-spot", "wide-flood"):
    cases.append((f"{fx} / plate and floor", [plate_scene(fx)]))
cases = [c for c in cases if any(o in c[0] for o in args.only.split(","))]


def render(tag, opts, seed):
    exr = os.path.join(args.out, "renders", f"{tag}-s{seed}.exr")
    side = exr[:-4] + ".json"
    if not os.path.exists(side):
        run([args.lumis, "render", "--size", args.size, "--spp", str(args.spp), "--threads", "1",
             "--seed", str(seed), "--quiet", "-o", exr] + opts)
    with open(side) as f:
        return exr, json.load(f)


def measure(tag, opts):
    renders = [render(tag, opts, 1 + s) for s in range(args.seeds)]
    mse = []
    for (a, _), (b, _) in zip(renders, renders[1:]):
        out = subprocess.run([args.lumis, "compare", a, b, "--json", "--no-hdr-flip"],
                             check=True, capture_output=True, text=True).stdout
        mse.append(json.loads(out)["mse"])
    var = sum(mse) / len(mse) / 2.0
    sides = [s for _, s in renders]
    t = sum(s["timings"]["render_seconds"] + s["timings"]["prep_seconds"] for s in sides) / len(sides)
    lum = sides[0]["luminaires"]
    return {"variance": var, "seconds": t, "work": var * t,
            "prep_seconds": sum(s["timings"]["prep_seconds"] for s in sides) / len(sides),
            "samples_per_pixel": lum["samples_per_pixel"],
            "chosen": lum.get("chosen"), "prediction": lum.get("prediction"),
            "band_gain": lum.get("band_gain")}


def slug(s):
    return "".join(ch if ch.isalnum() else "-" for ch in s).strip("-")


results = []
for name, scene in cases:
    for seq in args.sequences.split(","):
        print(f"== {name}, {seq}", file=sys.stderr)
        base = scene + ["--sequence", seq]
        m = {}
        for strat, k in (("restricted", args.budget), ("uniform", args.budget),
                         ("global", args.global_budget), ("auto", args.budget)):
            m[strat] = measure(f"{slug(name)}-{seq}-{strat}-k{k}",
                               base + ["--lum-strategy", strat, "--lum-budget", str(k)])
        if name in BANDS:
            m["auto-bands"] = measure(f"{slug(name)}-{seq}-auto-bands-k{args.budget}",
                                      base + ["--lum-strategy", "auto", "--lum-auto-bands",
                                              "--lum-budget", str(args.budget)])
        if m["global"]["work"] <= 0:
            print("   nothing lit: skipped", file=sys.stderr)
            continue
        pred = m["auto"]["prediction"]
        row = {"case": name, "sequence": seq, "runs": m, "chosen": m["auto"]["chosen"],
               "prediction": pred}
        for s in ("restricted", "uniform"):
            row[f"{s}_measured"] = m["global"]["work"] / m[s]["work"]
            row[f"{s}_predicted"] = pred[f"{s}_time_ratio"]
            row[f"{s}_sample_measured"] = (m["global"]["variance"] * m["global"]["samples_per_pixel"]) / (
                m[s]["variance"] * m[s]["samples_per_pixel"])
            row[f"{s}_sample_predicted"] = pred[f"{s}_sample_ratio"]
        best = min(("restricted", "uniform", "global"), key=lambda s: m[s]["work"])
        row["best"] = best
        row["auto_over_best"] = m["auto"]["work"] / m[best]["work"]
        # auto's own choice against the best, its prediction's time left out: the choice alone
        row["choice_over_best"] = m[row["chosen"]]["work"] / m[best]["work"]
        if name in BANDS:  # the lights' noise alone: every camera ray through its pixel's centre
            for strat, k in (("uniform", args.budget), ("global", args.global_budget)):
                m[strat + "-centers"] = measure(
                    f"{slug(name)}-{seq}-{strat}-centers-k{k}",
                    base + ["--lum-strategy", strat, "--lum-budget", str(k), "--pixel-centers"])
            row["uniform_centers_measured"] = m["global-centers"]["work"] / m["uniform-centers"]["work"]
        if "auto-bands" in m:
            row["bands_chosen"] = m["auto-bands"]["chosen"]
            row["band_gain_predicted"] = m["auto-bands"]["band_gain"]
            row["bands_over_best"] = m["auto-bands"]["work"] / m[best]["work"]
        results.append(row)

with open(os.path.join(args.out, "results.json"), "w") as f:
    json.dump(results, f, indent=1)


def ratio_cell(pred, meas):
    return f"{pred:.3g}x / {meas:.3g}x ({pred / meas:.2f})"


md = ["| case | seq | energy share | restricted: predicted / measured (pred/meas) | uniform: "
      "predicted / measured (pred/meas) | best | auto chose | auto / best | choice / best |",
      "|---|---|---|---|---|---|---|---|---|"]
for r in results:
    md.append(f"| {r['case']} | {r['sequence']} | {100 * r['prediction']['energy_share']:.2f} % | "
              f"{ratio_cell(r['restricted_predicted'], r['restricted_measured'])} | "
              f"{ratio_cell(r['uniform_predicted'], r['uniform_measured'])} | {r['best']} | "
              f"{r['chosen']} | {r['auto_over_best']:.2f} | {r['choice_over_best']:.2f} |")
md.append("")
md.append("| case | seq | restricted samples: predicted / measured | uniform samples: predicted / "
          "measured | auto's prediction, s | restricted s | global s |")
md.append("|---|---|---|---|---|---|---|")
for r in results:
    md.append(f"| {r['case']} | {r['sequence']} | "
              f"{ratio_cell(r['restricted_sample_predicted'], r['restricted_sample_measured'])} | "
              f"{ratio_cell(r['uniform_sample_predicted'], r['uniform_sample_measured'])} | "
              f"{r['runs']['auto']['prep_seconds']:.3f} | {r['runs']['restricted']['seconds']:.3f} | "
              f"{r['runs']['global']['seconds']:.3f} |")
md.append("")
md.append("| case | seq | auto chose | auto / best | with --lum-auto-bands | predicted gain of "
          "bands | measured: bands / best | uniform: predicted / measured with --pixel-centers |")
md.append("|---|---|---|---|---|---|---|---|")
for r in results:
    if "bands_chosen" in r:
        md.append(f"| {r['case']} | {r['sequence']} | {r['chosen']} | {r['auto_over_best']:.2f} | "
                  f"{r['bands_chosen']} | {r['band_gain_predicted']:.2f} | {r['bands_over_best']:.2f} | "
                  f"{ratio_cell(r['uniform_predicted'], r['uniform_centers_measured'])} |")
text = "\n".join(md) + "\n"
with open(os.path.join(args.out, "tables.md"), "w") as f:
    f.write(text)
print(text)

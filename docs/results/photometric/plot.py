#!/usr/bin/env python3
"""Plots results.json (bench_photometric --json) as distance-error.svg: the largest
|point / near-field - 1| in each fixture's field against the distance in units of its
luminous opening's largest dimension, log-log, with the 1 % line and photometry's rule of
thumb (five sizes).  No third-party module: the SVG is written by hand.

    python3 plot.py [results.json] [distance-error.svg]
"""
import json
import math
import sys

src = sys.argv[1] if len(sys.argv) > 1 else "results.json"
dst = sys.argv[2] if len(sys.argv) > 2 else "distance-error.svg"
with open(src) as f:
    r = json.load(f)
xs = r["distances_in_sizes"]
W, H, L, R, T, B = 700, 420, 70, 230, 40, 50
x0, x1 = math.log10(0.4), math.log10(25)
y0, y1 = math.log10(1e-4), math.log10(30)


def px(x):
    return L + (math.log10(x) - x0) / (x1 - x0) * (W - L - R)


def py(y):
    return T + (y1 - math.log10(y)) / (y1 - y0) * (H - T - B)


out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
       f'font-family="sans-serif" font-size="11"><rect width="{W}" height="{H}" fill="white"/>']
for e in range(-4, 2):
    y = py(10 ** e)
    out.append(f'<line x1="{L}" x2="{W - R}" y1="{y:.1f}" y2="{y:.1f}" stroke="#eee"/>')
    out.append(f'<text x="{L - 6}" y="{y + 4:.1f}" text-anchor="end">{100 * 10 ** e:g} %</text>')
for x in [0.5, 1, 2, 5, 10, 20]:
    X = px(x)
    out.append(f'<line x1="{X:.1f}" x2="{X:.1f}" y1="{T}" y2="{H - B}" stroke="#eee"/>')
    out.append(f'<text x="{X:.1f}" y="{H - B + 16}" text-anchor="middle">{x:g}</text>')
out.append(f'<line x1="{L}" x2="{W - R}" y1="{py(0.01):.1f}" y2="{py(0.01):.1f}" '
           f'stroke="#888" stroke-dasharray="4 3"/>')
out.append(f'<text x="{W - R - 4}" y="{py(0.01) - 4:.1f}" text-anchor="end" fill="#666">1 %</text>')
out.append(f'<line x1="{px(5):.1f}" x2="{px(5):.1f}" y1="{T}" y2="{H - B}" stroke="#888" '
           f'stroke-dasharray="4 3"/>')
out.append(f'<text x="{px(5) + 4:.1f}" y="{T + 12}" fill="#666">rule of thumb: 5 sizes</text>')
colours = ["#c0392b", "#2471a3", "#27ae60", "#8e44ad", "#d68910", "#555"]
for k, fx in enumerate(r["fixtures"]):
    pts = [(x, abs(e)) for x, e in zip(xs, fx["max_error"]) if abs(e) > 0]
    path = " ".join(f"{px(x):.1f},{py(max(e, 1e-4)):.1f}" for x, e in pts)
    c = colours[k % len(colours)]
    out.append(f'<polyline fill="none" stroke="{c}" stroke-width="2" points="{path}"/>')
    name = fx["file"].split("/")[-1].replace(".ies", "")
    within = fx["within_1pct_from_sizes"]
    label = f"{name}: 1 % from {within:.3g}" if within is not None else f"{name}: > 20"
    out.append(f'<line x1="{W - R + 10}" x2="{W - R + 30}" y1="{T + 14 + 18 * k}" '
               f'y2="{T + 14 + 18 * k}" stroke="{c}" stroke-width="2"/>')
    out.append(f'<text x="{W - R + 34}" y="{T + 18 + 18 * k}">{label}</text>')
out.append(f'<text x="{(L + W - R) / 2:.0f}" y="{H - 12}" text-anchor="middle">distance / the '
           'opening\'s largest dimension</text>')
out.append(f'<text x="14" y="{(T + H - B) / 2:.0f}" transform="rotate(-90 14 {(T + H - B) / 2:.0f})" '
           'text-anchor="middle">largest |point / near field - 1| in the field</text>')
out.append(f'<text x="{L}" y="22" font-size="13">The point model against the near field '
           '(bench_photometric)</text></svg>')
with open(dst, "w") as f:
    f.write("\n".join(out) + "\n")
print(f"wrote {dst}")

#!/usr/bin/env python3
"""Draws docs/images/photometric-aim.svg: how lumis_photometric_orient aims a fixture.

The frames are computed here with the formulas of include/lumis/render.h (a copy: the
test orientation_is_a_continuous_explicit_frame pins the library to the same formulas), and
drawn in an oblique view (x right, y up, z towards the viewer, down and to the right).

    python3 scripts/aim-figure.py > docs/images/photometric-aim.svg
"""
import math


def norm(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def orient(kind, aim, roll_deg=0.0):
    """(x, y, z) columns of R: kind 'C' or 'AB'."""
    a = norm(aim)
    z = [-c for c in a]
    h = math.hypot(a[0], a[2])
    if kind == "C":
        d = 1 - a[1] if a[1] <= 0 else h * h / (1 + a[1])
        x = [1, 0, 0] if (a[1] > 0 and h <= 1e-9) else [1 - a[0] ** 2 / d, a[0], -a[0] * a[2] / d]
    elif h > 1e-9:
        x = cross([a[2] / h, 0, -a[0] / h], z)
    else:
        x = [1, 0, 0]
    x = norm(x)
    y = cross(z, x)
    r = math.radians(roll_deg)
    xr = [x[k] * math.cos(r) + y[k] * math.sin(r) for k in range(3)]
    return xr, cross(z, xr), z


def tilted(t, p):
    t, p = math.radians(t), math.radians(p)
    return [math.sin(t) * math.cos(p), -math.cos(t), math.sin(t) * math.sin(p)]


def aimed(el, pan):
    el, pan = math.radians(el), math.radians(pan)
    return [math.cos(el) * math.cos(pan), math.sin(el), math.cos(el) * math.sin(pan)]


S = 62  # pixels per unit


def proj(o, v):
    return (o[0] + S * (v[0] + 0.45 * v[2]), o[1] - S * (v[1] - 0.3 * v[2]))


out = []


def line(o, a, b, colour, width=2.0, dash=None, head=False):
    p, q = proj(o, a), proj(o, b)
    extra = f' stroke-dasharray="{dash}"' if dash else ""
    mark = ' marker-end="url(#h-%s)"' % colour.lstrip("#") if head else ""
    out.append(f'<line x1="{p[0]:.1f}" y1="{p[1]:.1f}" x2="{q[0]:.1f}" y2="{q[1]:.1f}" '
               f'stroke="{colour}" stroke-width="{width}"{extra}{mark}/>')


def text(o, v, s, colour, anchor="start", size=12, dx=0, dy=0):
    p = proj(o, v)
    out.append(f'<text x="{p[0] + dx:.1f}" y="{p[1] + dy:.1f}" fill="{colour}" '
               f'text-anchor="{anchor}" font-size="{size}">{s}</text>')


def label(x, y, s, size=13, weight="normal"):
    out.append(f'<text x="{x}" y="{y}" font-size="{size}" font-weight="{weight}" '
               f'text-anchor="middle">{s}</text>')


def disk(o, c, R, radius, colour):
    """The fixture's face: a disk in its local xy plane, centred at c."""
    pts = []
    for k in range(32):
        t = 2 * math.pi * k / 32
        v = [c[i] + radius * (math.cos(t) * R[0][i] + math.sin(t) * R[1][i]) for i in range(3)]
        pts.append(proj(o, v))
    path = " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)
    out.append(f'<polygon points="{path}" fill="{colour}" fill-opacity="0.35" stroke="#333" '
               f'stroke-width="1"/>')


RED, BLUE, BLACK, GREEN, ORANGE, GREY = "#c0392b", "#2c6fbb", "#222222", "#1e8449", "#d68910", "#999999"


def axes(o):
    """World axes, small, in the panel's lower left corner."""
    o = (o[0] - 95, o[1] - 5)
    for v, n in (([1, 0, 0], "x"), ([0, 1, 0], "y"), ([0, 0, 1], "z")):
        line(o, [0, 0, 0], [0.45 * c for c in v], GREY, 1.2, head=True)
        text(o, [0.6 * c for c in v], n, GREY, "middle", 11, dy=4)


def panel_c(o, aim, title, sub):
    c = [0, 1.5, 0]
    R = orient("C", aim)
    fl = [[-1.2, 0, -1.3], [1.5, 0, -1.3], [1.5, 0, 1.0], [-1.2, 0, 1.0]]
    pts = " ".join("%.1f,%.1f" % proj(o, p) for p in fl)
    out.append(f'<polygon points="{pts}" fill="#f2f2f2" stroke="#ddd"/>')
    axes(o)
    a = norm(aim)
    if a[1] < 0:  # where the aim meets the floor
        s = -c[1] / a[1]
        line(o, c, [c[i] + s * a[i] for i in range(3)], BLACK, 1.0, "4,3")
    disk(o, c, R, 0.28, "#f7dc6f")
    line(o, c, [c[i] + 1.0 * a[i] for i in range(3)], BLACK, 2.2, head=True)
    line(o, c, [c[i] + 0.9 * R[0][i] for i in range(3)], RED, 2.2, head=True)
    line(o, c, [c[i] + 0.9 * R[1][i] for i in range(3)], BLUE, 2.2, head=True)
    text(o, [c[i] + 1.0 * R[0][i] for i in range(3)], "C0", RED, dx=2, dy=-2)
    text(o, [c[i] + 1.05 * R[1][i] for i in range(3)], "C90", BLUE, "end", dx=-2, dy=2)
    text(o, [c[i] + 1.05 * a[i] for i in range(3)], "aim", BLACK, dx=4, dy=12)
    label(o[0] + 15, o[1] - 190, title, 13, "bold")
    label(o[0] + 15, o[1] - 174, sub, 11)


def panel_ab(o, fixtures, title, sub):
    axes(o)
    for c, aim in fixtures:
        R = orient("AB", aim)
        a = norm(aim)
        # the beam: a flat fan, wide across (lateral, local +y), narrow up and down (+x)
        fan = []
        for k in range(-6, 7):
            t = math.radians(30 * k / 6)
            d = [math.cos(t) * a[i] + math.sin(t) * R[1][i] for i in range(3)]
            fan.append([c[i] + 1.3 * d[i] for i in range(3)])
        pts = " ".join("%.1f,%.1f" % proj(o, p) for p in [c] + fan)
        out.append(f'<polygon points="{pts}" fill="#f9e79f" fill-opacity="0.55" stroke="#e1c340"/>')
        disk(o, c, R, 0.2, "#f7dc6f")
        line(o, c, [c[i] + 1.0 * a[i] for i in range(3)], BLACK, 2.2, head=True)
        line(o, c, [c[i] + 0.7 * R[0][i] for i in range(3)], GREEN, 2.2, head=True)
        line(o, c, [c[i] + 0.7 * R[1][i] for i in range(3)], ORANGE, 2.2, head=True)
        text(o, [c[i] + 0.8 * R[0][i] for i in range(3)], "up", GREEN, "middle", dy=-3)
        text(o, [c[i] + 0.8 * R[1][i] for i in range(3)], "lateral", ORANGE, "end", dx=-3, dy=4)
    label(o[0] + 15, o[1] - 190, title, 13, "bold")
    label(o[0] + 15, o[1] - 174, sub, 11)


W, H = 1100, 300
out.append(f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" '
           f'viewBox="0 0 {W} {H}" font-family="sans-serif">')
out.append(f'<rect width="{W}" height="{H}" fill="white"/>')
out.append("<defs>")
for col in (RED, BLUE, BLACK, GREEN, ORANGE, GREY):
    out.append(f'<marker id="h-{col.lstrip("#")}" viewBox="0 0 10 10" refX="9" refY="5" '
               f'markerWidth="6" markerHeight="6" orient="auto-start-reverse">'
               f'<path d="M0,0 L10,5 L0,10 z" fill="{col}"/></marker>')
out.append("</defs>")
panel_c((130, 250), [0, -1, 0], "type C at rest", "hanging: aim -y, C0 +x, C90 -z")
panel_c((380, 250), tilted(35, 0), "type C tilted 35° towards +x", "C0 tilts with it")
panel_c((630, 250), tilted(35, 90), "type C tilted 35° towards +z",
        "C0 stays +x (turn it: roll or c0)")
panel_ab((900, 250), [([-0.9, 1.5, 0], aimed(-20, 0)), ([0.9, 1.5, 0], aimed(-20, 150))],
         "types A, B: a yoke", "aimed at +x, and panned 150°: the beam stays level")
out.append(f'<text x="{W / 2}" y="{H - 8}" font-size="11" fill="#555" text-anchor="middle">'
           "Type C: the hanging pose turned by the smallest rotation from -y to the aim. "
           "Types A, B: lateral axis horizontal, up above the aim. Then the roll, about the aim."
           "</text>")
out.append("</svg>")
print("\n".join(out))

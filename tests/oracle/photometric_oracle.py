#!/usr/bin/env python3
"""An independent reader of IES LM-63 and EULUMDAT files, and what lumis should say of them.

Written from the formats' standards and from the conventions of docs/photometric.md
("What is read", "Conventions"), without reading lumis's reader or model.  Standard
library only.

    python3 tests/oracle/photometric_oracle.py tests/data/photometric > expected.json

prints one JSON object keyed by file name (sorted keys, floats at repr precision).

Definitions (all in the file's own luminaire frame, docs/photometric.md):
- intensity: the table x candela multiplier x ballast factor (x the ballast-lamp
  photometric factor for files before LM-63-2002); EULUMDAT: value x flux of lamp set 1
  / 1000 x the conversion factor.  Bilinear in degrees after the symmetry maps a direction
  into the table; zero beyond the vertical range and behind types A and B.
- flux: the integral over the sphere of that interpolant, by Gauss-Legendre quadrature
  (GL_N x GL_N points) on every cell between consecutive break angles (the table's angles,
  their symmetry images and the zone edges), weight sin(gamma) (type C), cos V (type A),
  cos H (type B).  Not the closed form lumis uses, on purpose.
- beam/field: see plane_widths().
- zonal lumens, CIE flux code, BUG rating, spacing criterion: see their functions.
"""

import json
import math
import os
import re
import sys

GL_N = 12

# ---------------------------------------------------------------------------------------
# Gauss-Legendre nodes on [-1, 1], by Newton on the Legendre recurrence


def _gauss_legendre(n):
    xs, ws = [], []
    for i in range(1, n + 1):
        x = math.cos(math.pi * (i - 0.25) / (n + 0.5))
        for _ in range(100):
            p0, p1 = 1.0, x
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
            dp = n * (x * p1 - p0) / (x * x - 1.0)
            dx = p1 / dp
            x -= dx
            if abs(dx) < 1e-16:
                break
        p0, p1 = 1.0, x
        for k in range(2, n + 1):
            p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
        dp = n * (x * p1 - p0) / (x * x - 1.0)
        xs.append(x)
        ws.append(2.0 / ((1.0 - x * x) * dp * dp))
    return xs, ws


GL_X, GL_W = _gauss_legendre(GL_N)
DEG = math.pi / 180.0

# ---------------------------------------------------------------------------------------
# Reading


class Table:
    """A photometric table in lumis's model: type 'C', 'B' or 'A'; h (horizontal angles),
    v (vertical angles), cd[ih][iv] (candela, every factor applied)."""

    def __init__(self, ptype, h, v, cd):
        self.type, self.h, self.v, self.cd = ptype, h, v, cd
        if ptype == "C":
            if len(h) == 1:
                self.sym = "rotational"
            elif h[0] == 90 and h[-1] == 270:
                self.sym = "90-270"
            elif h[0] == 0 and h[-1] == 90:
                self.sym = "quadrant"
            elif h[0] == 0 and h[-1] == 180:
                self.sym = "0-180"
            elif h[0] == 0 and h[-1] <= 360:
                self.sym = "full"
            else:
                raise ValueError("horizontal angles %g..%g: no symmetry covers them" % (h[0], h[-1]))
        else:
            self.sym = ("H mirrored" if h[0] == 0 else "") + (" V mirrored" if v[0] == 0 else "")


def _numbers(tokens, n, what):
    if len(tokens) < n:
        raise ValueError("the file ends before %s" % what)
    out = [float(t) for t in tokens[:n]]
    del tokens[:n]
    return out


def _ies_year(first):
    s = first.strip().upper().replace(" ", "")
    if s.startswith("IES:LM-63-2019"):
        return 2019, first.strip()
    if s.startswith("IESNA:LM-63-2002"):
        return 2002, first.strip()
    if s.startswith("IESNA:LM-63-1995"):
        return 1995, first.strip()
    if s.startswith("IESNA91") or s.startswith("IESNA:LM-63-1991"):
        return 1991, first.strip()
    return 1986, "LM-63-1986"


# keywords that state a luminaire's flux (LM-63-2019 has none of its own; these are the
# user keywords some files carry)
IES_FLUX_KEYWORDS = ("_LUMINAIRE_LUMENS", "_LUMINAIRELUMENS", "LUMINOUSFLUX", "_LUMINOUSFLUX",
                     "_TOTALLUMENS", "_TOTAL_LUMENS", "_ABSOLUTELUMENS")


def read_ies(text):
    lines = text.split("\n")
    year, standard = _ies_year(lines[0])
    keywords = {}
    last = None
    tilt_at = None
    for i, line in enumerate(lines):
        s = line.strip()
        if s.upper().startswith("TILT="):
            tilt_at = i
            break
        if s.startswith("[") and "]" in s:
            key = s[1:s.index("]")].strip().upper()
            val = s[s.index("]") + 1:].strip()
            if key == "MORE" and last:
                keywords[last] += " " + val
            else:
                keywords.setdefault(key, val)
                last = key
    if tilt_at is None:
        raise ValueError("no TILT= line")
    tilt = lines[tilt_at].strip()[5:].strip().upper()
    tokens = " ".join(lines[tilt_at + 1:]).replace(",", " ").split()
    out = {"format": "IES", "standard": standard, "year": year, "tilt": tilt,
           "keywords": keywords}
    if tilt == "INCLUDE":
        geometry, ntilt = _numbers(tokens, 2, "the tilt table")
        _numbers(tokens, 2 * int(ntilt), "the tilt table")
        out["tilt_pairs"] = int(ntilt)
    elif tilt != "NONE":
        raise ValueError("TILT=%s: a tilt file is not read" % tilt)
    lamps, lumens, mult, nv, nh, ptype, units, width, length, height = _numbers(tokens, 10, "the counts")
    ballast, blp, watts = _numbers(tokens, 3, "the ballast line")
    nv, nh = int(nv), int(nh)
    v = _numbers(tokens, nv, "the vertical angles")
    h = _numbers(tokens, nh, "the horizontal angles")
    vals = _numbers(tokens, nv * nh, "the candela values")
    def is_number(x):
        try:
            float(x)
            return True
        except ValueError:
            return False

    if any(is_number(x) for x in tokens):
        raise ValueError("%d values after the candela values" % len(tokens))
    if tokens:  # old files end with "END" and a DOS end-of-file byte: not numbers, ignored
        out["trailing_text"] = " ".join(tokens)
    factor = mult * ballast * (blp if year < 2002 else 1.0)
    cd = [[vals[i * nv + j] * factor for j in range(nv)] for i in range(nh)]
    ptype = {1: "C", 2: "B", 3: "A"}[int(ptype)]
    out["table"] = Table(ptype, h, v, cd)
    feet = 0.3048 if int(units) == 1 else 1.0
    out.update({
        "lamps": int(lamps), "lumens_per_lamp": lumens, "candela_multiplier": mult,
        "ballast_factor": ballast, "ballast_lamp_factor": blp, "input_watts": watts,
        "units": "feet" if int(units) == 1 else "metres",
        "width_m": width * feet, "length_m": length * feet, "height_m": height * feet,
        "intensity_factor": factor,
    })
    out["absolute_photometry"] = lumens <= 0
    out["lamp_lumens"] = None if lumens <= 0 else lamps * lumens
    out["declared_luminaire_lumens"] = None
    for k in IES_FLUX_KEYWORDS:
        if k in keywords:
            try:
                out["declared_luminaire_lumens"] = float(keywords[k].split()[0])
                out["published_lm"] = out["declared_luminaire_lumens"]
                out["published_source"] = "IES keyword [%s]" % k
                break
            except (ValueError, IndexError):
                pass
    return out


def _num(s):
    return float(s.strip().replace(",", "."))


def read_ldt(text):
    lines = text.split("\n")
    if len(lines) < 26:
        raise ValueError("fewer than 26 lines")
    L = lambda k: lines[k - 1]  # noqa: E731  (the standard's 1-based line numbers)
    ityp, isym, mc, dc, ng, dg = int(_num(L(2))), int(_num(L(3))), int(_num(L(4))), _num(L(5)), \
        int(_num(L(6))), _num(L(7))
    lorl, conversion, nsets = _num(L(23)), _num(L(24)), int(_num(L(26)))
    sets = []
    k = 27
    for _ in range(nsets):  # set by set: lamps, type, flux, colour temperature, CRI, watts
        sets.append({"lamps": int(_num(lines[k - 1])), "type": lines[k].strip(),
                     "flux": _num(lines[k + 1]), "cct": lines[k + 2].strip(),
                     "cri": lines[k + 3].strip(), "watts": _num(lines[k + 4])})
        k += 6
    k += 10  # the direct ratios
    c = [_num(lines[k - 1 + i]) for i in range(mc)]
    k += mc
    g = [_num(lines[k - 1 + i]) for i in range(ng)]
    k += ng
    planes = {0: (0, mc), 1: (0, 1), 2: (0, mc // 2 + 1), 3: (mc // 4, mc // 4 + mc // 2 + 1),
              4: (0, mc // 4 + 1)}[isym]
    np_ = planes[1] - planes[0]
    rest = [s for s in lines[k - 1:] if s.strip()]
    if len(rest) < np_ * ng:
        raise ValueError("%d intensities, %d expected" % (len(rest), np_ * ng))
    vals = [_num(s) for s in rest[:np_ * ng]]
    flux1 = sets[0]["flux"]
    f = flux1 / 1000.0 * conversion
    cd = [[vals[i * ng + j] * f for j in range(ng)] for i in range(np_)]
    h = [0.0] if isym == 1 else c[planes[0]:planes[1]]
    out = {"format": "EULUMDAT", "standard": "EULUMDAT", "ityp": ityp, "isym": isym, "mc": mc,
           "ng": ng, "lamp_sets": sets, "lorl": lorl, "conversion_factor": conversion,
           "table": Table("C", h, g, cd), "intensity_factor": f}
    absolute = sets[0]["lamps"] < 0
    out["absolute_photometry"] = absolute
    out["lamp_lumens"] = flux1
    out["input_watts"] = sets[0]["watts"]
    out["declared_luminaire_lumens"] = flux1 * lorl / 100.0
    out["published_lm"] = out["declared_luminaire_lumens"]
    out["published_source"] = "EULUMDAT lamp set 1 flux x LORL / 100"
    return out


def read_file(path):
    with open(path, "rb") as fh:
        return read_file_text(fh.read().decode("latin-1"))


def read_file_text(text):
    """Either format, the content deciding (docs/photometric.md, "Which reader")."""
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    lines = text.split("\n")
    if lines[0].lstrip().upper().startswith("IES") or any(
            s.strip().upper().startswith("TILT=") for s in lines):
        return read_ies(text)
    return read_ldt(text)


# ---------------------------------------------------------------------------------------
# The interpolant


def _seg(xs, x):
    """Index i with xs[i] <= x <= xs[i+1] (xs increasing, len >= 2), or None outside."""
    if x < xs[0] - 1e-12 or x > xs[-1] + 1e-12:
        return None
    lo, hi = 0, len(xs) - 2
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if xs[mid] <= x:
            lo = mid
        else:
            hi = mid - 1
    return lo


def _lerp_col(t, ih, v):
    """The table's plane ih at vertical angle v (0 outside the vertical range)."""
    vs, col = t.v, t.cd[ih]
    j = _seg(vs, v)
    if j is None:
        return 0.0
    v0, v1 = vs[j], vs[j + 1]
    s = min(max((v - v0) / (v1 - v0), 0.0), 1.0)
    return col[j] + (col[j + 1] - col[j]) * s


def map_c(t, c):
    """Type C: a C angle (any) into the table's horizontal range; returns (h, wrap)."""
    c = c % 360.0
    if t.sym == "rotational":
        return 0.0
    if t.sym == "quadrant":
        if c > 180:
            c = 360 - c
        if c > 90:
            c = 180 - c
        return c
    if t.sym == "0-180":
        return 360 - c if c > 180 else c
    if t.sym == "90-270":
        if c < 90:
            return 180 - c
        if c > 270:
            return 540 - c
        return c
    return c  # full: 0..last, wrapping from last to 360 (= 0)


def intensity(t, h, v):
    """Intensity at table angles: type C (C, gamma), A/B (H, V), after the symmetry."""
    if t.type == "C":
        if v < -1e-12 or v > 180 + 1e-12:
            return 0.0
        if len(t.h) == 1:
            return _lerp_col(t, 0, v)
        c = map_c(t, h)
        hs = t.h
        if t.sym == "full" and c > hs[-1]:
            # between the last plane and the first one again at 360
            s = (c - hs[-1]) / (360.0 - hs[-1])
            a, b = _lerp_col(t, len(hs) - 1, v), _lerp_col(t, 0, v)
            return a + (b - a) * s
        i = _seg(hs, c)
        if i is None:
            return 0.0
        s = min(max((c - hs[i]) / (hs[i + 1] - hs[i]), 0.0), 1.0)
        a, b = _lerp_col(t, i, v), _lerp_col(t, i + 1, v)
        return a + (b - a) * s
    # types A, B
    if abs(h) > 90 + 1e-12 or abs(v) > 90 + 1e-12:
        return 0.0
    if t.h[0] == 0 and h < 0:
        h = -h
    if t.v[0] == 0 and v < 0:
        v = -v
    if len(t.h) == 1:
        return _lerp_col(t, 0, v) if abs(h - t.h[0]) < 1e-12 else 0.0
    i = _seg(t.h, h)
    if i is None:
        return 0.0
    s = min(max((h - t.h[i]) / (t.h[i + 1] - t.h[i]), 0.0), 1.0)
    a, b = _lerp_col(t, i, v), _lerp_col(t, i + 1, v)
    return a + (b - a) * s


# ---------------------------------------------------------------------------------------
# Quadrature


def _uniq(xs, lo, hi):
    out = sorted(set(round(x, 9) for x in xs if lo - 1e-9 <= x <= hi + 1e-9))
    out = [min(max(x, lo), hi) for x in out]
    if not out or out[0] > lo:
        out.insert(0, lo)
    if out[-1] < hi:
        out.append(hi)
    return sorted(set(out))


def h_breaks(t):
    """The angles where the interpolant may bend, around the whole horizontal circle."""
    if t.type == "C":
        hs = t.h
        if t.sym == "rotational":  # the zones' edges still cut it (a half is half the flux)
            return [0.0, 90.0, 180.0, 270.0, 360.0]
        imgs = []
        for h in hs:
            if t.sym == "quadrant":
                imgs += [h, 180 - h, 180 + h, 360 - h]
            elif t.sym == "0-180":
                imgs += [h, 360 - h]
            elif t.sym == "90-270":
                imgs += [h, (180 - h) % 360, 360 - (h - 180) if h > 180 else h]
            else:
                imgs += [h]
        imgs += [0.0, 90.0, 180.0, 270.0, 360.0]  # the principal planes (zones' edges)
        return _uniq(imgs, 0.0, 360.0)
    imgs = [h for h in t.h] + [-h for h in t.h] + [0.0]
    return _uniq(imgs, -90.0, 90.0)


def v_breaks(t, extra=()):
    if t.type == "C":
        return _uniq(list(t.v) + list(extra), 0.0, 180.0)
    return _uniq(list(t.v) + [-x for x in t.v] + [0.0] + list(extra), -90.0, 90.0)


GL2_X, GL2_W = _gauss_legendre(2)


def cell_flux(t, h0, h1, v0, v1):
    """Gauss-Legendre on one cell, where the interpolant is bilinear: GL_N points in the
    angle the solid-angle weight depends on (gamma or V for types C and A, H for type B),
    2 points in the other, along which the integrand is linear (2 points are exact up to
    cubics)."""
    hm, hr = 0.5 * (h0 + h1), 0.5 * (h1 - h0)
    vm, vr = 0.5 * (v0 + v1), 0.5 * (v1 - v0)
    if t.type == "B":
        hx, hw, vx, vw = GL_X, GL_W, GL2_X, GL2_W
    else:
        hx, hw, vx, vw = GL2_X, GL2_W, GL_X, GL_W
    total = 0.0
    for xi, wi in zip(hx, hw):
        h = hm + hr * xi
        for xj, wj in zip(vx, vw):
            v = vm + vr * xj
            if t.type == "C":
                w = math.sin(v * DEG)
            elif t.type == "A":
                w = math.cos(v * DEG)
            else:
                w = math.cos(h * DEG)
            total += wi * wj * intensity(t, h, v) * w
    return total * hr * vr * DEG * DEG


class Cells:
    """Every cell between consecutive breaks, integrated once; zones add cells up."""

    def __init__(self, t, hb, vb):
        self.hb, self.vb = hb, vb
        self.flux = [[cell_flux(t, a, b, c, d) for c, d in zip(vb, vb[1:])]
                     for a, b in zip(hb, hb[1:])]

    def zone(self, hlo, hhi, vlo, vhi):
        """Flux with h in [hlo, hhi], v in [vlo, vhi] (edges must be breaks)."""
        total = 0.0
        for i, (a, b) in enumerate(zip(self.hb, self.hb[1:])):
            if b <= hlo + 1e-7 or a >= hhi - 1e-7:
                continue
            row = self.flux[i]
            for j, (c, d) in enumerate(zip(self.vb, self.vb[1:])):
                if d <= vlo + 1e-7 or c >= vhi - 1e-7:
                    continue
                total += row[j]
        return total


# ---------------------------------------------------------------------------------------
# Beam and field angles


def plane_segments(t, k):
    """Plane k's intensity on the circle t in (-180, 180] as linear pieces
    (t0, I0, t1, I1), in increasing t, with the interpolant's steps at the ends of the
    vertical range kept (each piece carries its own end values)."""
    if t.type == "C":
        pos_c, neg_c = (0.0, 180.0) if k == 0 else (90.0, 270.0)
        gb = _uniq(list(t.v) + [0.0, 180.0], 0.0, 180.0)
        lo, hi = t.v[0], t.v[-1]

        def val(c, g0, g1, at):
            inside = g0 >= lo - 1e-12 and g1 <= hi + 1e-12
            if not inside:
                return 0.0
            # evaluate inside the piece (its ends may be steps)
            return intensity(t, c, min(max(at, lo), hi))

        segs = []
        for g0, g1 in reversed(list(zip(gb, gb[1:]))):  # C180 side: t = -gamma
            segs.append((-g1, val(neg_c, g0, g1, g1), -g0, val(neg_c, g0, g1, g0)))
        for g0, g1 in zip(gb, gb[1:]):  # C0 side: t = gamma
            segs.append((g0, val(pos_c, g0, g1, g0), g1, val(pos_c, g0, g1, g1)))
        return segs
    # types A, B: plane 0 is V = 0 (t = H), plane 1 is H = 0 (t = V)
    axis = t.h if k == 0 else t.v
    b = _uniq(list(axis) + [-x for x in axis] + [-180.0, -90.0, 0.0, 90.0, 180.0], -180.0, 180.0)

    def f(x):
        return intensity(t, x, 0.0) if k == 0 else intensity(t, 0.0, x)

    lo = min(axis + [-x for x in axis]) if axis[0] == 0 else axis[0]
    hi = axis[-1]
    segs = []
    for a, c in zip(b, b[1:]):
        inside = a >= max(lo, -90) - 1e-12 and c <= min(hi, 90) + 1e-12
        if inside:
            segs.append((a, f(a), c, f(c)))
        else:
            segs.append((a, 0.0, c, 0.0))
    return segs


def _peak(segs):
    """(P, index of the piece, end 0/1): the largest value; ties: smallest |t|, then t >= 0."""
    best = None
    for i, (t0, i0, t1, i1) in enumerate(segs):
        for end, (tt, ii) in enumerate(((t0, i0), (t1, i1))):
            key = (ii, -abs(tt), 1 if tt >= 0 else 0)
            if best is None or key > best[0]:
                best = (key, i, end)
    return best[0][0], best[1], best[2]


def arc_width(segs, level_share):
    P, i, end = _peak(segs)
    if P <= 0:
        return 0.0, 0.0
    L = level_share * P
    n = len(segs)
    total = 360.0

    def forward(i, from_t):
        # walk from from_t (inside piece i, at its start or its end) increasing t
        walked = 0.0
        t0, i0, t1, i1 = segs[i]
        if from_t == t1:
            i = (i + 1) % n
        for _ in range(n + 1):
            t0, i0, t1, i1 = segs[i]
            if i0 < L:
                return walked
            if i1 >= L:
                walked += t1 - t0
            else:
                return walked + (t1 - t0) * (i0 - L) / (i0 - i1)
            if walked >= total:
                return total
            i = (i + 1) % n
        return total

    def backward(i, from_t):
        walked = 0.0
        t0, i0, t1, i1 = segs[i]
        if from_t == t0:
            i = (i - 1) % n
        for _ in range(n + 1):
            t0, i0, t1, i1 = segs[i]
            if i1 < L:
                return walked
            if i0 >= L:
                walked += t1 - t0
            else:
                return walked + (t1 - t0) * (i1 - L) / (i1 - i0)
            if walked >= total:
                return total
            i = (i - 1) % n
        return total

    t0, i0, t1, i1 = segs[i]
    at = t0 if end == 0 else t1
    w = forward(i, at) + backward(i, at)
    return min(w, total), P


def plane_widths(t, k):
    """Beam (50 %) and field (10 %) widths of plane k: the length of the maximal arc of the
    circle containing the plane's peak on which I >= share x peak, ends at the exact
    crossings of the piecewise-linear interpolant; 360 if the whole circle qualifies; 0 for
    a plane without light."""
    segs = plane_segments(t, k)
    beam, P = arc_width(segs, 0.5)
    field, _ = arc_width(segs, 0.1)
    return beam, field, P


# ---------------------------------------------------------------------------------------
# Zones, CIE flux code, BUG

ZONES = [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0]
# CIE flux code (CIE 52:1982; CIBSE TM5): the cones of pi/2, pi and 3 pi/2 sr around the
# nadir, half angles acos(3/4) = 41.41, 60, acos(1/4) = 75.52 degrees.
CIE_CONES = [math.degrees(math.acos(0.75)), 60.0, math.degrees(math.acos(0.25))]
BUG_EDGES = [30.0, 60.0, 80.0, 90.0, 100.0]

# TM-15-11 Addendum A, tables A-1 (backlight), A-2 (uplight), A-3 (glare): the largest
# lumens allowed for ratings 0 to 4 (above the last: 5).  No copy of TM-15-11 was found to
# read them from; these are the values as the IES tables are commonly reproduced (B and U
# as holg/eulumdat-rs's bug_rating.rs has them, U also as the IDA-IES Model Lighting
# Ordinance's user's guide words them; FVH/BVH 10, 100, 225, 500, 750 as an open
# implementation found by search has them).  This oracle earlier remembered FVH/BVH as
# 10, 75, 150, 225, 350 and lumis 10, 75, 150, 500, 750: each half of the row.  The one
# corpus file that states its rating (luxcore_asa_15m_r2.ies: "B2 - U0 - G2") agrees.
BUG_B = {"BH": [110, 500, 1000, 2500, 5000], "BM": [220, 1000, 2500, 5000, 8500],
         "BL": [110, 500, 1000, 2500, 5000]}
BUG_U = {"UH": [0, 10, 50, 500, 1000], "UL": [0, 10, 50, 500, 1000]}
BUG_G = {"FVH": [10, 100, 225, 500, 750], "BVH": [10, 100, 225, 500, 750],
         "FH": [660, 1800, 5000, 7500, 12000], "BH": [110, 500, 1000, 2500, 5000]}
# Table A-3's half for quadrilaterally symmetric (type V) luminaires: no back to protect,
# so BH is held to FH's limits.  Applied to tables that declare rotational symmetry.
BUG_G_TYPE_V = dict(BUG_G, BH=BUG_G["FH"])


def _rating(zones, table):
    for r in range(5):
        if all(zones[z] <= table[z][r] for z in table):
            return r
    return 5


def analyse(path):
    f = read_file(path)
    t = f.pop("table")
    extra = ZONES + CIE_CONES + BUG_EDGES if t.type == "C" else []
    hb, vb = h_breaks(t), v_breaks(t, extra)
    cells = Cells(t, hb, vb)
    res = {k: v for k, v in f.items() if k not in ("lamp_sets", "keywords")}
    if "lamp_sets" in f:
        res["lamp_sets"] = f["lamp_sets"]
    res["type"] = t.type
    res["symmetry"] = t.sym
    res["nv"], res["nh"] = len(t.v), len(t.h)
    res["v_first"], res["v_last"], res["h_first"], res["h_last"] = t.v[0], t.v[-1], t.h[0], t.h[-1]

    # flux: all cells between breaks
    if t.type == "C":
        flux = cells.zone(0.0, 360.0, 0.0, 180.0)
    else:
        flux = cells.zone(-90.0, 90.0, -90.0, 90.0)
    res["flux"] = flux

    # peak of the table (after every factor); ties: the first in file order
    peak, ph, pv = -1.0, 0.0, 0.0
    for ih, col in enumerate(t.cd):
        for iv, x in enumerate(col):
            if x > peak:
                peak, ph, pv = x, t.h[ih], t.v[iv]
    res["peak_cd"], res["peak_h"], res["peak_v"] = peak, ph, pv

    beams, fields = [], []
    for k in (0, 1):
        b, fl, _ = plane_widths(t, k)
        beams.append(b)
        fields.append(fl)
    res["beam_deg"], res["field_deg"] = beams, fields

    lamp = f.get("lamp_lumens")
    relative = lamp is not None and lamp > 0 and not f.get("absolute_photometry")
    res["lor"] = flux / lamp if relative else None
    w = f.get("input_watts") or 0.0
    res["efficacy_lm_per_w"] = flux / w if w > 0 else None

    if t.type == "C":
        # The zonal-constant rule older photometric software uses for a file's stated
        # flux: each vertical angle's intensity, averaged over C (a 1-degree grid), times
        # the solid angle of its zone (from halfway to the previous angle to halfway to
        # the next).  Not lumis's flux; kept to show whether a file's stated lumens come
        # from its own table by that rule (docs/photometric.md, "declared lumens").
        mid = 0.0
        for i, g in enumerate(t.v):
            a = t.v[0] if i == 0 else 0.5 * (t.v[i - 1] + g)
            b = t.v[-1] if i == len(t.v) - 1 else 0.5 * (g + t.v[i + 1])
            mean = sum(intensity(t, float(c), g) for c in range(360)) / 360.0
            mid += mean * 2.0 * math.pi * (math.cos(math.radians(a)) - math.cos(math.radians(b)))
        res["flux_zone_midpoint"] = mid
        zonal = [cells.zone(0.0, 360.0, a, b) for a, b in zip(ZONES, ZONES[1:])]
        res["zonal_lm"] = zonal
        down = sum(zonal[:3])
        res["downward_lm"] = down
        res["downward_fraction"] = down / flux if flux > 0 else None
        res["spacing_criterion"] = [spacing_criterion(t, c, res["downward_fraction"])
                                    for c in (0.0, 90.0)]
        cones = [cells.zone(0.0, 360.0, 0.0, g) for g in CIE_CONES]
        raw = [100 * c / down if down > 0 else None for c in cones]
        raw.append(100 * down / flux if flux > 0 else None)
        raw.append(100 * flux / lamp if relative else None)
        res["cie_flux_code_raw"] = raw
        res["cie_flux_code"] = [None if x is None else int(math.floor(x + 0.5)) for x in raw]
        # BUG (TM-15-11): front and back halves split by a vertical plane through the
        # aim.  Which half is front: TM-15-11 puts the forward light "between 270 and 90
        # degrees horizontal", the half centred on C0, and the one corpus file that states
        # its rating (luxcore_asa_15m_r2.ies, "BUG RATING: B2 - U0 - G2", a 0-180 table)
        # gives it only so.  The other reading (the street side at C90, LM-63's roadway
        # convention, front 0 < C < 180) is kept beside it as bug_front_c90.
        for key, front, back in (("", [(0.0, 90.0), (270.0, 360.0)], [(90.0, 270.0)]),
                                 ("_front_c90", [(0.0, 180.0)], [(180.0, 360.0)])):
            z = {}
            for side, rng in (("F", front), ("B", back)):
                for name, (g0, g1) in (("L", (0, 30)), ("M", (30, 60)), ("H", (60, 80)),
                                       ("VH", (80, 90))):
                    z[side + name] = sum(cells.zone(a, b, g0, g1) for a, b in rng)
            z["UL"] = cells.zone(0.0, 360.0, 90.0, 100.0)
            z["UH"] = cells.zone(0.0, 360.0, 100.0, 180.0)
            res["bug_zone_lm" + key] = z
            glare = BUG_G_TYPE_V if t.sym == "rotational" else BUG_G
            res["bug" + key] = {"B": _rating(z, BUG_B), "U": _rating(z, BUG_U),
                                "G": _rating(z, glare)}
        for val in f.get("keywords", {}).values():
            m = re.search(r"B(\d)\s*-\s*U(\d)\s*-\s*G(\d)", val.upper())
            if m and "BUG" in val.upper():
                res["published_bug"] = {"B": int(m.group(1)), "U": int(m.group(2)),
                                        "G": int(m.group(3))}
    return res


def spacing_criterion(t, c, downward_fraction):
    """The spacing criterion along the plane C = c, c + 180 (docs/photometric.md): s / h at
    which the direct horizontal illuminance midway between two luminaires s apart, both
    lighting it, falls to the illuminance straight under one from that one alone.  Midway,
    each is seen at gamma with tan(gamma) = s / (2 h) and gives I cos^3(gamma) / h^2; under
    one, I0 / h^2 (I0: the mean of the plane's two nadir values).  Found by a uniform scan
    of gamma in steps of 1/200 degree for the first point at or under the balance, then
    bisection.  None where it does not apply: type A or B, under 40 % of the flux downward
    (CIE's semi-indirect and indirect classes), or no light at nadir."""
    if t.type != "C" or downward_fraction is None or not downward_fraction >= 0.4:
        return None
    i0 = 0.5 * (intensity(t, c, 0.0) + intensity(t, c + 180.0, 0.0))
    if not i0 > 0:
        return None

    def excess(g):
        cg = math.cos(math.radians(g))
        return (intensity(t, c, g) + intensity(t, c + 180.0, g)) * cg ** 3 - i0

    steps = 18000
    prev = 0.0
    for k in range(1, steps + 1):
        g = 90.0 * k / steps
        if excess(g) <= 0:
            lo, hi = prev, g
            for _ in range(100):
                mid = 0.5 * (lo + hi)
                if excess(mid) > 0:
                    lo = mid
                else:
                    hi = mid
            return 2.0 * math.tan(math.radians(0.5 * (lo + hi)))
        prev = g
    return None


def _clean(x):
    if isinstance(x, float):
        if x != x or x in (float("inf"), float("-inf")):
            return None
        return x
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    return x


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: photometric_oracle.py DIR\n")
        return 2
    d = argv[1]
    out = {}
    for name in sorted(os.listdir(d)):
        if name.lower().endswith((".ies", ".ldt")):
            try:
                out[name] = _clean(analyse(os.path.join(d, name)))
            except ValueError as e:
                raise SystemExit("%s: %s" % (name, e))
    json.dump(out, sys.stdout, indent=1, sort_keys=True)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

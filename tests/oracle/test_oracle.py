#!/usr/bin/env python3
"""The oracle against closed forms: python3 tests/oracle/test_oracle.py (plain asserts)."""

import math
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import photometric_oracle as o  # noqa: E402


def ies(values_by_h, v, h, ptype=1, lumens=1000.0, mult=1.0, year="IESNA:LM-63-2002"):
    lines = [year, "[TEST] oracle self-test", "TILT=NONE",
             "1 %r %r %d %d %d 2 0 0 0" % (lumens, mult, len(v), len(h), ptype), "1 1 0",
             " ".join(repr(x) for x in v), " ".join(repr(x) for x in h)]
    for col in values_by_h:
        lines.append(" ".join(repr(x) for x in col))
    return "\n".join(lines) + "\n"


def analyse_text(text, suffix=".ies"):
    fd, path = tempfile.mkstemp(suffix=suffix)
    with os.fdopen(fd, "w") as fh:
        fh.write(text)
    try:
        return o.analyse(path)
    finally:
        os.unlink(path)


def close(a, b, rel):
    return abs(a - b) <= rel * abs(b)


def exact_flux_c(t):
    """The closed form of docs/photometric.md, cell by cell (rotational tables only)."""
    v, col = t.v, t.cd[0]
    total = 0.0
    for j in range(len(v) - 1):
        g0, g1 = v[j] * o.DEG, v[j + 1] * o.DEG
        a, b = col[j], col[j + 1]
        dg = g1 - g0
        total += a * (math.cos(g0) - math.cos(g1)) + (b - a) / dg * (
            math.sin(g1) - math.sin(g0) - dg * math.cos(g1))
    return 2 * math.pi * total


def main():
    I0 = 1000.0
    v = [float(x) for x in range(0, 91)]

    # Lambertian: flux of the 1-degree table ~ pi I0, and the quadrature equals the closed
    # form of the interpolant to 1e-12
    lam = [I0 * math.cos(x * o.DEG) for x in v]
    r = analyse_text(ies([lam], v, [0.0]))
    t = o.read_file_text(ies([lam], v, [0.0]))["table"]
    exact = exact_flux_c(t)
    assert close(r["flux"], exact, 1e-12), (r["flux"], exact)
    assert close(r["flux"], math.pi * I0, 1e-4), r["flux"]
    assert close(r["downward_fraction"], 1.0, 1e-12)
    # Lambertian beam: cos t >= 1/2 over 120 degrees, field 2 acos(0.1)
    for k in (0, 1):
        assert abs(r["beam_deg"][k] - 120.0) < 0.01, r["beam_deg"]
        assert abs(r["field_deg"][k] - 2 * math.degrees(math.acos(0.1))) < 0.02, r["field_deg"]
    print("lambertian: flux %.9f (pi I0 %.9f, closed form %.9f), beam %.4f" % (
        r["flux"], math.pi * I0, exact, r["beam_deg"][0]))

    # cos^n spots: beam 2 acos(0.5^(1/n)), flux 2 pi I0 / (n + 1)
    for n in (1, 4, 10, 20, 80):
        vv = [x * 0.25 for x in range(0, 361)]
        col = [I0 * math.cos(x * o.DEG) ** n for x in vv]
        for sym, h in (("rotational", [0.0]), ("quadrant", [0.0, 45.0, 90.0]),
                       ("0-180", [0.0, 90.0, 180.0]), ("90-270", [90.0, 180.0, 270.0]),
                       ("full", [0.0, 120.0, 240.0, 360.0])):
            r = analyse_text(ies([col] * len(h), vv, h))
            assert r["symmetry"] == sym, (r["symmetry"], sym)
            beam = 2 * math.degrees(math.acos(0.5 ** (1.0 / n)))
            field = 2 * math.degrees(math.acos(0.1 ** (1.0 / n)))
            for k in (0, 1):
                assert abs(r["beam_deg"][k] - beam) < 0.01, (n, sym, r["beam_deg"], beam)
                assert abs(r["field_deg"][k] - field) < 0.01, (n, sym, r["field_deg"], field)
            assert close(r["flux"], 2 * math.pi * I0 / (n + 1), 2e-4), (n, r["flux"])
            t = o.read_file_text(ies([col], vv, [0.0]))["table"]
            assert close(r["flux"], exact_flux_c(t), 1e-12), (n, sym, r["flux"], exact_flux_c(t))
        print("cos^%d: beam %.4f (%.4f), flux %.6f (%.6f)" % (
            n, r["beam_deg"][0], beam, r["flux"], 2 * math.pi * I0 / (n + 1)))

    # An uplight: its peak at the zenith, the beam spans C0 and C180 across it
    vv = [float(x) for x in range(0, 181)]
    up = [I0 * max(0.0, -math.cos(x * o.DEG)) ** 4 for x in vv]
    r = analyse_text(ies([up], vv, [0.0]))
    beam = 2 * math.degrees(math.acos(0.5 ** 0.25))
    assert abs(r["beam_deg"][0] - beam) < 0.01, r["beam_deg"]
    assert r["downward_fraction"] < 1e-12
    assert r["bug"]["U"] == 5 and r["zonal_lm"][0] == 0.0
    print("uplight: beam %.4f across the zenith (%.4f)" % (r["beam_deg"][0], beam))

    # An isotropic table is >= any level on the whole circle: 360
    iso = [I0] * len(vv)
    r = analyse_text(ies([iso], vv, [0.0]))
    assert r["beam_deg"] == [360.0, 360.0], r["beam_deg"]
    assert close(r["flux"], 4 * math.pi * I0, 1e-12), r["flux"]

    # CIE flux code of a Lambertian: cones of pi/2, pi, 3pi/2 sr hold 1 - cos^2 of their
    # half angle of the downward flux: 43.75 %, 75 %, 93.75 %
    lam = [I0 * math.cos(x * o.DEG) for x in v]
    r = analyse_text(ies([lam], v, [0.0], lumens=4000.0))
    raw = r["cie_flux_code_raw"]
    for got, want in zip(raw[:3], (43.75, 75.0, 93.75)):
        assert abs(got - want) < 0.01, raw
    assert abs(raw[4] - 100 * math.pi * I0 / 4000.0) < 0.01
    print("CIE flux code of a Lambertian: %s" % r["cie_flux_code"])

    # Spacing criterion, worked by hand: midway between two luminaires s = 2 h tan(g) apart
    # each gives I0 cos^n(g) cos^3(g) / h^2, under one I0 / h^2, so 2 cos^(n+3)(g) = 1 and
    # SC = 2 tan(g) = 2 (2^(2/(n+3)) - 1)^(1/2): 1.2872 for a Lambertian (n = 1).  The
    # tables are linear between 1/4 degree, so to ~1e-5.
    for n in (1, 2, 4, 10):
        vv = [x * 0.25 for x in range(0, 361)]
        col = [I0 * math.cos(x * o.DEG) ** n for x in vv]
        r = analyse_text(ies([col, col, col], vv, [0.0, 90.0, 180.0]))
        want = 2 * math.sqrt(2 ** (2.0 / (n + 3)) - 1)
        for k in (0, 1):
            assert abs(r["spacing_criterion"][k] - want) < 1e-4, (n, r["spacing_criterion"], want)
        print("cos^%d: spacing criterion %.6f (%.6f)" % (n, r["spacing_criterion"][0], want))
    # An asymmetric table: C0 twice C180's cos, the midway sum 3 I0 cos^4 against I0
    # (the nadir mean of C0's 2 I0 and C180's I0 is 1.5 I0): 3 cos^4 = 1.5, as the
    # Lambertian's; along C90-C270 (1.5 I0 cos each side) the same again
    vv = [x * 0.25 for x in range(0, 361)]
    lam = [I0 * math.cos(x * o.DEG) for x in vv]
    cols = [[2 * x for x in lam], [1.5 * x for x in lam], [x for x in lam]]
    r = analyse_text(ies(cols, vv, [0.0, 90.0, 180.0]))
    for k in (0, 1):
        assert abs(r["spacing_criterion"][k] - 2 * math.sqrt(math.sqrt(2) - 1)) < 1e-4, r
    # Not applicable: the uplight above (no downward flux), a semi-indirect 30 % down
    r = analyse_text(ies([up], [float(x) for x in range(0, 181)], [0.0]))
    assert r["spacing_criterion"] == [None, None], r["spacing_criterion"]
    semi = [I0 * abs(math.cos(x * o.DEG)) * (0.43 if x <= 90 else 1.0)
            for x in range(0, 181)]
    r = analyse_text(ies([semi], [float(x) for x in range(0, 181)], [0.0]))
    assert 0.25 < r["downward_fraction"] < 0.4 and r["spacing_criterion"] == [None, None], r

    # Types A and B: an aimed cos^n, I0 cos^n(angle to the aim), flux 2 pi I0 / (n + 1)
    n = 6
    hh = [float(x) for x in range(-90, 91, 2)]
    for ptype in (2, 3):
        cols = []
        for h in hh:
            col = []
            for vx in hh:
                if ptype == 2:  # B: aim (0,0,-1); d = (cos H sin V, sin H, -cos H cos V)
                    c = math.cos(h * o.DEG) * math.cos(vx * o.DEG)
                else:  # A: d = (sin V, cos V sin H, -cos V cos H)
                    c = math.cos(vx * o.DEG) * math.cos(h * o.DEG)
                col.append(I0 * max(c, 0.0) ** n)
            cols.append(col)
        r = analyse_text(ies(cols, hh, hh, ptype=ptype))
        want = 2 * math.pi * I0 / (n + 1)
        assert close(r["flux"], want, 5e-4), (ptype, r["flux"], want)
        beam = 2 * math.degrees(math.acos(0.5 ** (1.0 / n)))
        for k in (0, 1):
            assert abs(r["beam_deg"][k] - beam) < 0.02, (ptype, r["beam_deg"], beam)
        print("type %s cos^%d: flux %.4f (%.4f), beam %s (%.4f)" % (
            "B" if ptype == 2 else "A", n, r["flux"], want, r["beam_deg"], beam))

    # EULUMDAT lamp sets, set by set: intensities per 1000 lm of set 1
    lines = ["oracle", "1", "1", "1", "0", "3", "45", "r", "n", "n", "f", "d",
             "0", "0", "0", "0", "0", "0", "0", "0", "0", "100", "80", "1", "0", "2",
             "1", "lamp A", "2000", "3000", "80", "20",
             "2", "lamp B", "5000", "4000", "90", "40"] + ["0"] * 10 + \
        ["0", "0", "45", "90", "100", "50", "0"]
    r = analyse_text("\r\n".join(lines) + "\r\n", suffix=".ldt")
    assert r["peak_cd"] == 200.0 and r["lamp_lumens"] == 2000.0, r
    assert r["declared_luminaire_lumens"] == 1600.0 and r["input_watts"] == 20.0
    assert len(r["lamp_sets"]) == 2 and r["lamp_sets"][1]["flux"] == 5000.0
    print("EULUMDAT with 2 lamp sets: peak %g cd from set 1's 2000 lm" % r["peak_cd"])
    print("all oracle self-tests passed")


if __name__ == "__main__":
    main()

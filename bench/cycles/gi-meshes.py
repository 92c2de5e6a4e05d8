"""Writes the meshes of the global-illumination comparison (README.md, "Global
illumination"), in lumis's world frame (y up), so that lumis (scene files, no transform)
and Blender (scene.py --lumis-scene) read the very same triangles:

  gi-icosphere.obj  a flat-shaded unit icosphere (4 subdivisions: 2562 vertices, 5120
                 triangles), placed by the scene files' transforms (scale, translate):
                 the balls, as meshes (Cycles has no analytic sphere to match Embree's);
  gi-room.obj    a closed box room 4 x 2.5 x 5 (x in [-2, 2], y in [0, 2.5],
                 z in [-2.5, 2.5]) whose wall at z = +2.5 has one window opening
                 x in [-1.6, 1.0], y in [0.6, 2.1] (the wall is 4 rectangles around it);

    python3 bench/cycles/gi-meshes.py        (writes into bench/cycles/)
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


def icosphere(level):
    t = (1.0 + 5 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        cache, nf = {}, []

        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                cache[k] = len(v) - 1
            return cache[k]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return v, f


def write_obj(name, verts, faces, comment):
    with open(os.path.join(HERE, name), "w") as out:
        out.write("# %s (written by gi-meshes.py; lumis world frame, y up)\n" % comment)
        for p in verts:
            out.write("v %.9g %.9g %.9g\n" % p)
        for a, b, c in faces:
            out.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


def ball(name, centre, radius):
    v, f = icosphere(4)
    write_obj(name, [tuple(centre[i] + radius * p[i] for i in range(3)) for p in v], f,
              "icosphere, 4 subdivisions, radius %g at %s" % (radius, centre))


def quad(verts, faces, a, b, c, d):
    base = len(verts)
    verts += [a, b, c, d]
    faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]


def room():
    x0, x1, y0, y1, z0, z1 = -2.0, 2.0, 0.0, 2.5, -2.5, 2.5
    wx0, wx1, wy0, wy1 = -1.6, 1.0, 0.6, 2.1  # the window, in the wall z = z1
    v, f = [], []
    quad(v, f, (x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1))  # floor
    quad(v, f, (x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0))  # ceiling
    quad(v, f, (x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0))  # back wall z0
    quad(v, f, (x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0))  # wall x0
    quad(v, f, (x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1))  # wall x1
    # the window wall z = z1: below, above, left and right of the opening
    quad(v, f, (x0, y0, z1), (x1, y0, z1), (x1, wy0, z1), (x0, wy0, z1))
    quad(v, f, (x0, wy1, z1), (x1, wy1, z1), (x1, y1, z1), (x0, y1, z1))
    quad(v, f, (x0, wy0, z1), (wx0, wy0, z1), (wx0, wy1, z1), (x0, wy1, z1))
    quad(v, f, (wx1, wy0, z1), (x1, wy0, z1), (x1, wy1, z1), (wx1, wy1, z1))
    write_obj("gi-room.obj", v, f, "box room with a window in the wall z = +2.5")


ball("gi-icosphere.obj", (0.0, 0.0, 0.0), 1.0)
room()

"""Mean luminance (Y = 0.2126 R + 0.7152 G + 0.0722 B) of linear EXR images, and of a
GxG grid of regions, with each image's relative difference from the first.  Run inside
Blender (no numpy needed):

    blender -b --factory-startup -P bench/cycles/imgstats.py -- REF.exr TEST.exr [...] [--grid G]
"""
import array
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1 :]
grid = 4
if "--grid" in argv:
    k = argv.index("--grid")
    grid = int(argv[k + 1])
    del argv[k : k + 2]


def stats(path):
    im = bpy.data.images.load(path)
    w, h = im.size
    px = array.array("f", bytes(4 * 4 * w * h))
    im.pixels.foreach_get(px)
    tot = 0.0
    reg = [[0.0] * grid for _ in range(grid)]
    cnt = [[0] * grid for _ in range(grid)]
    for y in range(h):  # Blender's row 0 is the bottom: region row 0 = top of the image
        gy = (h - 1 - y) * grid // h
        for x in range(w):
            i = 4 * (y * w + x)
            Y = 0.2126 * px[i] + 0.7152 * px[i + 1] + 0.0722 * px[i + 2]
            tot += Y
            gx = x * grid // w
            reg[gy][gx] += Y
            cnt[gy][gx] += 1
    return tot / (w * h), [[reg[j][i] / cnt[j][i] for i in range(grid)] for j in range(grid)]


ref = None
for p in argv:
    m, r = stats(p)
    if ref is None:
        ref = (m, r)
        print("MEAN_Y %s %.7g" % (p, m))
    else:
        print("MEAN_Y %s %.7g rel_diff %+.5f%%" % (p, m, 100.0 * (m / ref[0] - 1.0)))
    for j in range(grid):
        cells = []
        for i in range(grid):
            if p is argv[0]:
                cells.append("%10.5g" % r[j][i])
            else:
                cells.append("%+9.3f%%" % (100.0 * (r[j][i] / ref[1][j][i] - 1.0)
                                            if ref[1][j][i] else 0.0))
        print("  REGION_ROW %d %s" % (j, " ".join(cells)))

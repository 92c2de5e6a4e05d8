#!/usr/bin/env python3
"""Writes the PNG fixtures of test_io's png_bit_depths_palettes_and_interlacing.

Only zlib and the chunk format (PNG specification, 3rd edition): filter type 0 on every
row, Adam7 passes when interlaced.  The pixel formulas are repeated in the test.
Run from anywhere: python3 tests/data/png/make.py
"""
import os
import struct
import zlib

ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]
SAMPLES = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}  # per pixel, by colour type


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(path, w, h, depth, colour_type, interlace, pixel):
    fmt = ">H" if depth == 16 else "B"

    def row(xs, y):
        return b"\0" + b"".join(struct.pack(fmt, v) for x in xs for v in pixel(x, y))

    passes = ADAM7 if interlace else [(0, 0, 1, 1)]
    raw = b""
    for x0, y0, dx, dy in passes:
        xs = list(range(x0, w, dx))
        if xs:
            raw += b"".join(row(xs, y) for y in range(y0, h, dy))
    body = chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, colour_type, 0, 0, interlace))
    if colour_type == 3:  # palette entry i = (i, 255 - i, 7i mod 256)
        body += chunk(b"PLTE", bytes(v for i in range(256) for v in (i, 255 - i, (i * 7) & 255)))
    body += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + body)


here = os.path.dirname(os.path.abspath(__file__))
png(os.path.join(here, "rgba16-adam7.png"), 13, 11, 16, 6, 1,
    lambda x, y: ((x * 5003) & 65535, (y * 5807) & 65535, (x * y * 401) & 65535, 1000))
png(os.path.join(here, "palette-adam7.png"), 13, 11, 8, 3, 1, lambda x, y: ((x * 11 + y * 17) & 255,))
png(os.path.join(here, "grey16.png"), 13, 11, 16, 0, 0, lambda x, y: ((x * 5003 + y * 71) & 65535,))
png(os.path.join(here, "greyalpha8.png"), 13, 11, 8, 4, 0, lambda x, y: ((x * 19 + y) & 255, 7))

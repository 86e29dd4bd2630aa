#!/usr/bin/env python3
"""Writes leaves.png: a sprig of leaves on a transparent background, the
cutout texture of configs/scenes/cutout.yaml. 256x256 RGBA, sRGB colour,
straight (not premultiplied) alpha, with edges a texel or two soft so that
alpha-to-coverage has something to resolve. Made for facet; public domain
(CC0). Run it again to regenerate the file: python3 make_leaves.py"""
import math
import struct
import zlib

SIZE = 256


def leaf(px, py, x0, y0, angle, length, width):
    """Coverage (0..1) of a pointed leaf from (x0, y0) along `angle`, and the
    position along it (0 at the stem, 1 at the tip)."""
    dx, dy = px - x0, py - y0
    c, s = math.cos(angle), math.sin(angle)
    u = (dx * c + dy * s) / length  # along the leaf
    v = (-dx * s + dy * c)  # across, in texels
    if u <= 0.0 or u >= 1.0:
        return 0.0, u
    half = width * math.sin(math.pi * u) ** 0.8  # half-width at u
    return max(0.0, min(1.0, (half - abs(v)) / 1.5 + 0.5)), u


def main():
    # The stem: from the bottom centre up, leaves in pairs along it.
    leaves = []
    for k in range(5):
        t = 0.18 + 0.16 * k
        x, y = 128 + 10 * math.sin(3 * t), 240 - 200 * t
        size = 70 - 8 * k
        leaves.append((x, y, -math.pi / 2 - 0.9, size, size * 0.32))
        leaves.append((x, y, -math.pi / 2 + 0.9, size, size * 0.32))
    leaves.append((128 + 10 * math.sin(3 * 0.86), 240 - 200 * 0.86, -math.pi / 2, 40, 13))
    rows = []
    for py in range(SIZE):
        row = bytearray([0])  # PNG filter: none
        for px in range(SIZE):
            x, y = px + 0.5, py + 0.5
            alpha, shade = 0.0, 0.0
            for (x0, y0, a, length, width) in leaves:
                cover, u = leaf(x, y, x0, y0, a, length, width)
                if cover > alpha:
                    alpha, shade = cover, u
            stem_x = 128 + 10 * math.sin(3 * (240 - y) / 200)
            if 50 < y < 250:
                stem = max(0.0, min(1.0, 2.0 - abs(x - stem_x)))
                if stem > alpha:
                    alpha, shade = stem, 0.0
            r = int(40 + 60 * shade)
            g = int(110 + 80 * shade)
            b = int(30 + 20 * shade)
            row += bytes([r, g, b, int(round(255 * alpha))])
        rows.append(bytes(row))
    raw = zlib.compress(b"".join(rows), 9)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n" +
           chunk(b"IHDR", struct.pack(">IIBBBBB", SIZE, SIZE, 8, 6, 0, 0, 0)) +
           chunk(b"IDAT", raw) + chunk(b"IEND", b""))
    with open(__file__.replace("make_leaves.py", "leaves.png"), "wb") as f:
        f.write(png)


if __name__ == "__main__":
    main()

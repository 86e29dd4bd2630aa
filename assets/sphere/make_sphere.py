#!/usr/bin/env python3
"""Writes sphere.obj next to it: a unit sphere centred on the origin, for
facet's material demos. 48 segments around by 24 rings down, with normals
(the positions themselves) and UVs (u around from -Z, v down from the top
as OBJ counts it from the bottom); triangles wind counter-clockwise seen
from outside; the poles are rows of vertices of their own, one per segment,
so each pole triangle has its own UV. The output is the same byte for byte
on every run.

Made for facet; public domain (CC0). Run it again to regenerate the file,
from this folder: python3 make_sphere.py"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
SEGMENTS, RINGS = 48, 24


def main():
    lines = ["# a unit sphere, 48 x 24: assets/sphere/make_sphere.py"]
    for j in range(RINGS + 1):
        theta = math.pi * j / RINGS
        for i in range(SEGMENTS + 1):
            phi = 2.0 * math.pi * i / SEGMENTS
            x, y, z = math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi)
            lines.append("v %.6f %.6f %.6f" % (x, y, z))
            lines.append("vn %.6f %.6f %.6f" % (x, y, z))
            lines.append("vt %.6f %.6f" % (i / SEGMENTS, 1.0 - j / RINGS))
    row = SEGMENTS + 1
    for j in range(RINGS):
        for i in range(SEGMENTS):
            a = j * row + i + 1  # OBJ counts from 1
            b, c, d = a + 1, a + row, a + row + 1
            if j > 0:
                lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (a, a, a, b, b, b, c, c, c))
            if j < RINGS - 1:
                lines.append("f %d/%d/%d %d/%d/%d %d/%d/%d" % (b, b, b, d, d, d, c, c, c))
    with open(os.path.join(HERE, "sphere.obj"), "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()

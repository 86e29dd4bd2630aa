#!/usr/bin/env python3
"""Writes crate.obj, crate.mtl, wood.png and label.png next to it: a wooden
crate for facet's OBJ material demos. A 1 x 1 x 1 box standing on y = 0
(x, z in [-0.5, 0.5]) with three materials: "wood" on the box (wood.png,
planks with grain), "label" on a thin stencilled panel on the front (+z)
face (label.png: two arrows and "UP", so a flipped or mirrored texture shows)
and plain "iron" on two bands around it. Faces have normals and texcoords,
are triangles and wind counter-clockwise seen from outside. OBJ's v = 0 is
the image's bottom, so the textures appear upright. Textures are 256x256 RGB
with sRGB values. The output is the same byte for byte on every run.

Made for facet; public domain (CC0). Run it again to regenerate the files,
from this folder: python3 make_crate_obj.py"""
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SIZE = 256


# ---------------------------------------------------------------- helpers

def hash01(*keys):
    """A small integer hash of the keys, mapped to [0, 1). Deterministic."""
    h = 0x2545F491
    for k in keys:
        h ^= k & 0xFFFFFFFF
        h = (h * 0x85EBCA6B) & 0xFFFFFFFF
        h ^= h >> 13
        h = (h * 0xC2B2AE35) & 0xFFFFFFFF
        h ^= h >> 16
    return h / 4294967296.0


def value_noise(x, y, px, py, seed):
    """Smooth noise in [0, 1] on a lattice that wraps after px by py cells."""
    ix, iy = math.floor(x), math.floor(y)
    fx, fy = x - ix, y - iy
    fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
    x0, x1 = ix % px, (ix + 1) % px
    y0, y1 = iy % py, (iy + 1) % py
    a = hash01(x0, y0, seed)
    b = hash01(x1, y0, seed)
    c = hash01(x0, y1, seed)
    d = hash01(x1, y1, seed)
    return (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy


def fbm(x, y, cx, cy, octaves, seed):
    """Fractal noise around 0 (roughly -0.5..0.5); the largest features are
    cx by cy texels (powers of two), so it can be stretched along x."""
    total, amp, norm = 0.0, 1.0, 0.0
    for o in range(octaves):
        total += amp * (value_noise(x / cx, y / cy, SIZE // cx, SIZE // cy, seed + o) - 0.5)
        norm += amp
        cx, cy = max(1, cx // 2), max(1, cy // 2)
        amp *= 0.5
    return total / norm


def clamp(v, lo=0.0, hi=1.0):
    return lo if v < lo else hi if v > hi else v


def byte(v):
    return int(round(255 * clamp(v)))


def mix(a, b, t):
    return tuple(x + (y - x) * t for x, y in zip(a, b))


def write_png(name, pixel):
    """Writes a SIZE x SIZE 8-bit RGB PNG; pixel(x, y) returns (r, g, b)
    bytes. Rows use the Paeth filter, which suits smooth noisy images."""
    rows, prev = [], bytes(SIZE * 3)
    for y in range(SIZE):
        line = bytearray()
        for x in range(SIZE):
            line += bytes(pixel(x, y))
        out = bytearray([4])
        for i in range(len(line)):
            a = line[i - 3] if i >= 3 else 0
            b = prev[i]
            c = prev[i - 3] if i >= 3 else 0
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
            out.append((line[i] - pred) & 255)
        rows.append(bytes(out))
        prev = bytes(line)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n" +
           chunk(b"IHDR", struct.pack(">IIBBBBB", SIZE, SIZE, 8, 2, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b""))
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(png)


# ---------------------------------------------------------------- textures

PLANK = 64  # texels: four horizontal planks


def wood(x, y):
    """Four horizontal planks: grain along x, dark gaps between planks and a
    pair of nail heads at each plank's ends."""
    px, py = x + 0.5, y + 0.5
    plank = int(py // PLANK)
    fy = py % PLANK
    gap = clamp(1.5 - min(fy, PLANK - fy) + 0.5)  # 1 in the gap
    # Growth rings cut lengthwise: bands across the plank, bent by noise.
    bend = fbm(px, py, 128, 32, 3, 10 + plank) * 40.0
    rings = (fy + bend + 97.0 * hash01(plank, 11)) / (5.0 + 3.0 * hash01(plank, 12))
    late = clamp(abs(rings % 1.0 - 0.5) * 4.0 - 1.0) ** 2  # the darker late wood
    streak = fbm(px, py, 64, 2, 4, 20 + plank) * 0.5 + (hash01(y, 21) - 0.5) * 0.06
    tone = 0.85 + 0.25 * hash01(plank, 13)
    light = (0.78, 0.58, 0.36)
    dark = (0.56, 0.36, 0.19)
    col = mix(light, dark, clamp(late * 0.8 + streak))
    col = tuple(c * tone for c in col)
    # nail heads, 10 texels from each end, a quarter of the way in from each edge
    for nx in (10.0, SIZE - 10.0):
        for ny in (PLANK * 0.3, PLANK * 0.7):
            d = math.hypot(px - nx, fy - ny)
            if d < 4.0:
                k = clamp(3.0 - d + 0.5)
                shine = clamp(1 - math.hypot(px - nx + 1, fy - ny + 1) / 2.5) * 0.3
                col = mix(col, (0.22 + shine, 0.21 + shine, 0.20 + shine), k)
    col = mix(col, (0.12, 0.08, 0.05), gap)
    return tuple(byte(c) for c in col)


def seg_dist(px, py, ax, ay, bx, by):
    """Distance from (px, py) to the segment a-b."""
    dx, dy = bx - ax, by - ay
    t = clamp(((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy))
    return math.hypot(px - ax - t * dx, py - ay - t * dy)


def arc_dist(px, py, cx, cy, r, a0, a1):
    """Distance to the arc of radius r about (cx, cy) from angle a0 to a1
    (radians, image y down, a0 < a1)."""
    ang = math.atan2(py - cy, px - cx)
    while ang < a0:
        ang += 2 * math.pi
    if ang <= a1:
        return abs(math.hypot(px - cx, py - cy) - r)
    ends = [(cx + r * math.cos(a), cy + r * math.sin(a)) for a in (a0, a1)]
    return min(math.hypot(px - ex, py - ey) for ex, ey in ends)


def arrow(px, py, cx):
    """Ink coverage of an upward stencil arrow centred on x = cx: a head
    from y = 34 to 92, a shaft below it, split by a stencil bridge."""
    ink = 0.0
    if 34 <= py <= 92:  # the head: a triangle, its tip at the top
        half = (py - 34) / 58 * 29
        ink = clamp(half - abs(px - cx) + 0.5) * clamp(92 - py + 0.5)
    if 99 <= py <= 148:  # the shaft, below the bridge
        ink = max(ink, clamp(10 - abs(px - cx) + 0.5) * clamp(min(py - 99, 148 - py) + 0.5))
    return ink


def glyphs(px, py):
    """Ink coverage of stencilled "UP" below the arrows."""
    w = 7.5  # half the stroke
    d_u = min(seg_dist(px, py, 84, 170, 84, 204),
              seg_dist(px, py, 120, 170, 120, 204),
              arc_dist(px, py, 102, 204, 18, 0.0, math.pi))
    d_p = min(seg_dist(px, py, 148, 170, 148, 226),
              seg_dist(px, py, 148, 170, 164, 170),
              seg_dist(px, py, 148, 198, 164, 198),
              arc_dist(px, py, 164, 184, 14, -math.pi / 2, math.pi / 2))
    ink = clamp(w - min(d_u, d_p) + 0.5)
    # stencil bridges: gaps where a real stencil holds its islands
    if abs(px - 102) < 2.5 and py > 200:
        ink *= clamp(abs(px - 102) - 2.0)
    if 155.5 - 2.5 < px < 155.5 + 2.5 and 165 < py < 203:
        ink *= clamp(abs(px - 155.5) - 2.0)
    return ink


def label(x, y):
    """A painted tan panel with a dark border, two stencilled arrows and UP."""
    px, py = x + 0.5, y + 0.5
    paint = 0.93 + fbm(px, py, 32, 32, 4, 30) * 0.12
    col = (0.80 * paint, 0.73 * paint, 0.55 * paint)
    edge = min(px, py, SIZE - px, SIZE - py)
    border = clamp(3.0 - abs(edge - 14.0) + 0.5)
    ink = max(border, arrow(px, py, 88.0), arrow(px, py, 168.0), glyphs(px, py))
    # sprayed paint is thin and uneven: let a little of the panel through
    ink *= 0.9 + fbm(px, py, 8, 8, 3, 31) * 0.25
    col = mix(col, (0.09, 0.08, 0.07), clamp(ink))
    return tuple(byte(c) for c in col)


# ---------------------------------------------------------------- geometry

def add(a, b, k=1.0):
    return tuple(x + k * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def rect(centre, right, up, uv0=(0.0, 0.0), uv1=(1.0, 1.0)):
    """A rectangle: `right` and `up` are its half extents as seen from
    outside, so right x up points out. OBJ UVs run from uv0 at the
    bottom-left to uv1 at the top-right (v up). Corners counter-clockwise."""
    n = cross(right, up)
    length = math.sqrt(sum(c * c for c in n))
    n = tuple(c / length for c in n)
    corners = [add(add(centre, right, -1), up, -1), add(add(centre, right, 1), up, -1),
               add(add(centre, right, 1), up, 1), add(add(centre, right, -1), up, 1)]
    uvs = [(uv0[0], uv0[1]), (uv1[0], uv0[1]), (uv1[0], uv1[1]), (uv0[0], uv1[1])]
    return corners, n, uvs


def box(lo, hi, uv_of):
    """The six outward faces of the box lo..hi; uv_of(face) gives (uv0, uv1)."""
    c = tuple((a + b) / 2 for a, b in zip(lo, hi))
    h = tuple((b - a) / 2 for a, b in zip(lo, hi))
    X, Y, Z = (h[0], 0, 0), (0, h[1], 0), (0, 0, h[2])
    neg = lambda v: tuple(-a for a in v)
    faces = {
        "+z": (add(c, Z), X, Y), "-z": (add(c, Z, -1), neg(X), Y),
        "+x": (add(c, X), neg(Z), Y), "-x": (add(c, X, -1), Z, Y),
        "+y": (add(c, Y), X, neg(Z)), "-y": (add(c, Y, -1), X, Z),
    }
    return {name: rect(ctr, r, u, *uv_of(name)) for name, (ctr, r, u) in faces.items()}


def band(y0, y1, inner, outer):
    """An iron band round the crate from y0 to y1: four outer sides and the
    top and bottom lips between the half widths `inner` and `outer`."""
    faces = []
    h = (y1 - y0) / 2
    yc = (y0 + y1) / 2
    for (c, r) in (((0, yc, outer), (outer, 0, 0)), ((0, yc, -outer), (-outer, 0, 0)),
                   ((outer, yc, 0), (0, 0, -outer)), ((-outer, yc, 0), (0, 0, outer))):
        faces.append(rect(c, r, (0, h, 0), (0.0, 0.0), (1.0, 0.1)))
    corners = [(1, 1), (-1, 1), (-1, -1), (1, -1)]  # (x, z) signs, clockwise seen from +y
    for y, n in ((y1, (0.0, 1.0, 0.0)), (y0, (0.0, -1.0, 0.0))):
        for k in range(4):
            (ax, az), (bx, bz) = corners[k], corners[(k + 1) % 4]
            quad = [(ax * outer, y, az * outer), (bx * outer, y, bz * outer),
                    (bx * inner, y, bz * inner), (ax * inner, y, az * inner)]
            e = cross(add(quad[1], quad[0], -1), add(quad[2], quad[0], -1))
            if sum(a * b for a, b in zip(e, n)) < 0:
                quad.reverse()
            faces.append((quad, n, [(0.0, 0.0), (1.0, 0.0), (1.0, 0.02), (0.0, 0.02)]))
    return faces


def num(v):
    s = ("%.6f" % v).rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def main():
    write_png("wood.png", wood)
    write_png("label.png", label)

    body = box((-0.5, 0.0, -0.5), (0.5, 1.0, 0.5), lambda f: ((0.0, 0.0), (1.0, 1.0)))
    # The label: a panel 0.44 square and 1 cm thick on the front face. Its
    # edges take a sliver of the image's border so they look painted.
    panel = box((-0.22, 0.28, 0.5), (0.22, 0.72, 0.51),
                lambda f: ((0.0, 0.0), (1.0, 1.0)) if f == "+z" else ((0.0, 0.99), (1.0, 1.0)))
    parts = [
        ("crate_body", "wood", list(body.values())),
        ("label", "label", [panel[f] for f in ("+z", "+x", "-x", "+y", "-y")]),
        ("band_bottom", "iron", band(0.08, 0.18, 0.5, 0.515)),
        ("band_top", "iron", band(0.82, 0.92, 0.5, 0.515)),
    ]

    verts, texs, norms = {}, {}, {}

    def index(table, key):
        if key not in table:
            table[key] = len(table) + 1
        return table[key]

    body_lines = []
    triangles = 0
    for name, material, faces in parts:
        body_lines += ["", "o " + name, "g " + name, "usemtl " + material]
        for corners, n, uvs in faces:
            ids = []
            for p, t in zip(corners, uvs):
                v = index(verts, tuple(num(c) for c in p))
                vt = index(texs, tuple(num(c) for c in t))
                vn = index(norms, tuple(num(c) for c in n))
                ids.append("%d/%d/%d" % (v, vt, vn))
            body_lines.append("f %s %s %s" % (ids[0], ids[1], ids[2]))
            body_lines.append("f %s %s %s" % (ids[0], ids[2], ids[3]))
            triangles += 2

    head = [
        "# A wooden crate, 1 x 1 x 1, standing on y = 0: a wood box, a stencilled",
        "# label panel on the front (+z) and two iron bands. Triangles, counter-",
        "# clockwise seen from outside; vt has v = 0 at the image's bottom.",
        "# %d vertices, %d texcoords, %d normals, %d triangles." % (
            len(verts), len(texs), len(norms), triangles),
        "# Made for facet by make_crate_obj.py; public domain (CC0).",
        "mtllib crate.mtl",
    ]
    lines = head + [""]
    lines += ["v %s %s %s" % k for k in verts]
    lines += ["vt %s %s" % k for k in texs]
    lines += ["vn %s %s %s" % k for k in norms]
    lines += body_lines
    with open(os.path.join(HERE, "crate.obj"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")

    mtl = """# Materials of crate.obj. Made for facet by make_crate_obj.py; public domain (CC0).

newmtl wood
Ka 0 0 0
Kd 1 1 1
Ks 0.05 0.05 0.05
Ns 10
d 1
illum 2
map_Kd wood.png

newmtl label
Ka 0 0 0
Kd 1 1 1
Ks 0.1 0.1 0.1
Ns 20
d 1
illum 2
map_Kd label.png

newmtl iron
Ka 0 0 0
Kd 0.3 0.3 0.32
Ks 0.6 0.6 0.6
Ns 60
d 1
illum 2
"""
    with open(os.path.join(HERE, "crate.mtl"), "w", newline="\n") as f:
        f.write(mtl)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes gallery.gltf, gallery.bin and the PNG textures next to it: a small
glTF 2.0 scene of several materials for facet's material demos. A tiled floor
(base colour, normal, occlusion/roughness), a gold sphere, a red plastic
sphere, a brick-and-steel crate (one mesh, two primitives, two materials, an
emissive ring on the steel) and a cutout leaf card (alphaMode MASK). Y up,
metres, everything standing on y = 0 within x, z in [-1.6, 1.6].

Textures are 256x256: tiles_basecolor.png, tiles_normal.png, tiles_orm.png
(R occlusion, G roughness, B metallic), brick_basecolor.png, brick_normal.png,
panel_emissive.png and leaves_basecolor.png (RGBA, straight alpha). Colour
textures hold sRGB values; normal maps are tangent space with green up (the
glTF / OpenGL convention). The output is the same byte for byte on every run.

Made for facet; public domain (CC0). Run it again to regenerate the files,
from this folder: python3 make_gallery.py"""
import json
import math
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SIZE = 256

# glTF enums
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
FLOAT, UNSIGNED_SHORT = 5126, 5123
LINEAR, LINEAR_MIPMAP_LINEAR = 9729, 9987
REPEAT, CLAMP_TO_EDGE = 10497, 33071


# ---------------------------------------------------------------- helpers

def hash01(*keys):
    """A small integer hash of the keys, mapped to [0, 1). Deterministic."""
    h = 0x9E3779B9
    for k in keys:
        h ^= k & 0xFFFFFFFF
        h = (h * 0x85EBCA6B) & 0xFFFFFFFF
        h ^= h >> 13
        h = (h * 0xC2B2AE35) & 0xFFFFFFFF
        h ^= h >> 16
    return h / 4294967296.0


def value_noise(x, y, period, seed):
    """Smooth noise in [0, 1] on a lattice of `period` cells that wraps."""
    ix, iy = math.floor(x), math.floor(y)
    fx, fy = x - ix, y - iy
    fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
    x0, x1 = ix % period, (ix + 1) % period
    y0, y1 = iy % period, (iy + 1) % period
    a = hash01(x0, y0, seed)
    b = hash01(x1, y0, seed)
    c = hash01(x0, y1, seed)
    d = hash01(x1, y1, seed)
    return (a + (b - a) * fx) * (1 - fy) + (c + (d - c) * fx) * fy


def fbm(x, y, cell, octaves, seed):
    """Fractal noise around 0 (roughly -0.5..0.5), tiling over SIZE texels;
    `cell` is the largest feature in texels (a power of two)."""
    total, amp, norm = 0.0, 1.0, 0.0
    for o in range(octaves):
        total += amp * (value_noise(x / cell, y / cell, SIZE // cell, seed + o) - 0.5)
        norm += amp
        cell = max(1, cell // 2)
        amp *= 0.5
    return total / norm


def clamp(v, lo=0.0, hi=1.0):
    return lo if v < lo else hi if v > hi else v


def smoothstep(e0, e1, v):
    t = clamp((v - e0) / (e1 - e0))
    return t * t * (3 - 2 * t)


def byte(v):
    """0..1 to 0..255, rounded."""
    return int(round(255 * clamp(v)))


def write_png(name, channels, pixel):
    """Writes a SIZE x SIZE 8-bit PNG (channels 3 = RGB, 4 = RGBA); pixel(x, y)
    returns a tuple of bytes. Each row takes whichever PNG filter leaves the
    smallest sum of residuals, which keeps noisy textures small."""
    rows, prev = [], bytes(SIZE * channels)
    for y in range(SIZE):
        line = bytearray()
        for x in range(SIZE):
            line += bytes(pixel(x, y))
        rows.append(filter_row(bytes(line), prev, channels))
        prev = bytes(line)

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    colour_type = 2 if channels == 3 else 6
    png = (b"\x89PNG\r\n\x1a\n" +
           chunk(b"IHDR", struct.pack(">IIBBBBB", SIZE, SIZE, 8, colour_type, 0, 0, 0)) +
           chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b""))
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(png)


def filter_row(line, prev, bpp):
    """The row filtered with each of PNG's five filters; returns the one whose
    residuals are smallest, with its filter byte in front."""
    n = len(line)
    candidates = [bytes([0]) + line]
    sub = bytearray([1])
    up = bytearray([2])
    avg = bytearray([3])
    paeth = bytearray([4])
    for i in range(n):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]
        c = prev[i - bpp] if i >= bpp else 0
        v = line[i]
        sub.append((v - a) & 255)
        up.append((v - b) & 255)
        avg.append((v - (a + b) // 2) & 255)
        p = a + b - c
        pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
        pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
        paeth.append((v - pred) & 255)
    candidates += [bytes(sub), bytes(up), bytes(avg), bytes(paeth)]

    def cost(row):
        return sum(v if v < 128 else 256 - v for v in row[1:])
    return min(candidates, key=cost)


def encode_normal(nx, ny, nz):
    """A tangent-space normal to RGB: n * 0.5 + 0.5, green up."""
    k = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz)
    return (byte(nx * k * 0.5 + 0.5), byte(ny * k * 0.5 + 0.5), byte(nz * k * 0.5 + 0.5))


def normal_map(height, depth):
    """A pixel function for the normal map of the surface height(x, y) * depth
    (in texels). Each texel averages the normals at its four quarter points,
    from central differences half a texel wide, so height is sampled once on
    a grid of half texels (offset by a quarter). Image y runs down and the
    normal's +Y points to the image's top, so the y slope changes sign."""
    n = 2 * SIZE
    grid = [[height(0.25 + 0.5 * i, 0.25 + 0.5 * j) for i in range(n)] for j in range(n)]

    def h(i, j):
        return grid[j % n][i % n]

    def pixel(x, y):
        sx = sy = 0.0
        for i in (2 * x, 2 * x + 1):          # the samples at x + 0.25, x + 0.75
            for j in (2 * y, 2 * y + 1):
                sx -= (h(i + 1, j) - h(i - 1, j)) * depth
                sy += (h(i, j + 1) - h(i, j - 1)) * depth
        return encode_normal(sx / 4, sy / 4, 1.0)
    return pixel


# ---------------------------------------------------------------- textures

TILE = 64          # texels per tile: 4x4 tiles
TILE_GROUT = 2.5   # half the grout's width
TILE_BEVEL = 3.0   # width of the rounded edge from grout to tile top


def tile_edge_distance(x, y):
    """Distance (texels) from (x, y) to the nearest grout line's centre."""
    fx, fy = x % TILE, y % TILE
    return min(fx, TILE - fx, fy, TILE - fy)


def tile_height(x, y):
    """0 at the bottom of the grout, 1 on a tile's face."""
    d = tile_edge_distance(x, y)
    return smoothstep(TILE_GROUT, TILE_GROUT + TILE_BEVEL, d)


def tile_id(x, y):
    return int(x // TILE) % (SIZE // TILE), int(y // TILE) % (SIZE // TILE)


def tiles_basecolor(x, y):
    cx, cy = x + 0.5, y + 0.5
    d = tile_edge_distance(cx, cy)
    grout = 1.0 - clamp(d - TILE_GROUT + 0.5)  # 1 in the grout, anti-aliased
    tx, ty = tile_id(cx, cy)
    # Per-tile glaze: a cream, a little lighter or darker, warmer or cooler.
    bright = 0.92 + 0.14 * hash01(tx, ty, 11)
    warm = (hash01(tx, ty, 12) - 0.5) * 0.06
    mottle = fbm(cx, cy, 32, 4, 20) * 0.10
    edge = 0.90 + 0.10 * smoothstep(TILE_GROUT, TILE_GROUT + TILE_BEVEL + 2, d)
    k = (bright + mottle) * edge
    tile = (0.86 * k * (1 + warm), 0.82 * k, 0.74 * k * (1 - warm))
    g = 0.36 + fbm(cx, cy, 8, 3, 30) * 0.10
    grout_c = (g, g * 0.96, g * 0.90)
    return tuple(byte(t * (1 - grout) + s * grout) for t, s in zip(tile, grout_c))


def tiles_height(px, py):
    """tile_height, with each tile tilted a tiny bit: tiles are not laid
    perfectly level."""
    tx, ty = tile_id(px, py)
    tilt_x = (hash01(tx, ty, 13) - 0.5) * 0.02
    tilt_y = (hash01(tx, ty, 14) - 0.5) * 0.02
    h = tile_height(px, py)
    return h * (1 + tilt_x * (px % TILE - TILE / 2) + tilt_y * (py % TILE - TILE / 2))


def tiles_orm(x, y):
    h = tile_height(x + 0.5, y + 0.5)
    occlusion = 0.45 + 0.55 * h
    rough = 0.9 + (0.35 - 0.9) * h + fbm(x + 0.5, y + 0.5, 16, 3, 40) * 0.04 * h
    return (byte(occlusion), byte(rough), 0)


BRICK_W, BRICK_H = 64, 32   # texels: 4 bricks across, 8 courses, running bond
MORTAR = 2.0                # half the mortar joint
BRICK_BEVEL = 2.5


def brick_cell(x, y):
    """(column, row) of the brick at (x, y), and the distance to its mortar."""
    row = int(y // BRICK_H)
    shift = BRICK_W / 2 if row % 2 else 0.0
    u = (x - shift) % SIZE
    col = int(u // BRICK_W)
    fx, fy = u % BRICK_W, y % BRICK_H
    d = min(fx, BRICK_W - fx, fy, BRICK_H - fy)
    return col, row % (SIZE // BRICK_H), d


def brick_basecolor(x, y):
    cx, cy = x + 0.5, y + 0.5
    col, row, d = brick_cell(cx, cy)
    mortar = 1.0 - clamp(d - MORTAR + 0.5)
    shade = 0.80 + 0.30 * hash01(col, row, 51)
    burnt = hash01(col, row, 52) < 0.2
    r, g, b = (0.58, 0.25, 0.17) if not burnt else (0.42, 0.19, 0.14)
    speck = fbm(cx, cy, 16, 4, 53) * 0.22 + (hash01(x, y, 54) - 0.5) * 0.05
    k = shade * (1 + speck)
    brick = (r * k, g * k * (1 + 0.3 * speck), b * k)
    m = 0.68 + fbm(cx, cy, 4, 2, 55) * 0.12
    mortar_c = (m, m * 0.97, m * 0.90)
    return tuple(byte(t * (1 - mortar) + s * mortar) for t, s in zip(brick, mortar_c))


def brick_height(px, py):
    """Bricks stand proud of the mortar, with a rough face."""
    _, _, d = brick_cell(px, py)
    h = smoothstep(MORTAR, MORTAR + BRICK_BEVEL, d)
    return h * (1 + fbm(px, py, 16, 4, 56) * 0.5) + fbm(px, py, 4, 2, 57) * 0.3


def panel_emissive(x, y):
    """Black, with a glowing cyan ring and four short ticks around it."""
    cx, cy = x + 0.5 - SIZE / 2, y + 0.5 - SIZE / 2
    r = math.hypot(cx, cy)
    d = abs(r - 80.0)
    core = clamp(3.0 - d + 0.5)
    angle = math.atan2(cy, cx)
    # ticks: radial stripes just outside the ring at 0, 90, 180, 270 degrees
    a = abs((angle + math.pi / 4) % (math.pi / 2) - math.pi / 4) * r
    if 92 <= r <= 108:
        core = max(core, clamp(2.5 - a + 0.5) * 0.8)
    glow = 0.35 * math.exp(-(d / 7.0) ** 2)
    return (byte(core * 0.55 + glow * 0.05), byte(core + glow * 0.8), byte(core + glow * 0.9))


# Leaves on a branch: (x, y) of the stem end, angle (radians, 0 = +x, image
# y down), length, half width.
LEAVES = []
for _k in range(6):
    _t = 0.12 + 0.14 * _k
    _bx, _by = 128 + 18 * math.sin(2.2 * _t) - 8 * _t, 236 - 205 * _t
    _side = -1 if _k % 2 else 1
    _len = 84 - 8 * _k
    LEAVES.append((_bx, _by, -math.pi / 2 + _side * (0.95 - 0.05 * _k), _len, _len * 0.30))
LEAVES.append((128 + 18 * math.sin(2.2 * 0.95) - 8 * 0.95, 236 - 205 * 0.95, -1.62, 34.0, 11.0))


def branch_x(y):
    t = (236 - y) / 205
    return 128 + 18 * math.sin(2.2 * t) - 8 * t


def leaves_basecolor(x, y):
    px, py = x + 0.5, y + 0.5
    best = None  # (coverage, u, v across in texels, v / half width, leaf index)
    for i, (x0, y0, ang, length, half) in enumerate(LEAVES):
        dx, dy = px - x0, py - y0
        c, s = math.cos(ang), math.sin(ang)
        u = (dx * c + dy * s) / length
        v = -dx * s + dy * c
        if not 0.0 < u < 1.0:
            continue
        # an ovate leaf: widest a third of the way out, pointed at the tip
        w = half * (math.sin(math.pi * u ** 0.75)) ** 0.9
        cover = clamp(w - abs(v) + 0.5)
        if cover > 0 and (best is None or cover > best[0]):
            best = (cover, u, v, v / max(w, 1e-6), i)
    stem_cover = 0.0
    if 10.0 < py < 252.0:
        stem_cover = clamp(1.8 - abs(px - branch_x(py)) + 0.5)
    if best is None and stem_cover <= 0:
        return (62, 104, 40, 0)  # transparent; leaf green so filtering bleeds no black
    if best is None or stem_cover > best[0]:
        return (byte(0.36), byte(0.28), byte(0.14), byte(stem_cover))
    cover, u, across, v, i = best
    tone = 0.85 + 0.3 * hash01(i, 71)
    base = (0.20 + 0.10 * u, 0.42 + 0.16 * u, 0.12 + 0.04 * u)
    # the midrib and side veins, a little lighter
    midrib = clamp(1.2 - abs(across)) * (1 - u) * 0.6
    side = (u * 9.0 - abs(v) * 2.2) % 1.0
    vein = clamp(1 - abs(side - 0.5) * 14) * 0.25 * (1 - abs(v))
    light = max(midrib, vein)
    k = tone * (1 + fbm(px, py, 8, 2, 72) * 0.15)
    col = tuple(c * k * (1 - light) + (0.55, 0.72, 0.35)[j] * light for j, c in enumerate(base))
    return (byte(col[0]), byte(col[1]), byte(col[2]), byte(cover))


# ---------------------------------------------------------------- geometry

def box_faces(hx, hy, hz, uv_of):
    """The six faces of a box centred at the origin, each as a quad with
    outward normal, its `right` and `up` directions seen from outside
    (right x up = normal) and UVs from uv_of(face, s, t) where s, t in
    [0, 1] run right and up. Returns {face: (positions, normals, uvs,
    indices)} with indices counter-clockwise seen from outside."""
    faces = {
        "+x": ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
        "-x": ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
        "+z": ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
        "-z": ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
        "+y": ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
        "-y": ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    }
    half = (hx, hy, hz)
    out = {}
    for name, (n, r, up) in faces.items():
        pos, nor, uvs = [], [], []
        for s, t in ((0, 0), (1, 0), (1, 1), (0, 1)):
            p = tuple(n[i] * half[i] + (2 * s - 1) * r[i] * half[i] + (2 * t - 1) * up[i] * half[i]
                      for i in range(3))
            pos.append(p)
            nor.append(n)
            uvs.append(uv_of(name, s, t))
        out[name] = (pos, nor, uvs, [0, 1, 2, 0, 2, 3])
    return out


def merge(parts):
    pos, nor, uvs, idx = [], [], [], []
    for p, n, t, i in parts:
        base = len(pos)
        pos += p
        nor += n
        uvs += t
        idx += [base + k for k in i]
    return pos, nor, uvs, idx


def floor_mesh():
    def uv(face, s, t):
        if face in ("+y", "-y"):
            return (2.0 * s, 2.0 * (1 - t))          # the 4x4 tiles twice across
        return (2.0 * s, 0.0625 * (1 - t))            # edges: 0.1 m of 1.6 m per repeat
    faces = box_faces(1.6, 0.05, 1.6, uv)
    pos, nor, uvs, idx = merge(faces.values())
    pos = [(x, y - 0.05, z) for x, y, z in pos]        # top face at y = 0
    return pos, nor, uvs, idx


def sphere_mesh(radius, segments, rings):
    """A UV sphere: u = longitude / 2 pi, v = 0 at the north pole. The seam's
    column is doubled (u = 0 and u = 1); each pole has one vertex per segment,
    with u at the segment's middle."""
    pos, nor, uvs, idx = [], [], [], []

    def add(theta, phi, u, v):
        n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
        if theta == 0.0:
            n = (0.0, 1.0, 0.0)
        elif theta == math.pi:
            n = (0.0, -1.0, 0.0)
        pos.append(tuple(radius * c for c in n))
        nor.append(n)
        uvs.append((u, v))
        return len(pos) - 1

    north = [add(0.0, 0.0, (j + 0.5) / segments, 0.0) for j in range(segments)]
    grid = []
    for i in range(1, rings):
        theta = math.pi * i / rings
        # the seam's second column (j = segments) repeats the first's positions exactly
        grid.append([add(theta, 2 * math.pi * (j % segments) / segments, j / segments, i / rings)
                     for j in range(segments + 1)])
    south = [add(math.pi, 0.0, (j + 0.5) / segments, 1.0) for j in range(segments)]
    for j in range(segments):
        idx += [north[j], grid[0][j], grid[0][j + 1]]
    for i in range(rings - 2):
        for j in range(segments):
            a, b = grid[i][j], grid[i + 1][j]
            c, d = grid[i + 1][j + 1], grid[i][j + 1]
            idx += [a, b, c, a, c, d]
    for j in range(segments):
        idx += [grid[-1][j], south[j], grid[-1][j + 1]]
    return pos, nor, uvs, idx


def crate_meshes():
    faces = box_faces(0.3, 0.3, 0.3, lambda face, s, t: (float(s), float(1 - t)))
    sides = merge([faces[f] for f in ("+z", "+x", "-z", "-x")])
    caps = merge([faces[f] for f in ("+y", "-y")])
    return sides, caps


def leaves_mesh():
    pos = [(-0.4, 0.0, 0.0), (0.4, 0.0, 0.0), (0.4, 0.8, 0.0), (-0.4, 0.8, 0.0)]
    nor = [(0.0, 0.0, 1.0)] * 4
    uvs = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
    return pos, nor, uvs, [0, 1, 2, 0, 2, 3]


# ---------------------------------------------------------------- glTF

class Gltf:
    def __init__(self):
        self.bin = bytearray()
        self.views, self.accessors = [], []

    def _view(self, data, target):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.bin),
                           "byteLength": len(data), "target": target})
        self.bin += data
        return len(self.views) - 1

    def floats(self, rows, kind, bounds=False):
        data = b"".join(struct.pack("<%df" % len(r), *r) for r in rows)
        acc = {"bufferView": self._view(data, ARRAY_BUFFER), "componentType": FLOAT,
               "count": len(rows), "type": kind}
        if bounds:
            # bounds of the values as stored (float32), written exactly
            stored = [struct.unpack("<%df" % len(r), struct.pack("<%df" % len(r), *r)) for r in rows]
            acc["min"] = [min(r[i] for r in stored) for i in range(len(rows[0]))]
            acc["max"] = [max(r[i] for r in stored) for i in range(len(rows[0]))]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def indices(self, idx):
        data = struct.pack("<%dH" % len(idx), *idx)
        self.accessors.append({"bufferView": self._view(data, ELEMENT_ARRAY_BUFFER),
                               "componentType": UNSIGNED_SHORT, "count": len(idx),
                               "type": "SCALAR"})
        return len(self.accessors) - 1

    def primitive(self, mesh, material):
        pos, nor, uvs, idx = mesh
        return {"attributes": {"POSITION": self.floats(pos, "VEC3", bounds=True),
                               "NORMAL": self.floats(nor, "VEC3"),
                               "TEXCOORD_0": self.floats(uvs, "VEC2")},
                "indices": self.indices(idx), "material": material, "mode": 4}


def y_rotation(degrees):
    h = math.radians(degrees) / 2
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def main():
    textures = [  # (image file, sampler): the texture index is the list index
        ("tiles_basecolor.png", 0, tiles_basecolor, 3),
        ("tiles_normal.png", 0, normal_map(tiles_height, 2.0), 3),
        ("tiles_orm.png", 0, tiles_orm, 3),
        ("brick_basecolor.png", 0, brick_basecolor, 3),
        ("brick_normal.png", 0, normal_map(brick_height, 1.6), 3),
        ("panel_emissive.png", 1, panel_emissive, 3),
        ("leaves_basecolor.png", 1, leaves_basecolor, 4),
    ]
    for name, _, pixel, channels in textures:
        write_png(name, channels, pixel)
    tex = {name: i for i, (name, _, _, _) in enumerate(textures)}

    materials = [
        {"name": "tiles",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": tex["tiles_basecolor.png"]},
                                  "metallicRoughnessTexture": {"index": tex["tiles_orm.png"]},
                                  "metallicFactor": 1.0, "roughnessFactor": 1.0},
         "normalTexture": {"index": tex["tiles_normal.png"], "scale": 1.0},
         "occlusionTexture": {"index": tex["tiles_orm.png"], "strength": 1.0}},
        {"name": "gold",
         "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.766, 0.336, 1.0],
                                  "metallicFactor": 1.0, "roughnessFactor": 0.3}},
        {"name": "red_plastic",
         "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.05, 0.04, 1.0],
                                  "metallicFactor": 0.0, "roughnessFactor": 0.45}},
        {"name": "brick",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": tex["brick_basecolor.png"]},
                                  "metallicFactor": 0.0, "roughnessFactor": 0.8},
         "normalTexture": {"index": tex["brick_normal.png"], "scale": 1.0}},
        {"name": "steel_plate",
         "pbrMetallicRoughness": {"baseColorFactor": [0.62, 0.62, 0.64, 1.0],
                                  "metallicFactor": 1.0, "roughnessFactor": 0.4},
         "emissiveTexture": {"index": tex["panel_emissive.png"]},
         "emissiveFactor": [1.0, 1.0, 1.0]},
        {"name": "leaves_cutout",
         "pbrMetallicRoughness": {"baseColorTexture": {"index": tex["leaves_basecolor.png"]},
                                  "metallicFactor": 0.0, "roughnessFactor": 0.6},
         "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True},
    ]
    mat = {m["name"]: i for i, m in enumerate(materials)}

    g = Gltf()
    floor = g.primitive(floor_mesh(), mat["tiles"])
    sphere = g.primitive(sphere_mesh(0.35, 48, 24), mat["gold"])
    plastic = dict(sphere, material=mat["red_plastic"])  # same accessors
    sides, caps = crate_meshes()
    crate = [g.primitive(sides, mat["brick"]), g.primitive(caps, mat["steel_plate"])]
    leaves = g.primitive(leaves_mesh(), mat["leaves_cutout"])
    while len(g.bin) % 4:
        g.bin.append(0)

    meshes = [
        {"name": "floor_slab", "primitives": [floor]},
        {"name": "sphere_gold_mesh", "primitives": [sphere]},
        {"name": "sphere_plastic_mesh", "primitives": [plastic]},
        {"name": "crate_mesh", "primitives": crate},
        {"name": "leaves_card", "primitives": [leaves]},
    ]
    nodes = [
        {"name": "floor", "mesh": 0},
        {"name": "sphere_gold", "mesh": 1, "translation": [-0.75, 0.35, 0.45]},
        {"name": "sphere_plastic", "mesh": 2, "translation": [0.15, 0.35, 0.85]},
        {"name": "crate", "mesh": 3, "translation": [0.7, 0.3, -0.25],
         "rotation": y_rotation(25.0)},
        {"name": "leaves", "mesh": 4, "translation": [-0.55, 0.0, -0.7],
         "rotation": y_rotation(20.0)},
    ]
    doc = {
        "asset": {"version": "2.0", "generator": "facet assets/gallery/make_gallery.py",
                  "copyright": "public domain (CC0)"},
        "scene": 0,
        "scenes": [{"name": "gallery", "nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "textures": [{"name": name[:-4], "source": i, "sampler": s}
                     for i, (name, s, _, _) in enumerate(textures)],
        "images": [{"name": name[:-4], "uri": name} for name, _, _, _ in textures],
        "samplers": [
            {"name": "repeat", "magFilter": LINEAR, "minFilter": LINEAR_MIPMAP_LINEAR,
             "wrapS": REPEAT, "wrapT": REPEAT},
            {"name": "clamp", "magFilter": LINEAR, "minFilter": LINEAR_MIPMAP_LINEAR,
             "wrapS": CLAMP_TO_EDGE, "wrapT": CLAMP_TO_EDGE},
        ],
        "accessors": g.accessors,
        "bufferViews": g.views,
        "buffers": [{"name": "gallery", "uri": "gallery.bin", "byteLength": len(g.bin)}],
    }
    with open(os.path.join(HERE, "gallery.bin"), "wb") as f:
        f.write(g.bin)
    with open(os.path.join(HERE, "gallery.gltf"), "w", newline="\n") as f:
        f.write(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes the texture_decode fuzz target's seeds into fuzz/seeds/texture_decode/.

Small images, one for each layout stb_image reads that facet's users bring:
PNG in every colour type and depth (palette, grey, grey with alpha, RGB,
RGBA; 1 to 16 bits), interlaced and not; BMP, TGA (plain and run-length),
PNM and Radiance HDR; and JPEG (baseline, progressive, grey) through cjpeg
(Debian: libjpeg-turbo-progs), when it is installed.

Each seed starts with the target's flags byte (fuzz/texture_decode.cpp): 0,
then 0x15, so that both the colour and the data path and each filter and
wrap are seeded. The files are kept in the repository; run this again only
to change them.
"""
import os
import shutil
import struct
import subprocess
import tempfile
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "texture_decode")
W, H = 5, 3  # neither a power of two nor square


def pattern(channels, maximum):
    """Rows of W x H pixels, each channel a different ramp."""
    rows = []
    for y in range(H):
        row = []
        for x in range(W):
            for c in range(channels):
                row.append((x * 53 + y * 97 + c * 71) * (maximum + 1) // 512 % (maximum + 1))
        rows.append(row)
    return rows


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))


def pack_row(row, depth):
    if depth == 16:
        return b"".join(struct.pack(">H", v) for v in row)
    if depth == 8:
        return bytes(row)
    bits, out, acc, n = depth, bytearray(), 0, 0
    for v in row:
        acc = (acc << bits) | v
        n += bits
        if n == 8:
            out.append(acc)
            acc, n = 0, 0
    if n:
        out.append(acc << (8 - n))
    return bytes(out)


def png(colour_type, depth, interlace=False):
    channels = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[colour_type]
    rows = pattern(channels, (1 << depth) - 1)
    raw = bytearray()
    if interlace:  # Adam7: each pass's pixels, filter 0
        for x0, y0, dx, dy in [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4),
                               (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]:
            for y in range(y0, H, dy):
                xs = list(range(x0, W, dx))
                if not xs:
                    continue
                row = [v for x in xs for v in rows[y][x * channels:(x + 1) * channels]]
                raw += b"\0" + pack_row(row, depth)
    else:
        for y, row in enumerate(rows):
            raw += bytes([y % 5]) if depth == 8 else b"\0"  # filters 0-4 on the 8-bit rows
            if depth == 8 and y % 5:
                raw += filtered(row, rows[y - 1] if y else None, y % 5, channels)
            else:
                raw += pack_row(row, depth)
    out = b"\x89PNG\r\n\x1a\n"
    out += chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, depth, colour_type, 0, 0, int(interlace)))
    if colour_type == 3:
        out += chunk(b"PLTE", bytes(range(3 * (1 << depth))))
        out += chunk(b"tRNS", bytes([255, 128, 0][:1 << depth]))
    out += chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    return out + chunk(b"IEND", b"")


def filtered(row, above, kind, bpp):
    """PNG filter `kind` (1 sub, 2 up, 3 average, 4 Paeth) of an 8-bit row."""
    out = bytearray()
    for i, v in enumerate(row):
        a = row[i - bpp] if i >= bpp else 0
        b = above[i] if above else 0
        c = above[i - bpp] if above and i >= bpp else 0
        if kind == 1:
            p = a
        elif kind == 2:
            p = b
        elif kind == 3:
            p = (a + b) // 2
        else:
            pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
            p = a if pa <= pb and pa <= pc else b if pb <= pc else c
        out.append((v - p) & 255)
    return bytes(out)


def bgr(row, channels):
    """A row with each pixel's red and blue swapped, as BMP and TGA store them."""
    out = list(row)
    for i in range(0, len(out), channels):
        out[i], out[i + 2] = out[i + 2], out[i]
    return out


def bmp():
    rows = [bgr(r, 3) for r in pattern(3, 255)]
    stride = (W * 3 + 3) & ~3
    pixels = b"".join(bytes(r) + b"\0" * (stride - W * 3) for r in reversed(rows))
    header = struct.pack("<IiiHHIIiiII", 40, W, H, 1, 24, 0, len(pixels), 2835, 2835, 0, 0)
    return b"BM" + struct.pack("<IHHI", 14 + len(header) + len(pixels), 0, 0, 54) + header + pixels


def tga(rle):
    rows = [bgr(r, 4) for r in pattern(4, 255)]
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, 10 if rle else 2, 0, 0, 0, 0, 0, W, H, 32, 8)
    body = bytearray()
    for row in reversed(rows):
        pixels = [bytes(row[i * 4:i * 4 + 4]) for i in range(W)]
        if rle:  # a run packet of the first pixel alone, then a raw packet of the rest
            body += bytes([0x80]) + pixels[0] + bytes([W - 2]) + b"".join(pixels[1:])
        else:
            body += b"".join(pixels)
    return header + bytes(body)


def pnm():
    return b"P6\n%d %d\n255\n" % (W, H) + b"".join(bytes(r) for r in pattern(3, 255))


def hdr():
    rows = pattern(4, 255)
    body = b"".join(bytes(r) for r in rows)  # flat RGBE, no run-length
    return b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (H, W) + body


def jpegs():
    cjpeg = shutil.which("cjpeg")
    if not cjpeg:
        print("cjpeg not found (apt-get install libjpeg-turbo-progs): no JPEG seeds")
        return {}
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "in.ppm")
        with open(src, "wb") as f:
            f.write(pnm())
        for name, flags in [("baseline", []), ("progressive", ["-progressive"]),
                            ("grey", ["-grayscale"]), ("optimized", ["-optimize", "-quality", "40"])]:
            out["jpeg-" + name + ".jpg"] = subprocess.run(
                [cjpeg, *flags, src], check=True, capture_output=True).stdout
    return out


def main():
    os.makedirs(OUT, exist_ok=True)
    seeds = {
        "png-rgba8.png": png(6, 8), "png-rgb8.png": png(2, 8), "png-grey8.png": png(0, 8),
        "png-grey-alpha8.png": png(4, 8), "png-palette4.png": png(3, 4),
        "png-palette1.png": png(3, 1), "png-grey2.png": png(0, 2),
        "png-rgba16.png": png(6, 16), "png-grey16.png": png(0, 16),
        "png-rgb8-interlaced.png": png(2, 8, interlace=True),
        "bmp-rgb24.bmp": bmp(), "tga-rgba.tga": tga(False), "tga-rgba-rle.tga": tga(True),
        "pnm-rgb.ppm": pnm(), "hdr-flat.hdr": hdr(),
    }
    seeds.update(jpegs())
    for i, (name, data) in enumerate(sorted(seeds.items())):
        flags = b"\x00" if i % 2 == 0 else b"\x15"
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(flags + data)
    print(f"{len(seeds)} seeds in {OUT}")


if __name__ == "__main__":
    main()

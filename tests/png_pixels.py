"""The pixels of a PNG facet writes (8-bit RGBA), with Python's zlib alone:
for tests that compare images from facet's APIs with facet-render's.

    python3 png_pixels.py A.png B.png [RAW WxH]

exits 0 when A and B (and the raw RGBA file RAW of W x H, if given) hold
the same pixels, and says what each is."""
import struct
import sys
import zlib


def pixels(path):
    """((width, height), rows): each row the bytes of its RGBA pixels."""
    data = open(path, "rb").read()
    pos, idat, size = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            size = struct.unpack(">II", body[:8])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h = size
    raw, rows, prev = zlib.decompress(idat), [], bytearray(w * 4)
    for y in range(h):
        f = raw[y * (w * 4 + 1)]
        line = bytearray(raw[y * (w * 4 + 1) + 1:(y + 1) * (w * 4 + 1)])
        for i in range(w * 4):
            a = line[i - 4] if i >= 4 else 0
            b, c = prev[i], prev[i - 4] if i >= 4 else 0
            p = a + b - c
            pred = [0, a, b, (a + b) // 2,
                    a if abs(p - a) <= abs(p - b) and abs(p - a) <= abs(p - c)
                    else b if abs(p - b) <= abs(p - c) else c][f]
            line[i] = (line[i] + pred) & 255
        rows.append(bytes(line))
        prev = line
    return size, rows


if __name__ == "__main__":
    a, b = pixels(sys.argv[1]), pixels(sys.argv[2])
    print(sys.argv[1], a[0], sys.argv[2], b[0], "equal" if a == b else "differ")
    ok = a == b
    if len(sys.argv) > 4:
        w, h = map(int, sys.argv[4].split("x"))
        data = open(sys.argv[3], "rb").read()
        raw = ((w, h), [data[y * w * 4:(y + 1) * w * 4] for y in range(h)])
        print(sys.argv[3], raw[0], "equal" if raw == b else "differs")
        ok = ok and raw == b
    sys.exit(0 if ok else 1)

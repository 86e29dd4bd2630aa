#!/usr/bin/env python3
"""Writes the gltf fuzz target's seeds into fuzz/seeds/gltf/.

Small self-contained glTF 2.0 files (buffers and images as data: URIs, or a
GLB's binary chunk), each reaching a part of facet's glTF import that a
user's file does: PBR materials with every texture slot, an embedded PNG,
alpha modes, KHR extensions, a node hierarchy with animation (linear, step
and cubic-spline samplers), a skin and morph targets, several primitives
and sparse accessors.

Each seed starts with the target's flags byte (fuzz/gltf.cpp): 0 for .gltf,
1 for .glb. The files are kept in the repository; run this again only to
change them.
"""
import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "gltf")

FLOAT, USHORT, UBYTE = 5126, 5123, 5121


def png_2x2():
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))
    raw = b"\0" + bytes([255, 0, 0, 255, 0, 255, 0, 128]) + b"\0" + bytes([0, 0, 255, 255, 255, 255, 255, 0])
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


class Builder:
    """Accessors over one buffer, as a glTF file lays them out."""

    def __init__(self):
        self.data = bytearray()
        self.views, self.accessors = [], []

    def view(self, payload, target=None):
        while len(self.data) % 4:
            self.data.append(0)
        v = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload)}
        if target:
            v["target"] = target
        self.data += payload
        self.views.append(v)
        return len(self.views) - 1

    def accessor(self, values, kind, component=FLOAT, target=34962, bounds=False):
        width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}[kind]
        fmt = {FLOAT: "f", USHORT: "H", UBYTE: "B"}[component]
        flat = [x for v in values for x in (v if isinstance(v, (list, tuple)) else [v])]
        a = {"bufferView": self.view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target),
             "componentType": component, "count": len(values), "type": kind}
        if bounds:
            a["min"] = [min(flat[i::width]) for i in range(width)]
            a["max"] = [max(flat[i::width]) for i in range(width)]
        self.accessors.append(a)
        return len(self.accessors) - 1


QUAD = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
QUAD_UV = [(0, 1), (1, 1), (1, 0), (0, 0)]


def primitive(b, material=None, colours=False, tangents=False, targets=False, skin=False):
    attrs = {"POSITION": b.accessor(QUAD, "VEC3", bounds=True),
             "NORMAL": b.accessor([(0, 0, 1)] * 4, "VEC3"),
             "TEXCOORD_0": b.accessor(QUAD_UV, "VEC2")}
    if colours:
        attrs["COLOR_0"] = b.accessor([(1, 0.5, 0.25, 1)] * 4, "VEC4")
    if tangents:
        attrs["TANGENT"] = b.accessor([(1, 0, 0, 1)] * 4, "VEC4")
    if skin:
        attrs["JOINTS_0"] = b.accessor([(0, 1, 0, 0)] * 4, "VEC4", UBYTE)
        attrs["WEIGHTS_0"] = b.accessor([(0.5, 0.5, 0, 0)] * 4, "VEC4")
    p = {"attributes": attrs,
         "indices": b.accessor([0, 1, 2, 0, 2, 3], "SCALAR", USHORT, 34963)}
    if material is not None:
        p["material"] = material
    if targets:
        p["targets"] = [{"POSITION": b.accessor([(0, 0, 0.5)] * 4, "VEC3", bounds=True)}]
    return p


def finish(doc, b, images=()):
    """The document with its buffer (and PNG images) as data: URIs."""
    for img in images:
        doc.setdefault("images", []).append(
            {"uri": "data:image/png;base64," + base64.b64encode(img).decode()})
    doc["buffers"] = [{"byteLength": len(b.data),
                       "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(b.data)).decode()}]
    doc["bufferViews"], doc["accessors"] = b.views, b.accessors
    return json.dumps(doc, separators=(",", ":")).encode()


def glb(doc, b, images=()):
    """A GLB: the JSON chunk, then the binary chunk holding buffer and images."""
    for img in images:
        doc.setdefault("images", []).append({"bufferView": b.view(img), "mimeType": "image/png"})
    while len(b.data) % 4:
        b.data.append(0)
    doc["buffers"] = [{"byteLength": len(b.data)}]
    doc["bufferViews"], doc["accessors"] = b.views, b.accessors
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(b.data), b"BIN\0") + bytes(b.data)
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def base(meshes, nodes=None):
    return {"asset": {"version": "2.0"}, "scene": 0,
            "scenes": [{"nodes": [0]}], "nodes": nodes or [{"mesh": 0}], "meshes": meshes}


def pbr_materials():
    return [{"name": "painted", "pbrMetallicRoughness": {
                "baseColorFactor": [0.8, 0.6, 0.4, 1], "baseColorTexture": {"index": 0},
                "metallicFactor": 0.3, "roughnessFactor": 0.7,
                "metallicRoughnessTexture": {"index": 0}},
             "normalTexture": {"index": 0, "scale": 0.5},
             "occlusionTexture": {"index": 0, "strength": 0.8},
             "emissiveTexture": {"index": 0}, "emissiveFactor": [1, 0.5, 0],
             "alphaMode": "MASK", "alphaCutoff": 0.4, "doubleSided": True},
            {"name": "glass", "alphaMode": "BLEND",
             "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 1, 0.3]}}]


def textured(b):
    doc = base([{"primitives": [primitive(b, 0, colours=True, tangents=True), primitive(b, 1)]}])
    doc["materials"] = pbr_materials()
    doc["samplers"] = [{"magFilter": 9728, "minFilter": 9987, "wrapS": 33648, "wrapT": 33071}]
    doc["textures"] = [{"source": 0, "sampler": 0}]
    return doc


def extensions(b):
    doc = base([{"primitives": [primitive(b, 0), primitive(b, 1), primitive(b, 2)]}])
    doc["extensionsUsed"] = ["KHR_materials_unlit", "KHR_texture_transform",
                             "KHR_materials_emissive_strength", "KHR_materials_pbrSpecularGlossiness",
                             "KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat"]
    doc["materials"] = [
        {"name": "flat", "extensions": {"KHR_materials_unlit": {}},
         "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}},
        {"name": "moved", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {
            "KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2], "rotation": 0.3}}}},
         "emissiveFactor": [1, 1, 1], "extensions": {
             "KHR_materials_emissive_strength": {"emissiveStrength": 4},
             "KHR_materials_ior": {"ior": 1.7},
             "KHR_materials_specular": {"specularFactor": 0.5, "specularColorFactor": [1, 0.5, 0.5]},
             "KHR_materials_clearcoat": {"clearcoatFactor": 1, "clearcoatRoughnessFactor": 0.2,
                                         "clearcoatTexture": {"index": 0, "extensions": {
                                             "KHR_texture_transform": {"scale": [4, 4], "texCoord": 0}}}}}},
        {"name": "old", "extensions": {"KHR_materials_pbrSpecularGlossiness": {
            "diffuseFactor": [0.5, 0.5, 0.5, 1], "glossinessFactor": 0.2}}}]
    doc["textures"] = [{"source": 0}]
    return doc


def animated(b):
    nodes = [{"name": "root", "children": [1], "translation": [0, 1, 0]},
             {"name": "arm", "mesh": 0, "rotation": [0, 0, 0, 1], "scale": [1, 2, 1]}]
    doc = base([{"primitives": [primitive(b)]}], nodes)
    times = b.accessor([0.0, 0.5, 1.0], "SCALAR", bounds=True)
    move = b.accessor([(0, 0, 0), (1, 0, 0), (1, 1, 0)], "VEC3")
    turn = b.accessor([(0, 0, 0, 1), (0, 0.7071, 0, 0.7071), (0, 1, 0, 0)], "VEC4")
    # Cubic spline: in-tangent, value, out-tangent for each key.
    grow = b.accessor([(0, 0, 0), (1, 1, 1), (0, 0, 0), (0, 0, 0), (2, 2, 2), (0, 0, 0),
                       (0, 0, 0), (1, 1, 1), (0, 0, 0)], "VEC3")
    doc["animations"] = [{"name": "wave", "samplers": [
        {"input": times, "output": move, "interpolation": "LINEAR"},
        {"input": times, "output": turn, "interpolation": "STEP"},
        {"input": times, "output": grow, "interpolation": "CUBICSPLINE"}],
        "channels": [{"sampler": 0, "target": {"node": 0, "path": "translation"}},
                     {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                     {"sampler": 2, "target": {"node": 1, "path": "scale"}}]},
        {"name": "idle", "samplers": [{"input": times, "output": move}],
         "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}]}]
    return doc


def skinned(b):
    nodes = [{"name": "body", "mesh": 0, "skin": 0, "children": [1, 2]},
             {"name": "bone0"}, {"name": "bone1", "translation": [0, 1, 0]}]
    doc = base([{"primitives": [primitive(b, targets=True, skin=True)], "weights": [0.5]}], nodes)
    identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]
    doc["skins"] = [{"joints": [1, 2], "inverseBindMatrices": b.accessor([identity] * 2, "MAT4", target=None)}]
    times = b.accessor([0.0, 1.0], "SCALAR", bounds=True)
    doc["animations"] = [{"samplers": [{"input": times, "output": b.accessor([0.0, 1.0], "SCALAR")}],
                          "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}]}]
    return doc


def sparse(b):
    doc = base([{"primitives": [primitive(b)], "name": "patched"}])
    positions = b.accessors[doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
    positions["sparse"] = {"count": 1,
                           "indices": {"bufferView": b.view(struct.pack("<H", 2)), "componentType": USHORT},
                           "values": {"bufferView": b.view(struct.pack("<3f", 1, 1, 1))}}
    positions["max"] = [1, 1, 1]
    return doc


def main():
    os.makedirs(OUT, exist_ok=True)
    image = png_2x2()
    seeds = {}
    for name, make, images in [("textured", textured, [image]), ("extensions", extensions, [image]),
                               ("animated", animated, []), ("skinned", skinned, []),
                               ("sparse", sparse, [])]:
        b = Builder()
        seeds[name + ".gltf"] = b"\0" + finish(make(b), b, images)
        b = Builder()
        seeds[name + ".glb"] = b"\1" + glb(make(b), b, images)
    for name, data in seeds.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
    print(f"{len(seeds)} seeds in {OUT}")


if __name__ == "__main__":
    main()

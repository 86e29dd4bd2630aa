#!/usr/bin/env python3
"""Writes the skinning and morph-target demo models, as glTF 2.0 with their
buffers embedded (base64 data URIs), in plain Python:

  tentacle.gltf  a tube on a chain of five joints, skinned with four joints a
                 vertex, and two clips: "wave" (a travelling sway about Z)
                 and "curl" (it rolls up about X and back).
  blob.gltf      a sphere with two morph targets, "spikes" (positions and
                 normals) and "squash", whose weights one clip animates.

    python3 assets/skin/make_skin.py [OUT_DIR]   (default: this folder)
"""
import base64
import json
import math
import os
import struct
import sys

FLOAT, USHORT, UINT = 5126, 5123, 5125


class Buffer:
    """One glTF buffer and its accessors, built up in order."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def add(self, values, fmt, component, kind, count, bounds=False):
        while len(self.data) % 4:
            self.data.append(0)
        start = len(self.data)
        self.data += struct.pack("<%d%s" % (len(values), fmt), *values)
        self.views.append({"buffer": 0, "byteOffset": start, "byteLength": len(self.data) - start})
        accessor = {"bufferView": len(self.views) - 1, "componentType": component,
                    "count": count, "type": kind}
        if bounds:
            width = len(values) // count
            accessor["min"] = [min(values[i::width]) for i in range(width)]
            accessor["max"] = [max(values[i::width]) for i in range(width)]
        self.accessors.append(accessor)
        return len(self.accessors) - 1

    def vec3s(self, points, bounds=False):
        return self.add([c for p in points for c in p], "f", FLOAT, "VEC3", len(points), bounds)

    def gltf(self):
        uri = "data:application/octet-stream;base64," + base64.b64encode(bytes(self.data)).decode()
        return {"buffers": [{"byteLength": len(self.data), "uri": uri}],
                "bufferViews": self.views, "accessors": self.accessors}


def quat_axis_angle(axis, angle):
    s = math.sin(angle / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2)]


def smoothstep(x):
    x = min(max(x, 0.0), 1.0)
    return x * x * (3 - 2 * x)


def tentacle(out_dir):
    joints, length, radius = 5, 0.5, 0.18
    around, rings = 24, 60
    height = joints * length
    buf = Buffer()
    positions, normals, joint_ids, weights, indices = [], [], [], [], []
    for r in range(rings + 1):
        y = height * r / rings
        taper = radius * (1.0 - 0.7 * y / height)
        # The two joints nearest this height, blended smoothly across each
        # joint, and the ones either side at small weights: four a vertex.
        s = min(y / length, joints - 1e-6)
        k = int(s)
        blend = smoothstep((s - k - 0.5) * 1.6 + 0.5)
        near = [(k, 1.0 - blend), (min(k + 1, joints - 1), blend)]
        ring = {}
        for j, w in near + [(max(k - 1, 0), 0.05), (min(k + 2, joints - 1), 0.05)]:
            ring[j] = ring.get(j, 0.0) + w
        ids = sorted(ring, key=lambda j: -ring[j])[:4]
        total = sum(ring[j] for j in ids)
        ws = [ring[j] / total for j in ids]
        ids += [0] * (4 - len(ids))
        ws += [0.0] * (4 - len(ws))
        for a in range(around + 1):
            t = 2 * math.pi * a / around
            positions.append((taper * math.cos(t), y, -taper * math.sin(t)))
            normals.append((math.cos(t), 0.0, -math.sin(t)))
            joint_ids.append(ids)
            weights.append(ws)
    for r in range(rings):
        for a in range(around):
            i = r * (around + 1) + a
            j = i + around + 1
            indices += [i, i + 1, j + 1, i, j + 1, j]
    # The tip's cap: a fan of its own vertices (facing up), weighted as the
    # top ring.
    top = rings * (around + 1)
    centre = len(positions)
    positions.append((0.0, height, 0.0))
    normals.append((0.0, 1.0, 0.0))
    joint_ids.append(joint_ids[top])
    weights.append(weights[top])
    for a in range(around + 1):
        positions.append(positions[top + a])
        normals.append((0.0, 1.0, 0.0))
        joint_ids.append(joint_ids[top + a])
        weights.append(weights[top + a])
    for a in range(around):
        indices += [centre, centre + 1 + a, centre + 2 + a]
    pos = buf.vec3s(positions, bounds=True)
    nrm = buf.vec3s(normals)
    jnt = buf.add([c for ids in joint_ids for c in ids], "H", USHORT, "VEC4", len(joint_ids))
    wgt = buf.add([c for w in weights for c in w], "f", FLOAT, "VEC4", len(weights))
    idx = buf.add(indices, "I", UINT, "SCALAR", len(indices))
    # Joint k sits at (0, k * length, 0) at bind: its inverse bind matrix
    # (column-major) moves it back to the origin.
    inverse_binds = []
    for k in range(joints):
        inverse_binds += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -k * length, 0, 1]
    ibm = buf.add(inverse_binds, "f", FLOAT, "MAT4", joints)
    nodes = [{"name": "tentacle", "mesh": 0, "skin": 0}]
    for k in range(joints):
        node = {"name": "joint%d" % k, "translation": [0, length if k else 0, 0]}
        if k + 1 < joints:
            node["children"] = [k + 2]
        nodes.append(node)
    clips = []
    for name, axis, angle in (("wave", (0, 0, 1), None), ("curl", (1, 0, 0), None)):
        keys = 49
        times = [2.0 * i / (keys - 1) for i in range(keys)]
        time_acc = buf.add(times, "f", FLOAT, "SCALAR", keys, bounds=True)
        channels, samplers = [], []
        for k in range(joints):
            values = []
            for t in times:
                if name == "wave":
                    a = 0.45 * math.sin(2 * math.pi * (t / 2.0) - 0.9 * k)
                else:
                    a = 0.55 * math.sin(math.pi * t / 2.0) ** 2 * (k + 1) / joints
                values += quat_axis_angle(axis, a)
            out = buf.add(values, "f", FLOAT, "VEC4", keys)
            samplers.append({"input": time_acc, "output": out, "interpolation": "LINEAR"})
            channels.append({"sampler": k, "target": {"node": k + 1, "path": "rotation"}})
        clips.append({"name": name, "channels": channels, "samplers": samplers})
    doc = {
        "asset": {"version": "2.0", "generator": "facet assets/skin/make_skin.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1]}],
        "nodes": nodes,
        "skins": [{"name": "spine", "joints": list(range(1, joints + 1)),
                   "inverseBindMatrices": ibm, "skeleton": 1}],
        "meshes": [{"name": "tentacle", "primitives": [{
            "attributes": {"POSITION": pos, "NORMAL": nrm, "JOINTS_0": jnt, "WEIGHTS_0": wgt},
            "indices": idx, "material": 0}]}],
        "materials": [{"name": "coral", "pbrMetallicRoughness": {
            "baseColorFactor": [0.85, 0.32, 0.25, 1.0], "metallicFactor": 0.0,
            "roughnessFactor": 0.45}}],
        "animations": clips,
    }
    doc.update(buf.gltf())
    write(out_dir, "tentacle.gltf", doc)


def spike_point(phi, theta):
    """The "spikes" target's surface: bumps along the sphere's normal."""
    n = (math.sin(phi) * math.cos(theta), math.cos(phi), -math.sin(phi) * math.sin(theta))
    r = 0.5 + 0.12 * max(0.0, math.sin(6 * theta) * math.sin(5 * phi)) ** 2
    return tuple(r * c for c in n)


def spike_normal(phi, theta, n):
    """The spiked surface's unit normal, by central differences (the
    sphere's at the poles, where the bumps vanish)."""
    h = 1e-4
    if math.sin(phi) < 1e-6:
        return n
    dp = [a - b for a, b in zip(spike_point(phi + h, theta), spike_point(phi - h, theta))]
    dt = [a - b for a, b in zip(spike_point(phi, theta + h), spike_point(phi, theta - h))]
    c = (dt[1] * dp[2] - dt[2] * dp[1], dt[2] * dp[0] - dt[0] * dp[2], dt[0] * dp[1] - dt[1] * dp[0])
    length = math.sqrt(sum(x * x for x in c))
    c = tuple(x / length for x in c)
    return c if sum(a * b for a, b in zip(c, n)) > 0 else tuple(-x for x in c)


def blob(out_dir):
    rings = 32
    buf = Buffer()
    positions, normals, spikes, spike_normals, squash, indices = [], [], [], [], [], []
    for r in range(rings + 1):
        phi = math.pi * r / rings
        for a in range(2 * rings + 1):
            theta = 2 * math.pi * a / (2 * rings)
            n = (math.sin(phi) * math.cos(theta), math.cos(phi), -math.sin(phi) * math.sin(theta))
            positions.append(tuple(0.5 * c for c in n))
            normals.append(n)
            spiked = spike_point(phi, theta)
            spikes.append(tuple(spiked[i] - positions[-1][i] for i in range(3)))
            m = spike_normal(phi, theta, n)
            spike_normals.append(tuple(m[i] - n[i] for i in range(3)))
            squash.append((0.15 * n[0], -0.2 * n[1], 0.15 * n[2]))
    width = 2 * rings + 1
    for r in range(rings):
        for a in range(2 * rings):
            i = r * width + a
            j = i + width
            indices += [i, j, j + 1, i, j + 1, i + 1]
    pos = buf.vec3s(positions, bounds=True)
    nrm = buf.vec3s(normals)
    t0 = buf.vec3s(spikes, bounds=True)
    t0n = buf.vec3s(spike_normals)
    t1 = buf.vec3s(squash, bounds=True)
    idx = buf.add(indices, "I", UINT, "SCALAR", len(indices))
    keys = 41
    times = [2.0 * i / (keys - 1) for i in range(keys)]
    time_acc = buf.add(times, "f", FLOAT, "SCALAR", keys, bounds=True)
    weights = []
    for t in times:
        weights += [math.sin(math.pi * t / 2.0) ** 2, 0.5 - 0.5 * math.cos(math.pi * t)]
    out = buf.add(weights, "f", FLOAT, "SCALAR", 2 * keys)
    doc = {
        "asset": {"version": "2.0", "generator": "facet assets/skin/make_skin.py"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"name": "blob", "mesh": 0}],
        "meshes": [{"name": "blob", "weights": [0.0, 0.0],
                    "extras": {"targetNames": ["spikes", "squash"]},
                    "primitives": [{
                        "attributes": {"POSITION": pos, "NORMAL": nrm},
                        "targets": [{"POSITION": t0, "NORMAL": t0n}, {"POSITION": t1}],
                        "indices": idx, "material": 0}]}],
        "materials": [{"name": "jelly", "pbrMetallicRoughness": {
            "baseColorFactor": [0.25, 0.55, 0.9, 1.0], "metallicFactor": 0.0,
            "roughnessFactor": 0.3}}],
        "animations": [{"name": "pulse", "channels": [
            {"sampler": 0, "target": {"node": 0, "path": "weights"}}],
            "samplers": [{"input": time_acc, "output": out, "interpolation": "LINEAR"}]}],
    }
    doc.update(buf.gltf())
    write(out_dir, "blob.gltf", doc)


def write(out_dir, name, doc):
    path = os.path.join(out_dir, name)
    with open(path, "w") as f:
        json.dump(doc, f, separators=(",", ":"))
        f.write("\n")
    print("wrote", path)


if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    tentacle(out)
    blob(out)

#!/usr/bin/env python3
"""Writes the hand-made seed files of the fuzz corpus (fuzz/corpus/<target>/seed-*), small
valid inputs the mutations start from: an OBJ, ASCII and binary PLYs, a glTF with a data URI and
a GLB, and for `gltf_anim` a skinned and morphed glTF/GLB with animations. Deterministic; run
from anywhere: `python3 fuzz/seeds.py`."""

import base64
import json
import os
import struct

CORPUS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")

# An octahedron's upper half (unit sphere patches), 5 vertices, 4 triangles.
P = [(1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0), (0, 0, 1)]
T = [(0, 1, 4), (1, 2, 4), (2, 3, 4), (3, 0, 4)]


def write(target, name, data):
    d = os.path.join(CORPUS, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "seed-" + name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def obj():
    s = "# octahedron cap\n"
    s += "".join("v %g %g %g\n" % p for p in P)
    s += "".join("vn %g %g %g\n" % p for p in P)
    s += "".join("f %d//%d %d//%d %d//%d\n" % (a + 1, a + 1, b + 1, b + 1, c + 1, c + 1) for a, b, c in T)
    write("obj", "cap.obj", s)
    write("obj", "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")


def ply():
    head = "ply\nformat %s 1.0\nelement vertex 5\nproperty float x\nproperty float y\n" \
        "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n" \
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n"
    s = head % "ascii"
    s += "".join("%g %g %g %g %g %g\n" % (p + p) for p in P)
    s += "".join("3 %d %d %d\n" % t for t in T)
    write("ply", "cap-ascii.ply", s)
    b = (head % "binary_little_endian").encode()
    b += b"".join(struct.pack("<6f", *(p + p)) for p in P)
    b += b"".join(struct.pack("<B3i", 3, *t) for t in T)
    write("ply", "cap-binary.ply", b)


def pad4(b, fill=b"\0"):
    return b + fill * (-len(b) % 4)


def glb(doc, binary):
    js = pad4(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    binary = pad4(binary)
    out = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js) + 8 + len(binary))
    out += struct.pack("<I4s", len(js), b"JSON") + js
    out += struct.pack("<I4s", len(binary), b"BIN\0") + binary
    return out


class Buf:
    """One buffer of several views and accessors."""

    def __init__(self):
        self.data, self.views, self.accessors = b"", [], []

    def add(self, fmt, rows, typ, comp, minmax=False):
        body = b"".join(struct.pack("<" + fmt, *r) for r in rows)
        self.data = pad4(self.data)
        self.views.append({"buffer": 0, "byteOffset": len(self.data), "byteLength": len(body)})
        self.data += body
        acc = {"bufferView": len(self.views) - 1, "componentType": comp, "count": len(rows), "type": typ}
        if minmax:
            acc["min"] = [min(r[i] for r in rows) for i in range(len(rows[0]))]
            acc["max"] = [max(r[i] for r in rows) for i in range(len(rows[0]))]
        self.accessors.append(acc)
        return len(self.accessors) - 1


def static_doc():
    b = Buf()
    pos = b.add("3f", P, "VEC3", 5126, True)
    nrm = b.add("3f", P, "VEC3", 5126)
    idx = b.add("3H", T, "SCALAR", 5123)
    b.accessors[idx]["count"] = 3 * len(T)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm}, "indices": idx}]}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.data)}],
    }
    return doc, b.data


def animated_doc():
    """A strip of 6 vertices skinned to two joints, with one morph target, and two clips:
    joint 1's rotation and translation (LINEAR, STEP) and the morph weight (CUBICSPLINE)."""
    pos = [(x, y, 0.0) for y in (0.0, 1.0, 2.0) for x in (0.0, 1.0)]
    tri = [(0, 1, 3), (0, 3, 2), (2, 3, 5), (2, 5, 4)]
    b = Buf()
    a_pos = b.add("3f", pos, "VEC3", 5126, True)
    a_nrm = b.add("3f", [(0, 0, 1)] * 6, "VEC3", 5126)
    a_idx = b.add("3H", tri, "SCALAR", 5123)
    b.accessors[a_idx]["count"] = 12
    a_joints = b.add("4B", [(0, 1, 0, 0)] * 6, "VEC4", 5121)
    a_weights = b.add("4f", [(1 - p[1] / 2, p[1] / 2, 0, 0) for p in pos], "VEC4", 5126)
    a_target = b.add("3f", [(0.0, 0.0, 0.3 * p[1]) for p in pos], "VEC3", 5126, True)
    a_ibm = b.add("16f", [(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -0.5, -1 * j, 0, 1) for j in (0, 1)], "MAT4", 5126)
    a_t = b.add("f", [(0.0,), (0.5,), (1.0,)], "SCALAR", 5126, True)
    a_rot = b.add("4f", [(0, 0, 0, 1), (0, 0, 0.383, 0.924), (0, 0, 0.707, 0.707)], "VEC4", 5126)
    a_tr = b.add("3f", [(0, 1, 0), (0.1, 1, 0), (0, 1.2, 0)], "VEC3", 5126)
    a_w = b.add("f", [(0,), (0,), (0,), (0,), (1,), (0,), (0,), (0.5,), (0,)], "SCALAR", 5126)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0, "skin": 0},
            {"children": [2], "translation": [0, 0, 0]},
            {"translation": [0, 1, 0]},
        ],
        "skins": [{"joints": [1, 2], "inverseBindMatrices": a_ibm}],
        "meshes": [{
            "primitives": [{
                "attributes": {"POSITION": a_pos, "NORMAL": a_nrm, "JOINTS_0": a_joints, "WEIGHTS_0": a_weights},
                "indices": a_idx,
                "targets": [{"POSITION": a_target}],
            }],
            "weights": [0.0],
        }],
        "animations": [
            {"name": "bend", "samplers": [
                {"input": a_t, "output": a_rot, "interpolation": "LINEAR"},
                {"input": a_t, "output": a_tr, "interpolation": "STEP"},
            ], "channels": [
                {"sampler": 0, "target": {"node": 2, "path": "rotation"}},
                {"sampler": 1, "target": {"node": 2, "path": "translation"}},
            ]},
            {"name": "morph", "samplers": [{"input": a_t, "output": a_w, "interpolation": "CUBICSPLINE"}],
             "channels": [{"sampler": 0, "target": {"node": 0, "path": "weights"}}]},
        ],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(b.data)}],
    }
    return doc, b.data


def with_data_uri(doc, data):
    doc = json.loads(json.dumps(doc))
    doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    return json.dumps(doc, indent=1)


def gltf():
    doc, data = static_doc()
    write("gltf", "cap.gltf", with_data_uri(doc, data))
    write("glb", "cap.glb", glb(doc, data))
    doc, data = animated_doc()
    write("gltf_anim", "skin-morph.gltf", with_data_uri(doc, data))
    write("gltf_anim", "skin-morph.glb", glb(doc, data))
    sdoc, sdata = static_doc()
    write("gltf_anim", "static.glb", glb(sdoc, sdata))


if __name__ == "__main__":
    obj()
    ply()
    gltf()
